#pragma once
// An offscreen OpenGL context for the footprint renderer. This is the only
// place that knows the context comes from OSMesa: newer Mesa drops OSMesa in
// favour of EGL surfaceless (same llvmpipe rasteriser), and that switch should
// touch gl_context.cpp alone. The header deliberately includes no GL header.

#include <memory>
#include <string>

namespace bristle::render {

class GlContext {
 public:
  // Creates a core-profile context (3.3 requested; llvmpipe gives 4.5) and makes
  // it current on the calling thread. There is no usable default framebuffer:
  // callers draw into their own FBO. Throws std::runtime_error when the context
  // cannot be created (including a GALLIUM_DRIVER value OSMesa cannot load).
  GlContext();
  ~GlContext();
  GlContext(const GlContext&) = delete;
  GlContext& operator=(const GlContext&) = delete;

  // Makes this context current on the calling thread (cheap when it already is).
  // Needed when several contexts live in one process. A context may be current
  // on one thread at a time. Throws std::runtime_error.
  void makeCurrent();

  // GL_VERSION and GL_RENDERER, e.g. "4.5 (Core Profile) Mesa 22.3.6 | llvmpipe
  // (LLVM 15.0.6, 256 bits)", for logs and error messages.
  const std::string& description() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bristle::render

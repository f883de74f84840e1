// OSMesa behind GlContext. Every OSMesa call of the project lives in this file.
//
// Link trap: this library must link libOSMesa only. If libGL/libOpenGL (glvnd)
// were linked too, their gl* entry points would shadow OSMesa's and every call
// would silently do nothing; GL_GLEXT_PROTOTYPES makes OSMesa export the core
// 3.x/4.x entry points directly, so no loader is needed.

#include "render/gl/gl_context.h"

#include <GL/gl.h>
#include <GL/glext.h>
#include <GL/osmesa.h>

#include <array>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "engine/base/error.h"

namespace bristle::render {

namespace {

// The gallium drivers built into Debian's libOSMesa. Any other GALLIUM_DRIVER
// value (zink, swr, a typo) segfaults inside OSMesaCreateContextAttribs (Mesa
// 22.3), so refuse it up front with a message instead of a crash.
constexpr std::array<std::string_view, 2> kOsmesaDrivers = {"llvmpipe", "softpipe"};

void checkGalliumDriver() {
  const char* driver = std::getenv("GALLIUM_DRIVER");
  if (driver == nullptr || *driver == '\0') return;  // unset: llvmpipe
  for (std::string_view known : kOsmesaDrivers) {
    if (known == driver) return;
  }
  // The environment is part of the command's invocation: a usage error (64,
  // docs/errors.md), not an internal one.
  throw Error(ExitCode::kUsage, std::string("GALLIUM_DRIVER=") + driver +
                                    ": OSMesa supports only llvmpipe or softpipe; unset it "
                                    "to use llvmpipe");
}

// llvmpipe rasterises on LP_NUM_THREADS threads besides the caller's (by
// default one per CPU). bristle's footprints are small windows, drawn once per
// step: handing each to the threads and waiting for them costs more than the
// rasterising it saves. With none (0), the calling thread rasterises: the
// same pixels in less wall and CPU time (docs/PERFORMANCE.md, "Simulation
// and drawing on two threads").
// A value the user set is kept. Read once, when llvmpipe's screen is made.
void chooseRasteriserThreads() {
  ::setenv("LP_NUM_THREADS", "0", /*overwrite=*/0);
}

// Mesa keeps a cache of compiled shaders under the user's cache folder (and
// finds the home through the password file when HOME points elsewhere). A
// render writes nothing but its outputs (docs/errors.md, "Outputs"), and
// bristle's few shaders compile in milliseconds, so the cache is off unless
// the user set MESA_SHADER_CACHE_DISABLE. Read when llvmpipe's screen is made.
void disableShaderCache() {
  ::setenv("MESA_SHADER_CACHE_DISABLE", "true", /*overwrite=*/0);
}

std::string glString(GLenum name) {
  const GLubyte* s = glGetString(name);
  return s != nullptr ? reinterpret_cast<const char*>(s) : "(null)";
}

}  // namespace

struct GlContext::Impl {
  OSMesaContext context = nullptr;
  // OSMesa insists on a client colour buffer to make a context current. All
  // real drawing goes to FBOs, so one RGBA8 pixel is enough.
  std::array<GLubyte, 4> dummy_buffer{};
  std::string description;
};

GlContext::GlContext() : impl_(std::make_unique<Impl>()) {
  checkGalliumDriver();
  chooseRasteriserThreads();
  disableShaderCache();

  // No depth/stencil/accum on the dummy buffer: the FBO brings its own depth.
  const int attributes[] = {
      OSMESA_FORMAT, OSMESA_RGBA,
      OSMESA_DEPTH_BITS, 0,
      OSMESA_STENCIL_BITS, 0,
      OSMESA_ACCUM_BITS, 0,
      OSMESA_PROFILE, OSMESA_CORE_PROFILE,
      OSMESA_CONTEXT_MAJOR_VERSION, 3,
      OSMESA_CONTEXT_MINOR_VERSION, 3,
      0};
  impl_->context = OSMesaCreateContextAttribs(attributes, nullptr);
  if (impl_->context == nullptr) {
    throw std::runtime_error(
        "cannot create an OSMesa OpenGL 3.3 core context (is Mesa's llvmpipe "
        "available?)");
  }
  try {
    makeCurrent();
    impl_->description = glString(GL_VERSION) + " | " + glString(GL_RENDERER);
    GLint major = 0, minor = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    if (major * 10 + minor < 33) {
      throw std::runtime_error("OSMesa returned OpenGL " + impl_->description +
                               "; the footprint renderer needs 3.3 core");
    }
  } catch (...) {
    OSMesaDestroyContext(impl_->context);
    throw;
  }
}

GlContext::~GlContext() {
  // Unbind first if we are current, so no thread is left with a dangling context.
  if (OSMesaGetCurrentContext() == impl_->context) {
    OSMesaMakeCurrent(nullptr, nullptr, GL_UNSIGNED_BYTE, 0, 0);
  }
  OSMesaDestroyContext(impl_->context);
}

void GlContext::makeCurrent() {
  if (OSMesaGetCurrentContext() == impl_->context) return;
  if (!OSMesaMakeCurrent(impl_->context, impl_->dummy_buffer.data(),
                         GL_UNSIGNED_BYTE, 1, 1)) {
    throw std::runtime_error("OSMesaMakeCurrent failed for the footprint context");
  }
}

const std::string& GlContext::description() const { return impl_->description; }

}  // namespace bristle::render

// Footprint rendering (paper §4.2.1, after Baxter et al. 2001 [4]): draw the
// brush geometry orthographically as seen from the canvas, cull everything above
// a clip plane near the paper, and keep per pixel the brush point nearest the
// canvas. Core-profile GL into a float FBO; no blending, no multisampling, one
// readback path, so the same input gives the same bytes every time.

#include "render/footprint_renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "render/gl_context.h"
#include "render/gl_program.h"

namespace bristle::render {

namespace {

static_assert(std::is_standard_layout_v<FootprintVertex> &&
                  sizeof(FootprintVertex) == 5 * sizeof(float),
              "FootprintVertex is uploaded to GL as 5 packed floats");

// Depth buffer range: z in [floor, clip_mm] maps linearly to depth [0, 1]. The
// brush never goes below the canvas (z = 0), so 2 mm below it is ample room for
// solver slack; anything lower is clamped (GL_DEPTH_CLAMP), not clipped away.
constexpr double kDepthFloorMm = -2.0;
// Keeps the depth range non-degenerate when clip_mm is at or below the floor.
constexpr double kMinDepthRangeMm = 1.0;

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_mm;
layout(location = 1) in vec2 uv_in;
uniform vec2 origin_mm;      // window bottom-left corner
uniform vec2 ndc_per_mm;     // 2 * px_per_mm / window size in pixels
uniform float clip_mm;       // keep z <= clip_mm
uniform float depth_floor_mm;
out float gl_ClipDistance[1];
out vec2 uv;
out float depth_mm;
void main() {
  // Orthographic: window pixel c spans x0 + [c, c + 1] / px_per_mm exactly.
  vec2 ndc = (position_mm.xy - origin_mm) * ndc_per_mm - 1.0;
  // Smallest z (nearest the canvas) gets the smallest depth and wins GL_LESS.
  float z_ndc = 2.0 * (position_mm.z - depth_floor_mm) /
                (clip_mm - depth_floor_mm) - 1.0;
  gl_Position = vec4(ndc, z_ndc, 1.0);
  gl_ClipDistance[0] = clip_mm - position_mm.z;
  uv = uv_in;
  depth_mm = clip_mm - position_mm.z;
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
in vec2 uv;
in float depth_mm;
layout(location = 0) out vec4 texel;
void main() { texel = vec4(uv, depth_mm, 1.0); }
)";

void checkGl(const char* what) { render::checkGl("footprint renderer", what); }

GLuint linkProgram() {
  return render::linkProgram("footprint renderer", kVertexShader, kFragmentShader);
}

}  // namespace

struct FootprintRenderer::Impl {
  GlContext context;  // first member: created first, destroyed last
  int max_size_px = 0;
  GLuint program = 0, vao = 0, vbo = 0, fbo = 0, color_texture = 0, depth_buffer = 0;
  GLint origin_loc = -1, ndc_per_mm_loc = -1, clip_loc = -1, floor_loc = -1;
  int target_width_px = 0, target_height_px = 0;  // current FBO attachment size

  // Grows the FBO attachments to hold the window; never shrinks them, so a
  // sequence of windows of varying size reallocates only a few times.
  void ensureTarget(int width_px, int height_px) {
    if (width_px <= target_width_px && height_px <= target_height_px) return;
    const int new_width = std::max(width_px, target_width_px);
    const int new_height = std::max(height_px, target_height_px);
    glBindTexture(GL_TEXTURE_2D, color_texture);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, new_width, new_height, 0, GL_RGBA,
                 GL_FLOAT, nullptr);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_buffer);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, new_width, new_height);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      throw std::runtime_error("footprint FBO incomplete at " + std::to_string(new_width) +
                               "x" + std::to_string(new_height) + " px");
    }
    checkGl("allocating the footprint FBO");
    // Recorded only on success, so a failed allocation is retried next time.
    target_width_px = new_width;
    target_height_px = new_height;
  }
};

FootprintRenderer::FootprintRenderer(int max_size_px) : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  GLint max_renderbuffer = 0, max_texture = 0, max_viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_texture);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
  const int gl_limit = std::min({max_renderbuffer, max_texture, max_viewport[0],
                                 max_viewport[1]});
  if (max_size_px <= 0 || max_size_px > gl_limit) {
    throw std::invalid_argument("footprint max_size_px = " + std::to_string(max_size_px) +
                                ": must be in [1, " + std::to_string(gl_limit) + "]");
  }
  s.max_size_px = max_size_px;

  s.program = linkProgram();
  s.origin_loc = glGetUniformLocation(s.program, "origin_mm");
  s.ndc_per_mm_loc = glGetUniformLocation(s.program, "ndc_per_mm");
  s.clip_loc = glGetUniformLocation(s.program, "clip_mm");
  s.floor_loc = glGetUniformLocation(s.program, "depth_floor_mm");

  glGenVertexArrays(1, &s.vao);
  glBindVertexArray(s.vao);
  glGenBuffers(1, &s.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, s.vbo);
  const auto offset = [](std::size_t bytes) {
    return reinterpret_cast<const void*>(static_cast<std::uintptr_t>(bytes));
  };
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(FootprintVertex),
                        offset(offsetof(FootprintVertex, x_mm)));
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, sizeof(FootprintVertex),
                        offset(offsetof(FootprintVertex, u)));
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);

  glGenTextures(1, &s.color_texture);
  glBindTexture(GL_TEXTURE_2D, s.color_texture);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glGenRenderbuffers(1, &s.depth_buffer);
  // Core profile: a generated name becomes an object only when first bound.
  glBindRenderbuffer(GL_RENDERBUFFER, s.depth_buffer);
  glGenFramebuffers(1, &s.fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                         s.color_texture, 0);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER,
                            s.depth_buffer);
  glDrawBuffer(GL_COLOR_ATTACHMENT0);
  glReadBuffer(GL_COLOR_ATTACHMENT0);

  // Fixed state for every render: nearest-to-canvas wins, the clip plane is the
  // only thing that removes geometry, both faces count (strips face either way),
  // and nothing mixes fragments.
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_DEPTH_CLAMP);
  glEnable(GL_CLIP_DISTANCE0);
  glDisable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_DITHER);
  glDisable(GL_MULTISAMPLE);
  glEnable(GL_SCISSOR_TEST);  // clear only the window, not the whole FBO
  glClearColor(0, 0, 0, 0);
  glClearDepth(1.0);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glUseProgram(s.program);
  checkGl("setting up the footprint renderer");
}

// The GL objects die with the context (Impl::context is destroyed last).
FootprintRenderer::~FootprintRenderer() = default;

void FootprintRenderer::render(std::span<const FootprintVertex> triangles,
                               const FootprintWindow& window, double clip_mm,
                               FootprintImage* out) {
  Impl& s = *impl_;
  const int width = window.width_px, height = window.height_px;
  if (width < 0 || height < 0 || width > s.max_size_px || height > s.max_size_px) {
    throw std::invalid_argument("footprint window " + std::to_string(width) + "x" +
                                std::to_string(height) + " px: each side must be in [0, " +
                                std::to_string(s.max_size_px) + "]");
  }
  if (!(window.px_per_mm > 0) || !std::isfinite(window.px_per_mm) ||
      !std::isfinite(window.x0_mm) || !std::isfinite(window.y0_mm) ||
      !std::isfinite(clip_mm)) {
    throw std::invalid_argument("footprint window: px_per_mm must be > 0 and the "
                                "origin and clip_mm finite");
  }
  if (triangles.size() % 3 != 0 || triangles.size() > static_cast<std::size_t>(INT_MAX)) {
    throw std::invalid_argument("footprint triangles: vertex count " +
                                std::to_string(triangles.size()) +
                                " must be a multiple of 3");
  }
  out->window = window;
  // Every texel is overwritten by the readback below.
  out->texels.resize(static_cast<std::size_t>(width) * height * 4);
  if (out->texels.empty()) return;

  s.context.makeCurrent();
  s.ensureTarget(width, height);
  glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
  glViewport(0, 0, width, height);
  glScissor(0, 0, width, height);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  if (!triangles.empty()) {
    const double depth_floor_mm = std::min(kDepthFloorMm, clip_mm - kMinDepthRangeMm);
    glUniform2f(s.origin_loc, static_cast<float>(window.x0_mm),
                static_cast<float>(window.y0_mm));
    glUniform2f(s.ndc_per_mm_loc, static_cast<float>(2.0 * window.px_per_mm / width),
                static_cast<float>(2.0 * window.px_per_mm / height));
    glUniform1f(s.clip_loc, static_cast<float>(clip_mm));
    glUniform1f(s.floor_loc, static_cast<float>(depth_floor_mm));
    glBindVertexArray(s.vao);
    glBindBuffer(GL_ARRAY_BUFFER, s.vbo);
    glBufferData(GL_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(triangles.size_bytes()), triangles.data(),
                 GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(triangles.size()));
  }

  // GL's row 0 is the bottom (smallest y); the image's row 0 is the top.
  glReadPixels(0, 0, width, height, GL_RGBA, GL_FLOAT, out->texels.data());
  checkGl("rendering the footprint");
  const std::size_t row_floats = static_cast<std::size_t>(width) * 4;
  for (int top = 0, bottom = height - 1; top < bottom; ++top, --bottom) {
    float* a = out->texels.data() + row_floats * top;
    std::swap_ranges(a, a + row_floats, out->texels.data() + row_floats * bottom);
  }
}

}  // namespace bristle::render

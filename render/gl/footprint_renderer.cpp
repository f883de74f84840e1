// Footprint rendering (paper §4.2.1, after Baxter et al. 2001 [4]): draw the
// brush geometry orthographically as seen from the canvas, cull everything above
// a clip plane near the paper, and keep per pixel the brush point nearest the
// canvas. Core-profile GL into a float FBO; no blending, no multisampling, one
// readback path, so the same input gives the same bytes every time.

#include "render/gl/footprint_renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "render/gl/gl_context.h"
#include "render/gl/gl_program.h"

namespace bristle::render {

namespace {

static_assert(std::is_standard_layout_v<FootprintVertex> &&
                  sizeof(FootprintVertex) == 5 * sizeof(float),
              "FootprintVertex is uploaded to GL as 5 packed floats");

// Depth buffer range: z in [floor, contact_band_mm] maps linearly to depth [0, 1]. The
// brush never goes below the canvas (z = 0), so 2 mm below it is ample room for
// solver slack; anything lower is clamped (GL_DEPTH_CLAMP), not clipped away.
constexpr double kDepthFloorMm = -2.0;
// Keeps the depth range non-degenerate when contact_band_mm is at or below the floor.
constexpr double kMinDepthRangeMm = 1.0;
// Triangles thinner than this (pixels) also leave a band this wide (kGeometryShader).
// One pixel: a band that wide covers a pixel centre in every column (or row)
// it crosses, whatever its offset and direction.
constexpr double kMinCoverWidthPx = 1.0;

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position_mm;
layout(location = 1) in vec2 uv_in;
uniform vec2 origin_mm;      // window bottom-left corner
uniform vec2 ndc_per_mm;     // 2 * px_per_mm / window size in pixels
uniform float contact_band_mm;       // keep z <= contact_band_mm
uniform float depth_floor_mm;
out gl_PerVertex {
  vec4 gl_Position;
  float gl_ClipDistance[1];
};
out vec2 uv_v;
out float depth_v;
void main() {
  // Orthographic: window pixel c spans x0 + [c, c + 1] / px_per_mm exactly.
  vec2 ndc = (position_mm.xy - origin_mm) * ndc_per_mm - 1.0;
  // Smallest z (nearest the canvas) gets the smallest depth and wins GL_LESS.
  float z_ndc = 2.0 * (position_mm.z - depth_floor_mm) /
                (contact_band_mm - depth_floor_mm) - 1.0;
  gl_Position = vec4(ndc, z_ndc, 1.0);
  gl_ClipDistance[0] = contact_band_mm - position_mm.z;
  uv_v = uv_in;
  depth_v = contact_band_mm - position_mm.z;
}
)";

// Hair finer than a pixel (paper §4.2.1: strips stand in for lines of geometric
// width). Rasterisation samples pixel centres, so a triangle thinner than a
// pixel is drawn only where it happens to cover one: a fan's hairs dragged
// along their own row, all on one line between two rows of centres, left no
// footprint at all. A hair triangle (setHairTextureRange: the strips, each a
// single hair; not the bundles and the surface, which stand for many) thinner
// than kMinCoverWidthPx (its height h over its longest edge, in pixels) is
// therefore drawn twice: as itself,
// and behind everything (in depth) as a band that wide centred on that
// edge, whose fragments carry the share of a pixel the hair covers
// (cover = h / kMinCoverWidthPx) instead of 1. A pixel whose centre some
// geometry covers keeps that geometry with coverage 1, exactly as before;
// only pixels every centre sample missed take a band's fragment. Where hair
// is dense nothing changes; a lone hair becomes a continuous line that
// claims up to twice its area (about 1 + (1 - h) times: the pixels it hits
// count whole, as they always did, and the ones it misses its share).
constexpr const char* kGeometryShader = R"(#version 330 core
layout(triangles) in;
layout(triangle_strip, max_vertices = 7) out;
in gl_PerVertex {
  vec4 gl_Position;
  float gl_ClipDistance[1];
} gl_in[];
in vec2 uv_v[];
in float depth_v[];
uniform vec2 px_per_ndc;     // half the window size in pixels
uniform float min_cover_px;  // thinner hair triangles also leave a band this wide
uniform vec2 hair_u;         // hair triangles: u in [hair_u.x, hair_u.y)
out gl_PerVertex {
  vec4 gl_Position;
  float gl_ClipDistance[1];
};
out vec2 uv;
out float depth_mm;
out float cover;
// Depth: the triangles as given in [-1, 0], the bands in [0, 1] (NDC).
void put(int i, vec2 shift_ndc, float coverage, float depth_half) {
  vec4 p = gl_in[i].gl_Position;
  gl_Position = vec4(p.xy + shift_ndc, 0.5 * p.z + depth_half, 1.0);
  gl_ClipDistance[0] = gl_in[i].gl_ClipDistance[0];
  uv = uv_v[i];
  depth_mm = depth_v[i];
  cover = coverage;
  EmitVertex();
}
void main() {
  vec2 p[3];
  for (int i = 0; i < 3; ++i) p[i] = gl_in[i].gl_Position.xy * px_per_ndc;
  int a = 0;
  float longest = -1.0;
  for (int i = 0; i < 3; ++i) {
    float e = length(p[(i + 1) % 3] - p[i]);
    if (e > longest) { longest = e; a = i; }
  }
  int b = (a + 1) % 3, c = (a + 2) % 3;
  vec2 ab = p[b] - p[a], ac = p[c] - p[a];
  float h = longest > 0.0 ? abs(ab.x * ac.y - ab.y * ac.x) / longest : 0.0;
  for (int i = 0; i < 3; ++i) put(i, vec2(0.0), 1.0, -0.5);
  EndPrimitive();
  bool hair = uv_v[0].x >= hair_u.x && uv_v[0].x < hair_u.y;
  if (!hair || h >= min_cover_px || h <= 0.0) return;
  // The band |offset from ab| <= m / 2, with a's and b's attributes.
  vec2 half_ndc = (0.5 * min_cover_px / longest) * vec2(-ab.y, ab.x) / px_per_ndc;
  float share = h / min_cover_px;
  put(a, -half_ndc, share, 0.5);
  put(b, -half_ndc, share, 0.5);
  put(a, half_ndc, share, 0.5);
  put(b, half_ndc, share, 0.5);
  EndPrimitive();
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
in vec2 uv;
in float depth_mm;
in float cover;
layout(location = 0) out vec4 texel;
void main() { texel = vec4(uv, depth_mm, cover); }
)";

void checkGl(const char* what) { render::checkGl("footprint renderer", what); }

GLuint linkProgram() {
  return render::linkProgram("footprint renderer", kVertexShader, kFragmentShader,
                             kGeometryShader);
}

}  // namespace

struct FootprintRenderer::Impl {
  GlContext context;  // first member: created first, destroyed last
  int max_size_px = 0;
  GLuint program = 0, vao = 0, vbo = 0, fbo = 0, color_texture = 0, depth_buffer = 0;
  GLint origin_loc = -1, ndc_per_mm_loc = -1, band_loc = -1, floor_loc = -1;
  GLint px_per_ndc_loc = -1, min_cover_loc = -1, hair_u_loc = -1;
  float hair_u_begin = std::numeric_limits<float>::lowest();
  float hair_u_end = std::numeric_limits<float>::max();
  int target_width_px = 0, target_height_px = 0;  // current FBO attachment size
  bool skip_unmarking = true;
  int untested_left = 0;  // draws left to send whole before testing again
  std::vector<FootprintVertex> drawn;  // the triangles that may mark a pixel
  std::size_t drawn_triangles = 0;

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
  s.band_loc = glGetUniformLocation(s.program, "contact_band_mm");
  s.floor_loc = glGetUniformLocation(s.program, "depth_floor_mm");
  s.px_per_ndc_loc = glGetUniformLocation(s.program, "px_per_ndc");
  s.min_cover_loc = glGetUniformLocation(s.program, "min_cover_px");
  s.hair_u_loc = glGetUniformLocation(s.program, "hair_u");

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

void FootprintRenderer::setHairTextureRange(float u_begin, float u_end) {
  impl_->hair_u_begin = u_begin;
  impl_->hair_u_end = u_end;
}

void FootprintRenderer::setSkipUnmarking(bool skip) {
  impl_->skip_unmarking = skip;
  impl_->untested_left = 0;
}

std::size_t FootprintRenderer::lastDrawnTriangles() const { return impl_->drawn_triangles; }

namespace {

// Whether a triangle that is not hair (so kGeometryShader adds no band for it)
// may mark a pixel. GL rasterises a triangle at the pixel centres it
// contains; window pixel column c has its centre at x = c + 1/2 in the vertex
// shader's pixel units (x_mm - x0_mm) * px_per_mm, rows likewise from y0_mm.
// The answer must never be "no" for a triangle GL would draw, so both tests
// allow every vertex to sit up to kVertexSlackPx away from where it is
// computed here, in x and in y: that covers the shader's float arithmetic
// (about 1e-4 px at 2,048 px) and llvmpipe's snapping of vertices to 1/256 px
// with room to spare. Clipping at the contact band and the depth clamp only
// ever remove coverage.
constexpr double kVertexSlackPx = 1.0 / 64;
// The box test widens the box by more than that; the value with which the
// 32 goldens were first checked byte for byte.
constexpr double kBoxSlackPx = 1.0 / 32;
// A triangle whose box holds more centres than this goes to GL untested:
// such a triangle is rarely a sliver between them.
constexpr int kMaxCentresTested = 16;
// The tests cost about what llvmpipe spends on one triangle in twenty, so
// where a footprint drops fewer than one in kWorthwhileDropShare of its
// triangles they cost more than they save. After such a draw the next
// kUntestedDraws go to GL whole, then the tests run again. Either
// way the bytes are the same, and the choice follows the draws alone, so it
// is as deterministic as they are (docs/PERFORMANCE.md, "Triangles that can
// mark no pixel left out").
constexpr std::size_t kWorthwhileDropShare = 16;
constexpr int kUntestedDraws = 15;

// Whether a centre p lies outside the edge from a to b, for a triangle of
// orientation `sign` (+1 counterclockwise), wherever its vertices may move
// within kVertexSlackPx. E = (b - a) x (p - a) moves by at most
// 2 sqrt2 d |p - a| + sqrt2 d |b - a| + 4 d^2 when each vertex moves by up
// to d in x and in y; the lengths are bounded by their L1 norms, which are
// larger and need no square root.
bool surelyOutside(const double* a, const double* b, double px, double py, double sign) {
  const double ux = b[0] - a[0], uy = b[1] - a[1], wx = px - a[0], wy = py - a[1];
  const double e = sign * (ux * wy - uy * wx);
  constexpr double d = kVertexSlackPx, k = 2 * 1.4142135623730951 * d;
  const double bound = k * (std::fabs(wx) + std::fabs(wy)) +
                       0.5 * k * (std::fabs(ux) + std::fabs(uy)) + 4 * d * d;
  return e < -bound;
}

bool mayMarkCentre(const FootprintVertex* v, const FootprintWindow& window, float x0_mm,
                   float y0_mm) {
  double p[3][2];
  double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
  for (int k = 0; k < 3; ++k) {
    p[k][0] = (double(v[k].x_mm) - x0_mm) * window.px_per_mm;
    p[k][1] = (double(v[k].y_mm) - y0_mm) * window.px_per_mm;
    for (int a = 0; a < 2; ++a) {
      if (!std::isfinite(p[k][a])) return true;  // left to GL, as before
      lo[a] = std::min(lo[a], p[k][a]);
      hi[a] = std::max(hi[a], p[k][a]);
    }
  }
  // The centres c + 1/2 in [lo, hi]: ceil(lo - 1/2) <= c <= floor(hi - 1/2).
  int first[2], last[2];
  for (int a = 0; a < 2; ++a) {
    first[a] = static_cast<int>(std::max(std::ceil(lo[a] - kBoxSlackPx - 0.5), -1.0));
    last[a] = static_cast<int>(std::min(std::floor(hi[a] + kBoxSlackPx - 0.5), 4096.0));
    if (first[a] > last[a]) return false;  // no centre in the box
  }
  if ((last[0] - first[0] + 1) * (last[1] - first[1] + 1) > kMaxCentresTested) return true;
  // A sliver: a centre in the box, but perhaps none in the triangle. GL's
  // triangle (its vertices moved as above) holds a centre only if, for its
  // orientation, no edge has the centre surely outside. A thin triangle's
  // orientation may flip with its vertices, so a centre is dropped only when
  // it is surely outside for both orientations; the computed one is tried
  // first.
  const double area2 = (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
                       (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
  const double sign = area2 > 0 ? 1.0 : -1.0;
  auto mayHold = [&](int c, int r) {
    const double cx = c + 0.5, cy = r + 0.5;
    for (const double o : {sign, -sign})
      if (!surelyOutside(p[0], p[1], cx, cy, o) && !surelyOutside(p[1], p[2], cx, cy, o) &&
          !surelyOutside(p[2], p[0], cx, cy, o))
        return true;
    return false;
  };
  // The centre nearest the centroid first: in a triangle that is not a
  // sliver it is usually inside, and the search ends there.
  int mid[2];
  for (int a = 0; a < 2; ++a) {
    const double centroid = (p[0][a] + p[1][a] + p[2][a]) / 3;
    mid[a] = std::clamp(static_cast<int>(std::lround(centroid - 0.5)), first[a], last[a]);
  }
  const int c_mid = mid[0], r_mid = mid[1];
  if (mayHold(c_mid, r_mid)) return true;
  for (int c = first[0]; c <= last[0]; ++c)
    for (int r = first[1]; r <= last[1]; ++r)
      if ((c != c_mid || r != r_mid) && mayHold(c, r)) return true;
  return false;
}

}  // namespace

void FootprintRenderer::render(std::span<const FootprintVertex> triangles,
                               const FootprintWindow& window, double contact_band_mm,
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
      !std::isfinite(contact_band_mm)) {
    throw std::invalid_argument("footprint window: px_per_mm must be > 0 and the "
                                "origin and contact_band_mm finite");
  }
  if (triangles.size() % 3 != 0 || triangles.size() > static_cast<std::size_t>(INT_MAX)) {
    throw std::invalid_argument("footprint triangles: vertex count " +
                                std::to_string(triangles.size()) +
                                " must be a multiple of 3");
  }
  out->window = window;
  s.drawn_triangles = 0;
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
    const double depth_floor_mm = std::min(kDepthFloorMm, contact_band_mm - kMinDepthRangeMm);
    glUniform2f(s.origin_loc, static_cast<float>(window.x0_mm),
                static_cast<float>(window.y0_mm));
    glUniform2f(s.ndc_per_mm_loc, static_cast<float>(2.0 * window.px_per_mm / width),
                static_cast<float>(2.0 * window.px_per_mm / height));
    glUniform1f(s.band_loc, static_cast<float>(contact_band_mm));
    glUniform1f(s.floor_loc, static_cast<float>(depth_floor_mm));
    glUniform2f(s.px_per_ndc_loc, 0.5f * static_cast<float>(width),
                0.5f * static_cast<float>(height));
    glUniform1f(s.min_cover_loc, static_cast<float>(kMinCoverWidthPx));
    glUniform2f(s.hair_u_loc, s.hair_u_begin, s.hair_u_end);
    glBindVertexArray(s.vao);
    glBindBuffer(GL_ARRAY_BUFFER, s.vbo);
    std::span<const FootprintVertex> drawn = triangles;
    if (s.skip_unmarking && s.untested_left > 0) {
      --s.untested_left;
    } else if (s.skip_unmarking) {
      // The shader's origin is a float uniform; the test uses the same floats.
      const float x0 = static_cast<float>(window.x0_mm), y0 = static_cast<float>(window.y0_mm);
      s.drawn.clear();
      for (std::size_t t = 0; t < triangles.size(); t += 3) {
        const FootprintVertex* v = &triangles[t];
        // The geometry shader's hair test, on the same float u.
        const bool hair = v[0].u >= s.hair_u_begin && v[0].u < s.hair_u_end;
        if (hair || mayMarkCentre(v, window, x0, y0)) s.drawn.insert(s.drawn.end(), v, v + 3);
      }
      drawn = s.drawn;
      const std::size_t dropped = (triangles.size() - drawn.size()) / 3;
      if (dropped * kWorthwhileDropShare < triangles.size() / 3) s.untested_left = kUntestedDraws;
    }
    s.drawn_triangles = drawn.size() / 3;
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(drawn.size_bytes()), drawn.data(),
                 GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(drawn.size()));
  } else {
    s.drawn_triangles = 0;
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

// GL passes of the brush preview. One shader program, drawn in a fixed order
// into an RGBA8 FBO at 2x the output size, read back once and box-filtered down
// on the CPU: the same scene gives the same bytes every run.
//
// Pass order and why:
//   backdrop, paper (+grid)  — depth-writing ground everything stands on
//   soft shadow              — 12 jittered flattened copies of the hair, each
//                              blended once per pixel (stencil), so overlaps do
//                              not darken and the penumbra closes at the contact
//   ferrule, spines          — opaque, depth-writing
//   strips, surface          — translucent, no depth writes; the surface's far
//                              side first, then its near side
//   spines again (LEQUAL)    — re-tints the spines seen through the hair

#include "render/preview/preview_renderer.h"

#include <GL/gl.h>
#include <GL/glext.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <span>
#include <stdexcept>
#include <string>

#include "render/gl/gl_context.h"
#include "render/gl/gl_program.h"
#include "render/preview/preview_geometry.h"
#include "render/preview/preview_overlay.h"
#include "render/image/text.h"

namespace bristle::render {

namespace {

using preview::Mesh;
using preview::MeshVertex;

constexpr int kSupersample = 2;
// Light samples of the soft shadow: 12 keep the penumbra free of visible steps.
constexpr int kShadowSamples = 12;
// Radius of the ring of light directions (per mm of height): the penumbra widens
// by ~2 x 0.07 mm per mm above the paper.
constexpr double kShadowJitter = 0.07;

constexpr const char* kVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 view_projection;
uniform int mode;  // 0 backdrop (position is NDC), else world mm
out vec3 world;
out vec3 world_normal;
void main() {
  world = position;
  world_normal = normal;
  gl_Position = mode == 0 ? vec4(position.xy, 0.0, 1.0) : view_projection * vec4(position, 1.0);
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
in vec3 world;
in vec3 world_normal;
uniform int mode;            // 0 backdrop, 1 paper, 2 flat colour, 3 lit
uniform vec4 color;
uniform vec4 material;       // ambient, diffuse, specular, shininess
uniform vec3 shine;          // rim strength, alpha gain at grazing angles, metal
uniform vec3 eye;
uniform vec3 cam_right;      // the camera's right axis in the world
uniform vec3 key_light;
uniform vec3 fill_light;
uniform float viewport_height;
uniform vec3 sky_top;
uniform vec3 sky_horizon;
uniform vec3 paper;
uniform vec3 grid_color;
uniform float grid_mm;
uniform vec2 ground_centre;
uniform vec2 fog_mm;         // fog start, end (distance from the target)
layout(location = 0) out vec4 frag;

float sq(float x) { return x * x; }  // pow() is undefined for negative bases

vec3 sky() {
  float t = clamp(gl_FragCoord.y / viewport_height, 0.0, 1.0);
  return mix(sky_horizon, sky_top, smoothstep(0.25, 1.0, t));
}

void main() {
  // Derivatives outside any branch: the facet normal for raw triangles.
  vec3 facet = cross(dFdx(world), dFdy(world));
  vec2 cell = world.xy / grid_mm;
  vec2 cell_fw = fwidth(cell);
  if (mode == 0) { frag = vec4(sky(), 1.0); return; }
  if (mode == 1) {
    vec2 dist_px = abs(fract(cell - 0.5) - 0.5) / max(cell_fw, vec2(1e-6));
    float line = 1.0 - smoothstep(0.5, 1.6, min(dist_px.x, dist_px.y));
    // Fade the grid where cells shrink to a few pixels (far away): no moire.
    line *= 1.0 - smoothstep(0.04, 0.12, max(cell_fw.x, cell_fw.y));
    vec3 c = mix(paper, grid_color, line);
    float fog = smoothstep(fog_mm.x, fog_mm.y, length(world.xy - ground_centre));
    frag = vec4(mix(c, sky(), fog), 1.0);
    return;
  }
  if (mode == 2) { frag = color; return; }
  // Sliver triangles can have a zero facet normal: any unit vector will do there.
  vec3 n = dot(world_normal, world_normal) > 0.25 ? normalize(world_normal)
           : dot(facet, facet) > 0.0              ? normalize(facet)
                                                  : vec3(0.0, 0.0, 1.0);
  vec3 v = normalize(eye - world);
  if (dot(n, v) < 0.0) n = -n;  // two-sided: the far side of translucent hair
  float facing = max(dot(n, v), 0.0);
  float grazing = pow(1.0 - facing, 3.0);
  vec3 h = normalize(key_light + v);
  float spec = material.z * pow(max(dot(n, h), 0.0), material.w);
  vec3 c = color.rgb * (material.x + material.y * max(dot(n, key_light), 0.0) +
                        0.35 * max(dot(n, fill_light), 0.0));
  // Metal: studio-style bands across the stub (a bright softbox stripe on the
  // key side, a weaker one opposite, dark towards the silhouette), the usual
  // product-shot look that reads as polished metal without an environment map.
  float across = dot(n, cam_right);
  float bands = 0.34 + 0.80 * exp(-sq((across + 0.42) / 0.24)) +
                0.30 * exp(-sq((across - 0.55) / 0.18));
  bands *= 1.0 - 0.45 * pow(1.0 - facing, 2.0);
  c = mix(c, color.rgb * bands, shine.z);
  c += vec3(spec) + shine.x * grazing * vec3(1.0, 0.92, 0.82);
  frag = vec4(c, mix(color.a, 1.0, shine.y * grazing));
}
)";

void checkGl(const char* what) { render::checkGl("preview renderer", what); }

GLuint linkProgram() {
  return render::linkProgram("preview renderer", kVertexShader, kFragmentShader);
}

// A material: base colour (sRGB, alpha) and how light plays on it.
struct Look {
  float r, g, b, a;
  float ambient, diffuse, specular, shininess;
  float rim, grazing_alpha, metal;
};
// Sable brown hair (translucent, more opaque at grazing angles so its outline
// reads); strips a shade darker; deep red spines; polished nickel.
// clang-format off
//                                   r     g     b     a     amb   diff  spec  shin rim   graz  metal
constexpr Look kSurfaceLook      = {0.60, 0.37, 0.19, 0.40, 0.42, 0.62, 0.18, 20, 0.30, 0.75, 0};
constexpr Look kStripLook        = {0.42, 0.25, 0.12, 0.62, 0.45, 0.60, 0.12, 16, 0.15, 0.20, 0};
constexpr Look kSpineLook        = {0.70, 0.04, 0.06, 1.00, 0.38, 0.70, 0.45, 40, 0.10, 0,    0};
constexpr Look kSpineThroughLook = {0.70, 0.04, 0.06, 0.60, 0.50, 0.55, 0.25, 40, 0,    0,    0};
constexpr Look kMetalLook        = {0.86, 0.86, 0.89, 1.00, 0.30, 0.70, 0.85, 60, 0.05, 0,    0.85};
// clang-format on
// Per sample: 12 samples overlapping make the umbra ~28% dark.
constexpr float kShadowRgba[4] = {0.30f, 0.23f, 0.16f, 0.027f};
// A screen-filling quad for the backdrop (mode 0 takes positions as NDC).
constexpr std::array<MeshVertex, 6> kBackdrop = {{{-1, -1, 0, 0, 0, 0},
                                                 {1, -1, 0, 0, 0, 0},
                                                 {1, 1, 0, 0, 0, 0},
                                                 {-1, -1, 0, 0, 0, 0},
                                                 {1, 1, 0, 0, 0, 0},
                                                 {-1, 1, 0, 0, 0, 0}}};

}  // namespace

struct PreviewRenderer::Impl {
  GlContext context;  // first member: created first, destroyed last
  Font font;
  GLuint program = 0, vao = 0, vbo = 0, fbo = 0, color_buffer = 0, depth_stencil = 0;
  int target_width = 0, target_height = 0;
  int max_size_px = 0;  // the GL implementation's largest renderbuffer / viewport side

  GLint loc(const char* name) const { return glGetUniformLocation(program, name); }
  void set(const char* name, const Eigen::Vector3d& v) const {
    glUniform3f(loc(name), static_cast<float>(v.x()), static_cast<float>(v.y()),
                static_cast<float>(v.z()));
  }
  void setLook(const Look& k) const {
    glUniform1i(loc("mode"), 3);
    glUniform4f(loc("color"), k.r, k.g, k.b, k.a);
    glUniform4f(loc("material"), k.ambient, k.diffuse, k.specular, k.shininess);
    glUniform3f(loc("shine"), k.rim, k.grazing_alpha, k.metal);
  }
  void draw(std::span<const MeshVertex> mesh) const {
    if (mesh.empty()) return;
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(mesh.size_bytes()),
                 mesh.data(), GL_STREAM_DRAW);
    glDrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(mesh.size()));
  }
  // Grows the attachments (never shrinks): a series of previews reallocates rarely.
  void ensureTarget(int width, int height) {
    if (width <= target_width && height <= target_height) return;
    if (width > max_size_px || height > max_size_px) {
      throw std::invalid_argument("preview: " + std::to_string(width) + "x" +
                                  std::to_string(height) + " px exceeds the GL limit of " +
                                  std::to_string(max_size_px) + " px");
    }
    const int w = std::max(width, target_width), h = std::max(height, target_height);
    glBindRenderbuffer(GL_RENDERBUFFER, color_buffer);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glBindRenderbuffer(GL_RENDERBUFFER, depth_stencil);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw std::runtime_error("preview FBO incomplete at " + std::to_string(w) + "x" +
                               std::to_string(h) + " px");
    }
    checkGl("allocating the preview FBO");
    target_width = w;
    target_height = h;
  }

  void drawScene(const preview::SceneMeshes& m, const PreviewCamera& cam, int w, int h) const;
};

PreviewRenderer::PreviewRenderer() : impl_(std::make_unique<Impl>()) {
  Impl& s = *impl_;
  GLint max_renderbuffer = 0, max_viewport[2] = {0, 0};
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_renderbuffer);
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, max_viewport);
  s.max_size_px = std::min({max_renderbuffer, max_viewport[0], max_viewport[1]});
  s.program = linkProgram();
  glGenVertexArrays(1, &s.vao);
  glBindVertexArray(s.vao);
  glGenBuffers(1, &s.vbo);
  glBindBuffer(GL_ARRAY_BUFFER, s.vbo);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex), nullptr);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(MeshVertex),
                        reinterpret_cast<const void*>(offsetof(MeshVertex, nx)));
  glEnableVertexAttribArray(0);
  glEnableVertexAttribArray(1);
  glGenRenderbuffers(1, &s.color_buffer);
  glBindRenderbuffer(GL_RENDERBUFFER, s.color_buffer);
  glGenRenderbuffers(1, &s.depth_stencil);
  glBindRenderbuffer(GL_RENDERBUFFER, s.depth_stencil);
  glGenFramebuffers(1, &s.fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, s.fbo);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, s.color_buffer);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                            s.depth_stencil);
  glDrawBuffer(GL_COLOR_ATTACHMENT0);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  glDisable(GL_DITHER);
  glDisable(GL_MULTISAMPLE);  // anti-aliasing is the 2x box filter, nothing else
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glUseProgram(s.program);
  checkGl("setting up the preview renderer");
}

PreviewRenderer::~PreviewRenderer() = default;

void PreviewRenderer::Impl::drawScene(const preview::SceneMeshes& m, const PreviewCamera& cam,
                                      int w, int h) const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glBindVertexArray(vao);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glUseProgram(program);
  glViewport(0, 0, w, h);
  glDepthMask(GL_TRUE);
  glStencilMask(0xFF);
  glClearColor(0, 0, 0, 1);
  glClearDepth(1.0);
  glClearStencil(0);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);

  // Lights follow the camera (the key from its upper left, in front of the
  // brush) so every brush is lit the same way whatever its pose.
  const Eigen::Vector3d right = cam.view.block<1, 3>(0, 0).transpose();
  const Eigen::Vector3d back = cam.view.block<1, 3>(2, 0).transpose();
  const Eigen::Vector3d front = Eigen::Vector3d(back.x(), back.y(), 0).normalized();
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const Eigen::Matrix4f vp = (cam.projection * cam.view).cast<float>();
  glUniformMatrix4fv(loc("view_projection"), 1, GL_FALSE, vp.data());  // both column-major
  set("eye", cam.eye_mm);
  set("cam_right", right);
  set("key_light", (-0.55 * right + 0.45 * front + 0.75 * up).normalized());
  set("fill_light", (0.70 * right + 0.30 * front + 0.20 * up).normalized());
  glUniform1f(loc("viewport_height"), static_cast<float>(h));
  glUniform3f(loc("sky_top"), 0.80f, 0.84f, 0.89f);
  glUniform3f(loc("sky_horizon"), 0.93f, 0.93f, 0.925f);
  glUniform3f(loc("paper"), 0.975f, 0.965f, 0.935f);
  glUniform3f(loc("grid_color"), 0.83f, 0.81f, 0.76f);
  glUniform1f(loc("grid_mm"), 5.0f);
  glUniform2f(loc("ground_centre"), static_cast<float>(cam.target_mm.x()),
              static_cast<float>(cam.target_mm.y()));
  glUniform2f(loc("fog_mm"), static_cast<float>(preview::kFogStartRadii * cam.radius_mm),
              static_cast<float>(preview::kFogEndRadii * cam.radius_mm));

  // Backdrop and paper.
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_STENCIL_TEST);
  glDisable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glUniform1i(loc("mode"), 0);
  draw(kBackdrop);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glUniform1i(loc("mode"), 1);
  draw(m.ground);

  // Soft shadow: light samples on a small ring around the main direction,
  // each flattened copy blended at most once per pixel (stencil).
  glDepthMask(GL_FALSE);
  glDisable(GL_DEPTH_TEST);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glEnable(GL_STENCIL_TEST);
  glStencilFunc(GL_EQUAL, 0, 0xFF);
  glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
  glUniform1i(loc("mode"), 2);
  glUniform4fv(loc("color"), 1, kShadowRgba);
  const Eigen::Vector3d shadow_light = -0.30 * right + 0.18 * front + up;
  Mesh shadow;
  for (int k = 0; k < kShadowSamples && !m.casters.empty(); ++k) {
    const double a = 2 * 3.14159265358979 * k / kShadowSamples;
    const Eigen::Vector3d jitter = kShadowJitter * (std::cos(a) * right + std::sin(a) * front);
    shadow.clear();
    preview::appendShadow(m.casters, shadow_light + jitter, &shadow);
    glClear(GL_STENCIL_BUFFER_BIT);
    draw(shadow);
  }
  glDisable(GL_STENCIL_TEST);

  // Opaque: ferrule and spines.
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_TRUE);
  setLook(kMetalLook);
  draw(m.ferrule);
  setLook(kSpineLook);
  draw(m.spines);

  // Translucent hair: strips, then the surface's far side, then its near side.
  glEnable(GL_BLEND);
  glDepthMask(GL_FALSE);
  setLook(kStripLook);
  draw(m.strips);
  setLook(kSurfaceLook);
  glEnable(GL_CULL_FACE);
  glFrontFace(m.surface_ccw_outward ? GL_CCW : GL_CW);
  for (GLenum culled : {GL_FRONT, GL_BACK}) {
    glCullFace(culled);
    draw(m.surface);
  }
  glDisable(GL_CULL_FACE);
  glDepthFunc(GL_LEQUAL);  // exactly the spine fragments that won the depth test
  setLook(kSpineThroughLook);
  draw(m.spines);
}

Image8 PreviewRenderer::render(const PreviewScene& scene, const PreviewOptions& options) {
  if (scene.surface.size() % 3 != 0 || scene.strips.size() % 3 != 0) {
    throw std::invalid_argument("preview: surface and strip vertex counts must be multiples of 3");
  }
  if (const FootprintImage* fp = scene.footprint) {
    const FootprintWindow& win = fp->window;
    if (!(win.px_per_mm > 0) || win.width_px < 0 || win.height_px < 0 ||
        fp->texels.size() != static_cast<std::size_t>(win.width_px) * win.height_px * 4) {
      throw std::invalid_argument("preview: the footprint's texels do not match its window");
    }
  }
  const preview::Layout layout = preview::layoutPreview(scene, options);  // checks the size
  const PreviewCamera cam = framePreview(scene, options);
  const preview::SceneMeshes meshes = preview::buildMeshes(scene, cam);

  const int w = options.width_px * kSupersample, h = options.height_px * kSupersample;
  impl_->context.makeCurrent();
  impl_->ensureTarget(w, h);
  impl_->drawScene(meshes, cam, w, h);
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(w) * h * 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  checkGl("rendering the preview");

  // 2x2 box filter with rounding; GL row 0 is the bottom, the image's the top.
  Image8 image;
  image.width = options.width_px;
  image.height = options.height_px;
  image.channels = 3;
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * 3);
  for (int y = 0; y < image.height; ++y) {
    const std::size_t r0 = static_cast<std::size_t>(2 * (image.height - 1 - y)) * w * 4;
    const std::size_t r1 = r0 + static_cast<std::size_t>(w) * 4;
    std::uint8_t* out = &image.pixels[static_cast<std::size_t>(y) * image.width * 3];
    for (int x = 0; x < image.width; ++x) {
      for (int c = 0; c < 3; ++c) {
        const std::size_t i = static_cast<std::size_t>(x) * 8 + c;
        const int sum = rgba[r0 + i] + rgba[r0 + i + 4] + rgba[r1 + i] + rgba[r1 + i + 4];
        out[x * 3 + c] = static_cast<std::uint8_t>((sum + 2) / 4);
      }
    }
  }
  preview::drawOverlays(scene, options, layout, impl_->font, &image);
  return image;
}

Image8 renderPreview(const PreviewScene& scene, const PreviewOptions& options) {
  PreviewRenderer renderer;
  return renderer.render(scene, options);
}

}  // namespace bristle::render

#include "bristle/render.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "api/model.h"
#include "api/stroke_setup.h"
#include "engine/dynamics/simulation.h"
#include "engine/geometry/first_contact.h"
#include "engine/model/canvas.h"
#include "engine/formats/scene.h"
#include "render/image/compose.h"
#include "render/scene_renderer.h"
#include "render/stroke_pipeline.h"

namespace bristle::api {

namespace {

// The ranges `bristle render` checks on its options (cli/options.cpp,
// cli/render_command.cpp), for the fields of the same names. The paint's and
// paper's fields meet their rules in strokeSetupOf, as the CLI's do.
std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

void checkRange(const char* field, double v, double lo, double hi,
                const char* options = "RenderOptions") {
  const bool ok = std::isfinite(v) && v >= lo && v <= hi;
  if (!ok)
    throw api::Error(ErrorCategory::kUsage, std::string(options) + "." + field + " " +
                                                shortNumber(v) + ": must be in [" +
                                                shortNumber(lo) + ", " + shortNumber(hi) + "]");
}

// The "thumbnail" preset's steps (presetOptions below).
constexpr double kThumbnailMaxStepMm = 1.0;
constexpr double kThumbnailMinRateHz = 30;
constexpr double kThumbnailSteadyStepMm = 0;
// Ipopt's overall tolerance for thumbnails, against the default's 1e-8
// (IpoptSettings::tol): 6-7 % fewer iterations on the data-set strokes, the
// SSIM against the default's as with 1e-8 (docs/PERFORMANCE.md, "Where a
// thumbnail's iterations go").
constexpr const char* kThumbnailIpoptTol = "tol=1e-4";

void checkRenderRanges(const RenderOptions& o) {
  checkRange("px_per_mm", o.px_per_mm, 0.5, 100);
  checkRange("solver_max_iterations", o.solver_max_iterations, 1, 100000);
  checkRange("max_step_mm", o.max_step_mm, 0.01, 5);
  checkRange("steady_step_mm", o.steady_step_mm, 0, 5);
  checkRange("min_rate_hz", o.min_rate_hz, 1, 10000);
  checkRange("contact_band_mm", o.contact_band_mm, 0.001, 2);
  checkRange("threads", o.threads, 0, 2);
}

// An 8-bit composition of a canvas as the public Image, placed on the canvas.
Image imageOf(const render::Image8& image8, const CanvasGrid& grid) {
  Image image;
  image.width_px = image8.width;
  image.height_px = image8.height;
  image.channels = image8.channels;
  image.pixels = image8.pixels;
  image.px_per_mm = grid.px_per_mm;
  image.x0_mm = grid.x0_mm;
  image.y0_mm = grid.y0_mm;
  return image;
}

// As `bristle render` (cli/render_command.cpp): depths become this brush's
// ferrule heights, then the trajectory is checked against the brush.
bristle::Trajectory placedFor(const Trajectory& trajectory, const bristle::Brush& brush) {
  bristle::Trajectory t = resolveDepths(trajectory.model().trajectory, brush);
  validateTrajectoryForBrush(t, brush);
  return t;
}

}  // namespace

namespace {

// renderStroke on a given GL context (render::StrokeRenderer).
RenderResult renderOn(render::StrokeRenderer* renderer, const Brush& brush,
                      const Trajectory& trajectory, const RenderOptions& options) {
  return translateErrors([&] {
    checkRenderRanges(options);
    const render::StrokeSetup setup =
        strokeSetupOf(options, options.ipopt_options, apiOptionNames());
    const bristle::Brush& b = brush.model().brush;
    const bristle::Trajectory t = placedFor(trajectory, b);
    render::canvasForStroke(b, t, setup.stroke);  // fails early if too large
    const StrokePixels pixels = renderer ? paintStrokePixels(*renderer, b, t, setup, options.impasto)
                                         : paintStrokePixels(b, t, setup, options.impasto);
    RenderResult r;
    r.image = imageOf(pixels.image, pixels.painted.canvas.grid());
    r.touched = pixels.painted.stroke.touched;
    r.ink_pixels = pixels.ink_pixels;
    r.paint_laid_mm3 = pixels.painted.stroke.deposited_mm3;
    r.failed_spine_solves = pixels.painted.stroke.stats.failed_spine_solves;
    return r;
  });
}

}  // namespace

RenderOptions presetOptions(const std::string& name) {
  RenderOptions o;
  if (name == "default") return o;
  if (name != "thumbnail")
    throw api::Error(ErrorCategory::kUsage,
                     "preset " + name + ": unknown (known: default, thumbnail)");
  // A step solved well moves no hair root more than max_step_mm
  // (docs/dynamics.md); at 2 px/mm a millimetre is two pixels, and a stroke
  // of 0.3 s still gets 9 steps or more. 0.6x the default's CPU time on the
  // data-set strokes, SSIM >= 0.95 against them (docs/PERFORMANCE.md, "A
  // thumbnail preset").
  o.max_step_mm = kThumbnailMaxStepMm;
  o.min_rate_hz = kThumbnailMinRateHz;
  o.steady_step_mm = kThumbnailSteadyStepMm;
  o.ipopt_options = {kThumbnailIpoptTol};
  return o;
}

RenderResult renderStroke(const Brush& brush, const Trajectory& trajectory,
                          const RenderOptions& options) {
  return renderOn(nullptr, brush, trajectory, options);
}

struct StrokeRenderer::Impl {
  std::unique_ptr<render::StrokeRenderer> renderer;  // made at the first stroke
};

StrokeRenderer::StrokeRenderer() : impl_(new Impl) {}
StrokeRenderer::~StrokeRenderer() = default;
StrokeRenderer::StrokeRenderer(StrokeRenderer&&) noexcept = default;
StrokeRenderer& StrokeRenderer::operator=(StrokeRenderer&&) noexcept = default;

RenderResult StrokeRenderer::render(const Brush& brush, const Trajectory& trajectory,
                                    const RenderOptions& options) {
  translateErrors([&] {
    if (!impl_->renderer) impl_->renderer = std::make_unique<render::StrokeRenderer>();
  });
  return renderOn(impl_->renderer.get(), brush, trajectory, options);
}

struct Canvas::Impl {
  render::StrokeRenderer renderer;  // one GL context for every stroke
  PaintCanvas canvas;
  render::StrokeSetup paper;  // the canvas's paper, mix and resolution
};

namespace {

CanvasGrid canvasGrid(double x0_mm, double y0_mm, int width_px, int height_px,
                      double px_per_mm) {
  const bool fits = width_px >= 1 && height_px >= 1 && width_px <= kMaxCanvasSidePx &&
                    height_px <= kMaxCanvasSidePx &&
                    long(width_px) * height_px <= kMaxCanvasPixels;
  if (!fits)
    throw api::Error(ErrorCategory::kUsage,
                     "Canvas: " + std::to_string(width_px) + " x " + std::to_string(height_px) +
                         " px: must be 1 to 16384 px a side and at most 64 Mpx");
  if (!std::isfinite(x0_mm) || !std::isfinite(y0_mm) || std::fabs(x0_mm) > kMaxPositionMm ||
      std::fabs(y0_mm) > kMaxPositionMm)
    throw api::Error(ErrorCategory::kUsage,
                     "Canvas: x0_mm, y0_mm: must be finite and within +-100000 mm");
  CanvasGrid grid;
  grid.x0_mm = x0_mm;
  grid.y0_mm = y0_mm;
  grid.width_px = width_px;
  grid.height_px = height_px;
  grid.px_per_mm = px_per_mm;
  return grid;
}

}  // namespace

Canvas::Canvas(double x0_mm, double y0_mm, int width_px, int height_px,
               const RenderOptions& paper) {
  translateErrors([&] {
    checkRenderRanges(paper);
    const render::StrokeSetup setup = strokeSetupOf(paper, {}, apiOptionNames());
    const CanvasGrid grid = canvasGrid(x0_mm, y0_mm, width_px, height_px, paper.px_per_mm);
    impl_.reset(new Impl{render::StrokeRenderer(), PaintCanvas(grid, setup.paper, setup.mix),
                         setup});
  });
}

Canvas::~Canvas() = default;
Canvas::Canvas(Canvas&&) noexcept = default;
Canvas& Canvas::operator=(Canvas&&) noexcept = default;

StrokeFacts Canvas::addStroke(const Brush& brush, const Trajectory& trajectory,
                              const RenderOptions& options) {
  return translateErrors([&] {
    RenderOptions own = options;
    own.px_per_mm = impl_->canvas.grid().px_per_mm;
    checkRenderRanges(own);
    render::StrokeSetup setup = strokeSetupOf(own, own.ipopt_options, apiOptionNames());
    setup.paper = impl_->paper.paper;
    setup.mix = impl_->paper.mix;
    const bristle::Brush& b = brush.model().brush;
    const bristle::Trajectory t = placedFor(trajectory, b);
    render::StrokeResult stroke;
    double loaded_mm3 = 0, left_mm3 = 0;
    render::paintStrokeOnto(impl_->renderer, b, t, setup, &impl_->canvas, &stroke, &loaded_mm3,
                            &left_mm3);
    return StrokeFacts{stroke.touched, stroke.deposited_mm3, stroke.stats.failed_spine_solves};
  });
}

void Canvas::dry() { impl_->canvas.dry(); }

Image Canvas::image(bool impasto) const {
  return translateErrors([&] {
    render::ComposeOptions compose;
    compose.impasto = impasto;
    return imageOf(render::composeRgb8(impl_->canvas, compose), impl_->canvas.grid());
  });
}

SceneResult renderScene(const std::string& path, const SceneOptions& options) {
  return translateErrors([&] {
    checkRange("solver_max_iterations", options.solver_max_iterations, 1, 100000, "SceneOptions");
    checkRange("threads", options.threads, 0, 2, "SceneOptions");
    const Scene scene = loadScene(path);
    PaintCanvas canvas = render::makeSceneCanvas(scene);
    render::SceneRenderOptions o;
    o.solver_max_iterations = options.solver_max_iterations;
    o.threads = options.threads;
    const render::SceneResult r = render::renderScene(scene, o, &canvas);
    render::ComposeOptions compose;
    compose.impasto = options.impasto;
    SceneResult out;
    out.image = imageOf(render::composeRgb8(canvas, compose), canvas.grid());
    out.paint_laid_mm3 = r.deposited_mm3;
    out.paint_picked_up_mm3 = r.picked_up_mm3;
    out.untouched = r.untouched;
    out.failed_spine_solves = r.stats.failed_spine_solves;
    return out;
  });
}

}  // namespace bristle::api

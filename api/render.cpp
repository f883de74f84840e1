#include "bristle/render.h"

#include <cmath>
#include <cstdio>
#include <string>

#include "api/model.h"
#include "api/stroke_setup.h"
#include "engine/dynamics/simulation.h"
#include "engine/geometry/first_contact.h"

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

void checkRange(const char* field, double v, double lo, double hi) {
  const bool ok = std::isfinite(v) && v >= lo && v <= hi;
  if (!ok)
    throw api::Error(ErrorCategory::kUsage, std::string("RenderOptions.") + field + " " +
                                                shortNumber(v) + ": must be in [" +
                                                shortNumber(lo) + ", " + shortNumber(hi) + "]");
}

void checkRenderRanges(const RenderOptions& o) {
  checkRange("px_per_mm", o.px_per_mm, 0.5, 100);
  checkRange("solver_max_iterations", o.solver_max_iterations, 1, 100000);
  checkRange("max_step_mm", o.max_step_mm, 0.01, 5);
  checkRange("steady_step_mm", o.steady_step_mm, 0, 5);
  checkRange("min_rate_hz", o.min_rate_hz, 1, 10000);
  checkRange("contact_band_mm", o.contact_band_mm, 0.001, 2);
}

}  // namespace

RenderResult renderStroke(const Brush& brush, const Trajectory& trajectory,
                          const RenderOptions& options) {
  return translateErrors([&] {
    checkRenderRanges(options);
    const render::StrokeSetup setup = strokeSetupOf(options, {}, apiOptionNames());
    const bristle::Brush& b = brush.model().brush;
    // As `bristle render` (cli/render_command.cpp): depths become this brush's
    // ferrule heights, then the trajectory is checked against the brush and
    // the canvas's size before anything is simulated.
    const bristle::Trajectory t = resolveDepths(trajectory.model().trajectory, b);
    validateTrajectoryForBrush(t, b);
    render::canvasForStroke(b, t, setup.stroke);
    const StrokePixels pixels = paintStrokePixels(b, t, setup, options.impasto);
    RenderResult r;
    const CanvasGrid& grid = pixels.painted.canvas.grid();
    r.image.width_px = pixels.image.width;
    r.image.height_px = pixels.image.height;
    r.image.channels = pixels.image.channels;
    r.image.pixels = pixels.image.pixels;
    r.image.px_per_mm = grid.px_per_mm;
    r.image.x0_mm = grid.x0_mm;
    r.image.y0_mm = grid.y0_mm;
    r.touched = pixels.painted.stroke.touched;
    r.ink_pixels = pixels.ink_pixels;
    r.paint_laid_mm3 = pixels.painted.stroke.deposited_mm3;
    r.failed_spine_solves = pixels.painted.stroke.stats.failed_spine_solves;
    return r;
  });
}

}  // namespace bristle::api

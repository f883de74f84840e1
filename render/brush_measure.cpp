#include "render/brush_measure.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "engine/geometry/brush_geometry.h"
#include "engine/model/canvas.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/dynamics/simulation.h"
#include "render/stroke_renderer.h"

namespace bristle::render {
namespace {

// The footprint's window: the brush's reach around the handle and this much more.
constexpr double kWindowMarginMm = 1;
// The largest footprint window measured (px a side): 4096^2 texels of 16 bytes
// are 268 MB, and 0.1 mm pixels already resolve a hair's footprint.
constexpr double kMaxWindowPx = 4096;
// The hover the pull starts from, above first contact (mm).
constexpr double kHoverMm = 2;

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

FootprintShape measureFootprintShape(const FootprintImage& image, double handle_x_mm) {
  const FootprintWindow& w = image.window;
  const double px = 1.0 / w.px_per_mm;
  FootprintShape shape;
  double y_lo = std::numeric_limits<double>::infinity(), y_hi = -y_lo;
  double rear_mm = -y_lo;  // the largest distance behind the handle of a touched pixel
  // Per column: its distance behind the handle and its touched extent across.
  std::vector<std::pair<double, double>> columns;
  for (int c = 0; c < w.width_px; ++c) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int r = 0; r < w.height_px; ++r) {
      if (image.at(c, r)[3] <= 0) continue;
      const double y = w.y0_mm + (w.height_px - r - 0.5) * px;
      lo = std::min(lo, y);
      hi = std::max(hi, y);
    }
    if (hi < lo) continue;
    const double behind = handle_x_mm - (w.x0_mm + (c + 0.5) * px);
    columns.emplace_back(behind, hi - lo + px);
    y_lo = std::min(y_lo, lo);
    y_hi = std::max(y_hi, hi);
    rear_mm = std::max(rear_mm, behind);
  }
  if (columns.empty()) return shape;
  shape.touched = true;
  shape.width_mm = y_hi - y_lo + px;
  // The widest section: the front-most column within a pixel of the widest
  // extent, since the model's footprint is widest at its front edge and a
  // rendered one has a plateau there a pixel's noise wide.
  double widest = 0;
  for (const auto& col : columns) widest = std::max(widest, col.second);
  double front = std::numeric_limits<double>::infinity();
  for (const auto& [behind, extent] : columns)
    if (extent >= widest - px) front = std::min(front, behind);
  shape.offset_mm = front;
  shape.drag_mm = rear_mm - front;
  return shape;
}

Trajectory constantDepthPull(const MeasureProtocol& p, double depth_mm) {
  Trajectory t;
  t.path = "the measurement pull at " + std::to_string(depth_mm) + " mm";
  t.depth_column = 4;
  auto sample = [&](double t_s, double x_mm, double depth) {
    TrajectorySample s;
    s.t_s = t_s;
    s.pose.position_mm = Eigen::Vector3d(x_mm, 0, 0);
    s.depth_mm = depth;
    s.line = static_cast<int>(t.samples.size()) + 2;
    t.samples.push_back(s);
  };
  sample(0, 0, -kHoverMm);
  sample(p.descend_s, 0, depth_mm);
  sample(p.descend_s + p.pull_mm / p.speed_mm_s, p.pull_mm, depth_mm);
  return t;
}

namespace {

// The protocol's pull at one depth: the states of its last quarter, evenly
// spaced, each measured.
DepthMeasure measureDepth(const Brush& brush, const MeasureProtocol& p,
                          const SolverSettings& settings, double depth_mm,
                          StrokeRenderer& renderer, BrushGeometry& geometry,
                          const std::function<void(int, int)>& on_step) {
  const Trajectory pull = resolveDepths(constantDepthPull(p, depth_mm), brush);
  StrokeOptions options;
  options.px_per_mm = p.px_per_mm;
  SolverPair solvers = makeSolverPair(settings, brush);
  Simulation sim(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
  const double from_s = pull.endTime() - 0.25 * p.pull_mm / p.speed_mm_s;
  std::vector<BrushState> settled;
  Stepper(sim, walkOptions(options, p.px_per_mm))
      .walk(pull, [&](const BrushState& s, int step, int steps) {
        if (s.t_s >= from_s) settled.push_back(s);
        if (on_step) on_step(step, steps);
      });

  DepthMeasure m;
  m.depth_mm = depth_mm;
  m.failed_steps = sim.stats().failed_steps;
  const double reach = brush.reachMm() + kWindowMarginMm;
  const int side_px = static_cast<int>(std::ceil(2 * reach * p.px_per_mm));
  std::vector<double> widths, offsets, drags;
  const int n = static_cast<int>(settled.size());
  for (int k = 0; k < p.samples && n > 0; ++k) {
    const int i = p.samples == 1 ? n - 1 : k * (n - 1) / (p.samples - 1);
    const BrushState& s = settled[static_cast<size_t>(i)];
    const Eigen::Vector3d h = s.handle.position_mm;
    const CanvasGrid grid{h.x() - reach, h.y() - reach, side_px, side_px, p.px_per_mm};
    FootprintImage image;
    if (!renderer.footprint(geometry, s, grid, options.contact_band_mm, &image)) continue;
    const FootprintShape shape = measureFootprintShape(image, h.x());
    widths.push_back(shape.width_mm);
    offsets.push_back(shape.offset_mm);
    drags.push_back(shape.drag_mm);
  }
  // Touching in most of the samples, or not at all: a footprint that comes and
  // goes is a brush barely reaching the paper.
  if (2 * static_cast<int>(widths.size()) > p.samples) {
    m.shape.touched = true;
    m.shape.width_mm = median(widths);
    m.shape.offset_mm = median(offsets);
    m.shape.drag_mm = median(drags);
  }
  return m;
}

}  // namespace

std::vector<DepthMeasure> measureBrush(const Brush& brush, const MeasureProtocol& protocol,
                                       const SolverSettings& solvers,
                                       const MeasureProgress& progress) {
  const double reach = brush.reachMm() + kWindowMarginMm;
  const double side_px = 2 * reach * protocol.px_per_mm;
  if (side_px > kMaxWindowPx)
    throw Error(ExitCode::kUsage,
                "--px-per-mm: the footprint window of this brush would be " +
                    std::to_string(static_cast<int>(std::ceil(side_px))) + " px a side at " +
                    std::to_string(protocol.px_per_mm) + " px/mm, over the measure's " +
                    std::to_string(static_cast<int>(kMaxWindowPx)) + " (lower --px-per-mm)");
  StrokeRenderer renderer;
  BrushGeometry geometry(brush);
  std::vector<DepthMeasure> out;
  const int total = static_cast<int>(protocol.depths_mm.size());
  for (int i = 0; i < total; ++i) {
    const auto on_step = [&](int step, int steps) {
      if (progress) progress(i, total, step, steps);
    };
    out.push_back(measureDepth(brush, protocol, solvers, protocol.depths_mm[static_cast<size_t>(i)],
                               renderer, geometry, on_step));
  }
  return out;
}

}  // namespace bristle::render

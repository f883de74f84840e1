#include "render/stroke_renderer.h"

#include <algorithm>
#include <cmath>

#include "engine/error.h"
#include "engine/spine_strips.h"

namespace bristle::render {

CanvasGrid canvasForStroke(const Brush& brush, const Trajectory& trajectory,
                           const StrokeOptions& options) {
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const TrajectorySample& s : trajectory.samples) {
    lo = lo.cwiseMin(s.pose.position_mm.head<2>());
    hi = hi.cwiseMax(s.pose.position_mm.head<2>());
  }
  const double pad = brush.reachMm() + options.margin_mm;
  CanvasGrid g;
  g.px_per_mm = options.px_per_mm;
  // Snap the corner to the pixel grid so that world positions map to the same
  // pixel boundaries whatever the trajectory's extent.
  g.x0_mm = std::floor((lo.x() - pad) * g.px_per_mm) / g.px_per_mm;
  g.y0_mm = std::floor((lo.y() - pad) * g.px_per_mm) / g.px_per_mm;
  const double w = std::ceil((hi.x() + pad - g.x0_mm) * g.px_per_mm);
  const double h = std::ceil((hi.y() + pad - g.y0_mm) * g.px_per_mm);
  if (w > kMaxCanvasSidePx || h > kMaxCanvasSidePx || w * h > double(kMaxCanvasPixels))
    throw dataError(trajectory.path, "extent",
                    "the stroke needs a " + std::to_string(long(w)) + " x " +
                        std::to_string(long(h)) +
                        " px canvas, above the limit of 16384 px a side and 64 Mpx; lower "
                        "--px-per-mm");
  g.width_px = static_cast<int>(w);
  g.height_px = static_cast<int>(h);
  return g;
}

StrokeRenderer::StrokeRenderer() : renderer_(2048) {}
StrokeRenderer::~StrokeRenderer() = default;

bool StrokeRenderer::footprint(const Brush& brush, const BrushState& state,
                               const CanvasGrid& grid, double clip_mm, FootprintImage* out) {
  std::vector<BrushVertex> tris;
  buildSpineGeometry(brush, state, &tris);
  // The window is the bounding box of the triangles that dip below the clip plane.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  vertices_.clear();
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    const float zmin = std::min({tris[t].z_mm, tris[t + 1].z_mm, tris[t + 2].z_mm});
    if (zmin > clip_mm) continue;
    for (int k = 0; k < 3; ++k) {
      const BrushVertex& v = tris[t + k];
      x0 = std::min(x0, double(v.x_mm));
      x1 = std::max(x1, double(v.x_mm));
      y0 = std::min(y0, double(v.y_mm));
      y1 = std::max(y1, double(v.y_mm));
      vertices_.push_back(FootprintVertex{v.x_mm, v.y_mm, v.z_mm, v.u, v.v});
    }
  }
  if (vertices_.empty()) return false;
  // Whole canvas pixels covering the box, clamped to the canvas.
  const int c0 = std::max(0, static_cast<int>(std::floor(grid.colOf(x0))));
  const int c1 = std::min(grid.width_px, static_cast<int>(std::ceil(grid.colOf(x1))));
  const int r0 = std::max(0, static_cast<int>(std::floor(grid.rowOf(y1))));
  const int r1 = std::min(grid.height_px, static_cast<int>(std::ceil(grid.rowOf(y0))));
  if (c1 <= c0 || r1 <= r0) return false;
  FootprintWindow win;
  win.px_per_mm = grid.px_per_mm;
  win.width_px = c1 - c0;
  win.height_px = r1 - r0;
  win.x0_mm = grid.x0_mm + c0 / grid.px_per_mm;
  win.y0_mm = grid.y0_mm + (grid.height_px - r1) / grid.px_per_mm;
  if (win.width_px > 2048 || win.height_px > 2048) return false;
  renderer_.render(vertices_, win, clip_mm, out);
  return true;
}

StrokeResult StrokeRenderer::render(const Brush& brush, const Trajectory& trajectory,
                                    std::unique_ptr<SpineSolver> solver,
                                    const StrokeOptions& options, Canvas* canvas,
                                    const StepCallback& on_step) {
  const CanvasGrid& grid = canvas->grid();
  Simulation sim(brush, options.sim, std::move(solver));
  const std::vector<double> times = planStepTimes(trajectory, brush, options.sim);
  StrokeResult result;
  FootprintImage fp;
  const int steps = static_cast<int>(times.size());
  sim.reset(trajectory.poseAt(times.front()), times.front());
  for (int i = 0; i < steps; ++i) {
    const BrushState& st = i == 0 ? sim.state() : sim.step(trajectory.poseAt(times[i]), times[i]);
    if (footprint(brush, st, grid, options.clip_mm, &fp)) {
      // Pixel offset of the window in the canvas.
      const int c0 = static_cast<int>(std::lround(grid.colOf(fp.window.x0_mm)));
      const int r0 = static_cast<int>(
          std::lround(grid.rowOf(fp.window.y0_mm + fp.window.height_px / grid.px_per_mm)));
      for (int r = 0; r < fp.window.height_px; ++r)
        for (int c = 0; c < fp.window.width_px; ++c) {
          const float* t = fp.at(c, r);
          if (t[3] <= 0) continue;
          result.touched = true;
          // Paint in proportion to how deep the brush reaches into the contact band.
          canvas->deposit(c0 + c, r0 + r, static_cast<float>(t[2] / options.clip_mm));
        }
    }
    if (on_step) on_step(st, i, steps);
  }
  result.stats = sim.stats();
  return result;
}

}  // namespace bristle::render

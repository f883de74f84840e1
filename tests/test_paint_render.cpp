// The paint model driven by real strokes: brush simulation -> footprint (OSMesa)
// -> transfer -> compose (render/stroke_renderer.h, render/compose.h).

#include <catch2/catch.hpp>

#include <cmath>

#include "engine/fnv1a64.h"
#include "engine/paint.h"
#include "engine/spine_solver.h"
#include "render/compose.h"
#include "render/stroke_renderer.h"

using namespace bristle;
using namespace bristle::render;

namespace {

const std::string kDir = BRISTLE_SOURCE_DIR;
const std::string kFlat = kDir + "/scenes/brushes/flat.json";
const std::string kRound = kDir + "/scenes/brushes/round.json";
const std::string kBroadside = kDir + "/scenes/trajectories/broadside-pull.csv";
const std::string kStraight = kDir + "/scenes/trajectories/straight-pull.csv";

Trajectory shifted(const std::string& path, double dx, double dy, double dz) {
  Trajectory t = loadTrajectory(path);
  for (TrajectorySample& s : t.samples) s.pose.position_mm += Eigen::Vector3d(dx, dy, dz);
  return t;
}

PaintLoad loadOf(PaintLoad::Mode mode, std::vector<std::string> paints, double amount = 1.0) {
  PaintLoad l;
  l.mode = mode;
  l.paints = std::move(paints);
  l.amount = amount;
  return l;
}

// Paints one stroke onto `canvas` with a freshly loaded (or, with no paints, clean) brush.
StrokeResult paintStroke(StrokeRenderer& renderer, const Brush& brush, const Trajectory& traj,
                         PaintCanvas& canvas, const PaintLoad& load) {
  BrushPaint paint(brush);
  if (load.paints.empty())
    paint.clean();
  else
    paint.load(load, canvas.model(), "test");
  return renderer.render(brush, traj, makeIpoptSolver(), StrokeOptions{}, &canvas, &paint);
}

// Pixel (col, row) of a world point.
[[maybe_unused]] int colAt(const CanvasGrid& g, double x) { return static_cast<int>(std::floor(g.colOf(x))); }
int rowAt(const CanvasGrid& g, double y) { return static_cast<int>(std::floor(g.rowOf(y))); }

bool wetAt(const PaintCanvas& c, int col, int row, double min_film_mm = 0.002) {
  return c.wet(c.index(col, row)).volume_mm3 / c.pixelAreaMm2() > min_film_mm;
}

// Painted pixels with world y in [y0, y1).
int coverageBetween(const PaintCanvas& c, double y0, double y1, double min_film_mm = 0.002) {
  const CanvasGrid& g = c.grid();
  int n = 0;
  for (int r = std::max(0, rowAt(g, y1)); r < std::min(g.height_px, rowAt(g, y0)); ++r)
    for (int col = 0; col < g.width_px; ++col) n += wetAt(c, col, r, min_film_mm);
  return n;
}

[[maybe_unused]] CanvasGrid unionGrid(const CanvasGrid& a, const CanvasGrid& b) {
  CanvasGrid g = a;
  g.x0_mm = std::min(a.x0_mm, b.x0_mm);
  g.y0_mm = std::min(a.y0_mm, b.y0_mm);
  g.width_px = static_cast<int>(
      std::ceil((std::max(a.x0_mm + a.widthMm(), b.x0_mm + b.widthMm()) - g.x0_mm) * g.px_per_mm));
  g.height_px = static_cast<int>(std::ceil(
      (std::max(a.y0_mm + a.heightMm(), b.y0_mm + b.heightMm()) - g.y0_mm) * g.px_per_mm));
  return g;
}

}  // namespace

TEST_CASE("explore light offsets", "[paint-render][.explore]") {
  const Brush round = loadBrush(kRound);
  StrokeRenderer renderer;
  for (double dz : {0.0, 4.0, 5.0, 5.5, 6.0, 6.5, 7.0}) {
    for (double tooth : {0.0, 0.05}) {
      const Trajectory t = shifted(kStraight, 0, 0, dz);
      PaperSpec paper;
      paper.tooth_depth_mm = tooth;
      PaintCanvas canvas(canvasForStroke(round, t, StrokeOptions{}), paper,
                         MixModel::kKubelkaMunk);
      paintStroke(renderer, round, t, canvas,
                  loadOf(PaintLoad::Mode::kSolid, {"ivory-black"}));
      WARN("dz " << dz << " tooth " << tooth << " coverage " << coverageBetween(canvas, 0, 100, 1e-4));
    }
  }
}

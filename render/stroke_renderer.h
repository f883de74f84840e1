#pragma once
// A whole stroke, end to end: trajectory -> simulation steps -> brush geometry
// -> footprint (OSMesa) -> paint on the canvas (ARCHITECTURE.md, data flow).

#include <functional>
#include <memory>

#include "engine/brush_geometry.h"
#include "engine/canvas.h"
#include "engine/simulation.h"
#include "render/footprint_renderer.h"

namespace bristle::render {

struct StrokeOptions {
  double px_per_mm = 8;
  double margin_mm = 5;  // canvas border around everything the brush can reach
  // The contact band: brush geometry below this height touches the paper.
  // About a hair's radius: spine joints resting on the canvas sit at z = 0.
  double clip_mm = 0.1;
  SimOptions sim;
};

// Called after every simulation step with the index of the planned step it
// belongs to and the planned step count (a split step reports its index twice).
using StepCallback = std::function<void(const BrushState&, int step, int steps)>;

struct StrokeResult {
  SimStats stats;
  bool touched = false;  // the brush reached the canvas at least once
};

// The canvas a stroke needs when no scene gives one: everything the brush can
// reach along the trajectory plus a margin. Throws kDataError (naming the
// trajectory) if it would exceed the canvas limits of engine/canvas.h.
CanvasGrid canvasForStroke(const Brush& brush, const Trajectory& trajectory,
                           const StrokeOptions& options);

class StrokeRenderer {
 public:
  StrokeRenderer();
  ~StrokeRenderer();

  // Simulates the brush along the trajectory and paints into canvas.
  StrokeResult render(const Brush& brush, const Trajectory& trajectory,
                      std::unique_ptr<SpineSolver> solver, const StrokeOptions& options,
                      Canvas* canvas, const StepCallback& on_step = {},
                      std::unique_ptr<SpineSolver> fallback = nullptr);

  // Footprint of one brush state on the canvas grid (for tests and previews).
  // Returns false when nothing touches the canvas.
  bool footprint(BrushGeometry& geometry, const BrushState& state, const CanvasGrid& grid,
                 double clip_mm, FootprintImage* out);

 private:
  void paintStep(BrushGeometry& geometry, const BrushState& state,
                 const StrokeOptions& options, Canvas* canvas, bool* touched);

  FootprintRenderer renderer_;
  FootprintImage image_;
  std::vector<BrushVertex> triangles_;
  std::vector<FootprintVertex> vertices_;
};

}  // namespace bristle::render

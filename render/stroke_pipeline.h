#pragma once
// One stroke on a canvas of its own, from a brush and a trajectory to paint:
// the canvas the stroke needs, a freshly loaded brush, fresh paper, the run's
// solvers, the render. `bristle render --brush --trajectory`, `record --png`,
// `replay` (cli/stroke_png.h) and every cell of a sheet (render/sheet_renderer.h)
// paint a stroke through here, so that they paint the same stroke alike.

#include <string>

#include "engine/model/brush.h"
#include "engine/paint/paint.h"
#include "engine/paint/paint_spec.h"
#include "engine/solvers/solver_pair.h"
#include "engine/model/trajectory.h"
#include "render/stroke_renderer.h"

namespace bristle::render {

struct StrokeSetup {
  PaintLoad load;       // checked by BrushPaint::load (checkPaintLoad)
  std::string load_where;  // names the load's source in its errors ("--paint", "s.json: /paint")
  MixModel mix = MixModel::kKubelkaMunk;
  PaperSpec paper;
  SolverSettings solvers;
  StrokeOptions stroke;  // resolution, contact band, simulation
};

struct PaintedStroke {
  PaintCanvas canvas;  // canvasForStroke's grid, the paper, the paint laid down
  StrokeResult stroke;
  double loaded_mm3 = 0;         // paint put on the brush before the stroke
  double left_on_brush_mm3 = 0;  // and on it after
};

// Throws what canvasForStroke, PaintCanvas, BrushPaint::load and makeSolverPair
// throw, before anything is simulated. `renderer` (one GL context) may serve
// many strokes.
PaintedStroke paintStroke(StrokeRenderer& renderer, const Brush& brush,
                          const Trajectory& trajectory, const StrokeSetup& setup,
                          const StepCallback& on_step = {});

// The same stroke painted onto a canvas that already exists (and may hold
// earlier strokes: bristle::api::Canvas), with a freshly loaded brush and the
// run's solvers. setup.mix must be the canvas's (the brush's paint is mixed
// by it); setup.paper is not read. Fills `stroke`, `loaded_mm3` and
// `left_on_brush_mm3`.
void paintStrokeOnto(StrokeRenderer& renderer, const Brush& brush, const Trajectory& trajectory,
                     const StrokeSetup& setup, PaintCanvas* canvas, StrokeResult* stroke,
                     double* loaded_mm3, double* left_on_brush_mm3,
                     const StepCallback& on_step = {});

// The brush as the stroke's render leaves it at time at_s: simulated with the
// run's solvers and stepped exactly as the render steps (Stepper::walk),
// up to its last step at or before at_s. Without a trajectory, the brush at
// rest, held upright with its tips 2 mm above the paper. For `bristle preview`,
// which must show a state the render reached.
BrushState strokeStateAt(const Brush& brush, const Trajectory* trajectory,
                         const StrokeOptions& options, double at_s,
                         const SolverSettings& solvers = {});

}  // namespace bristle::render

#include "render/stroke_pipeline.h"

#include <utility>

namespace bristle::render {

PaintedStroke paintStroke(StrokeRenderer& renderer, const Brush& brush,
                          const Trajectory& trajectory, const StrokeSetup& setup,
                          const StepCallback& on_step) {
  PaintedStroke out{PaintCanvas(canvasForStroke(brush, trajectory, setup.stroke), setup.paper,
                                setup.mix),
                    {}, 0, 0};
  BrushPaint paint(brush);
  paint.load(setup.load, setup.mix, setup.load_where);
  out.loaded_mm3 = paint.capacityMm3() * setup.load.amount;
  SolverPair solvers = makeSolverPair(setup.solvers);
  out.stroke = renderer.render(brush, trajectory, std::move(solvers.primary), setup.stroke,
                               &out.canvas, &paint, on_step, std::move(solvers.fallback));
  out.left_on_brush_mm3 = paint.totalVolumeMm3();
  return out;
}

}  // namespace bristle::render

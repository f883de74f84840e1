#include "render/stroke_pipeline.h"

#include <Eigen/Core>
#include <utility>

#include "engine/dynamics/stepper.h"

namespace bristle::render {

PaintedStroke paintStroke(StrokeRenderer& renderer, const Brush& brush,
                          const Trajectory& trajectory, const StrokeSetup& setup,
                          const StepCallback& on_step) {
  PaintedStroke out{PaintCanvas(canvasForStroke(brush, trajectory, setup.stroke), setup.paper,
                                setup.mix),
                    {}, 0, 0};
  paintStrokeOnto(renderer, brush, trajectory, setup, &out.canvas, &out.stroke, &out.loaded_mm3,
                  &out.left_on_brush_mm3, on_step);
  return out;
}

void paintStrokeOnto(StrokeRenderer& renderer, const Brush& brush, const Trajectory& trajectory,
                     const StrokeSetup& setup, PaintCanvas* canvas, StrokeResult* stroke,
                     double* loaded_mm3, double* left_on_brush_mm3,
                     const StepCallback& on_step) {
  BrushPaint paint(brush);
  paint.load(setup.load, setup.mix, setup.load_where);
  *loaded_mm3 = paint.capacityMm3() * setup.load.amount;
  SolverPair solvers = makeSolverPair(setup.solvers, brush);
  *stroke = renderer.render(brush, trajectory, std::move(solvers.primary), setup.stroke, canvas,
                            &paint, on_step, std::move(solvers.fallback));
  *left_on_brush_mm3 = paint.totalVolumeMm3();
}

BrushState strokeStateAt(const Brush& brush, const Trajectory* trajectory,
                         const StrokeOptions& options, double at_s,
                         const SolverSettings& settings) {
  SolverPair solvers = makeSolverPair(settings, brush);
  Simulation sim(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
  if (!trajectory) {
    Pose rest;
    rest.position_mm = Eigen::Vector3d(0, 0, brush.reachMm() + 2);
    sim.reset(rest, 0);
    return sim.state();
  }
  Stepper(sim, walkOptions(options, options.px_per_mm)).walk(*trajectory, {}, at_s);
  return sim.state();
}

}  // namespace bristle::render

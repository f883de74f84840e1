#include "render/scene_renderer.h"

#include <algorithm>
#include <memory>

#include "engine/solvers/solver_pair.h"
#include "engine/dynamics/stepper.h"
#include "render/stroke_renderer.h"

namespace bristle::render {

CanvasGrid sceneGrid(const Scene& scene) { return scene.canvas.grid(); }

PaintCanvas makeSceneCanvas(const Scene& scene) {
  return PaintCanvas(sceneGrid(scene), scene.canvas.paper, scene.mix);
}

SceneResult renderScene(const Scene& scene, const SceneRenderOptions& options,
                        PaintCanvas* canvas, const SceneStepCallback& on_step) {
  SceneResult result;
  StrokeOptions stroke_options;
  stroke_options.px_per_mm = scene.canvas.px_per_mm;
  stroke_options.contact_band_mm = options.contact_band_mm;
  stroke_options.sim = scene.sim;
  stroke_options.threads = options.threads;

  // The planned steps of every stroke, for progress over the whole scene.
  std::vector<long> planned;
  for (const SceneStroke& st : scene.strokes) {
    planned.push_back(static_cast<long>(
        planStepTimes(st.trajectory, scene.brushes[st.brush], scene.sim).size()));
    result.planned_steps += planned.back();
  }

  StrokeRenderer renderer;  // one GL context for the whole scene
  // One paint texture per distinct brush, washed and reloaded for each stroke.
  std::vector<BrushPaint> paints;
  for (const Brush& b : scene.brushes) paints.emplace_back(b);
  long done = 0;
  for (size_t i = 0; i < scene.strokes.size(); ++i) {
    const SceneStroke& st = scene.strokes[i];
    const Brush& brush = scene.brushes[st.brush];
    if (st.dry_before) canvas->dry();
    BrushPaint& paint = paints[size_t(st.brush)];
    paint.load(st.paint, scene.mix, scene.path + ": " + st.pointer + "/paint");
    // The scene's solver is the primary; a spine it fails on is tried with the other.
    SolverPair solvers =
        makeSolverPair({scene.solver, options.solver_max_iterations, {}}, brush);
    StepCallback step_cb;
    if (on_step)
      step_cb = [&](const BrushState& state, int step, int) {
        on_step(static_cast<int>(i), state, done + step, result.planned_steps);
      };
    const StrokeResult r = renderer.render(brush, st.trajectory, std::move(solvers.primary),
                                           stroke_options, canvas, &paint, step_cb,
                                           std::move(solvers.fallback));
    done += planned[i];
    if (!r.touched) result.untouched.push_back(static_cast<int>(i));
    result.deposited_mm3 += r.deposited_mm3;
    result.picked_up_mm3 += r.picked_up_mm3;
    result.stats.add(r.stats);
  }
  return result;
}

}  // namespace bristle::render

#pragma once
// A whole painting: the strokes of a scene (engine/formats/scene.h) painted in order onto
// one canvas, each by its own brush along its placed trajectory, through the
// same simulation -> geometry -> footprint -> paint path as a single stroke.

#include <functional>

#include "engine/paint/paint.h"
#include "engine/formats/scene.h"
#include "engine/dynamics/simulation.h"

namespace bristle::render {

struct SceneRenderOptions {
  // The contact band: brush geometry below this height touches the paper
  // (as StrokeOptions::contact_band_mm).
  double contact_band_mm = 0.1;
  // Per solve, for both solvers (SolverSettings::max_iterations).
  int solver_max_iterations = kDefaultSolverMaxIterations;
  int threads = 0;  // StrokeOptions::threads
};

// After every simulation step: which stroke, the state, and the step counts
// of the whole scene (done so far and planned in all).
using SceneStepCallback =
    std::function<void(int stroke, const BrushState& state, long step, long steps)>;

struct SceneResult {
  SimStats stats;               // summed over the strokes
  double deposited_mm3 = 0;     // paint laid down by all strokes
  double picked_up_mm3 = 0;     // wet paint the brushes took up from the canvas
  std::vector<int> untouched;   // strokes whose brush never touched the canvas
  long planned_steps = 0;
};

// The canvas of a scene (its size and resolution, origin at world 0, 0).
CanvasGrid sceneGrid(const Scene& scene);

// A fresh canvas for the scene: its grid, paper and mix model.
PaintCanvas makeSceneCanvas(const Scene& scene);

// Paints every stroke of the scene onto canvas (made by makeSceneCanvas), in
// order: each stroke's brush is cleaned and loaded afresh from its PaintLoad,
// the canvas dries first where the stroke asks (dry_before), and wet paint left
// by earlier strokes is picked up and carried on by later ones.
SceneResult renderScene(const Scene& scene, const SceneRenderOptions& options,
                        PaintCanvas* canvas, const SceneStepCallback& on_step = {});

}  // namespace bristle::render

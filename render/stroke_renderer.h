#pragma once
// A whole stroke, end to end: trajectory -> simulation steps -> brush geometry
// -> footprint (OSMesa) -> paint on the canvas (docs/design.md, "Where to start").

#include <memory>

#include "engine/geometry/brush_geometry.h"
#include "engine/model/canvas.h"
#include "engine/paint/paint.h"
#include "engine/dynamics/stepper.h"
#include "render/gl/footprint_renderer.h"

namespace bristle::render {

struct StrokeOptions {
  double px_per_mm = 8;
  double margin_mm = 5;  // canvas border around everything the brush can reach
  // The contact band: brush geometry below this height touches the paper.
  // About a hair's radius: spine joints resting on the canvas sit at z = 0.
  double contact_band_mm = 0.1;
  SimOptions sim;
  // Paint transfer per step (engine/paint/paint.h).
  TransferParams transfer;
  // 1: simulation and drawing take turns on the calling thread. 2: the steps
  // are simulated on a second thread while the calling thread draws the ones
  // already solved (render/step_pipeline.h); the same pixels either way.
  // 0: defaultRenderThreads(), 2 where the process may run on 2+ CPUs.
  int threads = 0;
  // A step whose hair on the paper jumps further than a step may move it is
  // redone in halves. Its try is given up as soon as a solve's iterate has
  // moved that hair this many times that far (Ipopt; 0: every try runs to its
  // end and is judged by its result): a try that will be thrown away is the
  // costliest kind of step (docs/PERFORMANCE.md, "A jumping step given up
  // early").
  double stop_on_jump = 1;
  // Between two steps the sweep stamps the hair once per pixel of motion.
  // The half solids that round the spines' bundles off at the joints, many
  // pixels wide where they press on the paper, are stamped only as often as
  // keeps the notches between their copies within this (px; 0: every stamp
  // draws them all): drawn at every stamp they would be most of a pressed
  // round's footprint triangles (docs/PERFORMANCE.md, "Joint caps stamped
  // less often").
  double sweep_notch_px = 0.25;
};

struct StrokeResult {
  SimStats stats;
  bool touched = false;  // the brush reached the canvas at least once
  double deposited_mm3 = 0;  // paint the brush laid down over the stroke
  double picked_up_mm3 = 0;  // wet paint the brush took up from the canvas
  // Steps whose footprint was the last one again (a brush held at rest): not
  // drawn, the last one's pixels reused.
  int footprints_kept = 0;
};

// The canvas a stroke needs when no scene gives one: everything the brush can
// reach along the trajectory plus a margin. Throws kDataError (naming the
// trajectory) if it would exceed the canvas limits of engine/model/canvas.h.
CanvasGrid canvasForStroke(const Brush& brush, const Trajectory& trajectory,
                           const StrokeOptions& options);

// How a render walks the simulation (engine/dynamics/stepper.h): the stroke's
// simulation, contact band and early stop, with the jump limit of a canvas
// at px_per_mm.
WalkOptions walkOptions(const StrokeOptions& options, double px_per_mm);

class StrokeRenderer {
 public:
  StrokeRenderer();
  ~StrokeRenderer();

  // Simulates the brush along the trajectory and moves paint both ways between
  // `paint` (the brush's texture, loaded by the caller) and `canvas`, every
  // step. Many strokes can share one canvas: call render once per stroke, each
  // with its own brush, trajectory (already placed on the canvas: offset the
  // trajectory's poses for a placement) and BrushPaint; dry the canvas between
  // strokes with PaintCanvas::dry() where a scene asks. One StrokeRenderer (one
  // GL context) serves any number of strokes and brushes.
  StrokeResult render(const Brush& brush, const Trajectory& trajectory,
                      std::unique_ptr<SpineSolver> solver, const StrokeOptions& options,
                      PaintCanvas* canvas, BrushPaint* paint, const StepCallback& on_step = {},
                      std::unique_ptr<SpineSolver> fallback = nullptr);

  // Footprint of one brush state on the canvas grid (for tests and previews).
  // Returns false when nothing touches the canvas.
  bool footprint(BrushGeometry& geometry, const BrushState& state, const CanvasGrid& grid,
                 double contact_band_mm, FootprintImage* out);

  // Footprint swept by the brush from `from` to `to`: the union of stamps of
  // states blended between the two (handle and joints moved along, relative
  // joint rotations turned along), spaced so that no touching joint moves more
  // than `spacing_mm` from one stamp to the next; `from` itself is not
  // stamped (the previous step painted it). Where two stamps overlap the
  // deeper wins, as for the geometry of one stamp.
  // The half solids at the spines' joints (buildSpineGeometry), most of the
  // triangles of a bundle, are stamped only as often as keeps the notches
  // between their copies within notch_px (0: all of them at every stamp).
  bool sweptFootprint(BrushGeometry& geometry, const BrushState& from, const BrushState& to,
                      const CanvasGrid& grid, double contact_band_mm, double spacing_mm,
                      FootprintImage* out, double notch_px = 0);
  // Triangles the last footprint drew (for tests).
  size_t lastFootprintTriangles() const { return drawn_vertices_.size() / 3; }
  // The footprint renderer (for tests and benchmarks of its options).
  FootprintRenderer& footprintRenderer() { return renderer_; }

 private:
  bool renderTriangles(const CanvasGrid& grid, double contact_band_mm, FootprintImage* out);
  // vertices_ drawn into the window, in tiles the GL target holds.
  void renderTiled(const FootprintWindow& win, double contact_band_mm, FootprintImage* out);
  void paintStep(BrushGeometry& geometry, const BrushState* from, const BrushState& state,
                 const StrokeOptions& options, PaintCanvas* canvas, BrushPaint* paint,
                 StrokeResult* result);

  FootprintRenderer renderer_;
  FootprintImage image_;
  FootprintImage tile_;  // one tile of a window larger than the GL target
  std::vector<BrushVertex> triangles_;
  std::vector<FootprintVertex> vertices_;
  // The last footprint drawn: its triangles, where it went and how; a draw
  // of the same is skipped (renderTriangles).
  std::vector<FootprintVertex> drawn_vertices_;
  const FootprintImage* drawn_into_ = nullptr;
  FootprintWindow drawn_window_;
  double drawn_band_mm_ = 0;
  bool kept_ = false;  // the last renderTriangles kept the footprint before
  BrushState blended_;
  HairSlide slide_;  // a flagged brush's slide over the paper this step
  HairPress press_;  // how hard the hair pressed the paper this step
  std::vector<JointCaps> stamp_plan_;  // [stamp][spine][joint]
};

}  // namespace bristle::render

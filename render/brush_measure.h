#pragma once
// A brush measured as a robot measures a real one (docs/fidelity.md, "Measuring
// a brush"): held upright, pressed to a constant depth past first contact and
// pulled along a straight line, its footprint on the paper read at steady
// state as a width, a drag and an offset. These are the three quantities of
// the dynamic virtual brush of Wang et al., "Robot Calligraphy using
// Pseudospectral Optimal Control in Conjunction with a Novel Dynamic Brush
// Model" (IROS 2020), whose robot measured them on a real calligraphy brush:
//   width   the footprint's extent across the motion: the width of the line;
//   offset  how far behind the handle's axis the footprint is widest;
//   drag    how far the footprint reaches behind that widest section, to the
//           tip trailing on the paper.
// Their model draws a footprint as a parabola, widest at its front edge
// `offset` behind the handle and closing `drag` behind that; the measures
// below read the same two distances off bristle's rendered footprint.

#include <functional>
#include <vector>

#include "engine/model/brush.h"
#include "engine/solvers/solver_pair.h"
#include "engine/model/trajectory.h"
#include "render/gl/footprint_renderer.h"

namespace bristle::render {

struct MeasureProtocol {
  // Press depths past first contact (mm; engine/geometry/first_contact.h), each its own pull.
  std::vector<double> depths_mm = {1, 2, 4, 6, 8, 10};
  double speed_mm_s = 20;  // along +x, the handle upright
  double pull_mm = 40;     // long enough for the footprint to settle
  double descend_s = 0.5;  // from 2 mm above first contact to the depth, at x = 0
  double px_per_mm = 10;   // the footprint's resolution: 0.1 mm
  // Footprints read, evenly spaced over the pull's last quarter; each measure
  // is their median, so that one step's straggling hair does not decide it.
  int samples = 5;
};

// Width, offset and drag of one footprint (mm), for a handle at x = handle_x_mm
// moving along +x. Untouched: nothing is on the paper.
struct FootprintShape {
  bool touched = false;
  double width_mm = 0, offset_mm = 0, drag_mm = 0;
};
FootprintShape measureFootprintShape(const FootprintImage& image, double handle_x_mm);

// The protocol's pull at one depth, as a depth trajectory (depth_mm column,
// not yet resolved for a brush).
Trajectory constantDepthPull(const MeasureProtocol& protocol, double depth_mm);

struct DepthMeasure {
  double depth_mm = 0;
  FootprintShape shape;  // medians over the protocol's samples
  int failed_steps = 0;  // steps of the pull with a failed spine solve
};

// Called after every step of a pull: the depth's index and count, the planned
// step's index and the pull's planned step count.
using MeasureProgress = std::function<void(int depth, int depths, int step, int steps)>;

// Runs the protocol: one simulated pull per depth, in order. Throws
// bristle::Error as the simulation's set-up does (solver settings, brush), and
// kUsage when the footprint window would exceed 4096 px a side.
std::vector<DepthMeasure> measureBrush(const Brush& brush, const MeasureProtocol& protocol,
                                       const SolverSettings& solvers,
                                       const MeasureProgress& progress = {});

}  // namespace bristle::render

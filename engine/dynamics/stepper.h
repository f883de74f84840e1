#pragma once
// The walk of a simulation along a handle's path: which steps are taken, and
// how (docs/design.md, "Layers"). A trajectory is planned into steps that
// move no spine root further than max_step_mm (planStepTimes); where the
// brush is steady several planned steps are solved as one; where the hair on
// the paper jumps further than a drawn step may move it, a step is redone in
// halves. A live session plans the steps towards each new stylus pose by the
// same rule (Stepper::stepTo). Every render, preview, scene, sheet and live
// session steps through here; what a state is drawn as is render/'s.

#include <functional>
#include <limits>
#include <vector>

#include "engine/dynamics/simulation.h"
#include "engine/model/trajectory.h"

namespace bristle {

// The most simulation steps one trajectory may plan: about 3 hours of solving
// at 1 ms a step, 80 MB of step times.
inline constexpr double kMaxPlannedSteps = 1e7;
// The most steps a segment may plan per second of gesture: a handle moving
// 250 m/s at the default 0.25 mm per step, 10 m/s at the finest 0.01 mm.
inline constexpr double kMaxStepsPerSecond = 1e6;

// The furthest any spine root of `brush` can move between two handle poses:
// |dp| + angle * (largest |root|), the bound step planning keeps under
// max_step_mm.
double rootMotionBoundMm(const Brush& brush, const Pose& a, const Pose& b);

// The steps a handle motion of `moved_mm` (rootMotionBoundMm) is cut into so
// that no spine root moves more than max_step_mm in one; at least 1.
double rootStepsFor(double moved_mm, const SimOptions& options);
// The steps a planned segment is cut into: rootStepsFor, and at least
// min_rate_hz a second over its `dt_s`. Counted as doubles, for the callers'
// limits (kMaxStepsPerSecond) to be checked before either becomes an integer.
double stepsForMotion(double moved_mm, double dt_s, const SimOptions& options);

// Times of the simulation steps for a trajectory: every sample time, subdivided
// by stepsForMotion. Throws kDataError naming the sample's line when the plan
// passes kMaxPlannedSteps or kMaxStepsPerSecond, before the steps are
// allocated.
std::vector<double> planStepTimes(const Trajectory& trajectory, const Brush& brush,
                                  const SimOptions& options);
// How many step times planStepTimes returns, with its checks and messages,
// without storing them.
double plannedStepCount(const Trajectory& trajectory, const Brush& brush,
                        const SimOptions& options);

// Throws kDataError naming the trajectory line when the brush would start inside
// the canvas or its ferrule would pass below it. A trajectory in press depths
// must have been resolved for the brush first (resolveDepths,
// engine/geometry/first_contact.h); planStepTimes requires that too (std::logic_error).
void validateTrajectoryForBrush(const Trajectory& trajectory, const Brush& brush);

// How far the hair near the paper moved across it between two states of one
// brush: the largest contactJumpMm over its spines.
double contactJumpMm(const Brush& brush, const BrushState& a, const BrushState& b,
                     double contact_band_mm);

// How a walk steps, beyond the plan's SimOptions.
struct WalkOptions {
  SimOptions sim;  // the plan (max_step_mm, min_rate_hz) and the steady merges (steady_step_mm)
  // The resolution the states are drawn at: a step may move the hair on the
  // paper max(kJumpPerRootStep max_step_mm, kJumpFloorPx px) before it is
  // redone in halves (stepper.cpp), and a merged step 2 px.
  double px_per_mm = 8;
  // The part of the brush that counts as on the paper: within this of it.
  double contact_band_mm = 0.1;
  // A try's hair jumping this many times the limit stops its solve at once
  // (Simulation::JumpLimit; 0: every try runs to its end).
  double stop_on_jump = 1;
};

// Called with every state a walk keeps: the planned step it ends (a split
// step reports its index once per piece; a merged one, the last planned step
// it covers) and the planned step count. A drawing sweeps from the state
// before to this one.
using StepCallback = std::function<void(const BrushState&, int step, int steps)>;

class Stepper {
 public:
  // `sim` must have been made with options.sim.
  Stepper(Simulation& sim, const WalkOptions& options);

  // Resets the simulation at the trajectory's first planned step time, then
  // steps it through the planned steps (planStepTimes), halving a step (down
  // to 1/32) while the hair on the paper jumps further than the limit of
  // WalkOptions::px_per_mm; with steady_step_mm above max_step_mm, runs of
  // planned steps are solved as one where the brush is steady
  // (docs/dynamics.md, "Steady steps"). on_step sees the state after the
  // reset and after every step kept. Stops at the last step that ends at or
  // before stop_t_s, so that `bristle preview --at` shows a state the render
  // shows. Steps merged, rejected and split are counted in the simulation's
  // SimStats, their undone tries' solver work too.
  void walk(const Trajectory& trajectory, const StepCallback& on_step = {},
            double stop_t_s = std::numeric_limits<double>::infinity());

  // A live session's step to the newest stylus pose: from the simulation's
  // state to `handle` at t_s in the pieces rootStepsFor gives its motion, the
  // handle interpolated. Nothing when t_s is not after the state's time. The
  // session's frame rate (paper §5: 30-60 Hz) stands in for min_rate_hz:
  // pieces the motion does not need make a frame late, and a late frame lets
  // the servo loop's force model go stale (docs/haptics.md, "The servo loop
  // and its safety"). The pieces
  // are capped at kMaxStepsPerSecond over the interval: a pose read live is
  // no input file to refuse.
  void stepTo(const Pose& handle, double t_s);

 private:
  void advance(const Trajectory& trajectory, double t0, double t1, int depth);
  bool tryMerged(const Trajectory& trajectory);
  void keep();

  Simulation& sim_;
  WalkOptions options_;
  // The walk running: its plan, where it is, how the steady merges fare.
  std::vector<double> times_;
  const StepCallback* on_step_ = nullptr;
  double stop_t_s_ = 0;
  double max_jump_mm_ = 0;
  int planned_ = 0;
  bool stopped_ = false;
  int group_ = 2, backoff_ = 1, hold_ = 0;
};

}  // namespace bristle

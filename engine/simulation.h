#pragma once
// The quasi-static brush simulation (paper §3.1): each step moves the handle,
// carries the spines rigidly with it (their joint angles unchanged), then solves
// every spine's constrained energy minimisation at the new pose.

#include <memory>
#include <vector>

#include "engine/brush.h"
#include "engine/spine_solver.h"
#include "engine/trajectory.h"

namespace bristle {

struct SimOptions {
  double max_step_mm = 0.25;  // no spine root moves further than this per step
  double min_rate_hz = 120;   // and steps come at least this often
  // Canvas multipliers below this are grazing contact, not contact
  // (SOLVER-NOTES.md: grazing joints show 1e-6..3e-4 N).
  double contact_threshold_n = 1e-3;
  // A contact joint that moved further than this over the canvas in one step
  // slid; below it, it stuck. 10x the smoothing width, where smoothed friction
  // has reached 99.5% of mu Fn.
  double slide_threshold_mm = 10 * kSmoothMm;
};

struct SpineState {
  SpineSolution solution;                  // angles, canvas forces, warm start
  std::vector<Eigen::Vector3d> joints_mm;  // n + 1 world positions, root first
  std::vector<bool> contact;               // n: joint 1..n touches the canvas
  std::vector<bool> sliding;               // n: contact joint slid this step
  std::vector<double> bend_rad;            // n: smoothed bend (damping reference)
  EnergyTerms energy;
  SolveSummary summary;
};

struct BrushState {
  int step = 0;
  double t_s = 0;
  Pose handle;
  std::vector<SpineState> spines;
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();  // canvas force on the handle
  bool anyContact() const;
};

struct SimStats {
  int steps = 0;
  int solved_steps = 0;   // steps where at least one spine needed a solve
  int failed_spine_solves = 0;
  int failed_steps = 0;
  long iterations = 0;
};

class Simulation {
 public:
  Simulation(const Brush& brush, const SimOptions& options, std::unique_ptr<SpineSolver> solver);

  // The brush at rest at this pose (no contact).
  void reset(const Pose& handle, double t_s);
  // One step (paper §3.1 steps 1-3) to the new handle pose.
  const BrushState& step(const Pose& handle, double t_s);

  const BrushState& state() const { return state_; }
  // Save and return to a state, e.g. to redo a step in smaller pieces.
  struct Snapshot {
    BrushState state;
    SimStats stats;
  };
  Snapshot snapshot() const { return {state_, stats_}; }
  void restore(const Snapshot& s) {
    state_ = s.state;
    stats_ = s.stats;
  }
  const SimStats& stats() const { return stats_; }
  const Brush& brush() const { return brush_; }
  SpineSolver& solver() { return *solver_; }

 private:
  void finishSpine(int s, const SpineProblem& problem);

  const Brush& brush_;
  SimOptions options_;
  std::unique_ptr<SpineSolver> solver_;
  BrushState state_;
  SimStats stats_;
  SpineFk fk_;
};

// Times of the simulation steps for a trajectory: every sample time, subdivided
// so that no spine root moves more than max_step_mm per step (bounded by
// |dp| + angle * |root|) and steps are at most 1 / min_rate_hz apart.
std::vector<double> planStepTimes(const Trajectory& trajectory, const Brush& brush,
                                  const SimOptions& options);

// Throws kDataError naming the trajectory line when the brush would start inside
// the canvas or its ferrule would pass below it.
void validateTrajectoryForBrush(const Trajectory& trajectory, const Brush& brush);

}  // namespace bristle

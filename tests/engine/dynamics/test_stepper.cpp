// The walk of a simulation (engine/dynamics/stepper.h): the plan's bound on
// how far a spine root moves in a step, steps redone in halves where the hair
// on the paper jumps, steady steps merged, and each counted where it happens.

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/dynamics/stepper.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/solvers/solver_pair.h"
#include "test_helpers.h"

using namespace bristle;
using namespace bristle::testing;

namespace {

const std::string kSource = BRISTLE_SOURCE_DIR;

struct Walked {
  std::vector<BrushState> states;
  std::vector<int> planned;  // the planned step each state ends
  int steps = 0;             // planned steps
  SimStats stats;
};

Walked walkOf(const Brush& brush, const Trajectory& traj, const WalkOptions& options) {
  SolverPair solvers = makeSolverPair();
  Simulation sim(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
  Walked w;
  Stepper(sim, options).walk(traj, [&](const BrushState& st, int step, int steps) {
    w.states.push_back(st);
    w.planned.push_back(step);
    w.steps = steps;
  });
  w.stats = sim.stats();
  return w;
}

}  // namespace

// The round pressed 8 mm and lifted: at lift-off its pressed tips spring back
// further in a planned step than a drawn step may move them (2 max_step_mm =
// 0.5 mm at the defaults, the floor of 2 px at 8 px/mm being 0.25 mm), and
// those steps are redone in halves.
TEST_CASE("a step whose hair on the paper jumps is redone in halves, each piece within the "
          "limits",
          "[dynamics][stepper]") {
  const Brush brush = loadBrush(kSource + "/scenes/brushes/round.json");
  const Trajectory traj = loadTrajectory(kSource + "/scenes/trajectories/press-lift.csv");
  const WalkOptions options;
  const Walked w = walkOf(brush, traj, options);
  REQUIRE(w.stats.jump_split_steps > 0);
  // Every planned step is reported, the first as the reset; a split one once
  // per piece kept, so pieces beyond the planned steps are the splits' extra.
  REQUIRE(w.planned.front() == 0);
  CHECK(w.planned.back() == w.steps - 1);
  int repeats = 0;
  for (size_t i = 1; i < w.planned.size(); ++i) {
    CHECK(w.planned[i] - w.planned[i - 1] <= 1);
    if (w.planned[i] == w.planned[i - 1]) ++repeats;
  }
  CHECK(static_cast<int>(w.states.size()) == w.steps + repeats);
  // Each split puts two tries for one: one state more.
  CHECK(repeats == w.stats.jump_split_steps);
  CHECK(w.stats.steps == static_cast<int>(w.states.size()) - 1);
  // The plan moves no spine root further than max_step_mm in a step, and a
  // piece of one less; 1e-9 of rounding in the interpolated poses. A kept
  // state whose hair still jumped further than the limit is a finest piece,
  // 1/32 of its planned step: halving gives up there (a tip springing back
  // as it lifts off jumps however short the step).
  const std::vector<double> times = planStepTimes(traj, brush, options.sim);
  const double jump_limit_mm = 2 * options.sim.max_step_mm;
  double worst_root_mm = 0;
  int over_limit = 0, over_limit_coarse = 0;
  for (size_t i = 1; i < w.states.size(); ++i) {
    worst_root_mm = std::max(
        worst_root_mm, rootMotionBoundMm(brush, w.states[i - 1].handle, w.states[i].handle));
    if (contactJumpMm(brush, w.states[i - 1], w.states[i], options.contact_band_mm) <=
        jump_limit_mm)
      continue;
    ++over_limit;
    const size_t k = static_cast<size_t>(w.planned[i]);
    const double finest_s = (times[k] - times[k - 1]) / 32;
    if (w.states[i].t_s - w.states[i - 1].t_s > finest_s * (1 + 1e-9)) ++over_limit_coarse;
  }
  CHECK(worst_root_mm <= options.sim.max_step_mm * (1 + 1e-9));
  CHECK(over_limit < w.stats.jump_split_steps);
  CHECK(over_limit_coarse == 0);
}

// With steady_step_mm above max_step_mm, a brush moving steadily through the
// air is solved a merged step at a time: each merged step is reported once,
// at the last planned step it covers, and counted with the planned steps it
// covered.
TEST_CASE("steady planned steps are merged, reported once and counted", "[dynamics][stepper]") {
  const Brush brush = loadBrush(kSource + "/scenes/brushes/round.json");
  Trajectory traj = loadTrajectory(kSource + "/scenes/trajectories/straight-pull.csv");
  // 40 mm up: the pull in the air, where nothing touches down or lifts.
  for (TrajectorySample& s : traj.samples) s.pose.position_mm.z() += 40;
  WalkOptions options;
  options.sim.steady_step_mm = 1;
  const Walked w = walkOf(brush, traj, options);
  REQUIRE(w.stats.steady_steps > 0);
  int merged_reports = 0, merged_planned = 0;
  for (size_t i = 1; i < w.planned.size(); ++i) {
    const int covered = w.planned[i] - w.planned[i - 1];
    if (covered >= 2) {
      ++merged_reports;
      merged_planned += covered;
    }
  }
  CHECK(merged_reports == w.stats.steady_steps);
  CHECK(merged_planned == w.stats.steady_merged);
  // In the air the brush is always steady: no merge is rejected. A merge
  // covers at most 8 planned steps (kMaxSteadyGroup) and 1 mm of handle path
  // (steady_step_mm; the straight move's root bound is within the path's).
  CHECK(w.stats.steady_rejected == 0);
  CHECK(w.stats.steady_merged <= 8 * w.stats.steady_steps);
  double longest_mm = 0;
  for (size_t i = 1; i < w.states.size(); ++i)
    longest_mm = std::max(longest_mm,
                          rootMotionBoundMm(brush, w.states[i - 1].handle, w.states[i].handle));
  CHECK(longest_mm <= options.sim.steady_step_mm * (1 + 1e-9));
  CHECK(w.planned.back() == w.steps - 1);
}

// The figures `bristle render --brush round --trajectory press-lift.csv
// --stats` reports for this stroke at the defaults (Ipopt, SLSQP as the
// fallback, 8 px/mm): 401 planned steps, 37 of them redone in halves, each
// of those given up at the first Ipopt iterate that showed the jump. The
// walk counts them, whichever command runs it; the iterations include the
// tries given up.
TEST_CASE("the walk counts what a render of the stroke reports", "[dynamics][stepper]") {
  const Brush brush = loadBrush(kSource + "/scenes/brushes/round.json");
  const Trajectory traj = loadTrajectory(kSource + "/scenes/trajectories/press-lift.csv");
  const Walked w = walkOf(brush, traj, WalkOptions{});
  CHECK(w.steps == 401);
  CHECK(w.stats.steps == 437);
  CHECK(w.stats.jump_split_steps == 37);
  CHECK(w.stats.jump_stopped_steps == 37);
  CHECK(w.stats.iterations == 5175);
}

// A live session steps towards each stylus pose by the plan's root bound: no
// spine root further than max_step_mm a step. Its frame rate stands in for
// min_rate_hz, so a slow move takes no more steps than a fast one.
TEST_CASE("a live step to a far pose is cut by the plan's root bound", "[dynamics][stepper]") {
  const Brush brush = loadBrush(kSource + "/scenes/brushes/round.json");
  WalkOptions options;
  SolverPair solvers = makeSolverPair();
  Simulation sim(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
  Stepper stepper(sim, options);
  // In the air, 40 mm above the paper: each piece is relaxed in closed form.
  const Pose from = poseAt(0, 0, 60);
  Pose to = poseAt(3, 1, 61);
  to.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()));
  sim.reset(from, 0);
  const double moved = rootMotionBoundMm(brush, from, to);
  const int root_steps = static_cast<int>(std::ceil(moved / options.sim.max_step_mm));
  // More than the plan's rate would give a fast move, fewer than a slow one.
  REQUIRE(root_steps > 0.01 * options.sim.min_rate_hz + 1);
  REQUIRE(root_steps < 1.0 * options.sim.min_rate_hz);
  const double t_s = GENERATE(0.01, 1.0);
  INFO("to t = " << t_s << " s");
  stepper.stepTo(to, t_s);
  CHECK(sim.stats().steps == root_steps);
  CHECK(sim.state().t_s == Approx(t_s).epsilon(1e-12));
  CHECK((sim.state().handle.position_mm - to.position_mm).norm() < 1e-12);
  // A pose no later than the state is no step.
  const int steps = sim.stats().steps;
  stepper.stepTo(from, sim.state().t_s);
  CHECK(sim.stats().steps == steps);
}

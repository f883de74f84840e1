// The quasi-static spine simulation (paper §3) against closed forms and the
// laws it must obey: the canvas constraint, Coulomb stick and slip.

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "test_helpers.h"

using namespace bristle;
using namespace bristle::testing;

TEST_CASE("one joint pressed into the canvas reaches the closed-form equilibrium",
          "[dynamics]") {
  // Frictionless (mu = 0), undamped: the tip slides until the constraint alone
  // holds it, so cos(theta*) = h / L and the canvas force balances the spring
  // torque about the root: Fn * L sin(theta*) = K (theta* - theta_rest).
  constexpr double L = 10, K = 5, h = 6, rest = 0.02;
  SpineSpec spine = makeSpine({L}, {K});
  spine.rest_angles_rad[0] = Eigen::Vector2d(rest, 0);
  const Brush brush = makeBrush({spine}, 0.0, 0.0);
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  sim.reset(poseAt(0, 0, 12), t);
  moveHandle(sim, poseAt(0, 0, 12), poseAt(0, 0, h), &t);
  const SpineState& s = sim.state().spines[0];
  const double theta_star = std::acos(h / L);
  const double fn_star = K * (theta_star - rest) / (L * std::sin(theta_star));
  // Ipopt's tol 1e-8 leaves joint angles within ~1e-6 rad; 1e-5 is the margin.
  constexpr double kAngleTol = 1e-5;
  CHECK(jointAngles(s, 0)[0] == Approx(theta_star).margin(kAngleTol));
  CHECK(jointAngles(s, 0)[1] == Approx(0).margin(kAngleTol));
  // The multiplier inherits the angle's accuracy times dFn/dtheta ~ 1 N/rad.
  CHECK(s.solution.normal_force_n[0] == Approx(fn_star).epsilon(1e-4));
  CHECK(s.contact[0]);
  CHECK(sim.state().force_n.z() == Approx(fn_star).epsilon(1e-4));
}

TEST_CASE("no joint ends a step below the canvas", "[dynamics]") {
  SpineSpec a = makeSpine({4, 4, 4}, {10, 8, 6}, 0.005, Eigen::Vector3d(1, 0, 0));
  SpineSpec b = makeSpine({4, 4, 4}, {10, 8, 6}, 0.005, Eigen::Vector3d(-1, 0.5, 0));
  a.rest_angles_rad[0] = Eigen::Vector2d(0.03, 0.01);
  b.rest_angles_rad[0] = Eigen::Vector2d(0.02, -0.02);
  const Brush brush = makeBrush({a, b}, 0.45, 0.35);
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  Pose start = poseAt(0, 0, 14);
  start.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
  Pose pressed = start, dragged = start;
  pressed.position_mm.z() = 6;
  dragged.position_mm = Eigen::Vector3d(8, 6, 6.5);
  sim.reset(start, t);
  // Ipopt's constraint tolerance (constr_viol_tol) is 1e-8 mm scaled; allow 1e-6 mm.
  constexpr double kPenetrationTolMm = 1e-6;
  double lowest = 1e9;
  for (const auto& [from, to] : {std::pair{start, pressed}, std::pair{pressed, dragged}}) {
    const double dist = (to.position_mm - from.position_mm).norm();
    const int n = static_cast<int>(std::ceil(dist / 0.1));
    for (int i = 1; i <= n; ++i) {
      t += 0.01;
      const BrushState& st = sim.step(interpolatePose(from, to, double(i) / n), t);
      for (const SpineState& s : st.spines) {
        REQUIRE(s.summary.usable());
        for (const Eigen::Vector3d& x : s.joints_mm) lowest = std::min(lowest, x.z());
      }
    }
  }
  CHECK(lowest >= -kPenetrationTolMm);
  CHECK(sim.state().anyContact());
}

TEST_CASE("a contact joint sticks under a small drag and slides under a large one",
          "[dynamics][friction]") {
  // Two joints so that the spine can flex while its tip holds.
  SpineSpec spine = makeSpine({6, 6}, {8, 5});
  spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
  const double mu = 0.5;
  const Brush brush = makeBrush({spine}, mu, mu);
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  sim.reset(poseAt(0, 0, 14), t);
  moveHandle(sim, poseAt(0, 0, 14), poseAt(0, 0, 8), &t);
  for (int i = 0; i < 5; ++i) sim.step(poseAt(0, 0, 8), t += 0.01);  // settle
  REQUIRE(sim.state().spines[0].contact[1]);
  const Eigen::Vector3d tip0 = sim.state().spines[0].joints_mm[2];

  SECTION("small drag: the tangential load stays below mu Fn and the tip holds") {
    sim.step(poseAt(0.05, 0, 8), t += 0.01);
    const BrushState& st = sim.state();
    const Eigen::Vector3d tip1 = st.spines[0].joints_mm[2];
    // Smoothed friction holds with a creep of order the smoothing width
    // (1e-3 mm); 5e-3 mm is far below the 0.05 mm the root moved.
    CHECK((tip1 - tip0).head<2>().norm() < 5e-3);
    CHECK_FALSE(st.spines[0].sliding[1]);
    CHECK(st.force_n.head<2>().norm() < mu * st.force_n.z());
  }
  SECTION("large drag: the tip slides and friction saturates at mu Fn") {
    // The spine first flexes while the tip holds (it trails), then the spring
    // load exceeds mu Fn and the tip follows the handle.
    moveHandle(sim, poseAt(0, 0, 8), poseAt(20, 0, 8), &t);
    const BrushState& st = sim.state();
    const Eigen::Vector3d tip1 = st.spines[0].joints_mm[2];
    INFO("tip moved " << (tip1 - tip0).transpose() << " force " << st.force_n.transpose());
    CHECK((tip1 - tip0).x() > 10.0);
    CHECK(st.spines[0].sliding[1]);
    // Friction uses the previous step's Fn (eq. 3 holds Fn constant during a
    // solve); while sliding steadily the two differ by well under 5%.
    CHECK(st.force_n.head<2>().norm() == Approx(mu * st.force_n.z()).epsilon(0.05));
    CHECK(st.force_n.x() < 0);  // friction opposes the drag
  }
}

TEST_CASE("the simulation is deterministic", "[dynamics][determinism]") {
  SpineSpec a = makeSpine({4, 4, 4}, {10, 8, 6}, 0.005, Eigen::Vector3d(1, 0, 0));
  a.rest_angles_rad[0] = Eigen::Vector2d(0.03, 0.01);
  const Brush brush = makeBrush({a, a}, 0.45, 0.35);
  auto run = [&] {
    Simulation sim(brush, SimOptions{}, makeIpoptSolver());
    double t = 0;
    sim.reset(poseAt(0, 0, 13), t);
    moveHandle(sim, poseAt(0, 0, 13), poseAt(0, 0, 7), &t);
    moveHandle(sim, poseAt(0, 0, 7), poseAt(5, 3, 7), &t);
    return sim.state().spines[0].joints_mm;
  };
  CHECK(run() == run());
}

TEST_CASE("step planning bounds root motion and keeps a minimum rate", "[dynamics]") {
  Trajectory tr;
  tr.path = "t.csv";
  TrajectorySample a, b;
  a.t_s = 0;
  a.pose = poseAt(0, 0, 10);
  b.t_s = 1;
  b.pose = poseAt(10, 0, 10);
  b.pose.rotation = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ());
  tr.samples = {a, b};
  SpineSpec s = makeSpine({5}, {5}, 0, Eigen::Vector3d(2, 0, 0));
  const Brush brush = makeBrush({s}, 0.4, 0.3);
  SimOptions opt;
  const std::vector<double> times = planStepTimes(tr, brush, opt);
  REQUIRE(times.front() == 0);
  REQUIRE(times.back() == 1);
  for (size_t i = 1; i < times.size(); ++i) {
    const Pose p0 = tr.poseAt(times[i - 1]), p1 = tr.poseAt(times[i]);
    const double moved = (p1.apply(s.root_mm) - p0.apply(s.root_mm)).norm();
    CHECK(moved <= opt.max_step_mm + 1e-12);
    CHECK(times[i] - times[i - 1] <= 1 / opt.min_rate_hz + 1e-12);
  }
}

TEST_CASE("a solve started from the stuck joints reaches the carried start's minima in fewer "
          "iterations",
          "[dynamics][start]") {
  // Two joints so that the spine can flex while its tip holds; a handle that
  // rocks back and forth by less than friction holds (the tip sticks), then
  // drags away (it slips). Simulation A starts each solve from the predicted
  // start (SimOptions::predict_start), B from the carried shape, both from A's
  // state at every step, so each step compares one solve with the other.
  SpineSpec spine = makeSpine({6, 6}, {8, 5});
  spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
  const Brush brush = makeBrush({spine}, 0.5, 0.4);
  SimOptions carried_only;
  carried_only.predict_start = false;
  Simulation a(brush, SimOptions{}, makeIpoptSolver());
  Simulation b(brush, carried_only, makeIpoptSolver());
  double t = 0;
  a.reset(poseAt(0, 0, 14), t);
  b.reset(poseAt(0, 0, 14), t);
  moveHandle(a, poseAt(0, 0, 14), poseAt(0, 0, 8), &t);
  REQUIRE(a.state().spines[0].contact[1]);
  std::vector<Pose> path;
  for (int i = 1; i <= 40; ++i) path.push_back(poseAt(0.08 * std::sin(0.4 * i), 0, 8));
  for (int i = 1; i <= 40; ++i) path.push_back(poseAt(0.25 * i, 0.05 * i, 8));
  // The acceptance bar for "the same minimum": joints within 1e-3 mm. Ipopt's
  // tol of 1e-8 leaves ~1e-6 mm, and a joint that sticks in one and creeps in
  // the other would differ by the slip distance, 1e-2 mm.
  constexpr double kSameMinimumMm = 1e-3;
  long iterations_a = 0, iterations_b = 0;
  int stuck_steps = 0;
  double worst_mm = 0;
  for (const Pose& pose : path) {
    const Simulation::Snapshot before = a.snapshot();
    b.restore(before);
    t += 0.01;
    a.step(pose, t);
    b.step(pose, t);
    REQUIRE(a.state().spines[0].summary.usable());
    REQUIRE(b.state().spines[0].summary.usable());
    iterations_a += a.stats().iterations - before.stats.iterations;
    iterations_b += b.stats().iterations - before.stats.iterations;
    if (before.state.spines[0].contact[1] && !before.state.spines[0].sliding[1]) ++stuck_steps;
    for (size_t j = 0; j < a.state().spines[0].joints_mm.size(); ++j)
      worst_mm = std::max(worst_mm, (a.state().spines[0].joints_mm[j] -
                                     b.state().spines[0].joints_mm[j]).norm());
  }
  INFO("iterations predicted " << iterations_a << ", carried " << iterations_b << " over "
                               << path.size() << " steps, " << stuck_steps
                               << " stuck; joints apart by up to " << worst_mm << " mm");
  CHECK(worst_mm < kSameMinimumMm);
  CHECK(stuck_steps >= 20);  // the rocking held the tip: the case the start is for
  // Observed: 442 iterations against 920 (0.48). 0.7 leaves room for other
  // Ipopt builds and still fails if the start were ignored.
  CHECK(iterations_a < 0.7 * iterations_b);
  CHECK(a.state().spines[0].sliding[1]);  // and the drag made it slide in the end
}

TEST_CASE("a solve that continues the last step's bend reaches the same minima in fewer "
          "iterations, and a reversing handle starts from the carried shape",
          "[dynamics][start]") {
  // Three joints pressed deeper and deeper while dragged: each step bends them
  // a little further, which the extrapolated start (SimOptions::
  // extrapolate_start) anticipates and the carried one does not. Then the
  // handle goes back the way it came: no part of the last motion repeats, so
  // both start from the same point and must take the same iterations.
  // A runs with the default start, B without the extrapolation, both from A's
  // state at every step, so each step compares one solve with the other.
  SpineSpec spine = makeSpine({5, 5, 4}, {10, 8, 6}, 0.005);
  spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
  const Brush brush = makeBrush({spine}, 0.5, 0.4);
  SimOptions no_extrapolation;
  no_extrapolation.extrapolate_start = false;
  Simulation a(brush, SimOptions{}, makeIpoptSolver());
  Simulation b(brush, no_extrapolation, makeIpoptSolver());
  double t = 0;
  a.reset(poseAt(0, 0, 16), t);
  b.reset(poseAt(0, 0, 16), t);
  moveHandle(a, poseAt(0, 0, 16), poseAt(0, 0, 12.5), &t);
  REQUIRE(a.state().spines[0].contact.back());
  std::vector<Pose> path;
  for (int i = 1; i <= 40; ++i) path.push_back(poseAt(0.2 * i, 0, 12.5 - 0.06 * i));
  const size_t back_from = path.size();
  for (int i = 1; i <= 10; ++i) path.push_back(poseAt(8 - 0.2 * i, 0, 10.1));
  // The acceptance bar for "the same minimum", as in the test above.
  constexpr double kSameMinimumMm = 1e-3;
  long iterations_a = 0, iterations_b = 0;
  double worst_mm = 0;
  for (size_t i = 0; i < path.size(); ++i) {
    const Simulation::Snapshot before = a.snapshot();
    b.restore(before);
    t += 0.01;
    a.step(path[i], t);
    b.step(path[i], t);
    REQUIRE(a.state().spines[0].summary.usable());
    REQUIRE(b.state().spines[0].summary.usable());
    const long step_a = a.stats().iterations - before.stats.iterations;
    const long step_b = b.stats().iterations - before.stats.iterations;
    iterations_a += step_a;
    iterations_b += step_b;
    for (size_t j = 0; j < a.state().spines[0].joints_mm.size(); ++j)
      worst_mm = std::max(worst_mm, (a.state().spines[0].joints_mm[j] -
                                     b.state().spines[0].joints_mm[j]).norm());
    // The first step back: the last motion is not repeated at all (u = 0).
    if (i == back_from) {
      CHECK(step_a == step_b);
      CHECK(a.state().spines[0].joints_mm.back() == b.state().spines[0].joints_mm.back());
    }
  }
  INFO("iterations extrapolated " << iterations_a << ", carried " << iterations_b << " over "
                                  << path.size() << " steps; joints apart by up to " << worst_mm
                                  << " mm");
  CHECK(worst_mm < kSameMinimumMm);
  // Observed: 292 iterations against 384 (0.76), the joints within 7e-9 mm.
  // 0.85 leaves room for other Ipopt builds and still fails if the start
  // were ignored (ratio 1).
  CHECK(iterations_a < 0.85 * iterations_b);
}

TEST_CASE("a lifted brush springs back: at rest one step after it leaves the canvas (D = 0)",
          "[dynamics][springback]") {
  // With no joint friction the minimum of E_s alone is the rest pose: a spine
  // that touches nothing must be there after a single step (closed form, so
  // only round-off remains: 1e-9 rad is far below any solver tolerance).
  SpineSpec spine = makeSpine({5, 5, 4}, {10, 8, 6}, 0.0);
  spine.rest_angles_rad = {{0.04, 0.0}, {0.0, 0.02}, {-0.05, 0.0}};
  const Brush brush = makeBrush({spine, makeSpine({5, 5, 4}, {10, 8, 6}, 0.0,
                                                  Eigen::Vector3d(1.5, 0, 0))},
                                0.5, 0.4);
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  sim.reset(poseAt(0, 0, 16), t);
  moveHandle(sim, poseAt(0, 0, 16), poseAt(0, 0, 7), &t);
  moveHandle(sim, poseAt(0, 0, 7), poseAt(10, 0, 7), &t);
  double bent = 0;
  for (int k = 0; k < 3; ++k) bent = std::max(bent, bendFromRest(spine, sim.state().spines[0], k));
  REQUIRE(bent > 0.3);  // pressed and dragged well away from rest
  int checked = 0;
  const Pose from = sim.state().handle;
  for (int i = 1; i <= 100; ++i) {
    bool was_clear = true;
    for (const SpineState& s : sim.state().spines)
      for (size_t j = 1; j < s.joints_mm.size(); ++j) was_clear = was_clear && s.joints_mm[j].z() > 1e-3;
    sim.step(interpolatePose(from, poseAt(10, 0, 20), i / 100.0), t += 0.01);
    if (!was_clear) continue;
    for (size_t s = 0; s < brush.spines.size(); ++s)
      for (int k = 0; k < 3; ++k) CHECK(bendFromRest(brush.spines[s], sim.state().spines[s], k) < 1e-9);
    ++checked;
  }
  CHECK(checked > 30);  // the last ~45 of the 100 lifting steps are clear
  CHECK(sim.stats().relaxed_spines > 0);
}

TEST_CASE("a heavy press bends joints past 90 degrees and never fails a step",
          "[dynamics][heavy]") {
  // Issue "Brush body": the flat pressed to 75% of its hair length and pulled
  // 50 mm failed 400 of 608 steps with eq. 10's angles, whose singularity is at a
  // 90-degree bend. Re-based angles have none within reach; both solvers must
  // solve every step.
  const Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/flat.json");
  double hair = 0;
  for (const SpineSpec& s : brush.spines) hair = std::max(hair, s.lengthMm());
  for (const char* solver : {"ipopt", "slsqp"}) {
    INFO(solver);
    Simulation sim(brush, SimOptions{},
                   std::string(solver) == "ipopt" ? makeIpoptSolver() : makeSlsqpSolver());
    double t = 0;
    sim.reset(poseAt(0, 0, hair + 1), t);
    const double z = hair * 0.25;
    moveHandle(sim, poseAt(0, 0, hair + 1), poseAt(0, 0, z), &t, 0.2);
    moveHandle(sim, poseAt(0, 0, z), poseAt(50, 0, z), &t, 0.2);
    double most = 0;  // the largest turn of a segment from the ferrule's axis
    for (const SpineState& s : sim.state().spines) {
      Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
      for (const Eigen::Matrix3d& k : s.rot) {
        r = r * k;
        most = std::max(most, std::acos(std::clamp(r(2, 2), -1.0, 1.0)));
      }
    }
    moveHandle(sim, poseAt(50, 0, z), poseAt(50, 0, hair + 1), &t, 0.2);
    CHECK(sim.stats().failed_steps == 0);
    // Past the ~76 degrees where every solve failed with eq. 10's angles (the
    // hair lies flat on the paper, 90 degrees, or curls beyond).
    CHECK(most > 1.4);
    CHECK_FALSE(sim.state().anyContact());
  }
}

namespace {
// The smallest ratio, over neighbouring spines' corresponding joints on the
// paper and over the steps of a pressed pull, of their distance to their
// distance at rest.
double tightestSqueeze(const Brush& brush) {
  const std::vector<VolumePair> pairs = volumePairs(brush);
  double hair = 0;
  for (const SpineSpec& s : brush.spines) hair = std::max(hair, s.lengthMm());
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver());
  double t = 0;
  Pose up = poseAt(0, 0, hair + 1), down = poseAt(0, 0, hair * 0.5), along = poseAt(30, 0, hair * 0.5);
  for (Pose* p : {&up, &down, &along}) p->rotation = Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY());
  sim.reset(up, t);
  moveHandle(sim, up, down, &t, 0.2);
  double tightest = HUGE_VAL;
  const int steps = 150;
  for (int i = 1; i <= steps; ++i) {
    const BrushState& st = sim.step(interpolatePose(down, along, double(i) / steps), t += 0.01);
    REQUIRE(sim.stats().failed_steps == 0);
    for (const VolumePair& vp : pairs)
      for (size_t j = 1; j <= vp.rest_mm.size(); ++j) {
        if (!st.spines[vp.s].contact[j - 1] || !st.spines[vp.t].contact[j - 1]) continue;
        const double d = (st.spines[vp.s].joints_mm[j] - st.spines[vp.t].joints_mm[j]).norm();
        tightest = std::min(tightest, d / vp.rest_mm[j - 1]);
      }
  }
  return tightest;
}
}  // namespace

TEST_CASE("hair volume: neighbouring hairs on the paper do not collapse onto each other",
          "[dynamics][volume]") {
  Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/calligraphy.json");
  brush.volume = VolumeSpec{};
  const double without = tightestSqueeze(brush);
  brush.volume.min_separation = 0.8;
  brush.volume.stiffness_n_per_mm = 5;
  const double with = tightestSqueeze(brush);
  INFO("tightest squeeze without volume " << without << ", with " << with);
  // Measured: 0.001 without (neighbours lie on top of each other) and 0.78 with.
  // With volume the joints may sink into the barrier by its smoothing width
  // (0.02 mm) plus force / stiffness (~0.2 N / 5 N/mm = 0.04 mm) against rest
  // spacings of ~0.5-2.6 mm: 0.7 of rest leaves room for both.
  CHECK(without < 0.5);
  CHECK(with > 0.7);
}

TEST_CASE("a failed step is retried in halves and counted once", "[dynamics][split]") {
  // Two energy evaluations cannot converge a contact solve: every piece fails,
  // so every contact step is split to the limit and still fails. To the
  // caller each is one step, failed once.
  SlsqpSettings starved;
  starved.max_evaluations = 2;
  const SpineSpec spine = makeSpine({5, 5}, {8, 5}, 0.005);
  const Brush brush = makeBrush({spine}, 0.4, 0.3);
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver(starved));
  double t = 0;
  sim.reset(poseAt(0, 0, 12), t);
  int calls = 0, runs = 0;  // runs of consecutive failed steps
  bool was_failed = false;
  for (int i = 1; i <= 40; ++i, ++calls) {
    const int failed_before = sim.stats().failed_steps;
    sim.step(poseAt(0.1 * i, 0, 12 - 0.1 * i), t += 0.01);
    const bool failed = sim.stats().failed_steps > failed_before;
    runs += failed && !was_failed;
    was_failed = failed;
  }
  const SimStats& st = sim.stats();
  CHECK(st.steps == calls);
  CHECK(sim.state().step == calls);
  REQUIRE(st.failed_steps > 0);
  CHECK(st.failed_steps <= calls);
  // The first failed step of each run was split to the limit first: halves,
  // quarters, eighths, 1 + 2 + 4 = 7 pieces redone in halves (15 attempts in
  // all); the rest of a run is not split again.
  REQUIRE(runs >= 1);
  CHECK(st.failed_steps > runs);  // the test has a real run to skip
  CHECK(st.split_steps == 7 * runs);
  CHECK(st.longest_failed_run <= st.failed_steps);
  CHECK(st.longest_failed_run >= 1);
}

// A snapshot holds the run of failed steps too: a failed step redone from its
// snapshot (as the renderer redoes a step that jumped) is split as the first
// failed step of a run, as it was the first time, not kept as the run's
// continuation.
TEST_CASE("a failed step redone from its snapshot is split as it was the first time",
          "[dynamics][split]") {
  SlsqpSettings starved;
  starved.max_evaluations = 2;  // every contact solve fails (test above)
  const SpineSpec spine = makeSpine({5, 5}, {8, 5}, 0.005);
  const Brush brush = makeBrush({spine}, 0.4, 0.3);
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver(starved));
  double t = 0;
  sim.reset(poseAt(0, 0, 12), t);
  Simulation::Snapshot before;
  Pose pose;
  for (int i = 1; i <= 40; ++i) {
    before = sim.snapshot();
    pose = poseAt(0.1 * i, 0, 12 - 0.1 * i);
    sim.step(pose, t += 0.01);
    if (sim.stats().failed_steps > before.stats.failed_steps) break;
  }
  REQUIRE(sim.stats().failed_steps == before.stats.failed_steps + 1);
  const int splits = sim.stats().split_steps - before.stats.split_steps;
  const std::vector<Eigen::Vector3d> joints = sim.state().spines[0].joints_mm;
  CHECK(splits == 7);  // halves, quarters, eighths
  sim.restore(before);
  sim.step(pose, t);
  CHECK(sim.stats().split_steps - before.stats.split_steps == splits);
  CHECK(sim.state().spines[0].joints_mm == joints);
}

TEST_CASE("a spine that springs back in the air never ends below the canvas or in a neighbour",
          "[dynamics][volume]") {
  // The badger (hair volume on) along the start of the S-curve, held 5 mm up as
  // the library sheet holds it. Neighbours push some spines up off the paper;
  // those spring back in closed form (relaxInAir) unless that would take them
  // into the canvas. A check that read the pose from the old step's angles on
  // the new base would let a spine spring back below the paper, be solved
  // back up the next step, and do so again every step (the renderer halving
  // every such step five times: minutes for a 3 s stroke).
  const Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/badger.json");
  const Trajectory traj =
      loadTrajectory(std::string(BRISTLE_SOURCE_DIR) + "/scenes/trajectories/s-curve.csv");
  Simulation sim(brush, SimOptions{}, makeIpoptSolver(), makeSlsqpSolver());
  const Eigen::Vector3d lift(0, 0, 5);
  auto poseOf = [&](double t) {
    Pose p = traj.poseAt(t);
    p.position_mm += lift;
    return p;
  };
  const std::vector<double> times = planStepTimes(traj, brush, SimOptions{});
  sim.reset(poseOf(times.front()), times.front());
  // As in "no joint ends a step below the canvas": Ipopt's constraint accuracy.
  constexpr double kPenetrationTolMm = 1e-6;
  // Steps move every spine root by 0.25 mm at most (planStepTimes); a joint
  // near the paper that jumps four times that in one step is chattering
  // between two poses. Springing back regardless of the neighbours' hair
  // volume, spines do so about 45 times in this 0.6 s; with the check, 2 (a
  // hair slipping or buckling jumps once). The bound of 5 separates the two.
  constexpr double kJumpMm = 1.0, kNearPaperMm = 2.0;
  double lowest = 1e9;
  int relaxed_below = 0, jumps = 0;
  BrushState before = sim.state();
  for (size_t i = 1; i < times.size() && times[i] <= 0.6; ++i) {
    const BrushState& st = sim.step(poseOf(times[i]), times[i]);
    for (size_t s = 0; s < st.spines.size(); ++s) {
      const SpineState& sp = st.spines[s];
      for (size_t j = 0; j < sp.joints_mm.size(); ++j) {
        const Eigen::Vector3d& x = sp.joints_mm[j];
        const Eigen::Vector3d& x0 = before.spines[s].joints_mm[j];
        lowest = std::min(lowest, x.z());
        if (sp.summary.status == SolveStatus::kFree && x.z() < -kPenetrationTolMm) ++relaxed_below;
        if (std::min(x.z(), x0.z()) < kNearPaperMm && (x - x0).head<2>().norm() > kJumpMm) ++jumps;
      }
    }
    before = st;
  }
  CHECK(relaxed_below == 0);
  CHECK(jumps <= 5);
  CHECK(lowest >= -kPenetrationTolMm);
  CHECK(sim.stats().relaxed_spines > 0);  // the case does spring spines back
}

// Simulation::JumpLimit: the renderer redoes in halves a step whose hair on
// the paper jumps further than a stamp covers, and a step given a limit is
// given up as soon as a solve's iterate shows such a jump, rather than after
// the solves have converged (render/stroke_renderer.cpp).
TEST_CASE("a step with a jump limit stops at the first iterate past it, and changes nothing",
          "[dynamics][jump]") {
  SpineSpec spine = makeSpine({6, 6}, {8, 5});
  spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
  const Brush brush = makeBrush({spine}, 0.5, 0.4);
  const Pose pressed = poseAt(0, 0, 8), dragged = poseAt(6, 1, 8);
  for (const bool ipopt : {true, false}) {
    INFO((ipopt ? "Ipopt" : "SLSQP"));
    Simulation sim(brush, SimOptions{}, ipopt ? makeIpoptSolver() : makeSlsqpSolver());
    double t = 0;
    sim.reset(poseAt(0, 0, 14), t);
    moveHandle(sim, poseAt(0, 0, 14), pressed, &t);
    // Held still, the tip sticks; the drag then tears it loose, so the step's
    // solves start with the tip on its anchor and move it on the way.
    for (int i = 0; i < 10 && sim.state().spines[0].sliding[1]; ++i) sim.step(pressed, t += 0.01);
    REQUIRE(sim.state().spines[0].contact[1]);
    REQUIRE_FALSE(sim.state().spines[0].sliding[1]);
    const Simulation::Snapshot before = sim.snapshot();
    t += 0.01;

    // The whole step, and how far it moved the hair on the paper.
    sim.step(dragged, t);
    const BrushState plain = sim.state();
    const long plain_iterations = sim.stats().iterations - before.stats.iterations;
    const double jump_mm = contactJumpMm(spine, before.state.spines[0].joints_mm,
                                         plain.spines[0].joints_mm, 0.1);
    INFO("the step moved the hair on the paper " << jump_mm << " mm in " << plain_iterations
                                                 << " iterations");
    REQUIRE(jump_mm > 0.5);  // the tip slid: a jump to watch for
    CHECK_FALSE(sim.stepStopped());

    // A limit no iterate reaches changes nothing, bit for bit. (An iterate
    // can swing past the result, so the limit is beyond any: the handle moved
    // 6 mm.)
    constexpr double kBeyondReachMm = 100;
    sim.restore(before);
    sim.step(dragged, t, {kBeyondReachMm, 0.1});
    CHECK_FALSE(sim.stepStopped());
    CHECK(sim.state().spines[0].joints_mm == plain.spines[0].joints_mm);
    CHECK(sim.stats().iterations - before.stats.iterations == plain_iterations);

    // A limit the path passes: Ipopt stops on the way, with the state as it
    // was before the step and the iterations it spent counted. SLSQP shows no
    // iterates, so its step runs to the end as without a limit. (Ipopt's
    // iterates, observed: the start 0.24 mm from where the tip stuck, as far
    // as the few Gauss-Newton steps of the predicted start put it back; then
    // 0.71, 0.74 ... 0.80 mm, and the stiction re-solve on to 0.83.)
    sim.restore(before);
    sim.step(dragged, t, {0.5 * jump_mm, 0.1});
    const long stopped_iterations = sim.stats().iterations - before.stats.iterations;
    INFO("with a limit of half of it: " << stopped_iterations << " iterations");
    if (ipopt) {
      CHECK(sim.stepStopped());
      CHECK(sim.state().spines[0].joints_mm == before.state.spines[0].joints_mm);
      CHECK(sim.state().step == before.state.step);
      CHECK(sim.stats().steps == before.stats.steps);
      CHECK(sim.stats().jump_stopped_steps == before.stats.jump_stopped_steps + 1);
      CHECK(stopped_iterations > 0);
      CHECK(stopped_iterations < plain_iterations);
      // The step after it is a step as any other.
      sim.step(dragged, t);
      CHECK_FALSE(sim.stepStopped());
      CHECK(sim.state().spines[0].joints_mm == plain.spines[0].joints_mm);
    } else {
      CHECK_FALSE(sim.stepStopped());
      CHECK(sim.state().spines[0].joints_mm == plain.spines[0].joints_mm);
      CHECK(stopped_iterations == plain_iterations);
    }
  }
}

TEST_CASE("a brush held still on the paper comes to rest and stops solving, where a solve "
          "would keep it",
          "[dynamics][settled]") {
  // Pressed, held still, then dragged: A skips the solves of a brush at rest
  // (SimOptions::settled_mm, the default), B solves every step. The round
  // brush's spines are coupled by hair volume and solved as one NLP by Ipopt;
  // the flat's are independent, solved one by one with SLSQP.
  struct Case {
    const char* brush;
    bool ipopt;
  };
  for (const Case c : {Case{"round", true}, Case{"flat", false}}) {
    INFO(c.brush);
    const Brush brush =
        loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + c.brush + ".json");
    auto solver = [&] { return c.ipopt ? makeIpoptSolver() : makeSlsqpSolver(); };
    SimOptions every_step;
    every_step.settled_mm = 0;
    Simulation a(brush, SimOptions{}, solver());
    Simulation b(brush, every_step, solver());
    // The hair is 17-20 mm long: 4 mm past first contact is a firm press.
    double top = 0;
    for (const SpineSpec& s : brush.spines) top = std::max(top, s.lengthMm());
    const Pose above = poseAt(30, 30, top + 1), pressed = poseAt(30, 30, top - 4);
    double ta = 0, tb = 0;
    a.reset(above, 0);
    b.reset(above, 0);
    moveHandle(a, above, pressed, &ta);
    moveHandle(b, above, pressed, &tb);
    int touching = 0;
    for (const SpineState& s : a.state().spines)
      touching += std::count(s.contact.begin(), s.contact.end(), true) > 0;
    REQUIRE(touching == static_cast<int>(brush.spines.size()));

    // Held: once at rest, every later held step keeps the last optimum and
    // solves nothing.
    int first_settled = -1;
    for (int i = 0; i < 300; ++i) {
      const SimStats before = a.stats();
      a.step(pressed, ta += 0.005);
      b.step(pressed, tb += 0.005);
      const bool settled = a.stats().settled_steps > before.settled_steps;
      if (settled && first_settled < 0) first_settled = i;
      if (first_settled >= 0) {
        CHECK(settled);
        CHECK(a.stats().iterations == before.iterations);
        CHECK(a.stats().solved_steps == before.solved_steps);
        for (const SpineState& s : a.state().spines)
          CHECK(std::string(toString(s.summary.status)) == "settled");
      }
    }
    INFO("first settled step of the hold: " << first_settled);
    CHECK(first_settled > 0);
    CHECK(b.stats().settled_steps == 0);
    // Where the solves would have kept it: within Ipopt's own accuracy at
    // tol 1e-8, about 3e-5 mm (engine/dynamics/simulation.h, kSettledMm). Observed:
    // 2.0e-6 and 2.5e-6 mm.
    constexpr double kHeldMm = 3e-5;
    const double held_mm = maxJointDistanceMm(a.state(), b.state());
    INFO("held apart by " << held_mm << " mm");
    CHECK(held_mm < kHeldMm);

    // Dragged again: every moving step solves, and the two stay on the same
    // minima (the acceptance bar, 1e-3 mm, as in the tests above).
    constexpr double kSameMinimumMm = 1e-3;
    double dragged_mm = 0;
    for (int i = 1; i <= 40; ++i) {
      const Pose p = poseAt(30 + 0.1 * i, 30, top - 4);
      const SimStats before = a.stats();
      a.step(p, ta += 0.005);
      b.step(p, tb += 0.005);
      CHECK(a.stats().settled_steps == before.settled_steps);
      CHECK(a.stats().solved_steps == before.solved_steps + 1);
      dragged_mm = std::max(dragged_mm, maxJointDistanceMm(a.state(), b.state()));
    }
    INFO("dragged apart by " << dragged_mm << " mm");
    CHECK(dragged_mm < kSameMinimumMm);
  }
}

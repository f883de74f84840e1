#include "tests/support/press_matrix.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <memory>
#include <numbers>

#include "engine/base/error.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/solvers/spine_solver.h"

namespace bristle::testsupport {

namespace {

std::unique_ptr<SpineSolver> makeSolver(const std::string& name) {
  if (name == "ipopt") return makeIpoptSolver();
  if (name == "slsqp") return makeSlsqpSolver();
  throw Error(ExitCode::kUsage, "unknown solver '" + name + "' (ipopt or slsqp)");
}

// A height well above anything a library brush can reach.
constexpr double kHighMm = 1000;

}  // namespace

Eigen::Quaterniond tiltRotation(double tilt_deg) {
  return Eigen::Quaterniond(
      Eigen::AngleAxisd(tilt_deg * std::numbers::pi / 180, Eigen::Vector3d::UnitY()));
}

double restLowestZMm(const Brush& brush, const Pose& handle) {
  // reset() places the spines at their rest angles and never calls the solver.
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver());
  sim.reset(handle, 0);
  double lowest = std::numeric_limits<double>::infinity();
  for (const SpineState& s : sim.state().spines)
    for (const Eigen::Vector3d& p : s.joints_mm) lowest = std::min(lowest, p.z());
  return lowest;
}

double spineContactHeightMm(const Brush& brush, const Eigen::Quaterniond& tilt) {
  Pose high;
  high.position_mm = Eigen::Vector3d(0, 0, kHighMm);
  high.rotation = tilt;
  return kHighMm - restLowestZMm(brush, high);
}

double hairLengthMm(const Brush& brush) {
  double len = 0;
  for (const SpineSpec& s : brush.spines) len = std::max(len, s.lengthMm());
  return len;
}

const char* toString(CaseKind kind) {
  return kind == CaseKind::kPull ? "pull" : "press_lift";
}

std::string describe(const Case& c) {
  char buf[96];
  if (c.kind == CaseKind::kPull)
    std::snprintf(buf, sizeof buf, "pull f%.2f t%g v%g", c.press_fraction, c.tilt_deg,
                  c.speed_mm_s);
  else
    std::snprintf(buf, sizeof buf, "press_lift f%.2f t%g", c.press_fraction, c.tilt_deg);
  return buf;
}

CaseTrajectory makeCaseTrajectoryDetailed(const Brush& brush, const Case& c) {
  if (!(c.press_fraction >= 0 && c.press_fraction <= 1))
    throw Error(ExitCode::kUsage, "press fraction must be in [0, 1]");
  if (c.kind == CaseKind::kPull && !(c.speed_mm_s > 0))
    throw Error(ExitCode::kUsage, "pull speed must be > 0");
  const Eigen::Quaterniond rot = tiltRotation(c.tilt_deg);
  CaseTrajectory out;
  out.contact_height_mm = spineContactHeightMm(brush, rot);
  out.asked_depth_mm = c.press_fraction * hairLengthMm(brush);
  // The lowest root sits at handle z + min_s (R root_s).z; keep it >= kMinRootZMm.
  double lowest_root = std::numeric_limits<double>::infinity();
  for (const SpineSpec& s : brush.spines)
    lowest_root = std::min(lowest_root, (rot * s.root_mm).z());
  const double min_handle_z = kMinRootZMm - lowest_root;
  const double pressed_z = std::max(out.contact_height_mm - out.asked_depth_mm, min_handle_z);
  out.clamped = pressed_z > out.contact_height_mm - out.asked_depth_mm;
  out.depth_mm = out.contact_height_mm - pressed_z;

  Trajectory& traj = out.trajectory;
  traj.path = describe(c);
  auto add = [&](double t, double x, double z) {
    TrajectorySample smp;
    smp.t_s = t;
    smp.pose.position_mm = Eigen::Vector3d(x, 0, z);
    smp.pose.rotation = rot;
    smp.line = static_cast<int>(traj.samples.size()) + 1;
    traj.samples.push_back(smp);
  };
  const double hover_z = out.contact_height_mm + kHoverMm;
  const double clear_z = out.contact_height_mm + kLiftClearMm;
  double t = 0, x = 0;
  add(t, x, hover_z);
  t += kDescendS;
  add(t, x, pressed_z);
  out.contact_start_s = t;
  if (c.kind == CaseKind::kPull) {
    t += kPullMm / c.speed_mm_s;
    x += kPullMm;
  } else {
    t += kHoldS;
  }
  add(t, x, pressed_z);
  out.contact_end_s = t;
  out.end_x_mm = x;
  t += kLiftS;
  add(t, x, clear_z);
  t += kAirHoldS;
  add(t, x, clear_z);
  return out;
}

Trajectory makeCaseTrajectory(const Brush& brush, const Case& c) {
  return makeCaseTrajectoryDetailed(brush, c).trajectory;
}

CaseResult runCase(const Brush& brush, const Case& c, const std::string& solver,
                   bool fallback) {
  using Clock = std::chrono::steady_clock;
  const CaseTrajectory ct = makeCaseTrajectoryDetailed(brush, c);
  const Trajectory& traj = ct.trajectory;
  validateTrajectoryForBrush(traj, brush);
  const SimOptions options;
  const std::vector<double> times = planStepTimes(traj, brush, options);

  Simulation sim(brush, options, makeSolver(solver),
                 fallback ? makeSolver(solver == "ipopt" ? "slsqp" : "ipopt") : nullptr);
  sim.reset(traj.poseAt(times.front()), times.front());

  CaseResult r;
  r.clamped = ct.clamped;
  r.depth_mm = ct.depth_mm;
  r.step_s.reserve(times.size());
  int run = 0;
  for (size_t i = 1; i < times.size(); ++i) {
    const int failed_before = sim.stats().failed_steps;
    const Pose pose = traj.poseAt(times[i]);
    const Clock::time_point a = Clock::now();
    sim.step(pose, times[i]);
    const Clock::time_point b = Clock::now();
    const double dt = std::chrono::duration<double>(b - a).count();
    r.step_s.push_back(dt);
    r.wall_s += dt;
    for (const SpineState& sp : sim.state().spines)
      r.contact_spine_steps += std::find(sp.contact.begin(), sp.contact.end(), true) !=
                               sp.contact.end();
    if (sim.stats().failed_steps > failed_before) {
      r.longest_failed_run = std::max(r.longest_failed_run, ++run);
    } else {
      run = 0;
    }
  }
  const SimStats& st = sim.stats();
  r.steps = static_cast<int>(r.step_s.size());
  r.failed_steps = st.failed_steps;
  r.failed_spine_solves = st.failed_spine_solves;
  r.fallback_solves = st.fallback_solves;
  r.iterations = st.iterations;
  r.resolves = st.resolves;
  r.split_steps = st.split_steps;
  r.s_per_step = r.steps > 0 ? r.wall_s / r.steps : 0;
  return r;
}

}  // namespace bristle::testsupport

#include "engine/dynamics/stepper.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "engine/base/error.h"
#include "engine/mechanics/spine_kinematics.h"

namespace bristle {

namespace {
// A trajectory in press depths has no ferrule heights until a brush gives them
// (resolveDepths, engine/geometry/first_contact.h): a caller that forgot is a bug.
void requireHeights(const Trajectory& traj) {
  if (traj.needsBrush())
    throw std::logic_error(traj.path + ": depth_mm not resolved for the brush (resolveDepths)");
}
}  // namespace

double rootMotionBoundMm(const Brush& brush, const Pose& a, const Pose& b) {
  double root_radius = 0;
  for (const SpineSpec& s : brush.spines) root_radius = std::max(root_radius, s.root_mm.norm());
  return (b.position_mm - a.position_mm).norm() +
         rotationAngleRad(a.rotation, b.rotation) * root_radius;
}

double rootStepsFor(double moved_mm, const SimOptions& options) {
  return std::max(1.0, std::ceil(moved_mm / options.max_step_mm));
}

double stepsForMotion(double moved_mm, double dt_s, const SimOptions& options) {
  return std::max(rootStepsFor(moved_mm, options), std::ceil(dt_s * options.min_rate_hz - 1e-9));
}

namespace {

std::string stepCountText(double v) {
  std::ostringstream ss;
  ss.precision(v < 1e15 ? 15 : 3);
  ss << v;
  return ss.str();
}

// The steps planned between samples k and k + 1, added to *planned (the
// steps up to sample k); throws when they pass a limit. Counted as doubles,
// before any becomes an integer or a step time.
double segmentSteps(const Trajectory& traj, const Brush& brush, const SimOptions& options,
                    size_t k, double* planned) {
  const TrajectorySample& a = traj.samples[k];
  const TrajectorySample& b = traj.samples[k + 1];
  const double dt = b.t_s - a.t_s;
  const double moved = rootMotionBoundMm(brush, a.pose, b.pose);
  const double n = stepsForMotion(moved, dt, options);
  auto where = [&] {
    return "line " + std::to_string(b.line) + ", column " + std::to_string(traj.t_column) +
           " (t_s)";
  };
  if (!std::isfinite(n) || (n > 1 && n > kMaxStepsPerSecond * dt))
    throw dataError(traj.path, where(),
                    "the " + stepCountText(dt) + " s since the previous sample plan " +
                        stepCountText(n) +
                        " simulation steps, over the limit of 1000000 steps per second of "
                        "gesture (the handle moves " + stepCountText(moved) + " mm)");
  *planned += n;
  if (*planned > kMaxPlannedSteps)
    throw dataError(traj.path, where(),
                    "the trajectory plans " + stepCountText(*planned) +
                        " simulation steps up to here, over the limit of 10000000 per "
                        "trajectory");
  return n;
}

}  // namespace

std::vector<double> planStepTimes(const Trajectory& traj, const Brush& brush,
                                  const SimOptions& options) {
  requireHeights(traj);
  std::vector<double> times{traj.samples.front().t_s};
  double planned = 1;
  for (size_t k = 0; k + 1 < traj.samples.size(); ++k) {
    const int steps = static_cast<int>(segmentSteps(traj, brush, options, k, &planned));
    const double t0 = traj.samples[k].t_s, dt = traj.samples[k + 1].t_s - t0;
    for (int i = 1; i < steps; ++i) times.push_back(t0 + dt * i / steps);
    times.push_back(traj.samples[k + 1].t_s);
  }
  return times;
}

double plannedStepCount(const Trajectory& traj, const Brush& brush, const SimOptions& options) {
  requireHeights(traj);
  double planned = 1;
  for (size_t k = 0; k + 1 < traj.samples.size(); ++k)
    segmentSteps(traj, brush, options, k, &planned);
  return planned;
}

void validateTrajectoryForBrush(const Trajectory& traj, const Brush& brush) {
  requireHeights(traj);
  auto fmt = [](double v) {
    std::ostringstream ss;
    ss.precision(4);
    ss << v;
    return ss.str();
  };
  for (const TrajectorySample& smp : traj.samples) {
    for (size_t s = 0; s < brush.spines.size(); ++s) {
      const double z = smp.pose.apply(brush.spines[s].root_mm).z();
      if (z < 0)
        throw dataError(traj.path, "line " + std::to_string(smp.line),
                        "the ferrule goes below the canvas (spine " + std::to_string(s) +
                            " root at z = " + fmt(z) + " mm); z must stay >= 0" +
                            (traj.depth_column != 0
                                 ? " (depth_mm = " + fmt(smp.depth_mm) + " presses '" +
                                       brush.name + "' too deep)"
                                 : std::string()));
    }
  }
  // The simulation starts from the rest shape: it must not start pressed in.
  // The message names the lowest joint, the one to raise the start past.
  const TrajectorySample& first = traj.samples.front();
  SpineFk fk;
  double lowest_z = 0;
  size_t lowest_spine = 0;
  int lowest_joint = 0;
  for (size_t s = 0; s < brush.spines.size(); ++s) {
    const SpineSpec& spec = brush.spines[s];
    std::vector<double> q(2 * spec.jointCount());
    for (int k = 0; k < spec.jointCount(); ++k) {
      q[2 * k] = spec.rest_angles_rad[k][0];
      q[2 * k + 1] = spec.rest_angles_rad[k][1];
    }
    spineForwardKinematics(spec, first.pose, q.data(), 0, &fk);
    for (int j = 1; j <= spec.jointCount(); ++j)
      if (fk.x[j].z() < lowest_z) {
        lowest_z = fk.x[j].z();
        lowest_spine = s;
        lowest_joint = j;
      }
  }
  if (lowest_z < 0)
    throw dataError(traj.path, "line " + std::to_string(first.line),
                    "the brush starts below the canvas (spine " + std::to_string(lowest_spine) +
                        " joint " + std::to_string(lowest_joint) + " at z = " + fmt(lowest_z) +
                        " mm at rest, its lowest); start the trajectory with the hairs above z = 0" +
                        (traj.depth_column != 0
                             ? " (a negative depth_mm, here " + fmt(first.depth_mm) + ")"
                             : std::string()));
}


double contactJumpMm(const Brush& brush, const BrushState& a, const BrushState& b,
                     double contact_band_mm) {
  double jump = 0;
  for (size_t s = 0; s < brush.spines.size(); ++s)
    jump = std::max(jump, contactJumpMm(brush.spines[s], a.spines[s].joints_mm,
                                        b.spines[s].joints_mm, contact_band_mm));
  return jump;
}

namespace {

// At most this many planned steps are taken as one steady step.
constexpr int kMaxSteadyGroup = 8;
constexpr int kMaxSteadyBackoff = 16;

// A step taken over several planned steps is kept when the brush did nothing
// the planned steps would resolve differently: no joint touched down or lifted,
// none switched between sticking and sliding, no solve failed, and the part on
// the paper jumped no further than a steady step.
bool steadyStep(const Simulation::Snapshot& before, const Simulation& sim, double max_jump_mm,
                double contact_band_mm) {
  const SimStats& a = before.stats;
  const SimStats& b = sim.stats();
  if (b.failed_spine_solves != a.failed_spine_solves || b.split_steps != a.split_steps ||
      b.fallback_solves != a.fallback_solves)
    return false;
  const BrushState& s0 = before.state;
  const BrushState& s1 = sim.state();
  for (size_t s = 0; s < s0.spines.size(); ++s)
    if (s0.spines[s].contact != s1.spines[s].contact || s0.spines[s].sliding != s1.spines[s].sliding)
      return false;
  return contactJumpMm(sim.brush(), s0, s1, contact_band_mm) <= max_jump_mm;
}

// Splitting stops after this many halvings (a step split into at most 32).
constexpr int kMaxJumpSplitDepth = 5;

// How far the part of the brush on the paper may move in one step: twice
// --max-step-mm (the most a spine root moves in a planned step), or 2 px of
// the canvas if that is further. A step that moved it further is redone in
// halves. Between two kept states the sweep stamps the hair along straight
// lines, one stamp per pixel, so the limit is the chord over which a tip's
// path is drawn straight: at the defaults (0.25 mm, 8 px/mm) 0.5 mm, over
// which a tip curling on a 2 mm radius strays from its arc by
// c^2 / 8R = 0.016 mm, a tenth of a pixel. A tighter limit redoes far more
// steps for no visible gain (docs/PERFORMANCE.md, "How far a step may move
// the hair"). A smaller --max-step-mm still refines the steps' contact.
constexpr double kJumpPerRootStep = 2;
constexpr double kJumpFloorPx = 2;

}  // namespace

Stepper::Stepper(Simulation& sim, const WalkOptions& options) : sim_(sim), options_(options) {}

// Steps from t0 to t1, halving the step while the touching part jumps too far.
void Stepper::advance(const Trajectory& trajectory, double t0, double t1, int depth) {
  if (stopped_) return;
  const Simulation::Snapshot before = sim_.snapshot();
  // A try that is going to be redone is given up as soon as it shows it.
  const bool may_split = depth < kMaxJumpSplitDepth;
  Simulation::JumpLimit watch;
  if (may_split) watch = {options_.stop_on_jump * max_jump_mm_, options_.contact_band_mm};
  sim_.step(trajectory.poseAt(t1), t1, watch);
  if (may_split && (sim_.stepStopped() || contactJumpMm(sim_.brush(), before.state, sim_.state(),
                                                        options_.contact_band_mm) > max_jump_mm_)) {
    // The first try's solves were done: their iterations stay counted.
    const SimStats tried = sim_.stats();
    sim_.restore(before);
    sim_.countJumpSplit(before.stats, tried);
    const double tm = 0.5 * (t0 + t1);
    advance(trajectory, t0, tm, depth + 1);
    advance(trajectory, tm, t1, depth + 1);
    return;
  }
  if (t1 > stop_t_s_) {  // the render goes on; a preview stops before this step
    sim_.restore(before);
    stopped_ = true;
    return;
  }
  keep();
}

void Stepper::keep() {
  if (*on_step_) (*on_step_)(sim_.state(), planned_, static_cast<int>(times_.size()));
}

// Steady steps: where the brush is steady, several planned steps are taken
// as one (docs/dynamics.md, "Steady steps"). Merges start at 2 planned
// steps and double while kept; after one is redone, the next tries wait 1,
// 2, 4 ... kMaxSteadyBackoff planned steps.
bool Stepper::tryMerged(const Trajectory& trajectory) {
  const double steady_mm = options_.sim.steady_step_mm;
  const int steps = static_cast<int>(times_.size());
  // The longest run of planned steps from planned - 1 whose handle path stays
  // within steady_mm, at most `group` of them.
  double path = 0;
  int k = 0;
  while (k < group_ && planned_ + k < steps) {
    const double m = rootMotionBoundMm(sim_.brush(), trajectory.poseAt(times_[planned_ + k - 1]),
                                       trajectory.poseAt(times_[planned_ + k]));
    if (path + m > steady_mm) break;
    path += m;
    ++k;
  }
  if (k < 2 || hold_ > 0) {
    hold_ = std::max(hold_ - 1, 0);
    return false;
  }
  const double t1 = times_[planned_ + k - 1];
  if (t1 > stop_t_s_) return false;
  const Simulation::Snapshot before = sim_.snapshot();
  sim_.step(trajectory.poseAt(t1), t1);
  const double steady_jump_mm = std::max(steady_mm, 2.0 / options_.px_per_mm);
  if (!steadyStep(before, sim_, steady_jump_mm, options_.contact_band_mm)) {
    const SimStats tried = sim_.stats();
    sim_.restore(before);
    sim_.countRejectedSteady(before.stats, tried);
    group_ = 2;
    hold_ = backoff_;
    backoff_ = std::min(2 * backoff_, kMaxSteadyBackoff);
    return false;
  }
  sim_.countSteady(k);
  planned_ += k - 1;
  group_ = std::min(2 * group_, kMaxSteadyGroup);
  backoff_ = 1;
  keep();
  return true;
}

void Stepper::walk(const Trajectory& trajectory, const StepCallback& on_step, double stop_t_s) {
  times_ = planStepTimes(trajectory, sim_.brush(), options_.sim);
  on_step_ = &on_step;
  stop_t_s_ = stop_t_s;
  max_jump_mm_ = std::max(kJumpPerRootStep * options_.sim.max_step_mm,
                          kJumpFloorPx / options_.px_per_mm);
  stopped_ = false;
  group_ = 2;
  backoff_ = 1;
  hold_ = 0;
  const int steps = static_cast<int>(times_.size());
  sim_.reset(trajectory.poseAt(times_.front()), times_.front());
  planned_ = 0;
  keep();
  const bool merge = options_.sim.steady_step_mm > options_.sim.max_step_mm;
  for (planned_ = 1; planned_ < steps && !stopped_; ++planned_) {
    if (merge && tryMerged(trajectory)) continue;
    advance(trajectory, times_[planned_ - 1], times_[planned_], 0);
  }
  on_step_ = nullptr;
}

void Stepper::stepTo(const Pose& handle, double t_s) {
  const Pose from = sim_.state().handle;
  const double t0 = sim_.state().t_s;
  if (t_s <= t0) return;
  const double dt = t_s - t0;
  const double planned = rootStepsFor(rootMotionBoundMm(sim_.brush(), from, handle), options_.sim);
  const int n = static_cast<int>(std::min(planned, std::max(1.0, kMaxStepsPerSecond * dt)));
  for (int i = 1; i <= n; ++i)
    sim_.step(interpolatePose(from, handle, double(i) / n), t0 + dt * i / n);
}

}  // namespace bristle

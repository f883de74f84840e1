#include "engine/simulation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/error.h"
#include "engine/smooth.h"

namespace bristle {

bool BrushState::anyContact() const {
  for (const SpineState& s : spines)
    for (bool c : s.contact)
      if (c) return true;
  return false;
}

Simulation::Simulation(const Brush& brush, const SimOptions& options,
                       std::unique_ptr<SpineSolver> solver)
    : brush_(brush), options_(options), solver_(std::move(solver)) {}

void Simulation::reset(const Pose& handle, double t_s) {
  state_ = BrushState{};
  state_.t_s = t_s;
  state_.handle = handle;
  state_.spines.resize(brush_.spines.size());
  for (size_t s = 0; s < brush_.spines.size(); ++s) {
    const SpineSpec& spec = brush_.spines[s];
    const int n = spec.jointCount();
    SpineState& st = state_.spines[s];
    st.solution.q.resize(2 * n);
    for (int k = 0; k < n; ++k) {
      st.solution.q[2 * k] = spec.rest_angles_rad[k][0];
      st.solution.q[2 * k + 1] = spec.rest_angles_rad[k][1];
    }
    st.solution.normal_force_n.assign(n, 0.0);
    st.summary.status = SolveStatus::kFree;
    SpineProblem rest;
    rest.spine = &spec;
    rest.handle = handle;
    rest.friction_n.assign(n, 0.0);
    rest.anchor_xy_mm.assign(n, Eigen::Vector2d::Zero());
    rest.prev_bend_rad.assign(n, 0.0);
    finishSpine(static_cast<int>(s), rest);
  }
  stats_ = SimStats{};
}

const BrushState& Simulation::step(const Pose& handle, double t_s) {
  const size_t ns = brush_.spines.size();
  std::vector<SpineProblem> problems(ns);
  std::vector<const SpineProblem*> to_solve;
  std::vector<SpineSolution*> solutions;
  std::vector<SpineSolution> trial(ns);
  std::vector<int> which;

  for (size_t s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush_.spines[s];
    const SpineState& prev = state_.spines[s];
    const int n = spec.jointCount();
    SpineProblem& p = problems[s];
    p.spine = &spec;
    p.handle = handle;
    p.friction_n.assign(n, 0.0);
    p.anchor_xy_mm.resize(n);
    p.prev_bend_rad = prev.bend_rad;
    bool touching = false;
    for (int j = 0; j < n; ++j) {
      p.anchor_xy_mm[j] = prev.joints_mm[j + 1].head<2>();
      if (prev.contact[j]) {
        touching = true;
        // eq. 3: |F_n| of the previous step, held constant during this solve.
        const double mu = prev.sliding[j] ? brush_.friction.mu_kinetic : brush_.friction.mu_static;
        p.friction_n[j] = mu * prev.solution.normal_force_n[j];
      }
    }
    // Step 2 of §3.1: the spine moves rigidly with the handle. If it then touches
    // nothing and did not touch before, its previous angles remain the optimum
    // (spring and damping alone, nothing pushes it), so no solve is needed.
    spineForwardKinematics(spec, handle, prev.solution.q.data(), 0, &fk_);
    bool clear = !touching;
    for (int j = 1; j <= n && clear; ++j) clear = fk_.x[j].z() > 0;
    trial[s] = prev.solution;
    if (!clear) {
      to_solve.push_back(&p);
      solutions.push_back(&trial[s]);
      which.push_back(static_cast<int>(s));
    }
  }

  SolveSummary summary;
  summary.status = SolveStatus::kFree;
  if (!to_solve.empty()) {
    ++stats_.solved_steps;
    summary = solver_->solve(to_solve, solutions);
    stats_.iterations += summary.iterations;
    if (!summary.usable() && to_solve.size() > 1) {
      // Isolate the failure: solve each spine on its own from a cold start.
      for (size_t i = 0; i < to_solve.size(); ++i) {
        SpineSolution cold = state_.spines[which[i]].solution;
        cold.lambda.clear();
        SpineSolution* one = &cold;
        const SpineProblem* pone = to_solve[i];
        SolveSummary si = solver_->solve({&pone, 1}, {&one, 1});
        stats_.iterations += si.iterations;
        if (si.usable()) trial[which[i]] = std::move(cold);
        state_.spines[which[i]].summary = si;
      }
    } else if (!summary.usable()) {
      SpineSolution cold = state_.spines[which[0]].solution;
      cold.lambda.clear();
      SpineSolution* one = &cold;
      SolveSummary si = solver_->solve(to_solve, {&one, 1});
      stats_.iterations += si.iterations;
      if (si.usable()) trial[which[0]] = std::move(cold);
      state_.spines[which[0]].summary = si;
    } else {
      for (int s : which) state_.spines[s].summary = summary;
    }
  }

  bool step_failed = false;
  for (size_t s = 0; s < ns; ++s) {
    SpineState& st = state_.spines[s];
    const bool solved = std::find(which.begin(), which.end(), int(s)) != which.end();
    if (!solved) st.summary = SolveSummary{SolveStatus::kFree, 0, ""};
    if (solved && !st.summary.usable()) {
      // Keep the last good angles (carried rigidly with the handle); report it.
      ++stats_.failed_spine_solves;
      step_failed = true;
    } else {
      st.solution = std::move(trial[s]);
    }
    finishSpine(static_cast<int>(s), problems[s]);
  }
  if (step_failed) ++stats_.failed_steps;

  state_.handle = handle;
  state_.t_s = t_s;
  ++state_.step;
  ++stats_.steps;

  // Force of the canvas on the brush (and so, through it, on the handle):
  // normal forces plus the friction forces -dE_f/dx on contact joints.
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (size_t s = 0; s < ns; ++s) {
    const SpineState& st = state_.spines[s];
    const SpineProblem& p = problems[s];
    for (size_t j = 0; j < st.contact.size(); ++j) {
      if (st.contact[j]) f.z() += st.solution.normal_force_n[j];
      if (p.friction_n[j] > 0) {
        const Eigen::Vector2d d = st.joints_mm[j + 1].head<2>() - p.anchor_xy_mm[j];
        f.head<2>() -= p.friction_n[j] * smoothNorm(d, p.eps_mm).grad;
      }
    }
  }
  state_.force_n = f;
  return state_;
}

void Simulation::finishSpine(int s, const SpineProblem& problem) {
  const SpineSpec& spec = brush_.spines[s];
  SpineState& st = state_.spines[s];
  const int n = spec.jointCount();
  spineEnergy(problem, st.solution.q.data(), &fk_, &st.energy, nullptr, nullptr);
  st.joints_mm = fk_.x;
  st.contact.assign(n, false);
  st.sliding.assign(n, false);
  st.bend_rad.resize(n);
  st.solution.normal_force_n.resize(n, 0.0);
  for (int j = 0; j < n; ++j) {
    st.bend_rad[j] = smoothedBendRad(spec, j, st.solution.q.data(), problem.eps_rad);
    const double fn = st.solution.normal_force_n[j];
    st.contact[j] = fn > options_.contact_threshold_n;
    if (!st.contact[j]) st.solution.normal_force_n[j] = 0.0;
    if (problem.friction_n[j] > 0) {
      const double moved = (st.joints_mm[j + 1].head<2>() - problem.anchor_xy_mm[j]).norm();
      st.sliding[j] = moved > options_.slide_threshold_mm;
    }
  }
}

std::vector<double> planStepTimes(const Trajectory& traj, const Brush& brush,
                                  const SimOptions& options) {
  double root_radius = 0;
  for (const SpineSpec& s : brush.spines) root_radius = std::max(root_radius, s.root_mm.norm());
  std::vector<double> times{traj.samples.front().t_s};
  for (size_t k = 0; k + 1 < traj.samples.size(); ++k) {
    const TrajectorySample& a = traj.samples[k];
    const TrajectorySample& b = traj.samples[k + 1];
    const double dt = b.t_s - a.t_s;
    const double moved = (b.pose.position_mm - a.pose.position_mm).norm() +
                         rotationAngleRad(a.pose.rotation, b.pose.rotation) * root_radius;
    const double n = std::max({1.0, std::ceil(moved / options.max_step_mm),
                               std::ceil(dt * options.min_rate_hz - 1e-9)});
    const int steps = static_cast<int>(n);
    for (int i = 1; i < steps; ++i) times.push_back(a.t_s + dt * i / steps);
    times.push_back(b.t_s);
  }
  return times;
}

void validateTrajectoryForBrush(const Trajectory& traj, const Brush& brush) {
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
                            " root at z = " + fmt(z) + " mm); z must stay >= 0");
    }
  }
  // The simulation starts from the rest shape: it must not start pressed in.
  const TrajectorySample& first = traj.samples.front();
  SpineFk fk;
  for (size_t s = 0; s < brush.spines.size(); ++s) {
    const SpineSpec& spec = brush.spines[s];
    std::vector<double> q(2 * spec.jointCount());
    for (int k = 0; k < spec.jointCount(); ++k) {
      q[2 * k] = spec.rest_angles_rad[k][0];
      q[2 * k + 1] = spec.rest_angles_rad[k][1];
    }
    spineForwardKinematics(spec, first.pose, q.data(), 0, &fk);
    for (int j = 1; j <= spec.jointCount(); ++j)
      if (fk.x[j].z() < 0)
        throw dataError(traj.path, "line " + std::to_string(first.line),
                        "the brush starts below the canvas (spine " + std::to_string(s) +
                            " joint " + std::to_string(j) + " at z = " + fmt(fk.x[j].z()) +
                            " mm at rest); start the trajectory with the hairs above z = 0");
  }
}

}  // namespace bristle

#include "bristle/simulation.h"

#include <cmath>
#include <memory>
#include <string>

#include "api/model.h"
#include "engine/dynamics/simulation.h"
#include "engine/solvers/solver_pair.h"

namespace bristle::api {

namespace {

[[noreturn]] void badPose(const std::string& rule) {
  throw api::Error(ErrorCategory::kUsage, "Simulation::step: " + rule);
}

// A pose as the trajectory reader takes one (engine/model/trajectory.cpp's limits).
bristle::Pose enginePose(const Pose& p) {
  for (double v : p.xyz_mm)
    if (!std::isfinite(v) || std::fabs(v) > kMaxPositionMm)
      badPose("ferrule.xyz_mm: must be finite and within +-100000 mm");
  for (double c : p.quaternion_wxyz)
    if (!std::isfinite(c) || std::fabs(c) > kMaxQuaternionComponent)
      badPose("ferrule.quaternion_wxyz: must be finite and within +-1e6");
  const Eigen::Quaterniond q(p.quaternion_wxyz[0], p.quaternion_wxyz[1], p.quaternion_wxyz[2],
                             p.quaternion_wxyz[3]);
  if (q.norm() < 1e-6) badPose("ferrule.quaternion_wxyz: has near-zero norm");
  bristle::Pose pose;
  pose.position_mm = Eigen::Vector3d(p.xyz_mm[0], p.xyz_mm[1], p.xyz_mm[2]);
  pose.rotation = q.normalized();
  return pose;
}

std::array<double, 3> array3(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

struct Simulation::Impl {
  // The engine's simulation and solvers refer to the brush's model: this copy
  // keeps it alive however long the caller keeps its Brush (a temporary, as
  // in `Simulation sim(Brush::load("round"))`).
  Brush brush;
  std::unique_ptr<bristle::Simulation> sim;
  bool started = false;
  StepResult result;

  void copyState() {
    const BrushState& st = sim->state();
    result.t_s = st.t_s;
    result.force_n = array3(st.force_n);
    result.contact_joints = 0;
    result.spines.resize(st.spines.size());
    for (size_t s = 0; s < st.spines.size(); ++s) {
      const bristle::SpineState& from = st.spines[s];
      SpineState& to = result.spines[s];
      to.joints_mm.clear();
      for (const Eigen::Vector3d& j : from.joints_mm) to.joints_mm.push_back(array3(j));
      to.contact = from.contact;
      to.force_n = array3(from.force_n);
      to.solved = from.summary.usable();
      for (const bool c : from.contact) result.contact_joints += c ? 1 : 0;
    }
  }
};

namespace {

std::unique_ptr<bristle::Simulation> makeSimulation(const Brush& brush, Solver solver,
                                                    int max_iterations) {
  if (max_iterations < 1 || max_iterations > 100000)
    throw api::Error(ErrorCategory::kUsage,
                     "Simulation: solver_max_iterations " + std::to_string(max_iterations) +
                         ": must be in [1, 100000]");
  SolverSettings settings;
  settings.kind = solver == Solver::kSlsqp ? SolverKind::kSlsqp : SolverKind::kIpopt;
  settings.max_iterations = max_iterations;
  SolverPair pair = makeSolverPair(settings, brush.model().brush);
  return std::make_unique<bristle::Simulation>(brush.model().brush, SimOptions{},
                                               std::move(pair.primary), std::move(pair.fallback));
}

}  // namespace

Simulation::Simulation(const Brush& brush, Solver solver, int solver_max_iterations) {
  translateErrors([&] {
    auto impl = std::unique_ptr<Impl>(new Impl{brush, nullptr, false, {}});
    impl->sim = makeSimulation(impl->brush, solver, solver_max_iterations);
    impl_ = std::move(impl);
  });
}

Simulation::~Simulation() = default;
Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;

void Simulation::reset(const Pose& ferrule, double t_s) {
  translateErrors([&] {
    if (!std::isfinite(t_s) || std::fabs(t_s) > kMaxTimeS)
      badPose("t_s: must be finite and within +-1e9 s");
    impl_->sim->reset(enginePose(ferrule), t_s);
    impl_->started = true;
    impl_->copyState();
  });
}

const StepResult& Simulation::step(const Pose& ferrule, double t_s) {
  return translateErrors([&]() -> const StepResult& {
    const bristle::Pose pose = enginePose(ferrule);
    if (!std::isfinite(t_s) || std::fabs(t_s) > kMaxTimeS)
      badPose("t_s: must be finite and within +-1e9 s");
    if (!impl_->started) {
      impl_->sim->reset(pose, t_s);
      impl_->started = true;
    } else if (!(t_s > impl_->sim->state().t_s)) {
      badPose("t_s = " + std::to_string(t_s) + ": must be after the last step's " +
              std::to_string(impl_->sim->state().t_s) + " s");
    }
    if (impl_->sim->state().t_s < t_s) impl_->sim->step(pose, t_s);
    impl_->copyState();
    return impl_->result;
  });
}

const StepResult& Simulation::state() const { return impl_->result; }

}  // namespace bristle::api

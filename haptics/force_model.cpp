#include "haptics/force_model.h"

#include <algorithm>
#include <cmath>

namespace bristle::haptics {

namespace {

void store(const Eigen::Matrix3d& m, double* out) {
  Eigen::Map<Eigen::Matrix3d> dst(out);
  dst = m;
}

// Unit chord of a spine: root to its first joint on the canvas, else the tip.
Eigen::Vector3d chordOf(const SpineState& st) {
  size_t end = st.joints_mm.size() - 1;
  for (size_t j = 0; j < st.contact.size(); ++j)
    if (st.contact[j]) {
      end = j + 1;
      break;
    }
  const Eigen::Vector3d c = st.joints_mm[end] - st.joints_mm.front();
  if (c.norm() < 1e-12) return -Eigen::Vector3d::UnitZ();
  return c.normalized();
}

}  // namespace

Eigen::Matrix3d ForceModel::matrix(const double* m) const {
  return Eigen::Map<const Eigen::Matrix3d>(m);
}

Eigen::Vector3d ForceModel::compressTerm(const Eigen::Vector3d& dp) const {
  const Eigen::Matrix3d b = matrix(basis);
  const double a = b.col(0).dot(dp);
  return matrix(a > 0 ? response_pos : response_neg).col(0) * a;
}

Eigen::Vector3d ForceModel::bendTerm(const Eigen::Vector3d& dp) const {
  const Eigen::Matrix3d b = matrix(basis);
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int k = 1; k < 3; ++k) {
    const double a = b.col(k).dot(dp);
    f += matrix(a > 0 ? response_pos : response_neg).col(k) * a;
  }
  return f;
}

Eigen::Vector3d ForceModel::expansion(const Eigen::Vector3d& p_mm) const {
  if (!valid) return Eigen::Vector3d::Zero();
  Eigen::Vector3d dp = p_mm - p0();
  const double d = dp.norm();
  if (d > radius_mm) dp *= radius_mm / d;
  return f0() + compressTerm(dp) + bendTerm(dp);  // eqs. 21-22
}

Eigen::Vector3d ForceModel::evaluate(const Eigen::Vector3d& p_mm) const {
  return limitToContactCone(expansion(p_mm), cone_mu);
}

Eigen::Vector3d limitToContactCone(const Eigen::Vector3d& f, double mu) {
  const double n = std::max(f.z(), 0.0);
  const double t = std::hypot(f.x(), f.y());
  const double scale = t > mu * n ? mu * n / t : 1.0;  // t > 0 whenever it is < 1
  return Eigen::Vector3d(f.x() * scale, f.y() * scale, n);
}

// An orthonormal basis whose first vector is u.
Eigen::Matrix3d basisAlong(const Eigen::Vector3d& u) {
  const Eigen::Vector3d helper =
      std::fabs(u.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d v = (helper - helper.dot(u) * u).normalized();
  Eigen::Matrix3d b;
  b << u, v, u.cross(v);
  return b;
}

std::vector<SpineForceModel> spineForceModels(Simulation* sim, const ForceModelOptions& options) {
  const Simulation::Snapshot base = sim->snapshot();
  const BrushState& st0 = base.state;
  const size_t ns = st0.spines.size();
  std::vector<SpineForceModel> models(ns);
  Eigen::Vector3d mean_chord = Eigen::Vector3d::Zero();
  for (size_t s = 0; s < ns; ++s) {
    models[s].f0_n = st0.spines[s].force_n;
    models[s].chord = chordOf(st0.spines[s]);
    mean_chord += models[s].chord;
  }
  const Eigen::Matrix3d basis =
      basisAlong(mean_chord.norm() > 1e-9 ? Eigen::Vector3d(mean_chord.normalized())
                                          : Eigen::Vector3d(-Eigen::Vector3d::UnitZ()));
  const double h = options.probe_mm;
  for (int k = 0; k < 3; ++k) {
    for (int sign : {+1, -1}) {
      Pose p = st0.handle;
      p.position_mm += sign * h * basis.col(k);
      const BrushState& st = sim->step(p, st0.t_s);
      for (size_t s = 0; s < ns; ++s) {
        const Eigen::Vector3d slope = sign * (st.spines[s].force_n - models[s].f0_n) / h;
        (sign > 0 ? models[s].response_pos : models[s].response_neg).col(k) = slope;
      }
      sim->restore(base);
    }
  }
  for (SpineForceModel& m : models) m.basis = basis;
  return models;
}

ForceModel averageForceModel(const std::vector<SpineForceModel>& spines, const Pose& handle,
                             double sim_t_s, std::uint64_t frame, double radius_mm,
                             double mu_static) {
  ForceModel m;
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rp = Eigen::Matrix3d::Zero(), rn = rp;
  for (const SpineForceModel& s : spines) {
    f0 += s.f0_n;
    rp += s.response_pos;
    rn += s.response_neg;
  }
  if (!spines.empty()) {
    const double inv = 1.0 / static_cast<double>(spines.size());  // §5: the average
    f0 *= inv;
    rp *= inv;
    rn *= inv;
    store(spines.front().basis, m.basis);
  }
  for (int i = 0; i < 3; ++i) {
    m.p0_mm[i] = handle.position_mm[i];
    m.f0_n[i] = f0[i];
  }
  store(rp, m.response_pos);
  store(rn, m.response_neg);
  m.radius_mm = radius_mm;
  const double f0_t = std::hypot(f0.x(), f0.y());
  m.cone_mu = f0.z() > 0 ? std::max(mu_static, f0_t / f0.z()) : mu_static;
  m.sim_t_s = sim_t_s;
  m.frame = frame;
  m.valid = f0.allFinite() && rp.allFinite() && rn.allFinite();
  return m;
}

ForceModel buildForceModel(Simulation* sim, std::uint64_t frame, const ForceModelOptions& options) {
  const std::vector<SpineForceModel> spines = spineForceModels(sim, options);
  return averageForceModel(spines, sim->state().handle, sim->state().t_s, frame,
                           options.radius_mm, sim->brush().friction.mu_static);
}

}  // namespace bristle::haptics

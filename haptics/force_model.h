#pragma once
// The local force model of paper §5 (eqs. 21-22). The simulation runs at
// 30-60 Hz; the device's servo loop at 1 kHz. Instead of one force sample per
// sim frame, the sim thread sends a first-order expansion of the force about
// the handle position p0 of its latest state:
//   F(p0 + dp) = F0 + F_compress(dp) + F_bend(dp)                  (eqs. 21-22)
// one per spine, averaged over the spines (§5: "use the average as the force").
//
// Per spine, F0 is the canvas force on the spine in the simulated state
// (contact normal forces plus friction, engine/dynamics/simulation.h). The linear terms
// are measured on the quasi-static solve itself: the engine's energy
// minimisation stepped from the current state to p0 +- h b_k and restored,
// along a basis b whose first vector u is the brush's chord -- the mean over
// spines of root -> first joint on the canvas (else the tip), the direction in
// which the spines are bent -- and two directions across it:
//   F_compress(dp) = C(u . dp)                   motion along the bent spines
//   F_bend(dp)     = B_v(v . dp) + B_w(w . dp)   motion across them
// Each coefficient is one-sided: C(a) = C+ a for a > 0 and C- a for a < 0.
// With stiction (§3.4.1) and joint friction (§3.5) the brush has a kink at
// dp = 0: a pressed round pushed 0.05 mm further into the paper pushes back
// ~1 N/mm more, lifted 0.05 mm its force barely changes (the joints hold their
// bend), and a central slope would split the difference, wrong both ways.
// The paper gives no closed form for the coefficients; measuring them on the
// solver keeps the model the simulation's own, in newtons, with no scaling (§5).

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "engine/dynamics/simulation.h"

namespace bristle::haptics {

// Trivially copyable (it crosses threads through a seqlock): plain arrays.
struct ForceModel {
  double p0_mm[3] = {0, 0, 0};
  double f0_n[3] = {0, 0, 0};
  // Column-major: basis columns u, v, w (unit, world); response columns
  // dF/d(b_k . dp) in N/mm for b_k . dp > 0 (pos) and < 0 (neg). Column 0 is
  // the compression coefficient, columns 1-2 the bending ones.
  double basis[9] = {0, 0, -1, 1, 0, 0, 0, 1, 0};
  double response_pos[9] = {}, response_neg[9] = {};
  // Beyond this distance from p0 the expansion is not trusted: dp is clamped.
  double radius_mm = 1.0;
  // The paper can only push: the force it exerts through the brush lies in
  // the cone |F_tangential| <= cone_mu * F_normal about the canvas normal +z
  // (unilateral contact with Coulomb friction, §3.4). The brush's mu_static,
  // widened when the simulated F0 itself leans further (a step's friction
  // uses the normal force of the step before), so that F0 is always inside.
  double cone_mu = 0;
  double sim_t_s = 0;       // simulation time of the state it expands about
  std::uint64_t frame = 0;  // sim frame counter, 0 = no model yet
  bool valid = false;

  // eqs. 21-22 at the stylus position p (mm), projected onto the contact
  // cone: the force on the handle in N. A linear expansion extrapolated to a
  // lifted stylus would otherwise pull the pen into the paper.
  Eigen::Vector3d evaluate(const Eigen::Vector3d& p_mm) const;
  // eqs. 21-22 alone, unprojected.
  Eigen::Vector3d expansion(const Eigen::Vector3d& p_mm) const;
  Eigen::Vector3d f0() const { return Eigen::Vector3d(f0_n[0], f0_n[1], f0_n[2]); }
  Eigen::Vector3d p0() const { return Eigen::Vector3d(p0_mm[0], p0_mm[1], p0_mm[2]); }
  // F_compress(dp), F_bend(dp) of eq. 22 (dp already clamped to radius_mm).
  Eigen::Vector3d compressTerm(const Eigen::Vector3d& dp_mm) const;
  Eigen::Vector3d bendTerm(const Eigen::Vector3d& dp_mm) const;
  Eigen::Matrix3d matrix(const double* m) const;
};

// One spine's expansion (eq. 21 for spine s).
struct SpineForceModel {
  Eigen::Vector3d f0_n = Eigen::Vector3d::Zero();
  Eigen::Matrix3d basis = Eigen::Matrix3d::Identity();         // shared by all spines
  Eigen::Matrix3d response_pos = Eigen::Matrix3d::Zero();  // see ForceModel
  Eigen::Matrix3d response_neg = Eigen::Matrix3d::Zero();
  Eigen::Vector3d chord = Eigen::Vector3d::UnitZ();  // unit, root -> contact or tip
};

struct ForceModelOptions {
  // One-sided difference step of the handle. Large against the solver's joint
  // accuracy (~3e-5 mm, docs/design.md, "Solver notes") so the difference is not round-off,
  // small against a segment (3.5-6 mm) so the spine stays near-linear.
  double probe_mm = 0.05;
  double radius_mm = 1.0;  // see ForceModel::radius_mm
};

// Builds the per-spine models at the simulation's current state. The
// simulation is stepped to the probe poses and restored: on return it is
// exactly as before (state and stats).
std::vector<SpineForceModel> spineForceModels(Simulation* sim, const ForceModelOptions& options);

// f limited to the cone |f_xy| <= mu f_z as the contact's own rules limit it:
// the normal part cannot pull (it is clamped at zero), and friction cannot
// exceed mu times the normal part (the tangential part is shortened, its
// direction kept). So no force appears that the expansion did not predict,
// and the map is continuous in f: the device feels no step at the cone.
Eigen::Vector3d limitToContactCone(const Eigen::Vector3d& f, double mu);

// The average of the per-spine models (§5), expanded about the current handle;
// mu_static is the brush's (ForceModel::cone_mu).
ForceModel averageForceModel(const std::vector<SpineForceModel>& spines, const Pose& handle,
                             double sim_t_s, std::uint64_t frame, double radius_mm,
                             double mu_static);

// Both in one: what the sim thread sends the servo loop every frame.
ForceModel buildForceModel(Simulation* sim, std::uint64_t frame, const ForceModelOptions& options);

}  // namespace bristle::haptics

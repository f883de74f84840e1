#pragma once
// The energy one spine minimises at every step (paper eq. 1):
//   E = E_s + E_f + E_d
//   E_s = sum_i K_i beta_i^2 / 2                            (eqs. 2, 12)
//   E_f = sum_i (1 - eta_i) mu F_n,i |dx_c,i|               (eqs. 3, 13-14)
//   E_d = sum_i D_i |d beta_i|                              (eq. 4)
//   E_v = sum_c k psi(min_c - s_c) + k_t psi(r_c - max_c)   (hair volume, cohesion)
//     (r_c the distance of a pair of joints, s_c its offset along the direction
//     held for the step; VolumeLink below)
//   E_c = sum_i k_i psi(r_i - z_i)                          (the hair under a joint,
//     HairCushion below)
// with |d beta_i| taken as the joint's angular displacement in joint space,
// |(theta_i, phi_i) - (theta_i, phi_i)_prev|: eq. 15's "constant resistance in
// joint space". (With re-based angles, prev is 0 and this is the angle the
// joint's axis turns in this step, to second order.) It equals |d beta| for bending in a fixed plane and also resists
// a turn of the bend direction, and unlike |d beta| it is smooth at a straight
// joint, where beta = acos(cos theta cos phi) has a cone point.
// subject to the canvas constraint z(x_i) >= 0 (eq. 5 with the canvas at z = 0).
// |.| is smoothed (engine/base/smooth.h) so that Ipopt sees a C2 function.

#include <Eigen/Core>
#include <vector>

#include "engine/model/brush.h"
#include "engine/model/pose.h"
#include "engine/mechanics/spine_kinematics.h"

namespace bristle {

// Smoothing widths (docs/design.md, "Solver notes"): energies at the smoothed optimum differ from
// the exact minimum by a few 1e-6 N mm; a sticking joint creeps by about eps.
inline constexpr double kSmoothMm = 1e-3;
// The damping term (eq. 4) is smoothed much more finely: smoothed, joint
// friction turns viscous near zero and a bent brush would creep back towards
// rest at every solve, eating the plasticity of §3.5, whose residual bend is
// only D/K (~1e-3 rad). At 1e-5 rad the residual is kept to about 1%.
inline constexpr double kSmoothDampRad = 1e-5;
// A spine given to a solver is held by the canvas or its neighbours: one that
// only its springs and damping act on relaxes in closed form instead
// (Simulation::relaxInAir). Its joints are driven by that contact and joint
// friction's creep is immaterial, so the damping term takes the width of the
// friction term, which Ipopt solves in a third of the iterations. The fine
// width is kept for the one step in which a spine lifts off the paper, which
// sets the residual bend that plasticity leaves (docs/design.md, "Smoothing").
inline constexpr double kSmoothDampContactRad = 1e-3;

struct EnergyTerms {
  double spring_nmm = 0, friction_nmm = 0, damping_nmm = 0, volume_nmm = 0, cushion_nmm = 0;
  double total() const {
    return spring_nmm + friction_nmm + damping_nmm + volume_nmm + cushion_nmm;
  }
};

// The hair bundle under a joint as a compliant layer (docs/dynamics.md, "The
// bundle bears load"). Eq. 5 holds the spine itself above the paper, but the
// bundle around joint j reaches r_j below it (a round bundle: its radius,
// SpineSpec::bundleReachMm), and hair pressed onto the paper pushes back
// before the spine gets there. The renderer presses a bundle into the paper
// r * load / flat_load_n deep (engine/geometry/spine_bundles.h,
// bundlePressDepth): a spring of stiffness flat_load_n / r. The solve takes
// the same spring, so that the load the canvas bears and the depth the
// bundle is drawn at agree: E_c = k psi(r - z) with k = flat_load_n / r, psi
// the hair volume's C2 barrier (kVolumeSmoothMm wide, then k v^2 / 2). Its
// push k psi'(r - z) counts as the joint's normal force (contact, the
// bundle's press and the paint's pressure, the haptic force), but not for
// friction (eq. 3): the soft hair bends sideways and slides rather than pin
// the joint (Simulation::setFriction). Only a spine that says
// bundle_bears_load (the badger's soft hair) has one: without it a bundle
// bears no force until its joint does, as eq. 5 has it.
struct HairCushion {
  double reach_mm = 0;            // r: how far below the joint the hair reaches
  double stiffness_n_per_mm = 0;  // k; 0: no cushion
};
HairCushion hairCushion(const SpineSpec& spec, int joint);
// The cushion's push (N, >= 0) on a joint at height z_mm above the paper.
double cushionForceN(const HairCushion& c, double z_mm);

// Hair volume (docs/dynamics.md): joint `joint` (1..n) must keep `min_mm` from
// a neighbouring spine's joint at `other_mm`, that spine's position at the
// start of the step carried with the handle (held fixed during this solve).
// Cohesion: beyond max_mm (0 = none) the pair pulls back together.
// push_dir: see VolumeLink.
struct VolumeContact {
  int joint = 1;
  Eigen::Vector3d other_mm = Eigen::Vector3d::Zero();
  double min_mm = 0;
  double max_mm = 0;
  Eigen::Vector3d push_dir = Eigen::Vector3d::Zero();
  // The push's stiffness; 0 takes the problem's volume_stiffness_n_per_mm.
  // A squashed bundle's spread (VolumeSpec::spread_n_per_mm) has its own.
  double stiffness_n_per_mm = 0;
};

// Smoothing width of the volume barrier (mm): within it the push grows from
// zero as the square of the overlap, beyond it linearly (C2 throughout).
inline constexpr double kVolumeSmoothMm = 0.02;

// The hair-volume energy of one pair of joints at distance r (docs/dynamics.md):
// f(r) = k psi(min - r) + k_t psi(r - max) (no cohesion when max_mm is 0), and
// its first and second derivatives in r. Shared by the one-spine energy below
// (neighbour held fixed) and the whole-brush NLP (both joints free).
struct VolumePairEnergy {
  double f = 0, df = 0, ddf = 0;
};
VolumePairEnergy volumePairEnergy(double r, double min_mm, double max_mm,
                                  double stiffness_n_per_mm, double cohesion_n_per_mm);

// Hair volume between two spines that are solved together (docs/dynamics.md):
// the energy volumePairEnergy() of the distance between joint `joint` of
// problems[a] and joint `joint` of problems[b] (indices into the span given to
// SpineSolver::solve, engine/solvers/spine_solver.h), with both joints free.
//
// The push is measured along push_dir, the unit direction from b's joint to
// a's where the step starts, held for the step: the push's r is
// push_dir . (x_a - x_b), not |x_a - x_b| (docs/dynamics.md, "The push's
// direction is held for a step"). The barrier of a linear function of the
// positions is convex in them, where a push along the joints' own line has
// curvature -f'(r) / r across it, and that made Ipopt's Newton systems
// indefinite. Cohesion, a convex pull, keeps the true distance. A zero
// push_dir measures the push along the joints' own line.
struct VolumeLink {
  int a = 0, b = 0, joint = 1;
  double min_mm = 0, max_mm = 0;  // max_mm 0: no cohesion
  double stiffness_n_per_mm = 0, cohesion_n_per_mm = 0;
  Eigen::Vector3d push_dir = Eigen::Vector3d::Zero();
};

// Adds one link's energy (returned) and its derivatives, given both spines'
// kinematics (order 2 when hessians are wanted): grad_a and grad_b (vars of
// each), hess_aa and hess_bb (full, column-major, as spineEnergy's) and hess_ba,
// d2E / dq_b,u dq_a,v at [v * vars_b + u]. Any pointer may be null.
// active_parts (if given) gets how many parts (push, cohesion) acted: with
// none, nothing was added anywhere.
double volumeLinkEnergy(const VolumeLink& link, const SpineFk& fa, const SpineFk& fb,
                        double* grad_a, double* grad_b, double* hess_aa, double* hess_bb,
                        double* hess_ba, int* active_parts = nullptr);

// Everything that stays fixed during one solve of one spine.
struct SpineProblem {
  const SpineSpec* spine = nullptr;
  Pose handle;                              // handle pose of this step
  // Per joint j = 1..n (index j - 1): the friction force magnitude mu F_n of the
  // previous step (N; 0 = no contact, no friction, eq. 3 "only joints in contact").
  std::vector<double> friction_n;
  std::vector<Eigen::Vector2d> anchor_xy_mm;  // joint positions at the previous step
  // Per joint: d_p of eq. 14, the way a trailing hair is dragged (unit, canvas
  // plane; zero = no preferred direction). Strength and exponent from the brush.
  std::vector<Eigen::Vector2d> pull_dir;
  double anisotropy_strength = 0, anisotropy_exponent = 2;
  std::vector<double> prev_q;                 // joint angles at the previous step (2n)
  std::vector<VolumeContact> volume;          // hair volume, empty when off
  double volume_stiffness_n_per_mm = 0;
  double cohesion_n_per_mm = 0;
  // Per joint j = 1..n (index j - 1): the hair under it (HairCushion); empty
  // or stiffness 0: none.
  std::vector<HairCushion> cushion;
  // Base rotation B_k of every joint (engine/mechanics/spine_kinematics.h): the angles q
  // are an increment from it. Empty: B_k = I, q are eq. 10's angles themselves.
  std::vector<Eigen::Matrix3d> base;
  const Eigen::Matrix3d* baseData() const { return base.empty() ? nullptr : base.data(); }
  double eps_mm = kSmoothMm, eps_damp_rad = kSmoothDampRad;

  int vars() const { return 2 * spine->jointCount(); }
};

// Which terms spineEnergy adds up.
enum class EnergyParts {
  kAll,
  // All but the friction (eqs. 3, 13-14), which a solver then takes joint by
  // joint from frictionJointTerm (the epigraph form, engine/solvers/ipopt/ipopt_solver.cpp).
  kWithoutFriction,
};

// Evaluates E at q. grad (size 2n) and hess (2n x 2n, column-major, full) may be
// null. fk is a workspace; on return it holds the kinematics at q (order 2 if hess).
double spineEnergy(const SpineProblem& p, const double* q, SpineFk* fk, EnergyTerms* terms,
                   double* grad, double* hess, EnergyParts parts = EnergyParts::kAll);

// The friction of one joint j = 1..n that touched the canvas: weight * G(q),
// with weight = mu F_n of the previous step and G = (1 - eta) |dx| smoothed
// (eqs. 3, 13-14). E_f of spineEnergy is the sum of these over the joints.
struct FrictionJointTerm {
  double weight = 0;          // N; 0 when the joint did not touch
  double g = 0;               // mm
  int var_count = 0;          // G depends on q[0, var_count): the 2j angles before x_j
  std::vector<double> grad;   // var_count: dG/dq
  std::vector<double> hess;   // var_count^2, column-major: d2G/dq2
};
// Joint j's term at the kinematics fk (of order >= `order`; order 0 gives G, 1
// adds the gradient, 2 the Hessian). Returns false, with weight 0, for a joint
// without friction this step.
bool frictionJointTerm(const SpineProblem& p, const SpineFk& fk, int joint, int order,
                       FrictionJointTerm* out);

}  // namespace bristle

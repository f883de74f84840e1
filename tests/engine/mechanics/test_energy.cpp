// Energy terms of the spine problem (paper eqs. 2-4, 12) against finite
// differences and closed forms.

#include <Eigen/Eigenvalues>
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "engine/mechanics/friction.h"
#include "engine/base/smooth.h"
#include "engine/mechanics/spine_energy.h"
#include "test_helpers.h"

using namespace bristle;
using bristle::testing::makeSpine;

namespace {
// See test_kinematics.cpp: central differences at h = 1e-6 are good to ~1e-9;
// energies here are O(10 N mm) with derivatives O(10), so 1e-5 relative (with
// an absolute floor) separates round-off from a wrong term by orders of magnitude.
constexpr double kEnergyFdStep = 1e-6;
constexpr double kFdRelTol = 1e-5;
constexpr double kFdAbsTol = 1e-6;

bool close(double a, double b) {
  return std::fabs(a - b) <= kFdAbsTol + kFdRelTol * std::max(std::fabs(a), std::fabs(b));
}

// spineEnergy's gradient g and Hessian h (nv x nv, h[v * nv + w]) at q
// against central differences of its energy and of its gradient.
void checkAgainstDifferences(const SpineProblem& p, const std::vector<double>& q,
                             const std::vector<double>& g, const std::vector<double>& h) {
  const int nv = static_cast<int>(q.size());
  SpineFk fk;
  std::vector<double> gp(nv), gm(nv);
  for (int v = 0; v < nv; ++v) {
    std::vector<double> qp = q, qm = q;
    qp[v] += kEnergyFdStep;
    qm[v] -= kEnergyFdStep;
    const double ep = spineEnergy(p, qp.data(), &fk, nullptr, gp.data(), nullptr);
    const double em = spineEnergy(p, qm.data(), &fk, nullptr, gm.data(), nullptr);
    const double fd = (ep - em) / (2 * kEnergyFdStep);
    INFO("var " << v << " grad " << g[v] << " fd " << fd);
    CHECK(close(g[v], fd));
    for (int w = 0; w < nv; ++w) {
      INFO("hessian (" << w << "," << v << ")");
      CHECK(close(h[v * nv + w], (gp[w] - gm[w]) / (2 * kEnergyFdStep)));
    }
  }
}
}  // namespace

TEST_CASE("beta^2 series agrees with acos^2 and is smooth at the switch", "[energy]") {
  // acos(1 - w)^2 computed directly loses ~half the digits near w = 0 (acos's
  // infinite slope); 1e-10 relative is what it keeps at w >= 1e-6.
  constexpr double kRelTol = 1e-10;
  for (double w : {1e-6, 1e-4, 3e-3, 9.99e-3, 1e-2, 0.1, 0.5, 1.2}) {
    const double exact = std::pow(std::acos(1 - w), 2);
    INFO("w = " << w);
    CHECK(std::fabs(bendSquared(w).h - exact) <= kRelTol * exact);
  }
  // Derivatives on both sides of the series/closed-form switch at w = 1e-2.
  const BendSquared lo = bendSquared(1e-2 - 1e-12), hi = bendSquared(1e-2 + 1e-12);
  CHECK(std::fabs(lo.dh - hi.dh) < 1e-9);
  CHECK(std::fabs(lo.ddh - hi.ddh) < 1e-7);
  // h'(0) = 2 (beta^2 ~ 2w): the straight joint has a finite, non-zero slope in w.
  CHECK(bendSquared(0).dh == Approx(2.0));
  for (double w : {1e-3, 0.05, 0.7}) {
    const double h = 1e-7;
    CHECK(close(bendSquared(w).dh, (bendSquared(w + h).h - bendSquared(w - h).h) / (2 * h)));
    CHECK(close(bendSquared(w).ddh, (bendSquared(w + h).dh - bendSquared(w - h).dh) / (2 * h)));
  }
}

TEST_CASE("spring energy is K beta^2 / 2 with beta from eq. 12", "[energy]") {
  SpineSpec spine = makeSpine({5.0}, {7.0});
  SpineProblem p;
  p.spine = &spine;
  p.friction_n = {0};
  p.anchor_xy_mm = {Eigen::Vector2d::Zero()};
  p.prev_q = {0, 0};
  SpineFk fk;
  EnergyTerms e;
  double q[2] = {0.3, 0.4};
  spineEnergy(p, q, &fk, &e, nullptr, nullptr);
  const double beta = std::acos(std::cos(0.3) * std::cos(0.4));  // eq. 12
  CHECK(e.spring_nmm == Approx(7.0 * beta * beta / 2).epsilon(1e-12));
  CHECK(e.friction_nmm == 0);
  CHECK(e.damping_nmm == 0);
}

namespace {
// A three-joint spine, slightly curved at rest, whose joints 2 and 3 touched
// the canvas at the previous step, dragged with anisotropic friction
// (eqs. 13-14) pulling each its own way.
SpineSpec contactSpine() {
  SpineSpec spine = makeSpine({4.0, 3.5, 3.0}, {10, 7, 5}, 0.008, Eigen::Vector3d(0.5, 0, -0.3));
  spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, -0.02);
  spine.rest_angles_rad[2] = Eigen::Vector2d(-0.1, 0.2);
  return spine;
}
SpineProblem contactProblem(const SpineSpec* spine) {
  SpineProblem p;
  p.spine = spine;
  p.handle.position_mm = Eigen::Vector3d(10, 20, 6);
  p.handle.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
  p.friction_n = {0.0, 0.15, 0.4};  // joints 2 and 3 in contact
  p.anchor_xy_mm = {Eigen::Vector2d(0, 0), Eigen::Vector2d(11.0, 24.0), Eigen::Vector2d(9.5, 27.0)};
  p.prev_q = {0.1, -0.2, 0.45, 0.05, 0.2, 0.3};
  p.pull_dir = {Eigen::Vector2d::Zero(), Eigen::Vector2d(0.6, 0.8), Eigen::Vector2d(-1, 0)};
  return p;
}
}  // namespace

TEST_CASE("energy gradient and Hessian match finite differences", "[energy]") {
  SpineSpec spine = contactSpine();
  SpineProblem p = contactProblem(&spine);
  // Anisotropic friction on both contact joints, k = 1.5 and 3.
  p.anisotropy_strength = GENERATE(0.0, 0.7);
  p.anisotropy_exponent = GENERATE(1.5, 3.0);
  // Also re-based (docs/dynamics.md): the angles as increments from base
  // rotations bent well past eq. 10's singularity at 90 degrees.
  if (GENERATE(false, true)) {
    p.base = {Eigen::Matrix3d(Eigen::AngleAxisd(1.7, Eigen::Vector3d(1, 0.2, 0).normalized())),
              Eigen::Matrix3d(Eigen::AngleAxisd(2.4, Eigen::Vector3d(-0.3, 1, 0.1).normalized())),
              Eigen::Matrix3d(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 1, 0)))};
  }
  // Hair volume against neighbours' joints (docs/dynamics.md): far enough that
  // some trials push (within and beyond the smoothing width) and some do not.
  if (GENERATE(false, true)) {
    p.volume_stiffness_n_per_mm = 8;
    p.cohesion_n_per_mm = 0.7;  // and cohesion beyond max_mm
    p.volume = {{1, Eigen::Vector3d(10.5, 21.0, 3.0), 3.5, 0},
                {2, Eigen::Vector3d(12.0, 20.0, 0.5), 5.0, 6.0},
                {3, Eigen::Vector3d(9.0, 18.0, -1.0), 8.0, 0},
                {3, Eigen::Vector3d(11.0, 23.0, -4.0), 0.03, 2.0},
                {2, Eigen::Vector3d(7.0, 22.0, -2.0), 0.5, 0.9}};
    // The push held along a direction fixed for the step (spine_energy.h,
    // VolumeLink), on some contacts, or along the joints' own line.
    if (GENERATE(false, true)) {
      p.volume[1].push_dir = Eigen::Vector3d(0.6, -0.8, 0.0);
      p.volume[2].push_dir = Eigen::Vector3d(0.0, 0.6, 0.8);
      p.volume[3].push_dir = Eigen::Vector3d(1.0, 2.0, -2.0) / 3.0;
    }
    // A squashed bundle's spread (Simulation::addAxisSpread): a push out from
    // the handle's axis, held across it, with a stiffness of its own.
    p.volume.push_back({2, Eigen::Vector3d(9.0, 21.5, 1.0), 4.0, 0, Eigen::Vector3d(0.8, 0.6, 0.0), 30});
  }
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-0.9, 0.9);
  int pushed = 0;  // trials where the volume term acts
  for (int trial = 0; trial < 6; ++trial) {
    std::vector<double> q(6);
    for (double& a : q) a = angle(rng);
    if (trial == 0) std::fill(q.begin(), q.end(), 0.0);  // the straight spine: beta = 0
    std::vector<double> g(6), h(36);
    SpineFk fk;
    EnergyTerms terms;
    spineEnergy(p, q.data(), &fk, &terms, g.data(), h.data());
    pushed += terms.volume_nmm > 0;
    INFO("trial " << trial);
    checkAgainstDifferences(p, q, g, h);
  }
  if (!p.volume.empty()) CHECK(pushed >= 2);
}

TEST_CASE("hair volume between two free spines matches finite differences", "[energy][volume]") {
  // Two spines of a whole-brush NLP (engine/solvers/ipopt/ipopt_solver.cpp) coupled by one link
  // per joint: gradient in both spines' angles, both diagonal blocks and the
  // cross block d2E / dq_b dq_a, all against central differences of the energy
  // and of the gradient. Re-based (bent past 90 degrees) and not.
  SpineSpec sa = makeSpine({4.0, 3.5, 3.0}, {10, 7, 5}, 0.0, Eigen::Vector3d(0.5, 0, -0.3));
  SpineSpec sb = makeSpine({4.0, 3.0}, {9, 6}, 0.0, Eigen::Vector3d(-1.2, 0.8, 0));
  sb.rest_angles_rad[1] = Eigen::Vector2d(0.2, -0.1);
  Pose handle;
  handle.position_mm = Eigen::Vector3d(10, 20, 6);
  handle.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
  std::vector<Eigen::Matrix3d> base_a, base_b;
  if (GENERATE(false, true)) {
    base_a = {Eigen::Matrix3d(Eigen::AngleAxisd(1.7, Eigen::Vector3d(1, 0.2, 0).normalized())),
              Eigen::Matrix3d(Eigen::AngleAxisd(0.6, Eigen::Vector3d(-0.3, 1, 0.1).normalized())),
              Eigen::Matrix3d(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0, 1, 0)))};
    base_b = {Eigen::Matrix3d(Eigen::AngleAxisd(1.9, Eigen::Vector3d(0.9, 0.4, 0).normalized())),
              Eigen::Matrix3d(Eigen::AngleAxisd(0.3, Eigen::Vector3d(0, 0, 1)))};
  }
  // Limits chosen so that some trials squeeze, some pull apart (cohesion) and
  // some leave a link slack; within and beyond the barrier's smoothing width.
  std::vector<VolumeLink> links = {{0, 1, 1, 2.4, 2.9, 8, 0.7}, {0, 1, 2, 3.0, 5.0, 8, 0.7}};
  if (GENERATE(false, true)) {  // pushes held along fixed directions (VolumeLink)
    links[0].push_dir = Eigen::Vector3d(0.48, 0.6, 0.64);
    links[1].push_dir = Eigen::Vector3d(-0.8, 0.0, 0.6);
  }
  const int na = 6, nb = 4;
  auto energy = [&](const std::vector<double>& q, std::vector<double>* grad,
                    std::vector<double>* haa, std::vector<double>* hbb,
                    std::vector<double>* hba) {
    SpineFk fa, fb;
    const int order = haa ? 2 : 1;
    spineForwardKinematics(sa, handle, base_a.empty() ? nullptr : base_a.data(), q.data(), order,
                           &fa);
    spineForwardKinematics(sb, handle, base_b.empty() ? nullptr : base_b.data(), q.data() + na,
                           order, &fb);
    grad->assign(na + nb, 0.0);
    if (haa) {
      haa->assign(na * na, 0.0);
      hbb->assign(nb * nb, 0.0);
      hba->assign(na * nb, 0.0);
    }
    double e = 0;
    for (const VolumeLink& l : links)
      e += volumeLinkEnergy(l, fa, fb, grad->data(), grad->data() + na,
                            haa ? haa->data() : nullptr, hbb ? hbb->data() : nullptr,
                            hba ? hba->data() : nullptr);
    return e;
  };
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-0.8, 0.8);
  int acting = 0;
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<double> q(na + nb);
    for (double& a : q) a = angle(rng);
    std::vector<double> g, haa, hbb, hba, gp, gm;
    const double e = energy(q, &g, &haa, &hbb, &hba);
    acting += e > 0;
    for (int v = 0; v < na + nb; ++v) {
      std::vector<double> qp = q, qm = q;
      qp[v] += kEnergyFdStep;
      qm[v] -= kEnergyFdStep;
      const double ep = energy(qp, &gp, nullptr, nullptr, nullptr);
      const double em = energy(qm, &gm, nullptr, nullptr, nullptr);
      INFO("trial " << trial << " var " << v);
      CHECK(close(g[v], (ep - em) / (2 * kEnergyFdStep)));
      for (int w = 0; w < na + nb; ++w) {
        const double fd = (gp[w] - gm[w]) / (2 * kEnergyFdStep);  // d2E / dq_w dq_v
        double h;
        if (v < na && w < na) h = haa[v * na + w];
        else if (v >= na && w >= na) h = hbb[(v - na) * nb + (w - na)];
        else if (v < na) h = hba[v * nb + (w - na)];    // w of b, v of a
        else h = hba[w * nb + (v - na)];                // v of b, w of a
        INFO("hessian (" << w << "," << v << ")");
        CHECK(close(h, fd));
      }
    }
  }
  CHECK(acting >= 4);
}

namespace {
// Kinematics of a one-joint "spine" whose two variables are the x and y of its
// joint: a link's Hessian in these is its Hessian in the positions.
SpineFk planarJoint(const Eigen::Vector3d& x) {
  SpineFk fk;
  fk.n = 1;
  fk.x = {Eigen::Vector3d::Zero(), x};
  fk.dx = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX(),
           Eigen::Vector3d::UnitY()};
  fk.ddx.assign(2 * 2 * 2, Eigen::Vector3d::Zero());
  return fk;
}

// Smallest eigenvalue of a link's Hessian in both joints' x and y.
double smallestCurvature(const VolumeLink& link, const Eigen::Vector3d& xa,
                         const Eigen::Vector3d& xb) {
  const SpineFk fa = planarJoint(xa), fb = planarJoint(xb);
  double haa[4] = {}, hbb[4] = {}, hba[4] = {};
  volumeLinkEnergy(link, fa, fb, nullptr, nullptr, haa, hbb, hba);
  Eigen::Matrix4d h;
  for (int v = 0; v < 2; ++v)
    for (int w = 0; w < 2; ++w) {
      h(v, w) = haa[w * 2 + v];
      h(2 + v, 2 + w) = hbb[w * 2 + v];
      h(2 + v, w) = h(w, 2 + v) = hba[w * 2 + v];  // v of b, w of a
    }
  return Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(h).eigenvalues().minCoeff();
}
}  // namespace

TEST_CASE("a hair-volume pair reports whether it acted, and its own blocks are symmetric",
          "[energy][volume]") {
  // Joints 2 mm apart; limits 1-3 mm leave the pair idle, 2.5-3 mm push it.
  const Eigen::Vector3d xa(2.0, 0.3, 0.1), xb(0, 0, 0);
  const SpineFk fa = planarJoint(xa), fb = planarJoint(xb);
  double g[4] = {}, haa[4] = {}, hbb[4] = {}, hba[4] = {};
  int parts = -1;
  const VolumeLink idle{0, 1, 1, 1.0, 3.0, 10.0, 0.5};
  CHECK(volumeLinkEnergy(idle, fa, fb, g, g + 2, haa, hbb, hba, &parts) == 0.0);
  CHECK(parts == 0);  // and nothing was added: the caller may skip its copies
  for (int i = 0; i < 4; ++i) CHECK((g[i] == 0 && haa[i] == 0 && hbb[i] == 0 && hba[i] == 0));
  const VolumeLink pushed{0, 1, 1, 2.5, 3.0, 10.0, 0.5};
  CHECK(volumeLinkEnergy(pushed, fa, fb, g, g + 2, haa, hbb, hba, &parts) > 0.0);
  CHECK(parts == 1);
  // Each spine's block is filled from its lower triangle, so exactly symmetric.
  CHECK(haa[1] == haa[2]);
  CHECK(hbb[1] == hbb[2]);
  CHECK(haa[1] != 0.0);
}

TEST_CASE("a push held along one direction is convex in the joints' positions",
          "[energy][volume]") {
  // Two joints 0.5 mm apart that must keep 1 mm: the push along their own line
  // curves down across it by -f'(r) / r = -k (min - r) / r (beyond the barrier's
  // smoothing width), the indefinite Hessian Ipopt had to shift; held along a
  // direction it has no negative curvature (spine_energy.h, VolumeLink).
  const Eigen::Vector3d xa(0.5, 0, 0), xb(0, 0, 0);
  VolumeLink link{0, 1, 1, 1.0, 0.0, 10.0, 0.0};
  // -f'(r) = k psi'(min - r), with psi'(v) = v - w / 2 beyond the width w.
  const double push_n = 10.0 * (1.0 - 0.5 - kVolumeSmoothMm / 2);
  // The Hessian in (x_a, x_b) is [H, -H; -H, H] with H the one in x_a - x_b,
  // so its eigenvalues are twice H's: across the line 2 f'(r) / r. The
  // tolerance allows the eigen solver's round-off on entries of order 10.
  constexpr double kEigTol = 1e-9;
  CHECK(smallestCurvature(link, xa, xb) == Approx(-2 * push_n / 0.5).epsilon(1e-9));
  link.push_dir = Eigen::Vector3d::UnitX();
  CHECK(smallestCurvature(link, xa, xb) >= -kEigTol);
  // Cohesion, a pull, keeps the joints' own line and is convex anyway.
  VolumeLink pull{0, 1, 1, 0.0, 0.3, 0.0, 4.0};
  CHECK(smallestCurvature(pull, xa, xb) >= -kEigTol);
}

TEST_CASE("smoothed friction approaches mu Fn |dx| away from the kink", "[energy]") {
  // eq. 3 smoothed: |sqrt(d^2 + eps^2) - eps - |d|| <= eps.
  for (double d : {0.0, 1e-4, 0.01, 1.0}) {
    const Smooth2 s = smoothNorm(Eigen::Vector2d(d, 0), kSmoothMm);
    CHECK(std::fabs(s.f - d) <= kSmoothMm);
  }
  // Far from the kink the force is the full Coulomb force mu Fn in the motion direction.
  const Smooth2 far = smoothNorm(Eigen::Vector2d(0.3, -0.4), kSmoothMm);
  CHECK(far.grad.norm() == Approx(1.0).epsilon(1e-5));
}

TEST_CASE("anisotropic friction: C_eta removes friction along the pull direction only",
          "[energy][friction]") {
  // eq. 13-14 away from the smoothing: |dx| = 0.5 mm >> eps.
  Anisotropy a;
  a.pull_dir = Eigen::Vector2d(1, 0);
  a.strength = 0.6;
  a.exponent = 2;
  const double len = 0.5;
  // Smoothing shifts |dx| by eps and the cosine by ~eps^2 / |dx|^2: 1e-5 relative.
  constexpr double kTol = 2e-3 * 0.5;
  CHECK(frictionTerm({len, 0}, a, kSmoothMm).f == Approx((1 - 0.6) * len).margin(kTol));
  CHECK(frictionTerm({-len, 0}, a, kSmoothMm).f == Approx(len).margin(kTol));
  const double c45 = std::sqrt(0.5);
  CHECK(frictionTerm({len * c45, len * c45}, a, kSmoothMm).f ==
        Approx((1 - 0.6 * 0.5) * len).margin(kTol));
  a.strength = 0;  // C_eta = 0 recovers eq. 3
  CHECK(frictionTerm({len, 0}, a, kSmoothMm).f == Approx(len).margin(kTol));
  a.strength = 1;  // C_eta = 1: no friction at all in the pull direction
  CHECK(frictionTerm({len, 0}, a, kSmoothMm).f == Approx(0).margin(kTol));
}

TEST_CASE("friction joint by joint: the energy's friction, with its own derivatives",
          "[energy][friction]") {
  // The epigraph form of engine/solvers/ipopt/ipopt_solver.cpp takes the friction out of the
  // objective (EnergyParts::kWithoutFriction) and puts each joint's weight * G
  // into a constraint: the two must add back up to spineEnergy, and G's
  // gradient and Hessian must be G's own (central differences as above).
  const SpineSpec spine = contactSpine();
  SpineProblem p = contactProblem(&spine);
  p.anisotropy_strength = GENERATE(0.0, 0.7);
  p.anisotropy_exponent = 2.0;
  // The sums differ from spineEnergy's only by the order of additions.
  constexpr double kSumTol = 1e-12;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-0.9, 0.9);
  for (int trial = 0; trial < 4; ++trial) {
    std::vector<double> q(6);
    for (double& a : q) a = angle(rng);
    std::vector<double> g_all(6), h_all(36), g_rest(6), h_rest(36);
    SpineFk fk;
    EnergyTerms all, rest;
    const double e_all = spineEnergy(p, q.data(), &fk, &all, g_all.data(), h_all.data());
    const double e_rest = spineEnergy(p, q.data(), &fk, &rest, g_rest.data(), h_rest.data(),
                                      EnergyParts::kWithoutFriction);
    CHECK(rest.friction_nmm == 0);
    CHECK(rest.spring_nmm == all.spring_nmm);
    CHECK(rest.damping_nmm == all.damping_nmm);
    double sum = 0;
    std::vector<double> g_sum(6, 0.0), h_sum(36, 0.0);
    FrictionJointTerm t;
    CHECK_FALSE(frictionJointTerm(p, fk, 1, 2, &t));  // joint 1 did not touch
    CHECK(t.weight == 0);
    for (int j = 2; j <= 3; ++j) {
      REQUIRE(frictionJointTerm(p, fk, j, 2, &t));
      REQUIRE(t.var_count == 2 * j);
      CHECK(t.weight == p.friction_n[j - 1]);
      sum += t.weight * t.g;
      for (int v = 0; v < t.var_count; ++v) {
        g_sum[v] += t.weight * t.grad[v];
        for (int w = 0; w < t.var_count; ++w)
          h_sum[w * 6 + v] += t.weight * t.hess[w * t.var_count + v];
      }
      // G's own derivatives against central differences of G.
      for (int v = 0; v < t.var_count; ++v) {
        std::vector<double> qp = q, qm = q;
        qp[v] += kEnergyFdStep;
        qm[v] -= kEnergyFdStep;
        SpineFk fp, fm;
        FrictionJointTerm tp, tm;
        spineForwardKinematics(spine, p.handle, qp.data(), 1, &fp);
        spineForwardKinematics(spine, p.handle, qm.data(), 1, &fm);
        frictionJointTerm(p, fp, j, 1, &tp);
        frictionJointTerm(p, fm, j, 1, &tm);
        INFO("trial " << trial << " joint " << j << " var " << v);
        CHECK(close(t.grad[v], (tp.g - tm.g) / (2 * kEnergyFdStep)));
        for (int w = 0; w < t.var_count; ++w)
          CHECK(close(t.hess[v * t.var_count + w], (tp.grad[w] - tm.grad[w]) / (2 * kEnergyFdStep)));
      }
    }
    INFO("trial " << trial);
    CHECK(all.friction_nmm == Approx(sum).epsilon(kSumTol));
    CHECK(e_all - e_rest == Approx(sum).epsilon(1e-9).margin(kSumTol));
    for (int v = 0; v < 6; ++v) {
      CHECK(std::fabs(g_all[v] - g_rest[v] - g_sum[v]) <= kSumTol * (1 + std::fabs(g_all[v])));
      for (int w = 0; w < 6; ++w)
        CHECK(std::fabs(h_all[w * 6 + v] - h_rest[w * 6 + v] - h_sum[w * 6 + v]) <=
              kSumTol * (1 + std::fabs(h_all[w * 6 + v])));
    }
  }
}

TEST_CASE("the hair cushion under the joints matches finite differences", "[energy][cushion]") {
  // The hair bundle under each joint as a compliant layer (spine_energy.h,
  // HairCushion): E_c = k psi(r - z). Reaches chosen so that over the trials
  // some joints sink into their hair and some stay clear of it.
  const SpineSpec spine = contactSpine();
  SpineProblem p = contactProblem(&spine);
  // Stiffer than any brush's (the badger's 0.002-0.006 N/mm) so that the term
  // stands well above the differences' floor (kFdAbsTol).
  p.cushion = {{3.0, 2.0}, {1.0, 3.0}, {0.5, 1.5}};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-0.9, 0.9);
  int pressed = 0, clear = 0;  // joints, over the trials, in their hair and clear of it
  for (int trial = 0; trial < 8; ++trial) {
    std::vector<double> q(6);
    for (double& a : q) a = angle(rng);
    std::vector<double> g(6), h(36);
    SpineFk fk;
    EnergyTerms terms;
    spineEnergy(p, q.data(), &fk, &terms, g.data(), h.data());
    // Its push on each joint: beyond the barrier's smoothing, the spring's
    // k (r - z), less half the smoothing width; none clear of the hair.
    int pushing = 0;
    for (int j = 1; j <= 3; ++j) {
      const HairCushion& c = p.cushion[j - 1];
      const double z = fk.x[j].z(), f = cushionForceN(c, z);
      INFO("trial " << trial << " joint " << j << " z " << z);
      CHECK(f >= 0);
      if (c.reach_mm - z > kVolumeSmoothMm)
        CHECK(f == Approx(c.stiffness_n_per_mm * (c.reach_mm - z - 0.5 * kVolumeSmoothMm)));
      if (z >= c.reach_mm) CHECK(f == 0);
      pushing += f > 0;
    }
    pressed += pushing;
    clear += 3 - pushing;
    CHECK((pushing > 0) == (terms.cushion_nmm > 0));
    INFO("trial " << trial);
    checkAgainstDifferences(p, q, g, h);
  }
  CHECK(pressed >= 3);
  CHECK(clear >= 3);  // the clear side is checked too
}

TEST_CASE("a spine's hair cushion is its bundle pressed flat by flat_load_n", "[energy][cushion]") {
  // k = flat_load_n / r (spine_energy.h, HairCushion): the load that presses
  // the bundle flat in the renderer (bundlePressDepth) is the cushion's push
  // with the joint on the paper. Only a spine that says bundle_bears_load has
  // one; any other bundle bears no force until its joint does (eq. 5), even
  // one that declares how easily it splays (flat_load_n alone).
  SpineSpec spine = makeSpine({4.0, 3.5}, {10, 7});
  spine.width_mm = {5.0, 4.5, 3.5};
  CHECK(hairCushion(spine, 1).stiffness_n_per_mm == 0);
  spine.flat_load_n = 0.01;
  CHECK(hairCushion(spine, 2).stiffness_n_per_mm == 0);
  spine.bundle_bears_load = true;
  const HairCushion c = hairCushion(spine, 2);
  CHECK(c.reach_mm == Approx(1.75));
  CHECK(c.stiffness_n_per_mm == Approx(0.01 / 1.75));
  // On the paper it pushes with the flat load, less the smoothing's half width.
  CHECK(cushionForceN(c, 0.0) == Approx(0.01 * (1 - 0.5 * kVolumeSmoothMm / 1.75)));
  CHECK(cushionForceN(c, 1.75) == 0);
  CHECK(cushionForceN(c, 2.5) == 0);
  CHECK(hairCushion(spine, 0).stiffness_n_per_mm == 0);  // the root is the ferrule's
  // Without its own flat_load_n, the default's spring.
  spine.flat_load_n = 0;
  CHECK(hairCushion(spine, 2).stiffness_n_per_mm == Approx(kBundleFlatLoadN / 1.75));
}

#include "engine/mechanics/spine_energy.h"

#include <algorithm>
#include <cmath>

#include "engine/mechanics/friction.h"
#include "engine/base/smooth.h"

namespace bristle {
namespace {

// w = 1 - a_rest . a(q): one minus the cosine of the bend from the rest axis
// (eq. 12 generalised to a non-zero rest pose), with derivatives in (theta, phi).
struct BendW {
  double w;
  Eigen::Vector2d dw;
  Eigen::Matrix2d ddw;
};
// With a base rotation B_k the joint's axis is B_k a(q): a0 . B_k a(q) = (B_k^T a0) . a(q).
BendW bendW(const SpineSpec& spine, const Eigen::Matrix3d* base, int k, const double* q) {
  const Eigen::Vector2d& rest = spine.rest_angles_rad[k];
  Eigen::Vector3d a0 = jointAxis(rest[0], rest[1]).a;
  if (base) a0 = base[k].transpose() * a0;
  const JointAxis ax = jointAxis(q[2 * k], q[2 * k + 1]);
  BendW b;
  b.w = 1.0 - a0.dot(ax.a);
  for (int i = 0; i < 2; ++i) {
    b.dw[i] = -a0.dot(ax.d[i]);
    for (int j = 0; j < 2; ++j) b.ddw(i, j) = -a0.dot(ax.dd[i][j]);
  }
  return b;
}

struct VolumePsi {
  double psi, dpsi, ddpsi;
};
VolumePsi volumePsi(double v) {
  constexpr double w = kVolumeSmoothMm;
  if (v <= w) return {v * v * v / (6 * w), v * v / (2 * w), v / w};
  return {w * w / 6 + 0.5 * w * (v - w) + 0.5 * (v - w) * (v - w), 0.5 * w + (v - w), 1.0};
}

}  // namespace

VolumePairEnergy volumePairEnergy(double r, double min_mm, double max_mm,
                                  double stiffness_n_per_mm, double cohesion_n_per_mm) {
  VolumePairEnergy e;
  if (r < min_mm) {
    const VolumePsi ps = volumePsi(min_mm - r);
    e.f += stiffness_n_per_mm * ps.psi;
    e.df -= stiffness_n_per_mm * ps.dpsi;
    e.ddf += stiffness_n_per_mm * ps.ddpsi;
  }
  if (max_mm > 0 && r > max_mm) {
    const VolumePsi ps = volumePsi(r - max_mm);
    e.f += cohesion_n_per_mm * ps.psi;
    e.df += cohesion_n_per_mm * ps.dpsi;
    e.ddf += cohesion_n_per_mm * ps.ddpsi;
  }
  return e;
}

namespace {
// One part of a pair's volume energy, f(g) with g a function of the joints'
// offset delta = x_a - x_b: dg/ddelta = u, and d2g/ddelta2 = (I - u u^T) / r
// for the distance g = r = |delta| (u = delta / r) or 0 for the push along a
// held direction, g = u . delta (`curved` false).
struct VolumePart {
  double f = 0, df = 0, ddf = 0;
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  double r = 1;
  bool curved = false;
};

// The push and the cohesion of one pair (spine_energy.h, VolumeLink): up to two
// parts, written to out; returns how many.
int volumeParts(const Eigen::Vector3d& delta, const Eigen::Vector3d& push_dir, double min_mm,
                double max_mm, double stiffness_n_per_mm, double cohesion_n_per_mm,
                VolumePart out[2]) {
  const double r = std::sqrt(delta.squaredNorm() + 1e-18);
  const Eigen::Vector3d along = delta / r;
  int n = 0;
  const bool held = push_dir.squaredNorm() > 0;
  const double g = held ? push_dir.dot(delta) : r;
  const VolumePairEnergy push = volumePairEnergy(g, min_mm, 0, stiffness_n_per_mm, 0);
  if (push.f != 0 || push.df != 0)
    out[n++] = {push.f, push.df, push.ddf, held ? push_dir : along, r, !held};
  const VolumePairEnergy pull = volumePairEnergy(r, 0, max_mm, 0, cohesion_n_per_mm);
  if (pull.f != 0 || pull.df != 0) out[n++] = {pull.f, pull.df, pull.ddf, along, r, true};
  return n;
}
}  // namespace

// Both joints free, each part f(g(x_a - x_b)) (volumeParts): dg/dq_a = u . dx_a,
// dg/dq_b = -u . dx_b; within a spine d2g = (dx . dx' - (dg)(dg')) / r +- u . d2x,
// across the two d2g/dq_b dq_a = -(dx_b . dx_a + (dg/dq_b)(dg/dq_a)) / r, where
// the terms over r are those of the distance only (not of a held push).
double volumeLinkEnergy(const VolumeLink& l, const SpineFk& fa, const SpineFk& fb,
                        double* grad_a, double* grad_b, double* hess_aa, double* hess_bb,
                        double* hess_ba, int* active_parts) {
  VolumePart parts[2];
  const int np = volumeParts(fa.x[l.joint] - fb.x[l.joint], l.push_dir, l.min_mm, l.max_mm,
                             l.stiffness_n_per_mm, l.cohesion_n_per_mm, parts);
  const int nj = 2 * l.joint;  // only the joints before j move x_j
  const int nva = fa.vars(), nvb = fb.vars();
  double energy = 0;
  for (int i = 0; i < np; ++i) {
    const VolumePart& pt = parts[i];
    energy += pt.f;
    double ra[2 * kMaxJointsPerSpine], rb[2 * kMaxJointsPerSpine];  // dg/dq
    for (int v = 0; v < nj; ++v) {
      ra[v] = pt.u.dot(fa.d(l.joint, v));
      rb[v] = -pt.u.dot(fb.d(l.joint, v));
      if (grad_a) grad_a[v] += pt.df * ra[v];
      if (grad_b) grad_b[v] += pt.df * rb[v];
    }
    // Each spine's own block is symmetric: its lower triangle (row v >= column
    // w, all that Ipopt reads) is computed and mirrored.
    for (int w = 0; w < nj; ++w)
      for (int v = w; v < nj; ++v) {
        if (hess_aa) {
          const double across =
              pt.curved ? (fa.d(l.joint, v).dot(fa.d(l.joint, w)) - ra[v] * ra[w]) / pt.r : 0.0;
          const double d2 = across + pt.u.dot(fa.dd(l.joint, v, w));
          const double h = pt.ddf * ra[v] * ra[w] + pt.df * d2;
          hess_aa[w * nva + v] += h;
          if (v != w) hess_aa[v * nva + w] += h;
        }
        if (hess_bb) {
          const double across =
              pt.curved ? (fb.d(l.joint, v).dot(fb.d(l.joint, w)) - rb[v] * rb[w]) / pt.r : 0.0;
          const double d2 = across - pt.u.dot(fb.dd(l.joint, v, w));
          const double h = pt.ddf * rb[v] * rb[w] + pt.df * d2;
          hess_bb[w * nvb + v] += h;
          if (v != w) hess_bb[v * nvb + w] += h;
        }
      }
    if (hess_ba)
      for (int v = 0; v < nj; ++v)
        for (int w = 0; w < nj; ++w) {  // v: variable of b, w: variable of a
          const double d2 =
              pt.curved ? -(fb.d(l.joint, v).dot(fa.d(l.joint, w)) + rb[v] * ra[w]) / pt.r : 0.0;
          hess_ba[w * nvb + v] += pt.ddf * rb[v] * ra[w] + pt.df * d2;
        }
  }
  if (active_parts) *active_parts = np;
  return energy;
}

namespace {

// Where spineEnergy's terms add their value, gradient and Hessian (column
// major, nv x nv); grad and hess may be null.
struct EnergySums {
  EnergyTerms e;
  double* grad = nullptr;
  double* hess = nullptr;
  int nv = 0;
  double& H(int i, int j) { return hess[j * nv + i]; }
};

// eq. 2, the springs, and eq. 4, the joints' damping: each depends on one
// joint's two angles only, so both sit on the Hessian's 2 x 2 diagonal blocks.
void addJointTerms(const SpineProblem& p, const double* q, EnergySums& sum) {
  const SpineSpec& s = *p.spine;
  const int n = s.jointCount();
  EnergyTerms& e = sum.e;
  double* grad = sum.grad;
  double* hess = sum.hess;
  auto H = [&](int i, int j) -> double& { return sum.H(i, j); };
  for (int k = 0; k < n; ++k) {
    const BendW bw = bendW(s, p.baseData(), k, q);
    const BendSquared h = bendSquared(bw.w);
    // eq. 2: K beta^2 / 2 with beta^2 = h(w).
    const double K = s.stiffness_nmm_per_rad[k];
    e.spring_nmm += 0.5 * K * h.h;
    if (grad)
      for (int a = 0; a < 2; ++a) grad[2 * k + a] += 0.5 * K * h.dh * bw.dw[a];
    if (hess)
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
          H(2 * k + a, 2 * k + b) +=
              0.5 * K * (h.ddh * bw.dw[a] * bw.dw[b] + h.dh * bw.ddw(a, b));

    // eq. 4: D |d beta|, the joint's displacement since the previous step.
    const double D = s.damping_nmm[k];
    if (D > 0) {
      const Eigen::Vector2d d(q[2 * k] - p.prev_q[2 * k], q[2 * k + 1] - p.prev_q[2 * k + 1]);
      const Smooth2 sd = smoothNorm(d, p.eps_damp_rad);
      e.damping_nmm += D * sd.f;
      if (grad)
        for (int a = 0; a < 2; ++a) grad[2 * k + a] += D * sd.grad[a];
      if (hess)
        for (int a = 0; a < 2; ++a)
          for (int b = 0; b < 2; ++b) H(2 * k + a, 2 * k + b) += D * sd.hess(a, b);
    }
  }

}

// eqs. 3, 13-14, friction on the joints that touched the canvas at the
// previous step: (1 - eta) mu |F_n| |dx_c| each (frictionJointTerm).
void addFrictionTerms(const SpineProblem& p, const SpineFk* fk, EnergySums& sum) {
  const int n = p.spine->jointCount();
  const int order = sum.hess ? 2 : (sum.grad ? 1 : 0);
  // Kept between calls: its vectors are sized once, not on every evaluation
  // of a solver's hot loop.
  thread_local FrictionJointTerm t;
  for (int j = 1; j <= n; ++j) {
    if (!frictionJointTerm(p, *fk, j, order, &t)) continue;
    const double c = t.weight;
    sum.e.friction_nmm += c * t.g;
    if (sum.grad)
      for (int v = 0; v < t.var_count; ++v) sum.grad[v] += c * t.grad[v];
    if (sum.hess)
      for (int v = 0; v < t.var_count; ++v)
        for (int w = 0; w < t.var_count; ++w) sum.H(v, w) += c * t.hess[w * t.var_count + v];
  }
}

// The hair volume's pair terms with the neighbouring spines' joints.
void addVolumeTerms(const SpineProblem& p, const SpineFk* fk, EnergySums& sum) {
  EnergyTerms& e = sum.e;
  double* grad = sum.grad;
  double* hess = sum.hess;
  auto H = [&](int i, int j) -> double& { return sum.H(i, j); };
  // Hair volume (docs/dynamics.md): f(r) = k psi(min - r) + k_t psi(r - max) of
  // the distance r to a neighbour's joint, psi(v) = v^3 / (6w) for 0 <= v <= w,
  // then continued as a parabola with psi'' = 1: a C2 barrier whose push grows
  // like k v beyond the width w; the cohesion part pulls back alike.
  for (const VolumeContact& c : p.volume) {
    VolumePart parts[2];
    const double k = c.stiffness_n_per_mm > 0 ? c.stiffness_n_per_mm : p.volume_stiffness_n_per_mm;
    const int np = volumeParts(fk->x[c.joint] - c.other_mm, c.push_dir, c.min_mm, c.max_mm, k,
                               p.cohesion_n_per_mm, parts);
    const int nvj = 2 * c.joint;  // only joints before it move x_j
    for (int i = 0; i < np; ++i) {
      const VolumePart& pt = parts[i];
      e.volume_nmm += pt.f;
      if (grad)
        for (int a = 0; a < nvj; ++a) grad[a] += pt.df * pt.u.dot(fk->d(c.joint, a));
      if (!hess) continue;
      for (int a = 0; a < nvj; ++a) {
        const Eigen::Vector3d& da = fk->d(c.joint, a);
        const double na = pt.u.dot(da);
        for (int b = 0; b <= a; ++b) {
          const Eigen::Vector3d& db = fk->d(c.joint, b);
          const double nb = pt.u.dot(db);
          // d2g/dq2 = dx^T (I - u u^T) dx / r (the distance only) + u . d2x
          const double across = pt.curved ? (da.dot(db) - na * nb) / pt.r : 0.0;
          const double d2g = across + pt.u.dot(fk->dd(c.joint, a, b));
          const double val = pt.ddf * na * nb + pt.df * d2g;
          H(a, b) += val;
          if (a != b) H(b, a) += val;
        }
      }
    }
  }
}

// The hair under each joint (HairCushion): E_c = k psi(r - z_j), with
// dE/dq = -k psi' dz/dq and d2E/dq2 = k (psi'' dz dz^T - psi' d2z).
void addCushionTerms(const SpineProblem& p, const SpineFk* fk, EnergySums& sum) {
  const int n = std::min<int>(p.spine->jointCount(), static_cast<int>(p.cushion.size()));
  for (int j = 1; j <= n; ++j) {
    const HairCushion& c = p.cushion[j - 1];
    const double v = c.reach_mm - fk->x[j].z();
    if (!(c.stiffness_n_per_mm > 0) || !(v > 0)) continue;
    const VolumePsi ps = volumePsi(v);
    const double k = c.stiffness_n_per_mm;
    sum.e.cushion_nmm += k * ps.psi;
    const int nvj = 2 * j;  // only joints before it move x_j
    if (sum.grad)
      for (int a = 0; a < nvj; ++a) sum.grad[a] -= k * ps.dpsi * fk->d(j, a).z();
    if (!sum.hess) continue;
    for (int a = 0; a < nvj; ++a)
      for (int b = 0; b <= a; ++b) {
        const double val =
            k * (ps.ddpsi * fk->d(j, a).z() * fk->d(j, b).z() - ps.dpsi * fk->dd(j, a, b).z());
        sum.H(a, b) += val;
        if (a != b) sum.H(b, a) += val;
      }
  }
}

}  // namespace

HairCushion hairCushion(const SpineSpec& spec, int joint) {
  HairCushion c;
  if (!spec.bundle_bears_load || joint < 1 || joint > spec.jointCount()) return c;
  c.reach_mm = spec.bundleReachMm(static_cast<size_t>(joint));
  if (c.reach_mm > 0) c.stiffness_n_per_mm = spec.flatLoadN() / c.reach_mm;
  return c;
}

double cushionForceN(const HairCushion& c, double z_mm) {
  const double v = c.reach_mm - z_mm;
  if (!(c.stiffness_n_per_mm > 0) || !(v > 0)) return 0;
  return c.stiffness_n_per_mm * volumePsi(v).dpsi;
}

double spineEnergy(const SpineProblem& p, const double* q, SpineFk* fk, EnergyTerms* terms,
                   double* grad, double* hess, EnergyParts parts) {
  const SpineSpec& s = *p.spine;
  const int nv = 2 * s.jointCount();
  const int order = hess ? 2 : (grad ? 1 : 0);
  spineForwardKinematics(s, p.handle, p.baseData(), q, order, fk);
  if (grad) std::fill(grad, grad + nv, 0.0);
  if (hess) std::fill(hess, hess + nv * nv, 0.0);
  EnergySums sum;
  sum.grad = grad;
  sum.hess = hess;
  sum.nv = nv;
  addJointTerms(p, q, sum);
  if (parts == EnergyParts::kAll) addFrictionTerms(p, fk, sum);
  addVolumeTerms(p, fk, sum);
  addCushionTerms(p, fk, sum);
  if (terms) *terms = sum.e;
  return sum.e.total();
}

bool frictionJointTerm(const SpineProblem& p, const SpineFk& fk, int j, int order,
                       FrictionJointTerm* out) {
  out->weight = 0;
  const double c = p.friction_n[j - 1];
  if (c <= 0) return false;
  Anisotropy aniso;
  aniso.strength = p.anisotropy_strength;
  aniso.exponent = p.anisotropy_exponent;
  aniso.pull_dir = p.pull_dir.empty() ? Eigen::Vector2d::Zero() : p.pull_dir[j - 1];
  const Eigen::Vector2d d = fk.x[j].head<2>() - p.anchor_xy_mm[j - 1];
  const FrictionTerm sn = frictionTerm(d, aniso, p.eps_mm);
  const int nvj = 2 * j;  // only joints 0..j-1 move x_j
  out->weight = c;
  out->g = sn.f;
  out->var_count = nvj;
  if (order < 1) return true;
  out->grad.resize(nvj);
  for (int v = 0; v < nvj; ++v) out->grad[v] = sn.grad.dot(fk.d(j, v).head<2>());
  if (order < 2) return true;
  out->hess.resize(static_cast<size_t>(nvj) * nvj);
  for (int v = 0; v < nvj; ++v) {
    const Eigen::Vector2d hdv = sn.hess * fk.d(j, v).head<2>();
    for (int w = 0; w <= v; ++w) {
      const double val = hdv.dot(fk.d(j, w).head<2>()) + sn.grad.dot(fk.dd(j, v, w).head<2>());
      out->hess[w * nvj + v] = val;
      out->hess[v * nvj + w] = val;
    }
  }
  return true;
}

}  // namespace bristle

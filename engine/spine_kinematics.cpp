#include "engine/spine_kinematics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace bristle {

JointRotation jointRotation(double theta, double phi) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(phi), sp = std::sin(phi);
  // R = Ry(phi) Rx(theta); derivatives act on one factor at a time.
  Eigen::Matrix3d rx, rxd, rxdd, ry, ryd, rydd;
  rx << 1, 0, 0, 0, ct, -st, 0, st, ct;
  rxd << 0, 0, 0, 0, -st, -ct, 0, ct, -st;
  rxdd << 0, 0, 0, 0, -ct, st, 0, -st, -ct;
  ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  ryd << -sp, 0, cp, 0, 0, 0, -cp, 0, -sp;
  rydd << -cp, 0, -sp, 0, 0, 0, sp, 0, -cp;
  JointRotation j;
  j.r = ry * rx;                 // eq. 10
  j.d[0] = ry * rxd;
  j.d[1] = ryd * rx;
  j.dd[0][0] = ry * rxdd;
  j.dd[0][1] = j.dd[1][0] = ryd * rxd;
  j.dd[1][1] = rydd * rx;
  return j;
}

JointAxis jointAxis(double theta, double phi) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(phi), sp = std::sin(phi);
  JointAxis a;
  a.a = Eigen::Vector3d(sp * ct, -st, cp * ct);  // third column of eq. 10
  a.d[0] = Eigen::Vector3d(-sp * st, -ct, -cp * st);
  a.d[1] = Eigen::Vector3d(cp * ct, 0, -sp * ct);
  a.dd[0][0] = Eigen::Vector3d(-sp * ct, st, -cp * ct);
  a.dd[0][1] = a.dd[1][0] = Eigen::Vector3d(-cp * st, 0, sp * st);
  a.dd[1][1] = Eigen::Vector3d(-sp * ct, 0, -cp * ct);
  return a;
}

std::vector<Eigen::Matrix3d> restRotations(const SpineSpec& spine) {
  std::vector<Eigen::Matrix3d> r;
  r.reserve(spine.rest_angles_rad.size());
  for (const Eigen::Vector2d& a : spine.rest_angles_rad) r.push_back(jointRotation(a[0], a[1]).r);
  return r;
}

std::vector<Eigen::Vector3d> restPoints(const SpineSpec& spine) {
  std::vector<double> q;
  for (const Eigen::Vector2d& a : spine.rest_angles_rad) q.insert(q.end(), {a[0], a[1]});
  SpineFk fk;
  spineForwardKinematics(spine, Pose{}, q.data(), 0, &fk);
  return fk.x;
}

Eigen::Vector2d eulerAnglesOfAxis(const Eigen::Matrix3d& r) {
  // Third column of eq. 10: (sin phi cos theta, -sin theta, cos phi cos theta).
  const Eigen::Vector3d a = r.col(2);
  return {std::asin(std::clamp(-a.y(), -1.0, 1.0)), std::atan2(a.x(), a.z())};
}

Eigen::Matrix3d minimalRotation(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  // Rodrigues' formula, R = I + [a x b]x + [a x b]x^2 / (1 + a.b), is exact
  // only for unit a and b, and near a half turn it divides by 1 + a.b ~ 0: the
  // rounding of axes that have been through many steps' products then grows
  // into a matrix that is no rotation at all (a bent-back tip segment of a
  // soft brush stretched to 12 times its length in a few steps). Eigen's
  // quaternion between two directions normalises them; normalised itself, its
  // matrix is a rotation to rounding.
  return Eigen::Quaterniond::FromTwoVectors(a, b).normalized().toRotationMatrix();
}

void spineForwardKinematics(const SpineSpec& spine, const Pose& handle,
                            const Eigen::Matrix3d* base, const double* q, int order,
                            SpineFk* out) {
  const int n = spine.jointCount();
  const int nv = 2 * n;
  SpineFk& fk = *out;
  fk.n = n;
  fk.x.resize(n + 1);
  if (order >= 1) fk.dx.assign((n + 1) * nv, Eigen::Vector3d::Zero());
  if (order >= 2) fk.ddx.assign((n + 1) * nv * nv, Eigen::Vector3d::Zero());

  // Fixed-size scratch for the common case; spines have at most kMaxJointsPerSpine joints.
  JointRotation rot[kMaxJointsPerSpine];
  Eigen::Matrix3d prefix[kMaxJointsPerSpine + 1];  // prefix[k] = R_h R_0 ... R_{k-1}
  prefix[0] = handle.rotation.toRotationMatrix();
  for (int k = 0; k < n; ++k) {
    rot[k] = jointRotation(q[2 * k], q[2 * k + 1]);
    if (base) {
      // R_k = B_k J(q_k): B_k is constant, so it multiplies every partial.
      rot[k].r = base[k] * rot[k].r;
      for (int a = 0; a < 2; ++a) {
        rot[k].d[a] = base[k] * rot[k].d[a];
        for (int b = 0; b < 2; ++b) rot[k].dd[a][b] = base[k] * rot[k].dd[a][b];
      }
    }
    prefix[k + 1] = prefix[k] * rot[k].r;
  }

  fk.x[0] = handle.apply(spine.root_mm);
  for (int k = 0; k < n; ++k)
    fk.x[k + 1] = fk.x[k] + prefix[k + 1] * Eigen::Vector3d(0, 0, -spine.segment_lengths_mm[k]);
  if (order < 1) return;

  // For end joint j: x_j = x_m + prefix[m] R_m tail[m], where
  // tail[m] = l_m + R_{m+1} tail[m+1] and tail[j-1] = l_{j-1}; so joint m's angles
  // enter x_j only through R_m, and derivatives replace R_m by its partials.
  Eigen::Vector3d tail[kMaxJointsPerSpine];
  for (int j = 1; j <= n; ++j) {
    tail[j - 1] = Eigen::Vector3d(0, 0, -spine.segment_lengths_mm[j - 1]);
    for (int m = j - 2; m >= 0; --m)
      tail[m] = Eigen::Vector3d(0, 0, -spine.segment_lengths_mm[m]) + rot[m + 1].r * tail[m + 1];
    for (int m = 0; m < j; ++m) {
      for (int a = 0; a < 2; ++a) {
        fk.dx[j * nv + 2 * m + a] = prefix[m] * (rot[m].d[a] * tail[m]);
        if (order < 2) continue;
        // Same joint: second derivative of R_m.
        for (int b = 0; b < 2; ++b)
          fk.ddx[(j * nv + 2 * m + a) * nv + 2 * m + b] = prefix[m] * (rot[m].dd[a][b] * tail[m]);
        // Later joint p > m: dR_m ... dR_p.
        Eigen::Matrix3d chain = prefix[m] * rot[m].d[a];  // R_h R_0..R_{m-1} dR_m
        for (int p = m + 1; p < j; ++p) {
          for (int b = 0; b < 2; ++b) {
            const Eigen::Vector3d v = chain * (rot[p].d[b] * tail[p]);
            fk.ddx[(j * nv + 2 * m + a) * nv + 2 * p + b] = v;
            fk.ddx[(j * nv + 2 * p + b) * nv + 2 * m + a] = v;
          }
          chain = chain * rot[p].r;
        }
      }
    }
  }
}

}  // namespace bristle

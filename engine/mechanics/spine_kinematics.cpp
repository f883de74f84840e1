#include "engine/mechanics/spine_kinematics.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace bristle {

Eigen::Matrix3d jointRotation(double theta, double phi) {
  const double ct = std::cos(theta), st = std::sin(theta);
  const double cp = std::cos(phi), sp = std::sin(phi);
  Eigen::Matrix3d rx, ry;
  rx << 1, 0, 0, 0, ct, -st, 0, st, ct;
  ry << cp, 0, sp, 0, 1, 0, -sp, 0, cp;
  return ry * rx;  // eq. 10
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
  for (const Eigen::Vector2d& a : spine.rest_angles_rad) r.push_back(jointRotation(a[0], a[1]));
  return r;
}

double restHairLengthMm(const Brush& brush) {
  double deepest = 0;
  SpineFk fk;
  for (const SpineSpec& spec : brush.spines) {
    const std::vector<Eigen::Matrix3d> r = restRotations(spec);
    const std::vector<double> zero(2 * spec.jointCount(), 0.0);
    spineForwardKinematics(spec, Pose{}, r.data(), zero.data(), 0, &fk);
    for (const Eigen::Vector3d& x : fk.x) deepest = std::max(deepest, -x.z());
  }
  return deepest;
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
  // Below, every call writes the same entries: those of the angles that move
  // each point. The rest are zero, so they are zeroed only when sized.
  const auto sized = [](std::vector<Eigen::Vector3d>* v, size_t count) {
    if (v->size() != count) v->assign(count, Eigen::Vector3d::Zero());
  };
  if (order >= 1) sized(&fk.dx, static_cast<size_t>(n + 1) * nv);
  if (order >= 2) sized(&fk.ddx, static_cast<size_t>(n + 1) * nv * nv);

  // prefix[k] = R_h R_0 ... R_{k-1}, the frame segment k hangs from (eq. 11).
  // Fixed-size scratch: spines have at most kMaxJointsPerSpine joints.
  Eigen::Matrix3d prefix[kMaxJointsPerSpine + 1];
  // Each angle's axis in the world frame. Variable v = 2k is theta_k, 2k + 1
  // phi_k; R_k = B_k Ry(phi) Rx(theta) turns about B_k's y axis by phi, then
  // about the x axis that turn carried along by theta.
  Eigen::Vector3d axis[2 * kMaxJointsPerSpine];
  prefix[0] = handle.rotation.toRotationMatrix();
  for (int k = 0; k < n; ++k) {
    const Eigen::Matrix3d j = jointRotation(q[2 * k], q[2 * k + 1]);
    prefix[k + 1] = prefix[k] * (base ? Eigen::Matrix3d(base[k] * j) : j);
    if (order < 1) continue;
    const Eigen::Matrix3d frame = base ? Eigen::Matrix3d(prefix[k] * base[k]) : prefix[k];
    axis[2 * k + 1] = frame.col(1);
    axis[2 * k] = frame * j.col(0);  // Ry(phi) Rx(theta) e_x = Ry(phi) e_x
  }

  fk.x[0] = handle.apply(spine.root_mm);
  for (int k = 0; k < n; ++k)
    fk.x[k + 1] = fk.x[k] + prefix[k + 1] * Eigen::Vector3d(0, 0, -spine.segment_lengths_mm[k]);
  if (order < 1) return;

  // The angles as a chain of single-axis turns, outermost first: phi_0,
  // theta_0, phi_1, theta_1, ... A turn about a unit axis w through point o
  // moves a point p at rate w x (p - o); every later axis and pivot turns
  // with it. Both angles of joint m pivot about x_m, so
  //   d x_j / d q_v = w_v x (x_j - x_m)                      (j > m)
  // and, for turns e no later than i in that chain (differentiating
  // w_i x (x_j - x_m) once more, with d w_i / d q_e = w_e x w_i, and the
  // Jacobi identity),
  //   d2 x_j / d q_e d q_i = w_e x (d x_j / d q_i).
  // The same derivatives as differentiating eq. 10's matrices (tested
  // against central differences), with cross products in place of
  // the products of 3 x 3 matrices along the chain.
  const auto chainPos = [](int v) { return v % 2 == 0 ? v + 1 : v - 1; };  // phi before theta
  for (int j = 1; j <= n; ++j) {
    const int used = 2 * j;  // the angles of joints 0 .. j-1 move x_j
    for (int v = 0; v < used; ++v) fk.dx[j * nv + v] = axis[v].cross(fk.x[j] - fk.x[v / 2]);
    if (order < 2) continue;
    for (int v = 0; v < used; ++v) {
      for (int w = v; w < used; ++w) {
        const bool v_first = chainPos(v) <= chainPos(w);
        const int e = v_first ? v : w, i = v_first ? w : v;
        const Eigen::Vector3d dd = axis[e].cross(fk.dx[j * nv + i]);
        fk.ddx[(j * nv + v) * nv + w] = dd;
        fk.ddx[(j * nv + w) * nv + v] = dd;
      }
    }
  }
}

}  // namespace bristle

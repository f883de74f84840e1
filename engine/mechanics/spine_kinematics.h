#pragma once
// Spine forward kinematics (paper §3.2, eqs. 10-11) with exact first and second
// derivatives of every joint position with respect to the joint angles.
//
// Joint k (0-based) carries angles q[2k] = theta_k, q[2k+1] = phi_k and bends
// segment k relative to its parent frame (segment k-1, or the ferrule for k = 0):
//   R_k = B_k Ry(phi_k) Rx(theta_k)                                    (eq. 10)
//   x_{k+1} = x_k + R_handle R_0 ... R_k (0, 0, -L_k)                  (eq. 11)
// so x_0 is the root and x_n the tip. B_k is a fixed base rotation per joint.
// With B_k = I this is the paper's parameterisation: theta, phi are the XYZ
// Euler angles of eq. 10, whose singularity at theta = +-90 degrees a firmly
// pressed brush reaches. The simulation instead re-bases every step
// (docs/dynamics.md): B_k is the joint's rotation at the previous step and
// (theta, phi) a small increment from it, so the singularity sits a 90-degree
// turn within one step away, which no step takes. At theta = phi = 0 and
// B_k = I a segment continues its parent straight down (-z of the brush frame).

#include <Eigen/Core>
#include <vector>

#include "engine/model/brush.h"
#include "engine/model/pose.h"

namespace bristle {

// Rotation of eq. 10, R(theta, phi) = Ry(phi) Rx(theta). Its derivatives
// are those of turns about two axes (spineForwardKinematics).
Eigen::Matrix3d jointRotation(double theta, double phi);

// Axis of a segment in its parent frame: R(theta, phi) (0, 0, 1), with derivatives.
struct JointAxis {
  Eigen::Vector3d a;
  Eigen::Vector3d d[2];
  Eigen::Vector3d dd[2][2];
};
JointAxis jointAxis(double theta, double phi);

// Positions and derivatives of one spine's joints. Index j runs over the n + 1
// points (root first); v over the 2n angle variables.
struct SpineFk {
  int n = 0;
  std::vector<Eigen::Vector3d> x;    // (n + 1), world mm
  std::vector<Eigen::Vector3d> dx;   // (n + 1) * 2n: dx[j * 2n + v] = d x_j / d q_v
  std::vector<Eigen::Vector3d> ddx;  // (n + 1) * 2n * 2n: d2 x_j / dq_v dq_w

  int vars() const { return 2 * n; }
  const Eigen::Vector3d& d(int j, int v) const { return dx[j * vars() + v]; }
  const Eigen::Vector3d& dd(int j, int v, int w) const {
    return ddx[(j * vars() + v) * vars() + w];
  }
};

// order 0: positions only; 1: + first derivatives; 2: + second derivatives.
// `out` is resized on first use and reused without allocation afterwards.
// `base` holds the n base rotations B_k, or is null for B_k = I. They must be
// rotations (orthonormal, to rounding): the derivatives turn about their axes.
void spineForwardKinematics(const SpineSpec& spine, const Pose& handle,
                            const Eigen::Matrix3d* base, const double* q, int order,
                            SpineFk* out);
// The paper's parameterisation (every B_k = I): q are eq. 10's angles.
inline void spineForwardKinematics(const SpineSpec& spine, const Pose& handle, const double* q,
                                   int order, SpineFk* out) {
  spineForwardKinematics(spine, handle, nullptr, q, order, out);
}

// The rotation of each joint at rest, R(rest theta, rest phi) of eq. 10.
std::vector<Eigen::Matrix3d> restRotations(const SpineSpec& spine);
// The spine's n + 1 points at its rest angles under the identity handle, in
// the brush frame (mm), root first.
std::vector<Eigen::Vector3d> restPoints(const SpineSpec& spine);

// The length of the brush's hair along its axis at rest: how far below the
// ferrule its lowest joint hangs (mm).
double restHairLengthMm(const Brush& brush);

// The eq. 10 angles (theta, phi) whose rotation has the same axis as r: for
// reports (the trace) only; undefined in phi at theta = +-90 degrees.
Eigen::Vector2d eulerAnglesOfAxis(const Eigen::Matrix3d& r);

// The smallest rotation taking direction a to direction b (about a x b), an
// exact rotation whatever the inputs' lengths. Requires a . b > -|a||b| (not
// opposite).
Eigen::Matrix3d minimalRotation(const Eigen::Vector3d& a, const Eigen::Vector3d& b);

}  // namespace bristle

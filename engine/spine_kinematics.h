#pragma once
// Spine forward kinematics (paper §3.2, eqs. 10-11) with exact first and second
// derivatives of every joint position with respect to the joint angles.
//
// Joint k (0-based) carries angles q[2k] = theta_k, q[2k+1] = phi_k and bends
// segment k relative to its parent frame (segment k-1, or the ferrule for k = 0):
//   R_k = Ry(phi_k) Rx(theta_k)                                        (eq. 10)
//   x_{k+1} = x_k + R_handle R_0 ... R_k (0, 0, -L_k)                  (eq. 11)
// so x_0 is the root and x_n the tip. At theta = phi = 0 a segment continues its
// parent straight down (-z of the brush frame).

#include <Eigen/Core>
#include <vector>

#include "engine/brush.h"
#include "engine/pose.h"

namespace bristle {

// Rotation of eq. 10 and its partial derivatives.
struct JointRotation {
  Eigen::Matrix3d r;                  // R(theta, phi)
  Eigen::Matrix3d d[2];               // dR/dtheta, dR/dphi
  Eigen::Matrix3d dd[2][2];           // second partials (symmetric)
};
JointRotation jointRotation(double theta, double phi);

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
void spineForwardKinematics(const SpineSpec& spine, const Pose& handle, const double* q,
                            int order, SpineFk* out);

}  // namespace bristle

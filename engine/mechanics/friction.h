#pragma once
// Coulomb friction work of one contact joint (paper eq. 3) with the anisotropy
// of eqs. 13-14, smoothed so that Ipopt sees a C2 function:
//   E_f = (1 - eta) mu |F_n| |dx|,   eta = C_eta max(0, d_p . dx / |dx|)^k
// |dx| -> r - eps with r = sqrt(dx.dx + eps^2); dx / |dx| -> dx / r;
// max(0, s) -> (s + sqrt(s^2 + delta^2)) / 2.

#include <Eigen/Core>

namespace bristle {

struct FrictionTerm {
  double f = 0;  // energy per unit mu |F_n| (mm)
  Eigen::Vector2d grad = Eigen::Vector2d::Zero();
  Eigen::Matrix2d hess = Eigen::Matrix2d::Zero();
};

struct Anisotropy {
  Eigen::Vector2d pull_dir = Eigen::Vector2d::Zero();  // d_p, unit; zero = isotropic
  double strength = 0;                                  // C_eta in [0, 1]
  double exponent = 2;                                  // k >= 1
};

// Smoothing width of max(0, s) on the cosine s = d_p . dx / |dx|.
inline constexpr double kSmoothCos = 1e-3;

FrictionTerm frictionTerm(const Eigen::Vector2d& dx_mm, const Anisotropy& a, double eps_mm);

}  // namespace bristle

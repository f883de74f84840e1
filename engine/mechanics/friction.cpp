#include "engine/mechanics/friction.h"

#include <cmath>

namespace bristle {

FrictionTerm frictionTerm(const Eigen::Vector2d& dx, const Anisotropy& a, double eps) {
  const double r = std::sqrt(dx.squaredNorm() + eps * eps);
  const Eigen::Matrix2d I = Eigen::Matrix2d::Identity();
  FrictionTerm t;
  // Isotropic part, eq. 3: |dx| smoothed.
  const double f = r - eps;
  const Eigen::Vector2d gf = dx / r;
  const Eigen::Matrix2d hf = (I - dx * dx.transpose() / (r * r)) / r;
  if (a.strength <= 0 || a.pull_dir.squaredNorm() == 0) {
    t.f = f;
    t.grad = gf;
    t.hess = hf;
    return t;
  }
  // eq. 14: eta = C max(0, s)^k with s the cosine between d_p and dx.
  const Eigen::Vector2d& d = a.pull_dir;
  const double ad = d.dot(dx);
  const double s = ad / r;
  const Eigen::Vector2d gs = d / r - ad * dx / (r * r * r);
  const Eigen::Matrix2d hs = -(d * dx.transpose() + dx * d.transpose()) / (r * r * r) -
                             ad * (I / (r * r * r) - 3 * dx * dx.transpose() / std::pow(r, 5));
  const double q = std::sqrt(s * s + kSmoothCos * kSmoothCos);
  const double m = 0.5 * (s + q);  // smoothed max(0, s), > 0
  const double dm = 0.5 * (1 + s / q);
  const double ddm = 0.5 * kSmoothCos * kSmoothCos / (q * q * q);
  const double C = a.strength, k = a.exponent;
  const double mk1 = std::pow(m, k - 1);
  const double eta = C * mk1 * m;
  const double deta_ds = C * k * mk1 * dm;
  const double d2eta_ds2 = C * k * ((k - 1) * std::pow(m, k - 2) * dm * dm + mk1 * ddm);
  const Eigen::Vector2d geta = deta_ds * gs;
  const Eigen::Matrix2d heta = d2eta_ds2 * gs * gs.transpose() + deta_ds * hs;
  // eq. 13: (1 - eta) |dx|.
  t.f = (1 - eta) * f;
  t.grad = (1 - eta) * gf - f * geta;
  t.hess = (1 - eta) * hf - gf * geta.transpose() - geta * gf.transpose() - f * heta;
  return t;
}

}  // namespace bristle

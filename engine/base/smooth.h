#pragma once
// Smooth stand-ins for the non-smooth terms of the spine energy. Ipopt needs a
// twice-differentiable objective: unsmoothed, the optimum sits on a kink (a
// sticking joint has dx = 0) and Ipopt runs to max_iter (docs/design.md,
// "Solver notes").

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace bristle {

// ||v|| of a 2-vector ~ sqrt(v.v + eps^2) - eps, with gradient and Hessian.
struct Smooth2 {
  double f;
  Eigen::Vector2d grad;
  Eigen::Matrix2d hess;
};
inline Smooth2 smoothNorm(const Eigen::Vector2d& v, double eps) {
  const double r = std::sqrt(v.squaredNorm() + eps * eps);
  Smooth2 s;
  s.f = r - eps;
  s.grad = v / r;
  s.hess = (Eigen::Matrix2d::Identity() - v * v.transpose() / (r * r)) / r;
  return s;
}

// beta^2 as a function of w = 1 - cos(beta) (eq. 12: cos(beta) = cos(theta) cos(phi)),
// smooth at w = 0 where acos has an infinite derivative:
// beta^2 = 4 asin^2(sqrt(w / 2)) = 2 sum_n (2w)^n / (n^2 C(2n, n)).
struct BendSquared {
  double h, dh, ddh;  // beta^2 and its derivatives with respect to w
};
inline BendSquared bendSquared(double w) {
  // Below this w the series (8 terms) is exact to double precision: the first
  // omitted term is 2 (2w)^9 / (81 * 48620) < 3e-22 at w = 1e-2 (h is ~2e-2 there).
  constexpr double kSeriesBelow = 1e-2;
  BendSquared b{};
  if (w < kSeriesBelow) {
    const double x = 2 * w;
    double p1 = 1;       // x^(n-1)
    double p2 = 0;       // x^(n-2), absent for n = 1
    double binom = 2;    // C(2n, n)
    for (int n = 1; n <= 8; ++n) {
      const double c = 2.0 / (double(n) * n * binom);
      b.h += c * p1 * x;
      b.dh += c * n * 2 * p1;
      b.ddh += c * n * (n - 1) * 4 * p2;
      p2 = p1;
      p1 *= x;
      binom *= (2.0 * n + 1) * (2.0 * n + 2) / ((n + 1.0) * (n + 1.0));
    }
    return b;
  }
  const double beta = std::acos(std::max(-1.0, 1.0 - w));
  const double sb = std::max(std::sin(beta), 1e-12);
  const double cb = std::cos(beta);
  b.h = beta * beta;
  b.dh = 2 * beta / sb;                                  // dbeta/dw = 1 / sin(beta)
  b.ddh = 2 * (sb - beta * cb) / (sb * sb * sb);
  return b;
}

}  // namespace bristle

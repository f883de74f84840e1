#include "tests/support/tube_cage.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "engine/mechanics/spine_kinematics.h"  // restPoints

namespace bristle {

SurfaceSpec makeTubeCage(const Brush& brush, int ring_vertices, int refinement_level) {
  const int m = ring_vertices;
  if (m < 3 || m > 64)
    throw Error(ExitCode::kUsage,
                "makeTubeCage: ring_vertices = " + std::to_string(m) + ": must be in [3, 64]");
  if (refinement_level < 0 || refinement_level > kMaxRefinementLevel)
    throw Error(ExitCode::kUsage, "makeTubeCage: refinement_level = " +
                                      std::to_string(refinement_level) + ": must be in [0, " +
                                      std::to_string(kMaxRefinementLevel) + "]");
  if (brush.spines.empty()) throw Error(ExitCode::kUsage, brush.path + ": makeTubeCage: no spines");
  // A ring no thinner than this (mm) keeps a zero tip width from collapsing faces.
  constexpr double kMinRadiusMm = 0.01;
  // The Catmull-Clark limit of a regular m-gon ring is a B-spline circle whose
  // radius is (4 + 2 cos(2 pi / m)) / 6 of the ring's: grow the ring by the inverse.
  const double grow = 6 / (4 + 2 * std::cos(2 * std::numbers::pi / m));

  const int ns = static_cast<int>(brush.spines.size());
  std::vector<std::vector<Eigen::Vector3d>> rest(ns);  // rest points, brush frame
  int levels = 0;
  for (int s = 0; s < ns; ++s) {
    rest[s] = restPoints(brush.spines[s]);
    levels = std::max(levels, brush.spines[s].jointCount());
  }
  auto point = [&](int s, int j) { return std::min(j, brush.spines[s].jointCount()); };

  SurfaceSpec out;
  out.refinement_level = refinement_level;
  for (int j = 0; j <= levels; ++j) {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int s = 0; s < ns; ++s) centre += rest[s][point(s, j)] / double(ns);
    for (int i = 0; i < m; ++i) {
      const double a = 2 * std::numbers::pi * i / m;
      const Eigen::Vector3d d(std::cos(a), std::sin(a), 0);
      double r = kMinRadiusMm;  // support function of the inflated spine points
      for (int s = 0; s < ns; ++s)
        r = std::max(r, (rest[s][point(s, j)] - centre).dot(d) +
                            brush.spines[s].width_mm[point(s, j)] / 2);
      const Eigen::Vector3d x = centre + grow * r * d;
      int nearest = 0;
      for (int s = 1; s < ns; ++s)
        if ((rest[s][point(s, j)] - x).norm() < (rest[nearest][point(nearest, j)] - x).norm())
          nearest = s;
      out.cage_mm.push_back(x);
      out.skin.push_back({SkinInfluence{nearest, point(nearest, j), 1.0}});
    }
  }
  // The tip vertex: half the tip width beyond each tip, along its last segment.
  Eigen::Vector3d tip = Eigen::Vector3d::Zero();
  std::vector<SkinInfluence> tip_skin;
  for (int s = 0; s < ns; ++s) {
    const int n = brush.spines[s].jointCount();
    const Eigen::Vector3d dir = (rest[s][n] - rest[s][n - 1]).normalized();
    tip += (rest[s][n] + dir * brush.spines[s].width_mm[n] / 2) / double(ns);
    tip_skin.push_back({s, n, 1.0 / ns});
  }
  out.cage_mm.push_back(tip);
  out.skin.push_back(tip_skin);

  // Outward orientation: down ring i, across, back up (counter-clockwise rings).
  for (int j = 0; j < levels; ++j)
    for (int i = 0; i < m; ++i)
      out.faces.push_back(
          {j * m + i, (j + 1) * m + i, (j + 1) * m + (i + 1) % m, j * m + (i + 1) % m});
  const int last = levels * m, t = (levels + 1) * m;
  for (int i = 0; i < m; ++i) out.faces.push_back({last + i, t, last + (i + 1) % m});
  return out;
}

}  // namespace bristle

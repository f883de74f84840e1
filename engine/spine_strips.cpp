#include "engine/spine_strips.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bristle {

double bundleSpread(double radius_mm, double reach_mm) {
  const double r = radius_mm;
  if (!(r > 0) || reach_mm >= r) return 1;
  const double h = std::max(reach_mm, 0.0);
  // The circular segment beyond the canvas, r^2 acos(h/r) - h sqrt(r^2 - h^2),
  // is pressed aside: widening by f restores the area on the near side,
  // f (pi r^2 - segment) = pi r^2.
  const double area = std::numbers::pi * r * r;
  const double segment = r * r * std::acos(h / r) - h * std::sqrt(r * r - h * h);
  return area / (area - segment);
}

void buildSpineGeometry(const Brush& brush, const BrushState& state,
                        std::vector<BrushVertex>* triangles) {
  // Fallback side direction for a vertical segment: the brush frame's x axis.
  const Eigen::Vector3d brush_x = state.handle.rotation * Eigen::Vector3d::UnitX();
  const size_t ns = brush.spines.size();
  constexpr int F = kTubeFacets;
  std::vector<Eigen::Vector3d> ring;
  for (size_t s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush.spines[s];
    const std::vector<Eigen::Vector3d>& x = state.spines[s].joints_mm;
    const int n = spec.jointCount();
    ring.assign((n + 1) * (F + 1), Eigen::Vector3d::Zero());
    for (int j = 0; j <= n; ++j) {
      // Tangent at joint j: the mean of the adjacent segment directions.
      Eigen::Vector3d t = Eigen::Vector3d::Zero();
      if (j > 0) t += (x[j] - x[j - 1]).normalized();
      if (j < n) t += (x[j + 1] - x[j]).normalized();
      t.normalize();
      // Side: across the hair in the canvas plane; down: across the hair,
      // towards the canvas. The half tube spans side -> down -> -side.
      Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(t);
      if (side.norm() < 1e-6) side = brush_x - brush_x.dot(t) * t;
      // The tube starts on the brush's -x side, so that u runs across the
      // brush's width axis whichever way the hair points (the paint texture's
      // "across", engine/paint.h).
      if (side.dot(brush_x) > 0) side = -side;
      side.normalize();
      Eigen::Vector3d down = t.cross(side);
      if (down.z() > 0) down = -down;
      // The bundle flattens on the paper (see bundleSpread): the distance to
      // the canvas is measured along `down`, the direction the tube reaches it.
      const double r = 0.5 * spec.width_mm[j];
      const double reach = down.z() < -1e-9 ? x[j].z() / -down.z() : r;
      const double spread = bundleSpread(r, reach);
      for (int k = 0; k <= F; ++k) {
        const double a = std::numbers::pi * k / F;
        ring[j * (F + 1) + k] = x[j] + r * (spread * std::cos(a) * side + std::sin(a) * down);
      }
    }
    auto vtx = [&](int j, int k) {
      const Eigen::Vector3d& p = ring[j * (F + 1) + k];
      return BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                         static_cast<float>(p.z()), static_cast<float>((s + double(k) / F) / ns),
                         static_cast<float>(double(j) / n)};
    };
    // Round the bundle off at every joint with the lower half of a sphere of the
    // same radius: a joint that touches the canvas (a hair tip poking straight
    // down, say) always shows, however steeply its segments rise.
    for (int j = 1; j <= n; ++j) {
      const double r = 0.5 * spec.width_mm[j];
      if (r <= 0) continue;
      const double spread = bundleSpread(r, x[j].z());
      auto cap = [&](int lat, int lon) {  // lat 0 = lowest point .. kCapRings = equator
        const double polar = 0.5 * std::numbers::pi * lat / kCapRings;
        const double az = 2 * std::numbers::pi * lon / (2 * F);
        const Eigen::Vector3d p =
            x[j] + r * Eigen::Vector3d(spread * std::sin(polar) * std::cos(az),
                                       spread * std::sin(polar) * std::sin(az),
                                       -std::cos(polar));
        return BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                           static_cast<float>(p.z()), static_cast<float>((s + 0.5) / ns),
                           static_cast<float>(double(j) / n)};
      };
      for (int lat = 0; lat < kCapRings; ++lat)
        for (int lon = 0; lon < 2 * F; ++lon) {
          triangles->push_back(cap(lat, lon));
          triangles->push_back(cap(lat + 1, lon));
          triangles->push_back(cap(lat + 1, lon + 1));
          if (lat == 0) continue;  // the pole row is a fan
          triangles->push_back(cap(lat, lon));
          triangles->push_back(cap(lat + 1, lon + 1));
          triangles->push_back(cap(lat, lon + 1));
        }
    }
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < F; ++k) {
        triangles->push_back(vtx(j, k));
        triangles->push_back(vtx(j, k + 1));
        triangles->push_back(vtx(j + 1, k + 1));
        triangles->push_back(vtx(j, k));
        triangles->push_back(vtx(j + 1, k + 1));
        triangles->push_back(vtx(j + 1, k));
      }
  }
}

}  // namespace bristle

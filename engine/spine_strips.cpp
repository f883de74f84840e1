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

double bundlePressDepth(double radius_mm, double load_n) {
  if (!(radius_mm > 0) || !(load_n > 0)) return 0;
  return radius_mm * std::min(1.0, load_n / kBundleFlatLoadN);
}

void buildSpineGeometry(const Brush& brush, const BrushState& state,
                        std::vector<BrushVertex>* triangles) {
  // Fallback side direction for a vertical segment: the brush frame's x axis.
  const Eigen::Vector3d brush_x = state.handle.rotation * Eigen::Vector3d::UnitX();
  const size_t ns = brush.spines.size();
  constexpr int F = kTubeFacets;
  std::vector<Eigen::Vector3d> ring, sides, centre;
  for (size_t s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush.spines[s];
    const std::vector<Eigen::Vector3d>& x = state.spines[s].joints_mm;
    const int n = spec.jointCount();
    ring.assign((n + 1) * (F + 1), Eigen::Vector3d::Zero());
    sides.assign(n + 1, Eigen::Vector3d::Zero());
    // How hard this spine's bundle presses the paper: the canvas forces on its
    // joints (eq. 5's multipliers). The solver puts the contact load on
    // whichever joints are held on the canvas, while the hair between them
    // lies along the paper and shares it, so the load is the spine's, not
    // the joint's.
    double load_n = 0;
    for (double f : state.spines[s].solution.normal_force_n) load_n += f;
    // Each joint's bundle: its centre raised until the half sphere around it
    // (the part that reaches lowest) is only as deep below the canvas as the
    // load presses it, see kBundleFlatLoadN.
    centre.assign(n + 1, Eigen::Vector3d::Zero());
    for (int j = 0; j <= n; ++j) {
      const double r = 0.5 * spec.width_mm[j];
      const double sunk = r - std::max(x[j].z(), 0.0);  // below the canvas, as placed
      const double raise = std::max(0.0, sunk - bundlePressDepth(r, load_n));
      centre[j] = x[j] + raise * Eigen::Vector3d::UnitZ();
    }
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
      sides[j] = side;
      Eigen::Vector3d down = t.cross(side);
      if (down.z() > 0) down = -down;
      // The bundle flattens on the paper (see bundleSpread): the distance to
      // the canvas is measured along `down`, the direction the tube reaches it.
      const double r = 0.5 * spec.width_mm[j];
      const Eigen::Vector3d& c = centre[j];
      const double reach = down.z() < -1e-9 ? c.z() / -down.z() : r;
      const double spread = bundleSpread(r, reach);
      for (int k = 0; k <= F; ++k) {
        const double a = std::numbers::pi * k / F;
        ring[j * (F + 1) + k] = c + r * (spread * std::cos(a) * side + std::sin(a) * down);
      }
    }
    // Where a point of the bundle lies across it, as the texture's u: the
    // bundle's hair keeps its place across the brush, so a point spread
    // sideways (bundleSpread) by d mm from the spine stands for the hair
    // that lies d mm out at rest, u = s + 1/2 + d / width, clamped to the
    // spine's own [s, s + 1] (its edge hairs). Neighbouring spines then
    // agree on the hair at a point where their bundles meet, and a double
    // load blends across the seam instead of changing colour at it.
    auto acrossU = [&](int j, const Eigen::Vector3d& p) {
      const double d = -(p - centre[j]).dot(sides[j]);  // towards the brush's +x
      const double width = spec.width_mm[j] > 0 ? spec.width_mm[j] : 1.0;
      return static_cast<float>((s + std::clamp(0.5 + d / width, 0.0, 1.0)) / ns);
    };
    auto vtx = [&](int j, int k) {
      const Eigen::Vector3d& p = ring[j * (F + 1) + k];
      return BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                         static_cast<float>(p.z()), acrossU(j, p),
                         static_cast<float>(double(j) / n)};
    };
    // Round the bundle off at every joint with the lower half of a sphere of the
    // same radius: a joint that touches the canvas (a hair tip poking straight
    // down, say) always shows, however steeply its segments rise. Its u runs
    // across the bundle as the tube's does (acrossU), so that the hairs at
    // the tip keep their place across the brush: a flat's pressed tips carry
    // both paints of a double load, and each hair its own streak
    // (engine/paint.h, hairNoise).
    for (int j = 1; j <= n; ++j) {
      const double r = 0.5 * spec.width_mm[j];
      if (r <= 0) continue;
      const Eigen::Vector3d& c = centre[j];
      const double spread = bundleSpread(r, c.z());
      // The hairs of a bundle end together, cut to length: past the last
      // joint the bundle ends in a face, not a dome. So the tip's cap
      // reaches only kTipCapDepth of its radius beyond the tip along the
      // hair, in proportion to how flat the hair lies (a tip poking
      // straight down keeps its full depth below the joint: that is the
      // contact, eq. 5). A flat's stroke then starts square (docs/paint.md,
      // "Square ends": its stop end is squarer but still rounds at the corners).
      Eigen::Vector2d along = Eigen::Vector2d::Zero();
      if (j == n) {
        const Eigen::Vector3d t = (x[n] - x[n - 1]).normalized();
        along = t.head<2>();  // |along| = cos(elevation)
      }
      const double squash = 1 - kTipCapDepth;
      auto cap = [&](int lat, int lon) {  // lat 0 = lowest point .. kCapRings = equator
        const double polar = 0.5 * std::numbers::pi * lat / kCapRings;
        const double az = 2 * std::numbers::pi * lon / (2 * F);
        Eigen::Vector2d flat(spread * std::sin(polar) * std::cos(az),
                             spread * std::sin(polar) * std::sin(az));
        flat -= squash * flat.dot(along) * along;
        const Eigen::Vector3d p = c + r * Eigen::Vector3d(flat.x(), flat.y(), -std::cos(polar));
        return BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                           static_cast<float>(p.z()), acrossU(j, p),
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

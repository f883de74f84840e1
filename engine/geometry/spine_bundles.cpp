#include "engine/geometry/spine_bundles.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>
#include <vector>

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

double bundlePressDepth(double radius_mm, double load_n, double flat_load_n) {
  if (!(radius_mm > 0) || !(load_n > 0)) return 0;
  return radius_mm * std::min(1.0, load_n / flat_load_n);
}

namespace {

// The hair bundle around one joint. Across the hair it is a superellipse
// |x / a|^p + |y / b|^p = 1 with semi-axes a along e1 (the brush frame's x
// axis, projected across the hair: a flat's width) and b along e2 (across
// its face): a circle for a round bundle (a = b, p = 2), a rounded rectangle
// for a flat's slab (p = kSlabSectionExponent). Along the hair, for the half
// solid that rounds the bundle off at the joint, it reaches c = sqrt(a b)
// (= r for a round one), with an elliptic profile.
struct BundleSection {
  Eigen::Vector3d t, e1, e2;
  double a = 0, b = 0, c = 0, p = 2;
  double flare = 1;  // how much of bundleSpread's widening it takes

  // bundleSpread for this section, of the extent it reaches (mm) and how far
  // the canvas is from its centre that way (mm).
  double spread(double extent_mm, double reach_mm) const {
    return 1 + flare * (bundleSpread(extent_mm, reach_mm) - 1);
  }

  bool empty() const { return !(a > 0) || !(b > 0); }
  // The section's own norm of (x, y) in units of its semi-axes: 1 on its edge.
  double norm(double x, double y) const {
    if (p == 2) return std::hypot(x, y);
    if (p == kSlabSectionExponent) return slabNorm(x, y);
    return std::pow(std::pow(std::fabs(x), p) + std::pow(std::fabs(y), p), 1 / p);
  }
  // (|x|^24 + |y|^24)^(1/24) as m (1 + r^24)^(1/24), m the larger magnitude
  // and r <= 1 the ratio of the smaller to it: r^24 by squaring, and no root
  // at all where r^24 is below double precision's relative step (r < 0.22,
  // most of a slab's outline, where the norm is m to the last bit). Three
  // pow() calls per outline point would be a tenth of a flat's render with
  // SLSQP (docs/PERFORMANCE.md, "Three trims with the same bytes").
  static double slabNorm(double x, double y) {
    static_assert(kSlabSectionExponent == 24, "slabNorm computes r^24 by squaring");
    const double ax = std::fabs(x), ay = std::fabs(y);
    const double m = std::max(ax, ay);
    if (!(m > 0)) return 0;
    const double r = std::min(ax, ay) / m;
    const double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4, r24 = r8 * r8 * r8;
    if (r24 < 0x1p-53) return m;
    return m * std::pow(1 + r24, 1 / kSlabSectionExponent);
  }
  // Distance from the centre to the section's edge along d, a unit vector
  // across the hair.
  double radiusAcross(const Eigen::Vector3d& d) const {
    if (empty()) return 0;
    return 1 / norm(d.dot(e1) / a, d.dot(e2) / b);
  }
  // Distance from the centre to the half solid's surface along d, any unit
  // vector.
  double radius(const Eigen::Vector3d& d) const {
    if (empty()) return 0;
    const double s = norm(d.dot(e1) / a, d.dot(e2) / b), z = d.dot(t) / c;
    return 1 / std::sqrt(s * s + z * z);
  }
  // How far the section reaches from the centre along the unit vector d: its
  // support function, with the dual exponent q = p / (p - 1) (= r for a
  // round one).
  double extentAcross(const Eigen::Vector3d& d) const {
    const double x = a * d.dot(e1), y = b * d.dot(e2);
    if (p == 2) return std::hypot(x, y);
    const double q = p / (p - 1);
    return std::pow(std::pow(std::fabs(x), q) + std::pow(std::fabs(y), q), 1 / q);
  }
  // How far below its centre the half solid reaches.
  double depth() const {
    const double across = extentAcross(Eigen::Vector3d::UnitZ()), along = c * t.z();
    return std::sqrt(across * across + along * along);
  }
};

// Each point's bundle section, around the spine's points x (root first) of a
// brush held at `handle`.
void bundleSections(const SpineSpec& spec, const std::vector<Eigen::Vector3d>& x,
                    const Pose& handle, std::vector<BundleSection>* section_out) {
  const int n = spec.jointCount();
  const Eigen::Vector3d brush_x = handle.rotation * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d brush_y = handle.rotation * Eigen::Vector3d::UnitY();
  std::vector<BundleSection>& section = *section_out;
  section.assign(n + 1, BundleSection{});
  for (int j = 0; j <= n; ++j) {
    // Tangent at joint j: the mean of the adjacent segment directions.
    BundleSection& q = section[j];
    q.t = Eigen::Vector3d::Zero();
    if (j > 0) q.t += (x[j] - x[j - 1]).normalized();
    if (j < n) q.t += (x[j + 1] - x[j]).normalized();
    q.t.normalize();
    q.e1 = brush_x - brush_x.dot(q.t) * q.t;
    if (q.e1.norm() < 1e-6) q.e1 = brush_y - brush_y.dot(q.t) * q.t;
    q.e1.normalize();
    q.e2 = q.t.cross(q.e1);
    q.a = 0.5 * spec.width_mm[j];
    q.b = 0.5 * spec.thicknessMm(j);
    q.c = std::sqrt(q.a * q.b);
    if (!spec.thickness_mm.empty()) {
      q.p = kSlabSectionExponent;
      q.flare = kSlabFlare;
    }
  }
}

// Each point's bundle section, and the centre it is drawn around: the joint,
// raised until the bundle reaches only as deep below the canvas as the
// spine's load presses it (bundlePressDepth).
void spineBundles(const SpineSpec& spec, const SpineState& spine, const Pose& handle,
                  std::vector<BundleSection>* section_out,
                  std::vector<Eigen::Vector3d>* centre_out) {
  const std::vector<Eigen::Vector3d>& x = spine.joints_mm;
  const int n = spec.jointCount();
  bundleSections(spec, x, handle, section_out);
  const std::vector<BundleSection>& section = *section_out;
  std::vector<Eigen::Vector3d>& centre = *centre_out;
  // How hard this spine's bundle presses the paper: the canvas forces on its
  // joints (eq. 5's multipliers). The solver puts the contact load on
  // whichever joints are held on the canvas, while the hair between them
  // lies along the paper and shares it, so the load is the spine's, not
  // the joint's.
  double load_n = 0;
  for (double f : spine.solution.normal_force_n) load_n += f;
  // Each joint's bundle: its centre raised until the half solid around it
  // (the part that reaches lowest) is only as deep below the canvas as
  // the load presses it, see kBundleFlatLoadN (or the spine's own flat_load_n).
  const double flat_load_n = spec.flatLoadN();
  centre.assign(n + 1, Eigen::Vector3d::Zero());
  for (int j = 0; j <= n; ++j) {
    const double r = section[j].depth();
    const double sunk = r - std::max(x[j].z(), 0.0);  // below the canvas, as placed
    const double raise = std::max(0.0, sunk - bundlePressDepth(r, load_n, flat_load_n));
    centre[j] = x[j] + raise * Eigen::Vector3d::UnitZ();
  }
}

}  // namespace

BundlePlacement bundlePlacement(const SpineSpec& spec, const SpineState& spine,
                                const Pose& handle) {
  std::vector<BundleSection> section;
  std::vector<Eigen::Vector3d> centre;
  spineBundles(spec, spine, handle, &section, &centre);
  std::vector<double> raise(section.size()), depth(section.size());
  for (size_t j = 0; j < section.size(); ++j) {
    raise[j] = centre[j].z() - spine.joints_mm[j].z();
    depth[j] = std::max(0.0, section[j].depth() - centre[j].z());
  }
  return BundlePlacement{std::move(raise), std::move(depth)};
}

std::vector<double> bundleReachBelowPoints(const SpineSpec& spec,
                                           const std::vector<Eigen::Vector3d>& joints_mm,
                                           const Pose& handle) {
  std::vector<BundleSection> section;
  bundleSections(spec, joints_mm, handle, &section);
  std::vector<double> reach(section.size());
  // At the root the tube's section ends (no half solid there): it reaches
  // its section's extent downwards; at a joint, the half solid's depth.
  for (size_t j = 0; j < section.size(); ++j)
    reach[j] = section[j].empty() ? 0
               : j == 0           ? section[j].extentAcross(Eigen::Vector3d::UnitZ())
                                  : section[j].depth();
  return reach;
}

namespace {

constexpr int F = kTubeFacets;

// One spine's dressing for a step: its bundle sections, the centres they are
// drawn around (spineBundles), and the half-tube ring at each point 0..n
// (F + 1 points from side through down to -side).
struct SpineTube {
  std::vector<BundleSection> section;
  std::vector<Eigen::Vector3d> centre;
  std::vector<Eigen::Vector3d> sides;  // per point: across the hair, towards the brush's -x
  std::vector<Eigen::Vector3d> ring;   // (n + 1) x (F + 1)
  std::vector<BrushVertex> grid;       // one cap's or the tube's vertices (scratch)
};

// Appends triangle (a, b, c) if it reaches down to below_mm (reachesDown).
void pushTriangle(const BrushVertex& a, const BrushVertex& b, const BrushVertex& c,
                  double below_mm, std::vector<BrushVertex>* triangles) {
  if (!reachesDown(a, b, c, below_mm)) return;
  triangles->push_back(a);
  triangles->push_back(b);
  triangles->push_back(c);
}

// Float rounding of a cap's vertices (world mm, float: a relative 6e-8, so
// 6e-6 mm at 100 mm from the origin) is far below this margin of the caps'
// cull, which only needs to be safe: a cap within it is built and its
// triangles tested one by one.
constexpr double kCapCullMarginMm = 1e-3;

// The unit directions the spines' dressing is built from, computed once:
// every vertex of a half tube or half solid shares the same few angles, and
// their sines and cosines per vertex were a quarter of the dressing's cost
// (docs/PERFORMANCE.md, "Three trims with the same bytes").
// tube[k]: (cos a, sin a) of the half tube's angle a = pi k / F, from side
// (k = 0) through down to -side. cap[lat][lon]: the half solid's direction
// at polar angle 90 deg lat / kCapRings from straight down (lat 0, its lowest
// point, to kCapRings, its equator) and azimuth 360 deg lon / 2F.
struct DressingDirections {
  Eigen::Vector2d tube[F + 1];
  Eigen::Vector3d cap[kCapRings + 1][2 * F + 1];
};

const DressingDirections& dressingDirections() {
  static const DressingDirections dirs = [] {
    DressingDirections d;
    for (int k = 0; k <= F; ++k) {
      const double a = std::numbers::pi * k / F;
      d.tube[k] = Eigen::Vector2d(std::cos(a), std::sin(a));
    }
    for (int lat = 0; lat <= kCapRings; ++lat)
      for (int lon = 0; lon <= 2 * F; ++lon) {
        const double polar = 0.5 * std::numbers::pi * lat / kCapRings;
        const double az = 2 * std::numbers::pi * lon / (2 * F);
        d.cap[lat][lon] = Eigen::Vector3d(std::sin(polar) * std::cos(az),
                                          std::sin(polar) * std::sin(az), -std::cos(polar));
      }
    return d;
  }();
  return dirs;
}

// Places the half-tube rings of one spine.
void placeTubeRings(const SpineSpec& spec, const SpineState& spine, const Pose& handle,
                    SpineTube* tube) {
  const Eigen::Vector3d brush_x = handle.rotation * Eigen::Vector3d::UnitX();
  const int n = spec.jointCount();
  tube->ring.assign((n + 1) * (F + 1), Eigen::Vector3d::Zero());
  tube->sides.assign(n + 1, Eigen::Vector3d::Zero());
  spineBundles(spec, spine, handle, &tube->section, &tube->centre);
  const DressingDirections& dirs = dressingDirections();
  for (int j = 0; j <= n; ++j) {
    const BundleSection& q = tube->section[j];
    // Side: across the hair in the canvas plane; down: across the hair,
    // towards the canvas. The half tube spans side -> down -> -side.
    Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(q.t);
    if (side.norm() < 1e-6) side = brush_x - brush_x.dot(q.t) * q.t;
    // The tube starts on the brush's -x side, so that u runs across the
    // brush's width axis whichever way the hair points (the paint texture's
    // "across", engine/paint/paint.h).
    if (side.dot(brush_x) > 0) side = -side;
    side.normalize();
    tube->sides[j] = side;
    Eigen::Vector3d down = q.t.cross(side);
    if (down.z() > 0) down = -down;
    // The bundle flattens on the paper (see bundleSpread): the distance to
    // the canvas is measured along `down`, the direction the tube reaches
    // it, against the section's extent that way. An ellipse is a circle
    // stretched, so the share of it beyond the canvas, and the spread that
    // restores it, follow from that ratio alone (for a slab's rounded
    // rectangle it is the ellipse of the same extent's).
    const Eigen::Vector3d& c = tube->centre[j];
    const double extent = q.extentAcross(down);
    const double reach = down.z() < -1e-9 ? c.z() / -down.z() : extent;
    const double spread = q.spread(extent, reach);
    for (int k = 0; k <= F; ++k) {
      const double cos_a = dirs.tube[k].x(), sin_a = dirs.tube[k].y();
      const Eigen::Vector3d d = cos_a * side + sin_a * down;
      tube->ring[j * (F + 1) + k] =
          c + q.radiusAcross(d) * (spread * cos_a * side + sin_a * down);
    }
  }
}

// Where a point p of spine s's bundle at point j lies across it, as the
// texture's u: the bundle's hair keeps its place across the brush, so a
// point spread sideways (bundleSpread) by d mm from the spine stands for the
// hair that lies d mm out at rest, u = s + 1/2 + d / width, clamped to the
// spine's own [s, s + 1] (its edge hairs). Neighbouring spines then agree on
// the hair at a point where their bundles meet, and a double load blends
// across the seam instead of changing colour at it.
float acrossU(const SpineSpec& spec, const SpineTube& tube, size_t s, size_t ns, int j,
              const Eigen::Vector3d& p) {
  const double d = -(p - tube.centre[j]).dot(tube.sides[j]);  // towards the brush's +x
  const double width = spec.width_mm[j] > 0 ? spec.width_mm[j] : 1.0;
  return static_cast<float>((s + std::clamp(0.5 + d / width, 0.0, 1.0)) / ns);
}

// Rounds the bundle off at every joint with the lower half of an ellipsoid of
// the same section (BundleSection): a joint that touches the canvas (a hair
// tip poking straight down, say) always shows, however steeply its segments
// rise. Its u runs across the bundle as the tube's does (acrossU), so that
// the hairs at the tip keep their place across the brush: a flat's pressed
// tips carry both paints of a double load, and each hair its own streak
// (engine/paint/paint.h, hairNoise).
void appendJointCaps(const SpineSpec& spec, SpineTube& tube, size_t s, size_t ns,
                     const std::vector<char>* due, std::vector<BrushVertex>* triangles,
                     double below_mm) {
  const int n = spec.jointCount();
  const DressingDirections& dirs = dressingDirections();
  for (int j = 1; j <= n; ++j) {
    if (due && !(*due)[j]) continue;
    const BundleSection& q = tube.section[j];
    if (q.empty()) continue;
    const Eigen::Vector3d& c = tube.centre[j];
    // A cap's points lie within its section's box (a, b across the hair, c
    // along it) around the centre; flattening moves them across the canvas
    // only. So none is lower than the box's half diagonal below the centre,
    // and a cap whose box stays clear of below_mm by more than float
    // rounding (kCapCullMarginMm) has no triangle that reaches it.
    if (c.z() - std::sqrt(q.a * q.a + q.b * q.b + q.c * q.c) > below_mm + kCapCullMarginMm)
      continue;
    const double spread = q.spread(q.depth(), c.z());
    // The hairs of a bundle end together, cut to length: past the last
    // joint the bundle ends in a face, not a dome. So the tip's cap
    // reaches only kTipCapDepth of its radius beyond the tip along the
    // hair, in proportion to how flat the hair lies (a tip poking
    // straight down keeps its full depth below the joint: that is the
    // contact, eq. 5). A flat's stroke then starts square (docs/paint.md,
    // "Square ends": its stop end is squarer but still rounds at the corners).
    Eigen::Vector2d along = Eigen::Vector2d::Zero();
    if (j == n) along = q.t.head<2>();  // |along| = cos(elevation)
    const double squash = 1 - kTipCapDepth;
    auto cap = [&](int lat, int lon) {  // lat 0 = lowest point .. kCapRings = equator
      const Eigen::Vector3d& d = dirs.cap[lat][lon];
      Eigen::Vector2d flat = spread * d.head<2>();
      flat -= squash * flat.dot(along) * along;
      const Eigen::Vector3d p = c + q.radius(d) * Eigen::Vector3d(flat.x(), flat.y(), d.z());
      return BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                         static_cast<float>(p.z()), acrossU(spec, tube, s, ns, j, p),
                         static_cast<float>(double(j) / n)};
    };
    // Each vertex once (a triangle list uses most of them six times).
    constexpr int kLon = 2 * F + 1;
    std::vector<BrushVertex>& grid = tube.grid;
    grid.clear();
    for (int lat = 0; lat <= kCapRings; ++lat)
      for (int lon = 0; lon < kLon; ++lon) grid.push_back(cap(lat, lon));
    auto at = [&](int lat, int lon) { return grid[lat * kLon + lon]; };
    for (int lat = 0; lat < kCapRings; ++lat)
      for (int lon = 0; lon < 2 * F; ++lon) {
        pushTriangle(at(lat, lon), at(lat + 1, lon), at(lat + 1, lon + 1), below_mm, triangles);
        if (lat == 0) continue;  // the pole row is a fan
        pushTriangle(at(lat, lon), at(lat + 1, lon + 1), at(lat, lon + 1), below_mm, triangles);
      }
  }
}

// The half tube itself, two triangles per facet and segment.
void appendTube(const SpineSpec& spec, SpineTube& tube, size_t s, size_t ns,
                std::vector<BrushVertex>* triangles, double below_mm) {
  const int n = spec.jointCount();
  std::vector<BrushVertex>& grid = tube.grid;
  grid.clear();
  for (int j = 0; j <= n; ++j)
    for (int k = 0; k <= F; ++k) {
      const Eigen::Vector3d& p = tube.ring[j * (F + 1) + k];
      grid.push_back(BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                                 static_cast<float>(p.z()), acrossU(spec, tube, s, ns, j, p),
                                 static_cast<float>(double(j) / n)});
    }
  auto at = [&](int j, int k) { return grid[j * (F + 1) + k]; };
  for (int j = 0; j < n; ++j)
    for (int k = 0; k < F; ++k) {
      pushTriangle(at(j, k), at(j, k + 1), at(j + 1, k + 1), below_mm, triangles);
      pushTriangle(at(j, k), at(j + 1, k + 1), at(j + 1, k), below_mm, triangles);
    }
}

}  // namespace

void buildSpineGeometry(const Brush& brush, const BrushState& state,
                        std::vector<BrushVertex>* triangles, double below_mm,
                        const JointCaps* caps) {
  const size_t ns = brush.spines.size();
  SpineTube tube;
  for (size_t s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush.spines[s];
    const std::vector<char>* due = caps ? &(*caps)[s] : nullptr;
    placeTubeRings(spec, state.spines[s], state.handle, &tube);
    appendJointCaps(spec, tube, s, ns, due, triangles, below_mm);
    appendTube(spec, tube, s, ns, triangles, below_mm);
  }
}

void capPatchRoundness(const SpineSpec& spec, const SpineState& spine, const Pose& handle,
                       double band_mm, std::vector<double>* rho_mm) {
  const int n = spec.jointCount();
  rho_mm->assign(n + 1, 0.0);
  // A slab's rounded rectangle turns its corners within a few hairs.
  if (!spec.thickness_mm.empty()) return;
  std::vector<BundleSection> section;
  std::vector<Eigen::Vector3d> centre;
  spineBundles(spec, spine, handle, &section, &centre);
  // The half solid at point j, a half ball of radius r around its centre,
  // reaches `dip` into the contact band. There it is cut in a disc, as drawn:
  // its rings of latitude (appendJointCaps) lie at heights r (1 - cos a)
  // above its lowest point with radii r sin a, a = 90 deg i / kCapRings,
  // joined by flat facets, so the cut's radius grows linearly between them
  // (the ball's own sqrt(dip (2 r - dip)) is up to twice that just below the
  // first ring), and each is a polygon of 2 F sides, whose inscribed circle
  // is cos(pi / 2F) of it. Pressing spreads it wider (bundleSpread), which
  // only rounds it more.
  auto patch = [&](int j) {
    const double r = section[j].depth();
    const double dip = std::min(band_mm - (centre[j].z() - r), r);
    if (!(dip > 0)) return 0.0;
    double below = 0, below_radius = 0;
    for (int i = 1; i <= kCapRings; ++i) {
      const double a = 0.5 * std::numbers::pi * i / kCapRings;
      const double height = r * (1 - std::cos(a)), radius = r * std::sin(a);
      if (dip <= height) {
        const double cut = below_radius + (radius - below_radius) * (dip - below) / (height - below);
        return cut * std::cos(std::numbers::pi / (2 * F));
      }
      below = height;
      below_radius = radius;
    }
    return r * std::cos(std::numbers::pi / (2 * F));
  };
  for (int j = 1; j <= n; ++j) (*rho_mm)[j] = patch(j);
  // The tip's half solid is squashed along the hair to kTipCapDepth of its
  // radius: an ellipse whose sharpest turn has radius kTipCapDepth^2 r.
  (*rho_mm)[n] *= kTipCapDepth * kTipCapDepth;
}

}  // namespace bristle

// Layout, camera framing and meshes of the brush preview. Everything here is
// double-precision arithmetic on the scene, so the GL passes get the same
// vertices (and the same pixels) every run.

#include "render/preview/preview_geometry.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace bristle::render::preview {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMinSizePx = 64, kMaxSizePx = 4096;
// Ferrule size: 1.5x the spread of the spine roots, at least 1.15x the hairs
// at the mouth (those within kMouthBand of the hair length from it).
constexpr double kRootSpreadScale = 1.5, kHairScale = 1.15, kMouthBand = 0.12;
// Spine tubes and joint dots keep a constant size on screen (final pixels).
constexpr double kSpineRadiusPx = 1.6, kJointRadiusPx = 3.2;
constexpr int kFerruleSegments = 48, kTubeSides = 12, kSphereRings = 8, kSphereSegments = 14;

Eigen::Vector3d toVec(const BrushVertex& v) { return {v.x_mm, v.y_mm, v.z_mm}; }

void push(Mesh* mesh, const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
  mesh->push_back({static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()),
                   static_cast<float>(n.x()), static_cast<float>(n.y()),
                   static_cast<float>(n.z())});
}

// Two triangles of the quad a-b-c-d (counter-clockwise seen from outside).
void pushQuad(Mesh* mesh, const std::array<Eigen::Vector3d, 4>& p,
              const std::array<Eigen::Vector3d, 4>& n) {
  for (int k : {0, 1, 2, 0, 2, 3}) push(mesh, p[k], n[k]);
}

// Calls f(point) for every vertex of the brush geometry.
template <typename F>
void forEachPoint(const PreviewScene& scene, F&& f) {
  for (const BrushVertex& v : scene.surface) f(toVec(v));
  for (const BrushVertex& v : scene.strips) f(toVec(v));
  for (const auto& spine : scene.spines) {
    for (const Eigen::Vector3d& p : spine) f(p);
  }
}

}  // namespace

Layout layoutPreview(const PreviewScene& scene, const PreviewOptions& options) {
  const int w = options.width_px, h = options.height_px;
  if (w < kMinSizePx || h < kMinSizePx || w > kMaxSizePx || h > kMaxSizePx) {
    throw std::invalid_argument("preview size " + std::to_string(w) + "x" + std::to_string(h) +
                                " px: each side must be in [64, 4096]");
  }
  Layout l;
  l.margin_px = std::max(4, static_cast<int>(std::lround(0.03 * std::min(w, h))));
  l.title_size_px = std::clamp(static_cast<int>(std::lround(0.036 * h)), 10, 40);
  l.label_size_px = std::clamp(static_cast<int>(std::lround(0.024 * h)), 9, 24);
  int top = l.margin_px, bottom = h - l.margin_px, right = w - l.margin_px;
  if (!scene.title.empty()) top += static_cast<int>(std::lround(1.4 * l.title_size_px));
  if (options.legend) bottom -= static_cast<int>(std::lround(1.6 * l.label_size_px));
  if (scene.footprint != nullptr) {
    const int side = static_cast<int>(std::lround(std::min(0.3 * w, 0.42 * h)));
    l.inset = PixelRect{w - l.margin_px - side, h - l.margin_px - side, side, side};
    right = l.inset->x - l.margin_px;
  }
  l.content = PixelRect{l.margin_px, top, right - l.margin_px, bottom - top};
  return l;
}

std::optional<Ferrule> fitFerrule(const PreviewScene& scene) {
  const Eigen::Matrix3d r = scene.handle.rotation.normalized().toRotationMatrix();
  const Eigen::Vector3d origin = scene.handle.position_mm;
  std::vector<Eigen::Vector3d> brush_frame;
  forEachPoint(scene, [&](const Eigen::Vector3d& p) {
    brush_frame.push_back(r.transpose() * (p - origin));
  });
  if (brush_frame.empty()) return std::nullopt;

  double hair_mm = 0;
  for (const auto& b : brush_frame) hair_mm = std::max(hair_mm, -b.z());
  const double band_mm = std::max(kMouthBand * hair_mm, 0.3);
  // Principal axes of the hair cross-section at the mouth (flat brushes and
  // fans are wide along one axis), measured from the mouth centre (the origin).
  std::vector<Eigen::Vector2d> mouth, roots;
  for (const auto& b : brush_frame) {
    if (b.z() >= -band_mm) mouth.push_back(b.head<2>());
  }
  for (const auto& spine : scene.spines) {
    if (!spine.empty()) roots.push_back((r.transpose() * (spine.front() - origin)).head<2>());
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto* set : {&mouth, &roots}) {
    for (const auto& m : *set) mean += m / static_cast<double>(mouth.size() + roots.size());
  }
  for (const auto* set : {&mouth, &roots}) {
    for (const auto& m : *set) cov += (m - mean) * (m - mean).transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d major2 = eig.eigenvectors().col(1);  // largest eigenvalue
  const Eigen::Vector2d minor2(-major2.y(), major2.x());
  // Half-extent of a point set along an axis.
  const auto extent = [](const std::vector<Eigen::Vector2d>& set, const Eigen::Vector2d& axis) {
    double e = 0;
    for (const auto& m : set) e = std::max(e, std::abs(m.dot(axis)));
    return e;
  };
  // 1.5x the spine roots' spread (the brush's width as its file lays it out),
  // but never narrower than the hairs leaving the mouth.
  double e_major =
      std::max(kRootSpreadScale * extent(roots, major2), kHairScale * extent(mouth, major2));
  double e_minor =
      std::max(kRootSpreadScale * extent(roots, minor2), kHairScale * extent(mouth, minor2));
  // A single spine has no width of its own; real flat ferrules are ~1:3.
  e_major = std::max({e_major, 0.1 * hair_mm, 0.4});
  e_minor = std::max(e_minor, 0.35 * e_major);

  Ferrule f;
  f.mouth_mm = origin;
  f.axis = r.col(2);
  f.major = r * Eigen::Vector3d(major2.x(), major2.y(), 0);
  f.minor = f.axis.cross(f.major);
  f.major_radius_mm = e_major;
  f.minor_radius_mm = e_minor;
  f.length_mm = std::clamp(0.75 * hair_mm, 15.0, 20.0);
  return f;
}

Bounds sceneBounds(const PreviewScene& scene, const std::optional<Ferrule>& ferrule) {
  Bounds b;
  forEachPoint(scene, [&](const Eigen::Vector3d& p) { b.add(p); });
  if (ferrule) {
    for (int k = 0; k < 16; ++k) {
      const double a = 2 * kPi * k / 16;
      const Eigen::Vector3d ring = ferrule->major * ferrule->major_radius_mm * std::cos(a) +
                                   ferrule->minor * ferrule->minor_radius_mm * std::sin(a);
      b.add(ferrule->mouth_mm + ring);
      b.add(ferrule->mouth_mm + ring + ferrule->axis * ferrule->length_mm);
    }
  }
  return b;
}

SceneMeshes buildMeshes(const PreviewScene& scene, const PreviewCamera& camera) {
  SceneMeshes m;
  m.surface_ccw_outward = appendSmooth(scene.surface, &m.surface);
  appendFacetted(scene.strips, &m.strips);
  const double tube_mm = kSpineRadiusPx * camera.mm_per_px_at_target;
  const double joint_mm = kJointRadiusPx * camera.mm_per_px_at_target;
  for (const auto& spine : scene.spines) {
    for (std::size_t j = 0; j + 1 < spine.size(); ++j) {
      appendTube(spine[j], spine[j + 1], tube_mm, &m.spines);
    }
    for (const Eigen::Vector3d& p : spine) appendSphere(p, joint_mm, &m.spines);
  }
  if (const auto ferrule = fitFerrule(scene)) appendFerrule(*ferrule, &m.ferrule);
  for (const Mesh* part : {&m.surface, &m.strips, &m.spines}) {
    m.casters.insert(m.casters.end(), part->begin(), part->end());
  }
  // The paper: a square around the target, wide enough to fade out before its edge.
  const float x = static_cast<float>(camera.target_mm.x());
  const float y = static_cast<float>(camera.target_mm.y());
  const float g = static_cast<float>(kGroundRadii * camera.radius_mm);
  m.ground = {{x - g, y - g, 0, 0, 0, 1}, {x + g, y - g, 0, 0, 0, 1}, {x + g, y + g, 0, 0, 0, 1},
              {x - g, y - g, 0, 0, 0, 1}, {x + g, y + g, 0, 0, 0, 1}, {x - g, y + g, 0, 0, 0, 1}};
  return m;
}

void appendFerrule(const Ferrule& f, Mesh* mesh) {
  // Lathe profile (height along the axis, radius scale): the crimped taper down
  // to the hairs and a groove, so the stub reads as a ferrule at a glance.
  const double len = f.length_mm, crimp = 0.55 * len;
  const std::array<std::array<double, 2>, 11> profile = {{{0, 0.88},
                                                          {0.5, 0.90},
                                                          {1.5, 0.93},
                                                          {3.0, 0.965},
                                                          {4.5, 1.0},
                                                          {crimp, 1.0},
                                                          {crimp + 0.3, 0.97},
                                                          {crimp + 1.0, 0.97},
                                                          {crimp + 1.3, 1.0},
                                                          {len, 1.0},
                                                          {len, 0.0}}};
  const double a = f.major_radius_mm, b = f.minor_radius_mm, mean_r = 0.5 * (a + b);
  const auto rim = [&](int k, double scale, double h) {
    const double t = 2 * kPi * k / kFerruleSegments;
    return Eigen::Vector3d(f.mouth_mm + f.axis * h +
                           scale * (f.major * a * std::cos(t) + f.minor * b * std::sin(t)));
  };
  const auto radial = [&](int k) {  // outward normal of the ellipse at angle t
    const double t = 2 * kPi * k / kFerruleSegments;
    return Eigen::Vector3d((f.major * std::cos(t) / a + f.minor * std::sin(t) / b).normalized());
  };
  for (std::size_t s = 0; s + 1 < profile.size(); ++s) {
    const auto [h0, s0] = profile[s];
    const auto [h1, s1] = profile[s + 1];
    for (int k = 0; k < kFerruleSegments; ++k) {
      // Each band keeps its own normals: crisp edges, as on turned metal.
      // Init-captures: clang 14 (scripts/fuzz) cannot capture structured bindings.
      const auto normal = [&, h0 = h0, h1 = h1, s0 = s0, s1 = s1](int kk) {
        return Eigen::Vector3d((radial(kk) * (h1 - h0) - f.axis * (s1 - s0) * mean_r).normalized());
      };
      pushQuad(mesh, {rim(k, s0, h0), rim(k + 1, s0, h0), rim(k + 1, s1, h1), rim(k, s1, h1)},
               {normal(k), normal(k + 1), normal(k + 1), normal(k)});
    }
  }
  // The mouth (hidden in the hairs, but it closes the stub seen from below).
  for (int k = 0; k < kFerruleSegments; ++k) {
    for (const Eigen::Vector3d& p : {f.mouth_mm, rim(k + 1, 0.88, 0), rim(k, 0.88, 0)}) {
      push(mesh, p, -f.axis);
    }
  }
}

void appendTube(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_mm, Mesh* mesh) {
  const Eigen::Vector3d d = b - a;
  if (d.norm() < 1e-9) return;
  const Eigen::Vector3d axis = d.normalized();
  // Any perpendicular works; this one is stable for every direction.
  const Eigen::Vector3d helper =
      std::abs(axis.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d u = axis.cross(helper).normalized(), v = axis.cross(u);
  const auto dir = [&](int k) {
    const double t = 2 * kPi * k / kTubeSides;
    return Eigen::Vector3d(u * std::cos(t) + v * std::sin(t));
  };
  for (int k = 0; k < kTubeSides; ++k) {
    const Eigen::Vector3d n0 = dir(k), n1 = dir(k + 1);
    pushQuad(mesh, {a + radius_mm * n0, a + radius_mm * n1, b + radius_mm * n1, b + radius_mm * n0},
             {n0, n1, n1, n0});
  }
}

void appendSphere(const Eigen::Vector3d& centre, double radius_mm, Mesh* mesh) {
  const auto dir = [](int ring, int seg) {
    const double polar = kPi * ring / kSphereRings, az = 2 * kPi * seg / kSphereSegments;
    return Eigen::Vector3d(std::sin(polar) * std::cos(az), std::sin(polar) * std::sin(az),
                           std::cos(polar));
  };
  for (int ring = 0; ring < kSphereRings; ++ring) {
    for (int seg = 0; seg < kSphereSegments; ++seg) {
      const std::array<Eigen::Vector3d, 4> n = {dir(ring, seg), dir(ring + 1, seg),
                                                dir(ring + 1, seg + 1), dir(ring, seg + 1)};
      pushQuad(mesh,
               {centre + radius_mm * n[0], centre + radius_mm * n[1], centre + radius_mm * n[2],
                centre + radius_mm * n[3]},
               n);
    }
  }
}

bool appendSmooth(std::span<const BrushVertex> triangles, Mesh* mesh) {
  // Weld by exact position: the surface repeats each vertex in every triangle
  // (and twice along the u seam, with different u), always bit-identical.
  struct KeyHash {
    std::size_t operator()(const std::array<std::uint32_t, 3>& k) const {
      return (k[0] * 73856093u) ^ (k[1] * 19349663u) ^ (k[2] * 83492791u);
    }
  };
  std::unordered_map<std::array<std::uint32_t, 3>, int, KeyHash> index;
  std::vector<int> ids(triangles.size());
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const BrushVertex& v = triangles[i];
    const std::array<std::uint32_t, 3> key = {std::bit_cast<std::uint32_t>(v.x_mm + 0.0f),
                                              std::bit_cast<std::uint32_t>(v.y_mm + 0.0f),
                                              std::bit_cast<std::uint32_t>(v.z_mm + 0.0f)};
    ids[i] = index.emplace(key, static_cast<int>(index.size())).first->second;
  }
  std::vector<Eigen::Vector3d> normals(index.size(), Eigen::Vector3d::Zero());
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const BrushVertex& v : triangles)
    centroid += toVec(v) / static_cast<double>(triangles.size());
  double volume = 0;  // x6, signed: > 0 when counter-clockwise faces point outwards
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Eigen::Vector3d p0 = toVec(triangles[t]) - centroid,
                          p1 = toVec(triangles[t + 1]) - centroid,
                          p2 = toVec(triangles[t + 2]) - centroid;
    const Eigen::Vector3d area_normal = (p1 - p0).cross(p2 - p0);  // |.| = 2 x area
    for (int k = 0; k < 3; ++k) normals[ids[t + k]] += area_normal;
    volume += p0.dot(p1.cross(p2));
  }
  const double sign = volume >= 0 ? 1.0 : -1.0;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const Eigen::Vector3d& n = normals[ids[i]];
    // A vertex whose faces cancel (a fold) falls back to the facet normal.
    push(mesh, toVec(triangles[i]),
         n.norm() > 1e-12 ? Eigen::Vector3d(sign * n.normalized()) : Eigen::Vector3d::Zero());
  }
  return volume >= 0;
}

void appendFacetted(std::span<const BrushVertex> triangles, Mesh* mesh) {
  for (const BrushVertex& v : triangles) push(mesh, toVec(v), Eigen::Vector3d::Zero());
}

void appendShadow(const Mesh& caster, const Eigen::Vector3d& toward_light, Mesh* shadow) {
  const Eigen::Vector3d l = toward_light / toward_light.z();  // unit height step
  for (const MeshVertex& v : caster) {
    const Eigen::Vector3d p(v.x, v.y, v.z);
    const Eigen::Vector3d q = p - std::max(p.z(), 0.0) * l;
    push(shadow, Eigen::Vector3d(q.x(), q.y(), 0.0), Eigen::Vector3d::UnitZ());
  }
}

}  // namespace bristle::render::preview

namespace bristle::render {

std::optional<Eigen::Vector2d> PreviewCamera::project(const Eigen::Vector3d& p_mm) const {
  const Eigen::Vector4d clip = projection * view * p_mm.homogeneous();
  if (clip.w() <= 0) return std::nullopt;
  const double ndc_x = clip.x() / clip.w(), ndc_y = clip.y() / clip.w();
  return Eigen::Vector2d((ndc_x + 1) * 0.5 * width_px, (1 - ndc_y) * 0.5 * height_px);
}

PreviewCamera framePreview(const PreviewScene& scene, const PreviewOptions& options) {
  using preview::kPi;
  const preview::Layout layout = preview::layoutPreview(scene, options);
  preview::Bounds box = preview::sceneBounds(scene, preview::fitFerrule(scene));
  if (box.empty()) {  // nothing drawn but paper: a 30 mm patch under the handle
    const Eigen::Vector3d c(scene.handle.position_mm.x(), scene.handle.position_mm.y(), 0);
    box.add(c + Eigen::Vector3d(-15, -15, 0));
    box.add(c + Eigen::Vector3d(15, 15, 20));
  }
  // Keep the paper under a brush that hovers just above it in the picture.
  const double height_mm = box.hi.z() - box.lo.z();
  if (box.lo.z() > 0 && box.lo.z() < 0.5 * height_mm) box.lo.z() = 0;
  const Eigen::Vector3d target = 0.5 * (box.lo + box.hi);
  const Eigen::Vector3d half = (0.5 * (box.hi - box.lo)).cwiseMax(Eigen::Vector3d::Constant(1.0));

  const double az = preview::kAzimuthDeg * kPi / 180, el = preview::kElevationDeg * kPi / 180;
  const Eigen::Vector3d back(std::sin(az) * std::cos(el), -std::cos(az) * std::cos(el),
                             std::sin(el));  // from the target towards the eye
  const Eigen::Vector3d right = (-back).cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d up = right.cross(-back);

  // Distance at which every box corner fits the content rectangle (in tangent
  // units), then an off-centre projection puts the box's middle in its middle.
  const int w = options.width_px, h = options.height_px;
  const double ty = std::tan(0.5 * preview::kFovYDeg * kPi / 180), tx = ty * w / h;
  const preview::PixelRect& c = layout.content;
  const double hx = tx * c.width / w, hy = ty * c.height / h;
  std::array<Eigen::Vector3d, 8> corners;
  double distance = 0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d q((k & 1 ? 1 : -1) * half.x(), (k & 2 ? 1 : -1) * half.y(),
                            (k & 4 ? 1 : -1) * half.z());
    corners[k] = {q.dot(right), q.dot(up), q.dot(back)};
    distance = std::max({distance, corners[k].z() + std::abs(corners[k].x()) / hx,
                         corners[k].z() + std::abs(corners[k].y()) / hy});
  }
  double lo_x = 1e300, hi_x = -1e300, lo_y = 1e300, hi_y = -1e300;
  for (const auto& q : corners) {
    const double depth = distance - q.z();
    lo_x = std::min(lo_x, q.x() / depth), hi_x = std::max(hi_x, q.x() / depth);
    lo_y = std::min(lo_y, q.y() / depth), hi_y = std::max(hi_y, q.y() / depth);
  }
  const double centre_ndc_x = (2.0 * c.x + c.width) / w - 1;
  const double centre_ndc_y = 1 - (2.0 * c.y + c.height) / h;
  const double shift_x = centre_ndc_x - 0.5 * (lo_x + hi_x) / tx;
  const double shift_y = centre_ndc_y - 0.5 * (lo_y + hi_y) / ty;

  PreviewCamera cam;
  cam.width_px = w;
  cam.height_px = h;
  cam.target_mm = target;
  cam.eye_mm = target + distance * back;
  const double radius_mm = half.norm();
  cam.radius_mm = radius_mm;
  cam.near_mm = 0.05 * distance;  // the box is > 3 radii away: ample precision
  cam.far_mm = distance + preview::kGroundRadii * radius_mm * 1.5;
  cam.mm_per_px_at_target = 2 * distance * ty / h;
  cam.view.setIdentity();
  cam.view.block<1, 3>(0, 0) = right.transpose();
  cam.view.block<1, 3>(1, 0) = up.transpose();
  cam.view.block<1, 3>(2, 0) = back.transpose();
  cam.view.block<3, 1>(0, 3) = -(cam.view.block<3, 3>(0, 0) * cam.eye_mm);
  const double n = cam.near_mm, f = cam.far_mm;
  cam.projection << 1 / tx, 0, -shift_x, 0,            //
      0, 1 / ty, -shift_y, 0,                          //
      0, 0, -(f + n) / (f - n), -2 * f * n / (f - n),  //
      0, 0, -1, 0;
  return cam;
}

}  // namespace bristle::render

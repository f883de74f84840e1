#include "engine/geometry/brush_surface.h"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/stencilTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <mutex>
#include <numbers>

#include "engine/base/error.h"
#include "engine/geometry/spine_bundles.h"
#include "engine/mechanics/spine_kinematics.h"

namespace bristle {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// Double-precision weights: a level-2 stencil sums ~12 cage vertices (up to ~30
// at the tip pole), and float weights would leave ~1e-6 mm of noise on a 10 mm
// brush; the table is small (18k weights for a 100-vertex cage).
struct BrushSurface::Stencils {
  std::unique_ptr<const Far::StencilTableReal<double>> table;
};

namespace {

// The brush axis at rest: the polyline through the mean of the spines' point j
// (a shorter spine repeats its tip), root first.
std::vector<Eigen::Vector3d> restAxis(const Brush& brush) {
  std::vector<Eigen::Vector3d> axis;
  for (const SpineSpec& spine : brush.spines) {
    const std::vector<Eigen::Vector3d> x = restPoints(spine);
    if (axis.size() < x.size()) axis.resize(x.size(), Eigen::Vector3d::Zero());
    for (size_t j = 0; j < axis.size(); ++j)
      axis[j] += x[std::min(j, x.size() - 1)] / double(brush.spines.size());
  }
  return axis;
}

struct AxisAngle {
  double turns;    // angle around the axis / 2 pi, in [0, 1)
  double dist_mm;  // distance from the axis across it
};

// p's angle around the nearest axis segment, measured in the plane across it
// from the direction that the minimal rotation of -z onto the segment takes +x
// to: on a straight brush, from +x counter-clockwise seen from above.
AxisAngle angleAroundAxis(const std::vector<Eigen::Vector3d>& axis, const Eigen::Vector3d& p) {
  double best = 1e300;
  Eigen::Vector3d near = axis[0], t(0, 0, -1);
  for (size_t k = 0; k + 1 < axis.size(); ++k) {
    const Eigen::Vector3d seg = axis[k + 1] - axis[k];
    if (seg.squaredNorm() == 0) continue;
    const double a = std::clamp((p - axis[k]).dot(seg) / seg.squaredNorm(), 0.0, 1.0);
    const Eigen::Vector3d c = axis[k] + a * seg;
    if ((p - c).norm() < best) {
      best = (p - c).norm();
      near = c;
      t = seg.normalized();
    }
  }
  const Eigen::Vector3d down(0, 0, -1), v = down.cross(t);
  const double cos_a = down.dot(t);
  Eigen::Vector3d e1 = Eigen::Vector3d::UnitX();
  if (cos_a > -1 + 1e-9) {  // Rodrigues' minimal rotation (undefined for t = +z)
    Eigen::Matrix3d vx;
    vx << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
    e1 = (Eigen::Matrix3d::Identity() + vx + vx * vx / (1 + cos_a)) * e1;
  }
  const Eigen::Vector3d o = p - near, across = o - o.dot(t) * t;
  double turns = std::atan2(across.dot(e1.cross(t)), across.dot(e1)) / (2 * std::numbers::pi);
  if (turns < 0) turns += 1;
  if (turns >= 1) turns = 0;  // rounding of -0
  return {turns, across.norm()};
}

// Shortest signed difference of two angles in turns, in [-0.5, 0.5).
float turnDiff(float a, float b) {
  const float d = a - b;
  return d - std::floor(d + 0.5f);
}

// OpenSubdiv reports through process-wide callbacks (printf by default, on
// stdout, where the CLI writes data). Ours keep the first message of the
// constructor that is listening on this thread, and send the rest to stderr.
thread_local std::string* t_osd_capture = nullptr;

void osdMessage(const char* message) {
  std::string line = message ? message : "";
  std::replace(line.begin(), line.end(), '\n', ' ');
  if (t_osd_capture == nullptr)
    std::fprintf(stderr, "OpenSubdiv: %s\n", line.c_str());
  else if (t_osd_capture->empty())
    *t_osd_capture = line;
}

void installOsdCallbacks() {
  static std::once_flag once;
  std::call_once(once, [] {
    Far::SetErrorCallback([](Far::ErrorType, const char* m) { osdMessage(m); });
    Far::SetWarningCallback([](const char* m) { osdMessage(m); });
  });
}

struct OsdCapture {
  std::string text;
  OsdCapture() { t_osd_capture = &text; }
  ~OsdCapture() { t_osd_capture = nullptr; }
  OsdCapture(const OsdCapture&) = delete;
  OsdCapture& operator=(const OsdCapture&) = delete;
};

std::string edgeName(const Far::TopologyLevel& l, int e) {
  const Far::ConstIndexArray v = l.GetEdgeVertices(e);
  return "(" + std::to_string(v[0]) + ", " + std::to_string(v[1]) + ")";
}

// OpenSubdiv accepts non-manifold cages (it sharpens them), even with full
// validation; a brush cage must be a manifold, so reject them here by name.
void requireManifold(const Far::TopologyLevel& l, const std::string& path) {
  for (int e = 0; e < l.GetNumEdges(); ++e) {
    if (!l.IsEdgeNonManifold(e)) continue;
    const Far::ConstIndexArray f = l.GetEdgeFaces(e);
    if (f.size() > 2)
      throw dataError(path, "/surface/faces/" + std::to_string(f[2]),
                      "non-manifold edge " + edgeName(l, e) + ": shared by " +
                          std::to_string(f.size()) + " faces (at most 2)");
    const std::string where = "/surface/faces/" + std::to_string(f[f.size() - 1]);
    if (f.size() != 2 || f[0] == f[1])  // OpenSubdiv splits the edges of a repeated vertex
      throw dataError(path, where, "uses edge " + edgeName(l, e) + " twice (degenerate face)");
    throw dataError(path, where,
                    "non-manifold edge " + edgeName(l, e) +
                        ": its faces cross it in the same direction (inconsistent orientation)");
  }
  for (int v = 0; v < l.GetNumVertices(); ++v) {
    if (!l.IsVertexNonManifold(v)) continue;
    const std::string where = "/surface/cage_vertices_mm/" + std::to_string(v);
    if (l.GetVertexFaces(v).size() == 0) throw dataError(path, where, "is used by no face");
    throw dataError(path, where, "non-manifold vertex: its faces do not form one fan");
  }
}

std::unique_ptr<Far::TopologyRefiner> buildRefiner(const Brush& brush) {
  const SurfaceSpec& sf = brush.surface;
  std::vector<int> counts, indices;
  for (const std::vector<int>& f : sf.faces) {
    counts.push_back(static_cast<int>(f.size()));
    indices.insert(indices.end(), f.begin(), f.end());
  }
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(sf.cage_mm.size());
  desc.numFaces = static_cast<int>(counts.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();

  // A brush cage is usually open at the ferrule: its boundary is a sharp
  // B-spline curve and boundary corners stay put (EDGE_AND_CORNER).
  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  Factory::Options options(Sdc::SCHEME_CATMARK, sdc);
  options.validateFullTopology = true;

  installOsdCallbacks();
  OsdCapture capture;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(desc, options));
  if (!refiner || !capture.text.empty())
    throw dataError(brush.path, "/surface/faces",
                    "OpenSubdiv rejected the cage: " +
                        (capture.text.empty() ? std::string("invalid topology") : capture.text));
  requireManifold(refiner->GetLevel(0), brush.path);
  return refiner;
}

}  // namespace

BrushSurface::BrushSurface(const Brush& brush) {
  const SurfaceSpec& sf = brush.surface;
  if (!sf.present()) throw Error(ExitCode::kSoftware, brush.path + ": /surface: none to build");
  level_ = sf.refinement_level;
  spines_ = brush.spines;
  std::unique_ptr<Far::TopologyRefiner> refiner = buildRefiner(brush);
  if (level_ > 0) refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(level_));

  // The refined vertices as a fixed linear map of the cage (at level 0 the
  // identity, which needs the control vertices' own stencils).
  Far::StencilTableFactoryReal<double>::Options so;
  so.interpolationMode = Far::StencilTableFactoryReal<double>::INTERPOLATE_VERTEX;
  so.generateIntermediateLevels = false;
  so.generateOffsets = true;
  so.generateControlVerts = level_ == 0;
  so.maxLevel = static_cast<unsigned>(level_);
  stencils_ = std::make_unique<Stencils>();
  stencils_->table.reset(Far::StencilTableFactoryReal<double>::Create(*refiner, so));

  // Triangles of the refined level: quad (a, b, c, d) -> (a, b, c), (a, c, d).
  const Far::TopologyLevel& last = refiner->GetLevel(level_);
  for (int f = 0; f < last.GetNumFaces(); ++f) {
    const Far::ConstIndexArray v = last.GetFaceVertices(f);
    for (int k = 1; k + 1 < v.size(); ++k)
      tri_vertex_.insert(tri_vertex_.end(), {v[0], v[k], v[k + 1]});
  }
  cage_.resize(sf.cage_mm.size());
  refined_.resize(last.GetNumVertices());
  setupSkin(brush);
  setupUv(brush);
}

BrushSurface::~BrushSurface() = default;
BrushSurface::BrushSurface(BrushSurface&&) noexcept = default;
BrushSurface& BrushSurface::operator=(BrushSurface&&) noexcept = default;

void BrushSurface::spineFrames(const Eigen::Matrix3d& handle_r, const Eigen::Matrix3d* rot,
                               const Eigen::Vector3d* x, int n, Frame* out) {
  Eigen::Matrix3d r = handle_r;
  for (int k = 0; k < n; ++k) {
    r = r * rot[k];  // cumulative, eq. 11
    out[k] = Frame{r, x[k]};
  }
  out[n] = Frame{r, x[n]};  // the tip is oriented as the last segment
}

void BrushSurface::setupSkin(const Brush& brush) {
  // Rest frames: the spines at their rest angles under the identity handle.
  frame_offset_.clear();
  joint_count_.clear();
  int frames = 0;
  for (const SpineSpec& spine : brush.spines) {
    frame_offset_.push_back(frames);
    joint_count_.push_back(spine.jointCount());
    frames += spine.jointCount() + 1;
  }
  frames_.resize(frames);
  for (size_t s = 0; s < brush.spines.size(); ++s) {
    const SpineSpec& spine = brush.spines[s];
    spineFrames(Eigen::Matrix3d::Identity(), restRotations(spine).data(), restPoints(spine).data(),
                joint_count_[s], &frames_[frame_offset_[s]]);
  }
  // Each influence keeps the vertex's rest position in its frame; weights are
  // renormalised (the reader allows 1e-3 slack) so a rigid move is reproduced.
  const SurfaceSpec& sf = brush.surface;
  influence_.clear();
  influence_offset_.assign(1, 0);
  for (size_t i = 0; i < sf.cage_mm.size(); ++i) {
    double sum = 0;
    for (const SkinInfluence& in : sf.skin[i]) sum += in.weight;
    for (const SkinInfluence& in : sf.skin[i]) {
      const Frame& f = frames_[frame_offset_[in.spine] + in.point];
      influence_.push_back({frame_offset_[in.spine] + in.point, in.spine, in.point, in.weight / sum,
                            f.r.transpose() * (sf.cage_mm[i] - f.x)});
    }
    influence_offset_.push_back(static_cast<int>(influence_.size()));
  }
}

void BrushSurface::setupUv(const Brush& brush) {
  const SurfaceSpec& sf = brush.surface;
  for (size_t i = 0; i < sf.cage_mm.size(); ++i)
    cage_[i] = {sf.cage_mm[i].x(), sf.cage_mm[i].y(), sf.cage_mm[i].z()};
  refined_rest_.resize(refined_.size());
  stencils_->table->UpdateValues(cage_.data(), refined_rest_.data());

  double z_top = -1e300, z_bottom = 1e300;
  for (const SurfacePoint& p : refined_rest_) {
    z_top = std::max(z_top, p.z);
    z_bottom = std::min(z_bottom, p.z);
  }
  const double height = std::max(z_top - z_bottom, 1e-12);
  const std::vector<Eigen::Vector3d> axis = restAxis(brush);
  const size_t nv = refined_rest_.size();
  std::vector<double> dist(nv);
  uv_.resize(nv);
  for (size_t i = 0; i < nv; ++i) {
    const AxisAngle a = angleAroundAxis(axis, refined_rest_[i].vec());
    dist[i] = a.dist_mm;
    uv_[i] = Eigen::Vector2f(float(a.turns), float((z_top - refined_rest_[i].z) / height));
  }
  // Poles: where the axis pierces the surface (the tip), one vertex's fan winds
  // once around it. Its own angle means nothing, and its neighbours' fans may
  // wind too: of those that wind, the pole is the one nearest the axis.
  std::vector<float> winding(nv, 0.0f);
  const size_t nc = tri_vertex_.size();
  for (size_t t = 0; t < nc; t += 3)
    for (int c = 0; c < 3; ++c)
      winding[tri_vertex_[t + c]] += turnDiff(uv_[tri_vertex_[t + (c + 2) % 3]].x(),
                                              uv_[tri_vertex_[t + (c + 1) % 3]].x());
  std::vector<bool> pole(nv);
  for (size_t i = 0; i < nv; ++i) pole[i] = std::fabs(winding[i]) > 0.5f;
  std::vector<bool> nearest = pole;
  for (size_t t = 0; t < nc; t += 3)
    for (int c = 0; c < 3; ++c)
      for (int o = 0; o < 3; ++o) {
        const int a = tri_vertex_[t + c], b = tri_vertex_[t + o];
        if (pole[a] && pole[b] && dist[b] < dist[a]) nearest[a] = false;
      }
  // Per triangle corner: unwrap u across the seam next to the first corner that
  // is not a pole, give poles the mean of the others, and keep u >= 0.
  tri_uv_.resize(nc);
  for (size_t t = 0; t < nc; t += 3) {
    const int* v = &tri_vertex_[t];
    int ref = -1;
    for (int c = 2; c >= 0; --c)
      if (!nearest[v[c]]) ref = c;
    float u[3], sum = 0;
    for (int c = 0; c < 3; ++c) {
      u[c] = uv_[v[c]].x();
      if (ref >= 0) u[c] = uv_[v[ref]].x() + turnDiff(u[c], uv_[v[ref]].x());
      if (!nearest[v[c]]) sum += u[c];
    }
    const int with_angle = int(!nearest[v[0]]) + int(!nearest[v[1]]) + int(!nearest[v[2]]);
    for (int c = 0; c < 3; ++c)
      if (nearest[v[c]] && with_angle > 0) u[c] = sum / float(with_angle);
    const float shift = std::min({u[0], u[1], u[2]}) < 0 ? 1.0f : 0.0f;
    for (int c = 0; c < 3; ++c) tri_uv_[t + c] = Eigen::Vector2f(u[c] + shift, uv_[v[c]].y());
  }
}

void BrushSurface::update(const BrushState& state, std::vector<BrushVertex>* triangles) {
  if (state.spines.size() != joint_count_.size())
    throw Error(ExitCode::kSoftware, "BrushSurface::update: state of another brush");
  // Skinning (§4.1): each cage vertex is a weighted sum of its rest position
  // carried by the current frames of the spine points it follows.
  const Eigen::Matrix3d handle_r = state.handle.rotation.toRotationMatrix();
  for (size_t s = 0; s < joint_count_.size(); ++s)
    spineFrames(handle_r, state.spines[s].rot.data(), state.spines[s].joints_mm.data(),
                joint_count_[s], &frames_[frame_offset_[s]]);
  // The surface wraps the spines' hair, and hair is pressed into the paper
  // only as far as its spine's load presses it (bundlePressDepth). The hair
  // bundles are raised off their joints until they are (bundlePlacement),
  // and the surface follows its hair: each cage vertex rises by the weighted
  // raise of the bundles it follows, and reaches no deeper below the canvas
  // than they do. A lightly loaded brush then rests on the paper, surface
  // and spines alike; and a flat lifting off leaves a square end: its
  // surface's belly neither drags ahead of its hair (before the depth limit)
  // nor slides ahead of it as the hair rises (before the raise: 0.25 mm).
  bundles_.resize(joint_count_.size());
  for (size_t s = 0; s < joint_count_.size(); ++s)
    bundles_[s] = bundlePlacement(spines_[s], state.spines[s], state.handle);
  for (size_t i = 0; i < cage_.size(); ++i) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double depth = 0;
    for (int k = influence_offset_[i]; k < influence_offset_[i + 1]; ++k) {
      const Influence& in = influence_[k];
      const Frame& f = frames_[in.frame];
      p += in.weight * (f.x + f.r * in.local);
      const BundlePlacement& bundle = bundles_[in.spine];
      p.z() += in.weight * bundle.raise_mm[in.point];
      depth += in.weight * bundle.depth_mm[in.point];
    }
    p.z() = std::max(p.z(), -depth);
    cage_[i] = {p.x(), p.y(), p.z()};
  }
  stencils_->table->UpdateValues(cage_.data(), refined_.data());

  const size_t first = triangles->size();
  triangles->resize(first + tri_vertex_.size());
  BrushVertex* out = triangles->data() + first;
  for (size_t c = 0; c < tri_vertex_.size(); ++c) {
    const SurfacePoint& p = refined_[tri_vertex_[c]];
    out[c] = {float(p.x), float(p.y), float(p.z), tri_uv_[c].x(), tri_uv_[c].y()};
  }
}

}  // namespace bristle

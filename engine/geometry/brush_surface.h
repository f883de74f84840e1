#pragma once
// The brush's subdivision surface (paper §4.1): a Catmull-Clark control cage,
// placed each step by "standard matrix skinning" (linear-blend skinning) on the
// spines' joint frames and refined by OpenSubdiv. Refinement is linear in the
// cage, so OpenSubdiv's work is done once per brush: a stencil table maps the
// skinned cage to the refined vertices, and a step costs one skinning pass and
// one stencil pass (no allocation beyond the caller's output).
//
// Texture coordinates of the surface (the paint maps onto them, §4.2.1):
//   u = angle around the brush axis / 2 pi, in [0, 1). The axis is the polyline
//       through the mean of the spines' rest points (root .. tip); a vertex's
//       angle is measured across its nearest axis segment, from the image of +x
//       under the minimal rotation of -z onto that segment: on a straight brush,
//       the plain angle from +x, counter-clockwise seen from above (+z).
//       u is periodic: a triangle across the seam carries corner u values just
//       above 1 (e.g. 0.97, 1.02), so samplers must wrap (repeat) in u. Where
//       the axis leaves the surface (the tip pole: the vertex nearest the axis
//       whose fan winds around it) the pole corner of each triangle takes the
//       mean u of the triangle's other corners.
//   v = distance down the brush, (z_top - z) / (z_top - z_bottom) over the
//       refined surface at rest in the brush frame: 0 at the ferrule, 1 at the
//       lowest point of the tip.
// Both come from the rest shape and ride with the surface as it deforms.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/geometry/spine_bundles.h"

namespace bristle {

// A point in the form OpenSubdiv's stencil tables update (Clear/AddWithWeight).
struct SurfacePoint {
  double x = 0, y = 0, z = 0;
  void Clear(void* = nullptr) { x = y = z = 0; }
  void AddWithWeight(const SurfacePoint& p, double w) {
    x += w * p.x;
    y += w * p.y;
    z += w * p.z;
  }
  Eigen::Vector3d vec() const { return {x, y, z}; }
};

class BrushSurface {
 public:
  // Builds the refined topology, stencils, triangles and UVs of brush.surface
  // (which must be present). Throws Error(kDataError) naming
  // "<brush path>: /surface/..." when the cage is not a manifold OpenSubdiv
  // accepts: an edge of three or more faces, two faces that cross an edge in
  // the same direction (inconsistent orientation), a vertex whose faces do not
  // form one fan, or a vertex used by no face.
  explicit BrushSurface(const Brush& brush);
  ~BrushSurface();
  BrushSurface(BrushSurface&&) noexcept;
  BrushSurface& operator=(BrushSurface&&) noexcept;

  // Skins the cage to `state` and refines it, then appends the refined surface
  // as a triangle list (3 vertices per triangle, world mm, u v as above).
  void update(const BrushState& state, std::vector<BrushVertex>* triangles);

  int level() const { return level_; }
  int cageVertexCount() const { return static_cast<int>(cage_.size()); }
  int refinedVertexCount() const { return static_cast<int>(refined_.size()); }
  int triangleCount() const { return static_cast<int>(tri_vertex_.size() / 3); }
  // Results of the last update (world mm, double precision).
  Eigen::Vector3d cagePosition(int i) const { return cage_[i].vec(); }
  Eigen::Vector3d refinedPosition(int i) const { return refined_[i].vec(); }
  // Refined vertex i's rest position in the brush frame, and its (u, v).
  Eigen::Vector3d refinedRestPosition(int i) const { return refined_rest_[i].vec(); }
  Eigen::Vector2f uv(int i) const { return uv_[i]; }
  // Refined vertex indices of triangle t (quads split along their 0-2 diagonal,
  // keeping the cage's orientation).
  const int* triangle(int t) const { return &tri_vertex_[3 * t]; }

 private:
  // One skin influence, precomputed: the rest position in the influence's frame.
  struct Influence {
    int frame = 0;  // index into frames_ (spine s point k: frame_offset_[s] + k)
    int spine = 0, point = 0;
    double weight = 0;
    Eigen::Vector3d local = Eigen::Vector3d::Zero();
  };
  struct Frame {
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();  // segment orientation
    Eigen::Vector3d x = Eigen::Vector3d::Zero();      // point position (mm)
  };
  struct Stencils;  // wraps OpenSubdiv's stencil table (brush_surface.cpp)

  void setupSkin(const Brush& brush);
  void setupUv(const Brush& brush);
  // Frames of one spine's n + 1 points: orientation of the segment that starts
  // at the point (the last segment at the tip), R_handle R_0 ... R_k (eq. 10),
  // from the joints' rotations relative to their parents.
  static void spineFrames(const Eigen::Matrix3d& handle_r, const Eigen::Matrix3d* rot,
                          const Eigen::Vector3d* x, int n, Frame* out);

  int level_ = 0;
  std::vector<int> joint_count_;     // per spine
  std::vector<int> frame_offset_;    // per spine: first frame (point 0)
  std::vector<Influence> influence_;
  std::vector<int> influence_offset_;  // per cage vertex, + 1 at the end
  std::unique_ptr<Stencils> stencils_;
  std::vector<int> tri_vertex_;        // 3 refined vertex indices per triangle
  std::vector<Eigen::Vector2f> tri_uv_;  // (u, v) per triangle corner, unwrapped
  std::vector<Eigen::Vector2f> uv_;      // per refined vertex
  std::vector<SurfacePoint> refined_rest_;
  // Per-step scratch, reused.
  std::vector<Frame> frames_;
  std::vector<SpineSpec> spines_;          // the brush's, for their bundles' placement
  std::vector<BundlePlacement> bundles_;   // per spine (update)
  std::vector<SurfacePoint> cage_, refined_;
};

}  // namespace bristle

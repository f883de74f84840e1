#pragma once
// CPU side of the brush preview (render/preview/preview_renderer.h): where the overlays
// go, how the camera frames the brush, and the triangle meshes the GL passes
// draw (ferrule stub, spine tubes and joint spheres, the hair with normals, the
// shadow). Internal to render/; no GL here, so all of it is plain arithmetic.

#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "render/preview/preview_renderer.h"

namespace bristle::render::preview {

// A lit vertex: world mm and a unit normal, or a zero normal for "use the
// triangle's own facet normal" (strips and raw triangles of unknown winding).
struct MeshVertex {
  float x, y, z;
  float nx, ny, nz;
};
using Mesh = std::vector<MeshVertex>;  // triangle list

struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;  // final image pixels, y down
};

// Where the 2D parts of the picture go; the camera frames the brush in `content`.
struct Layout {
  int margin_px = 0;
  int title_size_px = 0, label_size_px = 0;  // font pixel sizes
  PixelRect content;                         // the brush is framed inside this
  std::optional<PixelRect> inset;            // footprint inset, bottom-right
};
Layout layoutPreview(const PreviewScene& scene, const PreviewOptions& options);

// The metal stub at the ferrule mouth: an elliptic cylinder along the brush
// axis, 1.5x the spread of the spine roots (and wider than the hairs at the
// mouth) on each cross-section axis: round brushes get a round ferrule, flats
// and fans a flattened one.
struct Ferrule {
  Eigen::Vector3d mouth_mm, axis, major, minor;  // axis = brush +z (world)
  double major_radius_mm = 0, minor_radius_mm = 0, length_mm = 0;
};
// Nothing when the scene has no brush geometry to size the stub by.
std::optional<Ferrule> fitFerrule(const PreviewScene& scene);

// World-space box of everything drawn (hair, spines, ferrule).
struct Bounds {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-1e300);
  bool empty() const { return lo.x() > hi.x(); }
  void add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
};
Bounds sceneBounds(const PreviewScene& scene, const std::optional<Ferrule>& ferrule);

// Camera directions, fixed relative to the world so previews compare: seen from
// the front (-y, the painter's near edge) and a little from the right, from
// kElevationDeg above the paper.
inline constexpr double kAzimuthDeg = 32, kElevationDeg = 16, kFovYDeg = 28;
// The paper is a square this many scene radii across each way from the
// target, fading into the backdrop between the two fog radii (no visible edge).
inline constexpr double kGroundRadii = 16, kFogStartRadii = 3, kFogEndRadii = 12;

// Everything the GL passes draw, in world mm. Spine tubes and joint dots are
// sized in image pixels (via the camera) so they read at every zoom.
struct SceneMeshes {
  Mesh surface, strips, spines, ferrule, ground;
  Mesh casters;  // what throws the shadow: hair and spines, not the ferrule
  bool surface_ccw_outward = true;
};
SceneMeshes buildMeshes(const PreviewScene& scene, const PreviewCamera& camera);

void appendFerrule(const Ferrule& ferrule, Mesh* mesh);
void appendTube(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius_mm, Mesh* mesh);
void appendSphere(const Eigen::Vector3d& centre, double radius_mm, Mesh* mesh);
// Smooth (area-weighted, welded by position) normals turned outwards by the
// sign of the enclosed volume. Returns true when counter-clockwise triangles
// face outwards, so the caller can cull back or front faces.
bool appendSmooth(std::span<const BrushVertex> triangles, Mesh* mesh);
void appendFacetted(std::span<const BrushVertex> triangles, Mesh* mesh);
// The mesh flattened onto the paper (z = 0) along the direction towards the light.
void appendShadow(const Mesh& caster, const Eigen::Vector3d& toward_light, Mesh* shadow);

}  // namespace bristle::render::preview

#pragma once
// A 3D picture of one brush state for people who design brushes (`bristle
// preview`; paper Fig. 2 shows brushes with their spine models): the hair
// surface and strips, the spines inside them, a metal ferrule stub that shows
// the handle pose, and the paper with a 5 mm grid and the brush's soft shadow,
// seen in perspective from the front-side, a little above the paper. An
// optional inset shows the footprint; an optional title names the brush.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/geometry/brush_vertex.h"
#include "engine/model/pose.h"
#include "render/gl/footprint_renderer.h"
#include "render/image/png_io.h"

namespace bristle::render {

struct PreviewScene {
  std::vector<BrushVertex> surface;  // triangles of the brush surface (may be empty)
  std::vector<BrushVertex> strips;   // triangles of bristle strips (may be empty)
  std::vector<std::vector<Eigen::Vector3d>> spines;  // polylines, world mm, root first
  // Places the ferrule stub (brush frame +z from the ferrule mouth). Drawn only
  // when there is brush geometry to size it by.
  Pose handle;
  const FootprintImage* footprint = nullptr;  // optional inset (cropped to the contact)
  std::string title;                          // optional, UTF-8, top-left
};

struct PreviewOptions {
  int width_px = 800;  // output size; each side in [64, 4096]
  int height_px = 600;
  bool legend = true;  // colour key and grid spacing, bottom-left
};

// The auto-framed perspective camera of a preview (exposed so tests and callers
// can find where things land in the image).
struct PreviewCamera {
  Eigen::Vector3d eye_mm = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_mm = Eigen::Vector3d::Zero();
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();        // world -> eye (GL convention)
  Eigen::Matrix4d projection = Eigen::Matrix4d::Identity();  // eye -> clip
  double near_mm = 1, far_mm = 1000;
  double radius_mm = 1;              // half diagonal of the framed box
  double mm_per_px_at_target = 0.1;  // image scale at the target's depth
  int width_px = 0, height_px = 0;

  // Pixel position (x right, y down, row 0 at the top) of a world point, or
  // nothing when the point is behind the camera.
  std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_mm) const;
};

// The camera renderPreview uses for this scene and image size. Throws
// std::invalid_argument for sizes outside [64, 4096].
PreviewCamera framePreview(const PreviewScene& scene, const PreviewOptions& options);

// Renders previews with one GL context (OSMesa) and one text face. Reuse it for
// several previews; it coexists with FootprintRenderer (each makes its own
// context current before drawing).
class PreviewRenderer {
 public:
  PreviewRenderer();
  ~PreviewRenderer();
  PreviewRenderer(const PreviewRenderer&) = delete;
  PreviewRenderer& operator=(const PreviewRenderer&) = delete;

  // RGB, row 0 at the top. Rendered at 2x and box-filtered down; the same scene
  // gives the same bytes every time. Throws std::invalid_argument for bad sizes
  // and std::runtime_error for GL or font failures.
  Image8 render(const PreviewScene& scene, const PreviewOptions& options);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot convenience: a PreviewRenderer for a single picture.
Image8 renderPreview(const PreviewScene& scene, const PreviewOptions& options = {});

}  // namespace bristle::render

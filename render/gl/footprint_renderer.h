#pragma once
// Footprint renderer (paper §4.2.1): the brush geometry is rendered with an
// orthographic projection from the canvas's point of view, and a clip plane
// just above the paper surface keeps only what touches it. The result is a
// float image carrying, per canvas pixel, which brush texel touches and how deep.

#include <cstddef>
#include <memory>
#include <span>
#include <vector>

namespace bristle::render {

class GlContext;

// One vertex of brush geometry in world millimetres (canvas frame: z out of the
// canvas, the paper at z = 0) with the brush texture coordinate it carries.
struct FootprintVertex {
  float x_mm, y_mm, z_mm;
  float u, v;
};

// A window of the canvas grid: pixel column c covers
// x in [x0_mm + c / px_per_mm, x0_mm + (c + 1) / px_per_mm]; pixel row r (row 0 at
// the top, the largest y) covers y in [y0_mm + (height_px - r - 1) / px_per_mm,
// y0_mm + (height_px - r) / px_per_mm]. (x0_mm, y0_mm) is the bottom-left corner.
struct FootprintWindow {
  double x0_mm = 0, y0_mm = 0;
  int width_px = 0, height_px = 0;
  double px_per_mm = 8;
  bool operator==(const FootprintWindow&) const = default;
};

// Per pixel, 4 floats: u, v (texture coordinate of the touching brush point
// nearest the canvas), depth_mm = contact_band_mm - z of that point (> 0 where touched),
// coverage: the share of the pixel the touching geometry covers, in (0, 1]: 1
// where geometry below the clip plane covers the pixel's centre, less where
// only a hair triangle thinner than a pixel passes by it (setHairTextureRange;
// footprint_renderer.cpp, kGeometryShader); 0 where nothing touches, and then
// u = v = depth = 0.
// Row 0 is the top row, as in the canvas and in PNG files.
struct FootprintImage {
  FootprintWindow window;
  std::vector<float> texels;  // width_px * height_px * 4
  const float* at(int col, int row) const {
    return &texels[(static_cast<size_t>(row) * window.width_px + col) * 4];
  }
};

class FootprintRenderer {
 public:
  // Windows up to max_size_px on a side are supported; larger ones throw
  // std::invalid_argument. The GL context is created here (OSMesa, llvmpipe).
  explicit FootprintRenderer(int max_size_px = 2048);
  ~FootprintRenderer();
  FootprintRenderer(const FootprintRenderer&) = delete;
  FootprintRenderer& operator=(const FootprintRenderer&) = delete;

  // Which triangles are single hairs: those whose first vertex's u lies in
  // [u_begin, u_end). A hair triangle thinner than a pixel also marks the
  // pixels its centre samples miss, with coverage below 1 (see `coverage`
  // above). By default every triangle counts as hair.
  void setHairTextureRange(float u_begin, float u_end);

  // Renders the triangles (3 consecutive vertices each) clipped to z <= contact_band_mm.
  // Deterministic: one fixed readback path (float colour attachment of an FBO).
  // Triangles that cannot mark a pixel (not hair, and no pixel centre inside)
  // are left out before GL sees them: the same bytes, less of llvmpipe's
  // per-triangle work.
  void render(std::span<const FootprintVertex> triangles,
              const FootprintWindow& window, double contact_band_mm, FootprintImage* out);

  // Leaving out the triangles that cannot mark a pixel (on by default); off,
  // every triangle goes to GL. For tests and benchmarks that compare the two.
  // Where a footprint drops few triangles, the next 15 are sent whole without
  // the tests (their cost would exceed the saving); setting this starts
  // testing again at the next render.
  void setSkipUnmarking(bool skip);
  // Triangles the last render sent to GL.
  std::size_t lastDrawnTriangles() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bristle::render

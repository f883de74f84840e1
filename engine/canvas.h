#pragma once
// The canvas: a grid of pixels over the canvas plane (world z = 0), holding how
// much paint each pixel received. First cut: one paint colour, an opacity per
// pixel; the paint issue replaces it with wet/dry pigment layers.

#include <cstdint>
#include <string>
#include <vector>

namespace bristle {

// Largest canvas accepted, refused before allocating: 16384 px on a side and
// 64 Mpx in all (a 256 MiB float layer).
inline constexpr int kMaxCanvasSidePx = 16384;
inline constexpr long kMaxCanvasPixels = 64L * 1024 * 1024;

struct CanvasGrid {
  double x0_mm = 0, y0_mm = 0;  // world position of the bottom-left corner
  int width_px = 0, height_px = 0;
  double px_per_mm = 8;
  double widthMm() const { return width_px / px_per_mm; }
  double heightMm() const { return height_px / px_per_mm; }
  // Pixel column / row (row 0 at the top) of a world point, possibly outside.
  double colOf(double x_mm) const { return (x_mm - x0_mm) * px_per_mm; }
  double rowOf(double y_mm) const { return height_px - (y_mm - y0_mm) * px_per_mm; }
};

struct Rgb {
  double r = 0, g = 0, b = 0;  // sRGB-encoded, 0..1
};
// Parses "#rrggbb"; returns false if it is not one.
bool parseHexColour(const std::string& text, Rgb* out);

class Canvas {
 public:
  explicit Canvas(const CanvasGrid& grid);
  const CanvasGrid& grid() const { return grid_; }
  float opacity(int col, int row) const { return opacity_[index(col, row)]; }
  // Paint reaches a pixel with the given opacity; the pixel keeps the most it got.
  void deposit(int col, int row, float opacity);
  bool blank() const;
  // 8-bit RGB, row 0 at the top: paint over background, mixed in linear light.
  std::vector<std::uint8_t> composeRgb8(const Rgb& paint, const Rgb& background) const;

 private:
  size_t index(int col, int row) const { return static_cast<size_t>(row) * grid_.width_px + col; }
  CanvasGrid grid_;
  std::vector<float> opacity_;
};

}  // namespace bristle

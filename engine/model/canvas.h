#pragma once
// The canvas grid: pixels over the canvas plane (world z = 0), and colours. The
// paint on it lives in engine/paint/paint.h (PaintCanvas).

#include <string>

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

}  // namespace bristle

#include "tests/support/mark_png.h"

#include <cstdio>

#include "render/image/png_io.h"

namespace bristle::testsupport {

Coverage loadCoveragePng(const std::string& path, double px_per_mm) {
  const render::Image8 rgba = render::readPngRgba8(path);
  double x0 = 0, y0 = 0, ppm = 8;
  for (const auto& [key, value] : render::readPngText(path)) {
    if (key != "bristle:canvas") continue;
    double a = 0, b = 0, c = 0;
    if (std::sscanf(value.c_str(), "x0_mm=%lf y0_mm=%lf px_per_mm=%lf", &a, &b, &c) == 3 && c > 0) {
      x0 = a;
      y0 = b;
      ppm = c;
    }
  }
  if (px_per_mm > 0) ppm = px_per_mm;
  Coverage img = coverageFromRgba8(rgba.width, rgba.height, rgba.pixels.data(), ppm);
  img.x0_mm = x0;
  img.y0_mm = y0;
  return img;
}

std::string pngText(const std::string& png, const std::string& key) {
  for (const auto& [k, v] : render::readPngText(png))
    if (k == key) return v;
  return "";
}

}  // namespace bristle::testsupport

#include "engine/canvas.h"

#include <algorithm>
#include <cmath>

namespace bristle {
namespace {

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double linearToSrgb(double c) {
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

}  // namespace

bool parseHexColour(const std::string& text, Rgb* out) {
  if (text.size() != 7 || text[0] != '#') return false;
  int v[3];
  for (int i = 0; i < 3; ++i) {
    v[i] = 0;
    for (int k = 0; k < 2; ++k) {
      const char c = text[1 + 2 * i + k];
      int d;
      if (c >= '0' && c <= '9') d = c - '0';
      else if (c >= 'a' && c <= 'f') d = c - 'a' + 10;
      else if (c >= 'A' && c <= 'F') d = c - 'A' + 10;
      else return false;
      v[i] = v[i] * 16 + d;
    }
  }
  *out = Rgb{v[0] / 255.0, v[1] / 255.0, v[2] / 255.0};
  return true;
}

Canvas::Canvas(const CanvasGrid& grid)
    : grid_(grid), opacity_(static_cast<size_t>(grid.width_px) * grid.height_px, 0.0f) {}

void Canvas::deposit(int col, int row, float opacity) {
  float& o = opacity_[index(col, row)];
  o = std::max(o, std::clamp(opacity, 0.0f, 1.0f));
}

bool Canvas::blank() const {
  return std::all_of(opacity_.begin(), opacity_.end(), [](float o) { return o == 0.0f; });
}

std::vector<std::uint8_t> Canvas::composeRgb8(const Rgb& paint, const Rgb& background) const {
  const double pl[3] = {srgbToLinear(paint.r), srgbToLinear(paint.g), srgbToLinear(paint.b)};
  const double bl[3] = {srgbToLinear(background.r), srgbToLinear(background.g),
                        srgbToLinear(background.b)};
  // Lookup per 8-bit opacity level keeps composing cheap and exactly repeatable.
  std::vector<std::uint8_t> lut(256 * 3);
  for (int a = 0; a < 256; ++a)
    for (int c = 0; c < 3; ++c) {
      const double lin = bl[c] + (pl[c] - bl[c]) * (a / 255.0);
      lut[a * 3 + c] = static_cast<std::uint8_t>(std::lround(255.0 * linearToSrgb(lin)));
    }
  std::vector<std::uint8_t> out(opacity_.size() * 3);
  for (size_t i = 0; i < opacity_.size(); ++i) {
    const int a = static_cast<int>(std::lround(opacity_[i] * 255.0f));
    for (int c = 0; c < 3; ++c) out[i * 3 + c] = lut[a * 3 + c];
  }
  return out;
}

}  // namespace bristle

#include "render/image/compose.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>

#include "bristle/version.h"
#include "engine/base/fnv1a64.h"

namespace bristle::render {

std::vector<float> composeLinear(const PaintCanvas& canvas, const ComposeOptions& options) {
  const CanvasGrid& g = canvas.grid();
  const int w = g.width_px, h = g.height_px;
  std::vector<float> out(canvas.pixels() * 3);
  for (size_t i = 0; i < canvas.pixels(); ++i) {
    const std::array<double, 3> r = canvas.reflectance(i);
    for (int c = 0; c < 3; ++c) out[i * 3 + c] = static_cast<float>(r[c]);
  }
  if (!options.impasto) return out;

  // Unit light and the Blinn half vector towards a viewer straight above.
  double l[3] = {options.light[0], options.light[1], options.light[2]};
  const double ln = std::sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
  for (double& x : l) x /= ln;
  double hv[3] = {l[0], l[1], l[2] + 1};
  const double hn = std::sqrt(hv[0] * hv[0] + hv[1] * hv[1] + hv[2] * hv[2]);
  for (double& x : hv) x /= hn;
  const double a = options.ambient;
  // A flat canvas keeps its colour: shading is relative to the flat normal (0, 0, 1).
  const double flat_diffuse = a + (1 - a) * std::max(0.0, l[2]);
  const double flat_spec = std::pow(hv[2], options.shininess);
  std::vector<float> height(canvas.pixels());
  for (size_t i = 0; i < canvas.pixels(); ++i)
    height[i] = static_cast<float>(canvas.heightMm(i) * options.relief);
  const double inv_2px_mm = 0.5 * g.px_per_mm;  // central difference over 2 pixels
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const size_t i = canvas.index(c, r);
      const float hl = height[canvas.index(std::max(c - 1, 0), r)];
      const float hr = height[canvas.index(std::min(c + 1, w - 1), r)];
      const float hu = height[canvas.index(c, std::max(r - 1, 0))];  // up = +y
      const float hd = height[canvas.index(c, std::min(r + 1, h - 1))];
      const double dx = (hr - hl) * inv_2px_mm, dy = (hu - hd) * inv_2px_mm;
      if (dx == 0 && dy == 0) continue;
      const double nn = std::sqrt(dx * dx + dy * dy + 1);
      const double n[3] = {-dx / nn, -dy / nn, 1 / nn};
      const double diffuse = a + (1 - a) * std::max(0.0, n[0] * l[0] + n[1] * l[1] + n[2] * l[2]);
      const double spec =
          std::pow(std::max(0.0, n[0] * hv[0] + n[1] * hv[1] + n[2] * hv[2]), options.shininess);
      const double gain = diffuse / flat_diffuse;
      const double gloss = options.specular * (spec - flat_spec);
      for (int k = 0; k < 3; ++k)
        out[i * 3 + k] =
            static_cast<float>(std::clamp(out[i * 3 + k] * gain + gloss, 0.0, 1.0));
    }
  return out;
}

namespace {

// linearToSrgb's pow would be most of composing a canvas (docs/PERFORMANCE.md,
// "Three trims with the same bytes"), and a canvas holds few
// distinct values: the bare paper, the flat inside of a stroke. A
// direct-mapped memo keyed by the float's bits gives every value the very
// result the function gives it, computed once per slot it lands in.
template <class T, int kMax>
void encodeSrgbInto(std::span<const float> linear, std::vector<T>* out) {
  constexpr int kSlots = 4096;  // 32 KB of keys and codes
  struct Slot {
    std::uint32_t key;
    T code;
    bool used;
  };
  std::vector<Slot> memo(kSlots, Slot{0, 0, false});
  out->reserve(out->size() + linear.size());
  for (const float v : linear) {
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(v);
    // Fibonacci hashing: the top 12 bits of the product mix every input bit.
    Slot& s = memo[(bits * 2654435769u) >> 20];
    if (!s.used || s.key != bits)
      s = Slot{bits, static_cast<T>(std::lround(double(kMax) * linearToSrgb(v))), true};
    out->push_back(s.code);
  }
}

}  // namespace

std::vector<std::uint8_t> encodeSrgb8(std::span<const float> linear) {
  std::vector<std::uint8_t> out;
  encodeSrgbInto<std::uint8_t, 255>(linear, &out);
  return out;
}

std::vector<std::uint16_t> encodeSrgb16(std::span<const float> linear) {
  std::vector<std::uint16_t> out;
  encodeSrgbInto<std::uint16_t, 65535>(linear, &out);
  return out;
}

Image8 composeRgb8(const PaintCanvas& canvas, const ComposeOptions& options) {
  Image8 img;
  img.width = canvas.grid().width_px;
  img.height = canvas.grid().height_px;
  img.channels = 3;
  img.pixels = encodeSrgb8(composeLinear(canvas, options));
  return img;
}

Image16 composeRgb16(const PaintCanvas& canvas, const ComposeOptions& options) {
  Image16 img;
  img.width = canvas.grid().width_px;
  img.height = canvas.grid().height_px;
  img.channels = 3;
  img.pixels = encodeSrgb16(composeLinear(canvas, options));
  return img;
}

void writeCanvasPng(const std::string& path, const PaintCanvas& canvas, const Image8& image8,
                    const ComposeOptions& options, int bits, const PngText& text) {
  if (bits == 16)
    writePng(path, composeRgb16(canvas, options), text);
  else
    writePng(path, image8, text);
}

PngText provenanceText(const std::vector<std::string>& inputs) {
  return provenanceText(fnv1a64Files(inputs));
}

PngText provenanceText(std::uint64_t inputs_fnv1a64) {
  return {{"Software", std::string("bristle ") + kVersion},
          {"bristle:version", kVersion},
          {"bristle:inputs-fnv1a64", hex64(inputs_fnv1a64)}};
}

std::array<std::uint8_t, 3> paperColour8(const PaperSpec& paper, MixModel model, double px_per_mm,
                                         const ComposeOptions& options) {
  CanvasGrid g;
  g.width_px = g.height_px = 1;
  g.px_per_mm = px_per_mm;
  const PaintCanvas blank(g, paper, model);
  const Image8 px = composeRgb8(blank, options);
  return {px.pixels[0], px.pixels[1], px.pixels[2]};
}

long inkPixels(const Image8& image, const std::array<std::uint8_t, 3>& paper) {
  long n = 0;
  const size_t pixels = size_t(image.width) * size_t(image.height);
  for (size_t i = 0; i < pixels; ++i) n += isInk(&image.pixels[i * size_t(image.channels)], paper);
  return n;
}

}  // namespace bristle::render

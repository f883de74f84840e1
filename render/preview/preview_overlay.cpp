// Title, colour key and footprint inset of the brush preview, drawn with plain
// integer/double arithmetic on the final image (deterministic, no GL).

#include "render/preview/preview_overlay.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace bristle::render::preview {

namespace {

constexpr double kGridMm = 5;  // matches the paper's grid in 3D
constexpr Rgb8 kPaper{250, 247, 240};
constexpr Rgb8 kGridLine{214, 209, 196};
constexpr Rgb8 kBorder{92, 92, 98};
// Footprint ink: shallow contact light, deep contact dark (indigo, so it never
// reads as hair or spine in the 3D view next to it).
constexpr double kInkShallow[3] = {150, 160, 196}, kInkDeep[3] = {24, 30, 78};
constexpr int kInsetSubsamples = 3;  // per axis, per inset pixel

std::uint8_t* pixelAt(Image8* image, int x, int y) {
  return &image->pixels[(static_cast<std::size_t>(y) * image->width + x) * image->channels];
}

void fillRect(Image8* image, int x, int y, int w, int h, Rgb8 c, double alpha = 1.0) {
  const int a = static_cast<int>(std::lround(std::clamp(alpha, 0.0, 1.0) * 255));
  for (int row = std::max(0, y); row < std::min(image->height, y + h); ++row) {
    for (int col = std::max(0, x); col < std::min(image->width, x + w); ++col) {
      std::uint8_t* px = pixelAt(image, col, row);
      const std::uint8_t rgb[3] = {c.r, c.g, c.b};
      for (int k = 0; k < 3; ++k)
        px[k] = static_cast<std::uint8_t>((px[k] * (255 - a) + rgb[k] * a + 127) / 255);
    }
  }
}

void strokeRect(Image8* image, const PixelRect& r, Rgb8 c) {
  fillRect(image, r.x - 1, r.y - 1, r.width + 2, 1, c);
  fillRect(image, r.x - 1, r.y + r.height, r.width + 2, 1, c);
  fillRect(image, r.x - 1, r.y, 1, r.height, c);
  fillRect(image, r.x + r.width, r.y, 1, r.height, c);
}

// The key: a swatch and a word per thing drawn, then the grid spacing.
void drawLegend(const PreviewScene& scene, const Layout& layout, Font& font, Image8* image) {
  const int size = layout.label_size_px, m = layout.margin_px;
  const int y = image->height - m - static_cast<int>(std::lround(1.2 * size));
  const int mid = y + font.ascent(size) - static_cast<int>(std::lround(0.35 * size));
  int x = m;
  const auto item = [&](Rgb8 colour, const char* word, bool line) {
    const int sw = static_cast<int>(std::lround(0.9 * size));
    if (line) {  // a spine: a bold stroke with a joint dot
      fillRect(image, x, mid - 1, sw, 3, colour);
      fillRect(image, x + sw / 2 - 2, mid - 3, 5, 7, colour);
    } else {
      fillRect(image, x, mid - sw / 2, sw, sw, colour);
    }
    x += sw + size / 3;
    x += drawText(font, word, size, x, y, kInkText, image) + size;
  };
  if (!scene.spines.empty()) item(kSpineKey, "spines", true);
  if (!scene.surface.empty()) item(kSurfaceKey, "surface", false);
  if (!scene.strips.empty()) item(kStripKey, "strips", false);
  drawText(font, "grid 5 mm", size, x, y, kMutedText, image);
}

}  // namespace

void drawFootprintInset(const FootprintImage& footprint, const PixelRect& rect, int label_size_px,
                        Font& font, Image8* image) {
  const FootprintWindow& win = footprint.window;
  const double ppm = win.px_per_mm;
  // The contact's bounding box in canvas pixels, and the deepest contact.
  int c0 = win.width_px, c1 = -1, r0 = win.height_px, r1 = -1;
  double max_depth = 0;
  for (int r = 0; r < win.height_px; ++r) {
    for (int c = 0; c < win.width_px; ++c) {
      const float* t = footprint.at(c, r);
      if (t[3] < 0.5f) continue;
      c0 = std::min(c0, c), c1 = std::max(c1, c), r0 = std::min(r0, r), r1 = std::max(r1, r);
      max_depth = std::max(max_depth, static_cast<double>(t[2]));
    }
  }
  double cx = win.x0_mm + 0.5 * win.width_px / ppm, cy = win.y0_mm + 0.5 * win.height_px / ppm;
  double side_mm = 10;  // no contact: 10 mm of empty paper in the window's middle
  if (c1 >= 0) {
    const double xa = win.x0_mm + c0 / ppm, xb = win.x0_mm + (c1 + 1) / ppm;
    const double ya = win.y0_mm + (win.height_px - 1 - r1) / ppm,
                 yb = win.y0_mm + (win.height_px - r0) / ppm;
    cx = 0.5 * (xa + xb), cy = 0.5 * (ya + yb);
    side_mm = std::max(6.0, 1.3 * std::max(xb - xa, yb - ya) + 2.0);
  }
  const double mm_per_px = side_mm / rect.width;
  const double left_mm = cx - 0.5 * side_mm, top_mm = cy + 0.5 * side_mm;

  fillRect(image, rect.x + 3, rect.y + 3, rect.width, rect.height, {0, 0, 0}, 0.12);  // lift
  for (int j = 0; j < rect.height; ++j) {
    // A grid line crosses this pixel row / column: paint it on the paper.
    const double y_hi = top_mm - j * mm_per_px, y_lo = y_hi - mm_per_px;
    const bool grid_row = std::floor(y_lo / kGridMm) != std::floor(y_hi / kGridMm);
    for (int i = 0; i < rect.width; ++i) {
      const double x_lo = left_mm + i * mm_per_px;
      const bool grid =
          grid_row || std::floor(x_lo / kGridMm) != std::floor((x_lo + mm_per_px) / kGridMm);
      const Rgb8 ground = grid ? kGridLine : kPaper;
      double sum[3] = {0, 0, 0};
      for (int b = 0; b < kInsetSubsamples; ++b) {
        for (int a = 0; a < kInsetSubsamples; ++a) {
          const double x = x_lo + (a + 0.5) / kInsetSubsamples * mm_per_px;
          const double y = y_hi - (b + 0.5) / kInsetSubsamples * mm_per_px;
          const int col = static_cast<int>(std::floor((x - win.x0_mm) * ppm));
          const int row = win.height_px - 1 - static_cast<int>(std::floor((y - win.y0_mm) * ppm));
          double rgb[3] = {double(ground.r), double(ground.g), double(ground.b)};
          if (col >= 0 && row >= 0 && col < win.width_px && row < win.height_px &&
              footprint.at(col, row)[3] >= 0.5f) {
            const double t =
                0.25 +
                0.75 * std::clamp(footprint.at(col, row)[2] / std::max(max_depth, 1e-9), 0.0, 1.0);
            for (int k = 0; k < 3; ++k)
              rgb[k] = kInkShallow[k] + t * (kInkDeep[k] - kInkShallow[k]);
          }
          for (int k = 0; k < 3; ++k) sum[k] += rgb[k];
        }
      }
      std::uint8_t* px = pixelAt(image, rect.x + i, rect.y + j);
      for (int k = 0; k < 3; ++k) {
        px[k] =
            static_cast<std::uint8_t>(std::lround(sum[k] / (kInsetSubsamples * kInsetSubsamples)));
      }
    }
  }
  strokeRect(image, rect, kBorder);
  const Image8 label = font.rasterize("footprint", label_size_px);
  const int pad = std::max(2, label_size_px / 3);
  fillRect(image, rect.x, rect.y, label.width + 2 * pad, label.height + pad, kPaper, 0.85);
  blendMask(label, rect.x + pad, rect.y + pad / 2, kInkText, image);
}

void drawOverlays(const PreviewScene& scene, const PreviewOptions& options, const Layout& layout,
                  Font& font, Image8* image) {
  if (!scene.title.empty()) {
    drawText(font, scene.title, layout.title_size_px, layout.margin_px,
             layout.margin_px - layout.title_size_px / 5, kInkText, image);
  }
  if (options.legend) drawLegend(scene, layout, font, image);
  if (scene.footprint != nullptr && layout.inset) {
    drawFootprintInset(*scene.footprint, *layout.inset, layout.label_size_px, font, image);
  }
}

}  // namespace bristle::render::preview

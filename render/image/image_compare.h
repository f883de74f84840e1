#pragma once
// Image comparison for `bristle compare` and the golden suite (docs/golden-tests.md):
// an exact pixel hash, per-channel differences, RMSE/PSNR and SSIM, checked
// against a tolerance preset.
//
// Both images are first normalised to 16-bit RGBA (readPngRgba16: an 8-bit
// sample v is v * 257, an image without alpha is opaque), so 8- and 16-bit,
// grey, RGB and RGBA files compare. Differences are reported in units of
// 1/255 of full scale ("8-bit steps"): an 8-bit difference of 3 is 3.0, a
// 16-bit difference of 257 is 1.0.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "render/image/png_io.h"

namespace bristle::render {

// The limits an image pair must meet. Unset limits are not checked.
struct CompareTolerance {
  std::string name;              // "exact", "strict", "loose" or "custom"
  bool require_identical = false;  // the pixel hashes must be equal
  std::optional<double> max_abs;   // largest per-channel |a - b| (8-bit steps)
  double pixel_threshold = 0;      // a pixel "differs" when a channel differs by more
                                   // than this (8-bit steps)
  std::optional<double> max_percent_over;  // at most this % of pixels differ
  std::optional<double> min_ssim;          // SSIM at least this
  std::optional<double> min_psnr_db;       // PSNR at least this (dB)
};

// "exact", "strict" or "loose" (the numbers and why: image_compare.cpp,
// docs/golden-tests.md). Throws std::invalid_argument for any other name.
CompareTolerance tolerancePreset(const std::string& name);

struct ImageComparison {
  int width = 0, height = 0;
  std::uint64_t hash_a = 0, hash_b = 0;  // FNV-1a 64 of the normalised pixels
  bool identical = false;                // hash_a == hash_b and every sample equal
  std::array<double, 4> max_abs{};       // per channel R, G, B, A (8-bit steps)
  double pixel_threshold = 0;            // the threshold pixels_over used (8-bit steps)
  std::int64_t pixels_differing = 0;     // any channel differs at all
  std::int64_t pixels_over = 0;          // a channel differs by more than the threshold
  double percent_over = 0;               // pixels_over / all pixels, in %
  double rmse = 0;                       // over R, G, B of all pixels (8-bit steps)
  double psnr_db = 0;                    // 20 log10(255 / rmse); +inf when rmse = 0
  double ssim = 1;                       // mean SSIM of the luma (Wang et al. 2004)
  int ssim_window = 0;                   // side of the Gaussian window used (px)
};

// The FNV-1a 64 hash of an image's pixels: the width and height as two
// little-endian 32-bit words, then every sample as two big-endian bytes.
std::uint64_t pixelHash(const Image16& image);

// Mean SSIM (Wang, Bovik, Sheikh, Simoncelli 2004, eq. 13 with their 11x11
// Gaussian window, sigma 1.5, K1 = 0.01, K2 = 0.03, L = 1) of the Rec. 601 luma
// of two RGBA images, over the windows that lie inside the image. Images
// narrower or lower than 11 px use a window as large as the image allows.
// `window` receives the side used. Throws std::invalid_argument on size mismatch.
double ssim(const Image16& a, const Image16& b, int* window = nullptr);

// All metrics of a pair of equally sized RGBA images; pixel_threshold (8-bit
// steps) decides which pixels count in pixels_over. Throws std::invalid_argument
// when the sizes differ or an image is not RGBA.
ImageComparison compareImages(const Image16& a, const Image16& b, double pixel_threshold);

// One limit of a tolerance against its measured value.
struct ToleranceCheck {
  std::string metric;  // "hash", "max_abs", "percent_over", "ssim", "psnr_db"
  double value = 0;
  double limit = 0;
  bool at_most = true;  // the value must be <= limit (else >= limit)
  bool pass = false;
};
std::vector<ToleranceCheck> checkTolerance(const ImageComparison& c,
                                           const CompareTolerance& t);
inline bool allPass(const std::vector<ToleranceCheck>& checks) {
  for (const ToleranceCheck& c : checks)
    if (!c.pass) return false;
  return true;
}

// The amplified difference image (8-bit RGB): where the pixels differ, red
// 64 + 191 * min(1, gain * d) with d the largest channel difference as a
// fraction of full scale (even the smallest difference shows as dark red);
// equal pixels within kDifferenceMarkerPx of a difference are marker yellow
// (255, 200, 0), so that a single differing pixel can be found in a large
// image; all other pixels are a's luma dimmed to 30% grey, to see where one is.
inline constexpr int kDifferenceMarkerPx = 3;
Image8 differenceImage(const Image16& a, const Image16& b, double gain);

// ---- Comparing renders by where they lie on the canvas (compare --align canvas)

// Where an image lies on the canvas, as the renderer records it in the PNG
// text "bristle:canvas" (cli canvasText): the bottom-left corner of the image
// in canvas millimetres, the scale, and the size. Row 0 of the image is its top.
struct CanvasPlacement {
  double x0_mm = 0, y0_mm = 0, px_per_mm = 0;
  int width_px = 0, height_px = 0;
};
inline constexpr const char* kCanvasTextKey = "bristle:canvas";
// Parses "x0_mm=X y0_mm=Y px_per_mm=S width_px=W height_px=H" (the five fields
// in that order, finite, S > 0, W and H > 0). Returns false when it is not that.
bool parseCanvasPlacement(const std::string& text, CanvasPlacement* out);

// Two renders at one scale whose canvases cover different regions, compared
// over the region both cover. The images' pixel grids must coincide: b's
// corner lies a whole number of pixels from a's (bristle snaps every canvas
// corner to its pixel grid, so renders at one px-per-mm always do).
struct AlignedComparison {
  ImageComparison c;      // the metrics over the overlap, with the ink outside it
                          // counted in (see compareAligned)
  int offset_x_px = 0, offset_y_px = 0;  // b's bottom-left corner from a's (px, y up)
  double overlap_x0_mm = 0, overlap_y0_mm = 0;  // bottom-left corner of the overlap
  int overlap_width_px = 0, overlap_height_px = 0;  // 0 x 0: the canvases do not meet
  std::int64_t ink_outside_a = 0, ink_outside_b = 0;  // ink pixels outside the overlap
  std::int64_t pixels = 0;  // overlap pixels + ink outside: percent_over's whole
  std::array<std::uint8_t, 3> paper_a{}, paper_b{};   // each image's paper colour (8-bit)
};

// The whole number of pixels b's corner lies from a's along each axis; false
// when the scales differ (relative 1e-6) or the offset is off the pixel grid
// by more than 1e-3 px (the text's 6 decimals are far finer).
bool canvasOffsetPx(const CanvasPlacement& a, const CanvasPlacement& b, int* dx, int* dy);

// The paper colour of a render: the most frequent 8-bit RGB colour of its
// outermost ring of pixels (a stroke's canvas has a margin of bare paper all
// round; ties go to the smallest colour).
std::array<std::uint8_t, 3> borderPaperColour(const Image16& image);

// Compares a and b where their canvases overlap. Within the overlap, every
// metric is compareImages' on the two crops. A pixel outside the overlap is
// ink when its R, G, B differ from its own image's paper colour by more than
// kInkLevels (6) 8-bit levels summed (render/image/compose.h, the rule of the batch's
// painted_pixels and of the sheets): the other image has no such mark, so each
// such pixel counts as one differing pixel and one pixel over the threshold;
// percent_over is then over the overlap's pixels plus these; the images are
// identical only when the crops are and no ink lies outside. Max abs, RMSE,
// PSNR and SSIM are of the overlap alone. Bare paper outside the overlap does
// not count: that is the point of aligning. Preconditions (else
// std::invalid_argument): canvasOffsetPx holds, and each placement's size is
// its image's. When the canvases do not overlap, c is left empty and
// overlap_width_px is 0.
AlignedComparison compareAligned(const Image16& a, const CanvasPlacement& pa, const Image16& b,
                                 const CanvasPlacement& pb, double pixel_threshold);

// The difference image of an aligned comparison, over the union of both
// canvases: the overlap as differenceImage draws it; outside it, a pixel
// that is ink in the image covering it is a difference (full red), bare paper is
// context grey; what neither canvas covers is black.
Image8 alignedDifferenceImage(const Image16& a, const CanvasPlacement& pa, const Image16& b,
                              const CanvasPlacement& pb, double gain);

}  // namespace bristle::render

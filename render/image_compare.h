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

#include "render/png_io.h"

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

}  // namespace bristle::render

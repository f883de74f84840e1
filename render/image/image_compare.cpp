// Image metrics of `bristle compare`. Everything is computed in double from the
// 16-bit normalised samples; differences are scaled to 8-bit steps (1/255 of
// full scale) only when reported.

#include "render/image/image_compare.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "engine/model/canvas.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "render/image/compose.h"

namespace bristle::render {

namespace {

constexpr double kFullScale = 65535.0;
constexpr double kStepsPerFullScale = 255.0;  // report unit: one 8-bit step

// SSIM constants of Wang et al. 2004 (section III.C): K1, K2, and their
// 11x11 circular-symmetric Gaussian weighting window with sigma 1.5 samples.
constexpr double kSsimK1 = 0.01;
constexpr double kSsimK2 = 0.03;
constexpr double kSsimDynamicRange = 1.0;  // L: luma in [0, 1]
constexpr int kSsimWindow = 11;
constexpr double kSsimSigma = 1.5;

// Rec. ITU-R BT.601 luma weights, the ones Wang et al.'s reference code uses
// (MATLAB rgb2gray) on colour images.
constexpr double kLumaR = 0.299, kLumaG = 0.587, kLumaB = 0.114;

void requireComparable(const Image16& a, const Image16& b) {
  if (a.channels != 4 || b.channels != 4) {
    throw std::invalid_argument("image comparison needs RGBA images");
  }
  if (a.width != b.width || a.height != b.height) {
    throw std::invalid_argument("image sizes differ: " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " and " +
                                std::to_string(b.width) + "x" + std::to_string(b.height));
  }
  if (a.pixels.size() != std::size_t(a.width) * a.height * 4 ||
      b.pixels.size() != a.pixels.size()) {
    throw std::invalid_argument("image pixel count does not match its size");
  }
}

// The luma of one row of an RGBA image, in [0, 1].
void lumaRow(const Image16& image, int y, std::vector<double>* out) {
  const std::uint16_t* p = &image.pixels[std::size_t(y) * image.width * 4];
  for (int x = 0; x < image.width; ++x, p += 4) {
    (*out)[x] = (kLumaR * p[0] + kLumaG * p[1] + kLumaB * p[2]) / kFullScale;
  }
}

// Normalised 1-D Gaussian weights of n taps (the 2-D window is their outer
// product, so filtering is separable).
std::vector<double> gaussianTaps(int n) {
  std::vector<double> w(static_cast<std::size_t>(n));
  const double centre = (n - 1) / 2.0;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double x = i - centre;
    w[i] = std::exp(-x * x / (2 * kSsimSigma * kSsimSigma));
    sum += w[i];
  }
  for (double& v : w) v /= sum;
  return w;
}

double toSteps(double sample_difference) {
  return sample_difference * kStepsPerFullScale / kFullScale;
}

}  // namespace

CompareTolerance tolerancePreset(const std::string& name) {
  CompareTolerance t;
  t.name = name;
  if (name == "exact") {
    // Same machine, same build: bristle is deterministic (a test checks it),
    // so any difference at all is a change.
    t.require_identical = true;
  } else if (name == "strict") {
    // Another machine or Mesa/compiler build: llvmpipe's SIMD width and FMA
    // contraction can move a float across an 8-bit rounding boundary, once in
    // the footprint and once more in the paint composite: at most 2 steps. A
    // footprint edge that moves by a rounding error changes a thin line of
    // pixels by 1-2 steps; 0.1% of a 500 x 300 px stroke image is 150 px, less
    // than one stroke outline (~1000 px), so a moved stroke still fails.
    t.max_abs = 2;
    t.pixel_threshold = 1;
    t.max_percent_over = 0.1;
  } else if (name == "loose") {
    // Long chains of solves (the paintings): another Ipopt/BLAS build can end a
    // solve elsewhere within its tolerance, moving a bristle by a fraction of a
    // pixel and its edge pixels by more than a few steps. SSIM >= 0.99 keeps
    // the structure (a missing or displaced stroke drops it well below), and at
    // most 1% of pixels may differ by more than 8 steps (3% of full scale, just
    // visible on flat paint).
    t.min_ssim = 0.99;
    t.pixel_threshold = 8;
    t.max_percent_over = 1.0;
  } else {
    throw std::invalid_argument("unknown tolerance '" + name +
                                "' (exact, strict or loose)");
  }
  return t;
}

std::uint64_t pixelHash(const Image16& image) {
  std::string bytes;
  for (const std::uint32_t v : {std::uint32_t(image.width), std::uint32_t(image.height)}) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
  }
  std::uint64_t h = fnv1a64(bytes);
  // Row by row, so the hash needs no copy of the whole image.
  const std::size_t row_samples = static_cast<std::size_t>(image.width) * image.channels;
  for (std::size_t start = 0; start < image.pixels.size(); start += row_samples) {
    bytes.clear();
    const std::size_t end = std::min(image.pixels.size(), start + row_samples);
    for (std::size_t i = start; i < end; ++i) {
      bytes.push_back(static_cast<char>(image.pixels[i] >> 8));
      bytes.push_back(static_cast<char>(image.pixels[i] & 0xff));
    }
    h = fnv1a64(bytes, h);
  }
  return h;
}

double ssim(const Image16& a, const Image16& b, int* window) {
  requireComparable(a, b);
  const int w = a.width, h = a.height;
  const int n = std::min({kSsimWindow, w, h});
  if (window != nullptr) *window = n;
  const std::vector<double> taps = gaussianTaps(n);
  const int ow = w - n + 1;
  const double c1 = (kSsimK1 * kSsimDynamicRange) * (kSsimK1 * kSsimDynamicRange);
  const double c2 = (kSsimK2 * kSsimDynamicRange) * (kSsimK2 * kSsimDynamicRange);

  // The window is separable: each image row is filtered horizontally into a
  // ring of the last n rows (for x, y, x^2, y^2, xy), and each output row
  // filters the ring vertically. Memory: 5 n (w - n + 1) doubles, not maps of
  // the whole image.
  constexpr int kQuantities = 5;
  std::vector<double> ring(static_cast<std::size_t>(kQuantities) * n * ow);
  const auto at = [&](int q, int slot, int x) -> double& {
    return ring[(static_cast<std::size_t>(q) * n + slot) * ow + x];
  };
  std::vector<double> lx(w), ly(w);
  double sum = 0;
  for (int y = 0; y < h; ++y) {
    lumaRow(a, y, &lx);
    lumaRow(b, y, &ly);
    const int slot = y % n;
    for (int x = 0; x < ow; ++x) {
      double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
      for (int k = 0; k < n; ++k) {
        const double u = lx[x + k], v = ly[x + k];
        sx += taps[k] * u;
        sy += taps[k] * v;
        sxx += taps[k] * (u * u);
        syy += taps[k] * (v * v);
        sxy += taps[k] * (u * v);
      }
      at(0, slot, x) = sx;
      at(1, slot, x) = sy;
      at(2, slot, x) = sxx;
      at(3, slot, x) = syy;
      at(4, slot, x) = sxy;
    }
    if (y < n - 1) continue;
    const int top = y - n + 1;  // the output row's first image row
    for (int x = 0; x < ow; ++x) {
      double m[kQuantities] = {};
      for (int k = 0; k < n; ++k) {
        const int s = (top + k) % n;
        for (int q = 0; q < kQuantities; ++q) m[q] += taps[k] * at(q, s, x);
      }
      // eq. 13, with the local statistics of eqs. 14-16 (weighted by the window).
      const double mx = m[0], my = m[1];
      const double var_x = m[2] - mx * mx, var_y = m[3] - my * my, cov = m[4] - mx * my;
      sum += ((2 * mx * my + c1) * (2 * cov + c2)) /
             ((mx * mx + my * my + c1) * (var_x + var_y + c2));
    }
  }
  return sum / (static_cast<double>(ow) * (h - n + 1));
}

ImageComparison compareImages(const Image16& a, const Image16& b, double pixel_threshold) {
  requireComparable(a, b);
  ImageComparison c;
  c.width = a.width;
  c.height = a.height;
  c.hash_a = pixelHash(a);
  c.hash_b = pixelHash(b);
  c.identical = c.hash_a == c.hash_b && a.pixels == b.pixels;
  c.pixel_threshold = pixel_threshold;
  std::array<int, 4> max_abs{};
  double squares = 0;
  const std::size_t count = static_cast<std::size_t>(a.width) * a.height;
  for (std::size_t i = 0; i < count; ++i) {
    int largest = 0;
    for (int ch = 0; ch < 4; ++ch) {
      const int d = std::abs(int(a.pixels[4 * i + ch]) - int(b.pixels[4 * i + ch]));
      max_abs[ch] = std::max(max_abs[ch], d);
      largest = std::max(largest, d);
      if (ch < 3) squares += double(d) * d;
    }
    if (largest > 0) ++c.pixels_differing;
    if (toSteps(largest) > pixel_threshold) ++c.pixels_over;
  }
  for (int ch = 0; ch < 4; ++ch) c.max_abs[ch] = toSteps(max_abs[ch]);
  c.percent_over = 100.0 * static_cast<double>(c.pixels_over) / static_cast<double>(count);
  c.rmse = toSteps(std::sqrt(squares / (3.0 * static_cast<double>(count))));
  c.psnr_db = c.rmse > 0 ? 20 * std::log10(kStepsPerFullScale / c.rmse)
                         : std::numeric_limits<double>::infinity();
  c.ssim = c.identical ? 1.0 : ssim(a, b, &c.ssim_window);
  if (c.identical) c.ssim_window = std::min({kSsimWindow, a.width, a.height});
  return c;
}

std::vector<ToleranceCheck> checkTolerance(const ImageComparison& c,
                                           const CompareTolerance& t) {
  std::vector<ToleranceCheck> checks;
  if (t.require_identical) {
    checks.push_back({"hash", c.identical ? 0.0 : 1.0, 0.0, true, c.identical});
  }
  if (t.max_abs) {
    const double m = *std::max_element(c.max_abs.begin(), c.max_abs.end());
    checks.push_back({"max_abs", m, *t.max_abs, true, m <= *t.max_abs});
  }
  if (t.max_percent_over) {
    checks.push_back({"percent_over", c.percent_over, *t.max_percent_over, true,
                      c.percent_over <= *t.max_percent_over});
  }
  if (t.min_ssim) {
    checks.push_back({"ssim", c.ssim, *t.min_ssim, false, c.ssim >= *t.min_ssim});
  }
  if (t.min_psnr_db) {
    checks.push_back({"psnr_db", c.psnr_db, *t.min_psnr_db, false, c.psnr_db >= *t.min_psnr_db});
  }
  return checks;
}

Image8 differenceImage(const Image16& a, const Image16& b, double gain) {
  requireComparable(a, b);
  // Context grey for equal pixels; the red ramp for differing ones; the marker
  // colour for equal pixels near a difference.
  constexpr double kContextLevel = 0.3;
  constexpr double kRedFloor = 64, kRedSpan = 191;
  constexpr std::uint8_t kMarker[3] = {255, 200, 0};
  const int w = a.width, h = a.height;
  const std::size_t count = static_cast<std::size_t>(w) * h;
  std::vector<int> largest(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    for (int ch = 0; ch < 4; ++ch) {
      const int d = std::abs(int(a.pixels[4 * i + ch]) - int(b.pixels[4 * i + ch]));
      largest[i] = std::max(largest[i], d);
    }
  }
  // Pixels within kDifferenceMarkerPx of a difference (a square): a max
  // filter along the rows, then along the columns.
  const int r = kDifferenceMarkerPx;
  std::vector<std::uint8_t> row_near(count, 0), near(count, 0);
  for (int y = 0; y < h; ++y) {
    const std::size_t row = std::size_t(y) * w;
    for (int x = 0; x < w; ++x) {
      for (int k = std::max(0, x - r); k <= std::min(w - 1, x + r); ++k) {
        if (largest[row + k] > 0) row_near[row + x] = 1;
      }
    }
  }
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      for (int k = std::max(0, y - r); k <= std::min(h - 1, y + r); ++k) {
        if (row_near[std::size_t(k) * w + x]) near[std::size_t(y) * w + x] = 1;
      }
    }
  }
  Image8 out{w, h, 3, {}};
  out.pixels.resize(count * 3);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint16_t* p = &a.pixels[4 * i];
    std::uint8_t* o = &out.pixels[3 * i];
    if (largest[i] > 0) {
      const double amplified = std::min(1.0, gain * largest[i] / kFullScale);
      o[0] = static_cast<std::uint8_t>(std::lround(kRedFloor + kRedSpan * amplified));
      o[1] = o[2] = 0;
    } else if (near[i]) {
      std::copy(kMarker, kMarker + 3, o);
    } else {
      const double y = (kLumaR * p[0] + kLumaG * p[1] + kLumaB * p[2]) / kFullScale;
      o[0] = o[1] = o[2] = static_cast<std::uint8_t>(std::lround(255 * kContextLevel * y));
    }
  }
  return out;
}

// ---- Comparing renders by where they lie on the canvas ---------------------

bool parseCanvasPlacement(const std::string& text, CanvasPlacement* out) {
  CanvasPlacement p;
  int consumed = -1;
  // %n after the last field: nothing may follow the five fields.
  if (std::sscanf(text.c_str(), "x0_mm=%lf y0_mm=%lf px_per_mm=%lf width_px=%d height_px=%d%n",
                  &p.x0_mm, &p.y0_mm, &p.px_per_mm, &p.width_px, &p.height_px, &consumed) != 5 ||
      consumed != static_cast<int>(text.size()))
    return false;
  if (!std::isfinite(p.x0_mm) || !std::isfinite(p.y0_mm) || !std::isfinite(p.px_per_mm) ||
      p.px_per_mm <= 0 || p.width_px <= 0 || p.height_px <= 0)
    return false;
  *out = p;
  return true;
}

bool canvasOffsetPx(const CanvasPlacement& a, const CanvasPlacement& b, int* dx, int* dy) {
  if (std::fabs(a.px_per_mm - b.px_per_mm) > 1e-6 * std::max(a.px_per_mm, b.px_per_mm))
    return false;
  const double fx = (b.x0_mm - a.x0_mm) * a.px_per_mm, fy = (b.y0_mm - a.y0_mm) * a.px_per_mm;
  // Far beyond any canvas (64 Mpx) is not an offset to round into an int.
  if (!(std::fabs(fx) < 1e9 && std::fabs(fy) < 1e9)) return false;
  const double rx = std::round(fx), ry = std::round(fy);
  if (std::fabs(fx - rx) > 1e-3 || std::fabs(fy - ry) > 1e-3) return false;
  *dx = static_cast<int>(rx);
  *dy = static_cast<int>(ry);
  return true;
}

namespace {

using Paper = std::array<std::uint8_t, 3>;

std::uint8_t to8(std::uint16_t v) { return static_cast<std::uint8_t>((v + 128) / 257); }

// Ink by compose.h's rule, on the 16-bit samples scaled to 8-bit levels.
bool isInk16(const std::uint16_t* px, const Paper& paper) {
  double d = 0;
  for (int ch = 0; ch < 3; ++ch) d += std::fabs(px[ch] / 257.0 - paper[ch]);
  return d > kInkLevels;
}

// A rectangle of pixels in a's frame: columns x0..x1-1, rows counted upwards
// from a's bottom edge y0..y1-1 (the canvas's y axis).
struct Box {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool contains(int x, int y) const { return x >= x0 && x < x1 && y >= y0 && y < y1; }
  int width() const { return std::max(0, x1 - x0); }
  int height() const { return std::max(0, y1 - y0); }
};

struct Frames {
  Box a, b, overlap, both;  // a's and b's pixels, their intersection and union
};

Frames framesOf(const Image16& a, const CanvasPlacement& pa, const Image16& b,
                const CanvasPlacement& pb) {
  int dx = 0, dy = 0;
  if (!canvasOffsetPx(pa, pb, &dx, &dy))
    throw std::invalid_argument("the canvases are not on one pixel grid");
  if (pa.width_px != a.width || pa.height_px != a.height || pb.width_px != b.width ||
      pb.height_px != b.height)
    throw std::invalid_argument("a canvas placement's size is not its image's");
  if (a.channels != 4 || b.channels != 4) throw std::invalid_argument("RGBA images needed");
  Frames f;
  f.a = {0, 0, a.width, a.height};
  f.b = {dx, dy, dx + b.width, dy + b.height};
  f.overlap = {std::max(f.a.x0, f.b.x0), std::max(f.a.y0, f.b.y0), std::min(f.a.x1, f.b.x1),
               std::min(f.a.y1, f.b.y1)};
  f.both = {std::min(f.a.x0, f.b.x0), std::min(f.a.y0, f.b.y0), std::max(f.a.x1, f.b.x1),
            std::max(f.a.y1, f.b.y1)};
  return f;
}

// The RGBA pixel of an image at (x, y) of a's frame, the image lying in `box`.
const std::uint16_t* pixelAt(const Image16& image, const Box& box, int x, int y) {
  const int col = x - box.x0, row = image.height - 1 - (y - box.y0);
  return &image.pixels[4 * (std::size_t(row) * image.width + col)];
}

Image16 crop(const Image16& image, const Box& box, const Box& region) {
  Image16 out{region.width(), region.height(), 4, {}};
  out.pixels.reserve(std::size_t(out.width) * out.height * 4);
  for (int y = region.y1 - 1; y >= region.y0; --y)  // the top row first
    for (int x = region.x0; x < region.x1; ++x) {
      const std::uint16_t* p = pixelAt(image, box, x, y);
      out.pixels.insert(out.pixels.end(), p, p + 4);
    }
  return out;
}

std::int64_t inkOutside(const Image16& image, const Box& box, const Box& overlap,
                        const Paper& paper) {
  std::int64_t n = 0;
  for (int y = box.y0; y < box.y1; ++y)
    for (int x = box.x0; x < box.x1; ++x)
      if (!overlap.contains(x, y) && isInk16(pixelAt(image, box, x, y), paper)) ++n;
  return n;
}

}  // namespace

std::array<std::uint8_t, 3> borderPaperColour(const Image16& image) {
  std::map<Paper, std::int64_t> counts;
  const auto count = [&](int col, int row) {
    const std::uint16_t* p = &image.pixels[4 * (std::size_t(row) * image.width + col)];
    ++counts[Paper{to8(p[0]), to8(p[1]), to8(p[2])}];
  };
  for (int col = 0; col < image.width; ++col) {
    count(col, 0);
    if (image.height > 1) count(col, image.height - 1);
  }
  for (int row = 1; row + 1 < image.height; ++row) {
    count(0, row);
    if (image.width > 1) count(image.width - 1, row);
  }
  Paper best{};
  std::int64_t most = -1;
  for (const auto& [colour, n] : counts)  // ascending: a tie keeps the smaller colour
    if (n > most) best = colour, most = n;
  return best;
}

AlignedComparison compareAligned(const Image16& a, const CanvasPlacement& pa, const Image16& b,
                                 const CanvasPlacement& pb, double pixel_threshold) {
  const Frames f = framesOf(a, pa, b, pb);
  AlignedComparison r;
  r.offset_x_px = f.b.x0;
  r.offset_y_px = f.b.y0;
  r.paper_a = borderPaperColour(a);
  r.paper_b = borderPaperColour(b);
  r.overlap_width_px = f.overlap.width();
  r.overlap_height_px = f.overlap.height();
  r.overlap_x0_mm = pa.x0_mm + f.overlap.x0 / pa.px_per_mm;
  r.overlap_y0_mm = pa.y0_mm + f.overlap.y0 / pa.px_per_mm;
  r.ink_outside_a = inkOutside(a, f.a, f.overlap, r.paper_a);
  r.ink_outside_b = inkOutside(b, f.b, f.overlap, r.paper_b);
  if (r.overlap_width_px == 0 || r.overlap_height_px == 0) {
    r.overlap_width_px = r.overlap_height_px = 0;
    return r;
  }
  r.c = compareImages(crop(a, f.a, f.overlap), crop(b, f.b, f.overlap), pixel_threshold);
  const std::int64_t outside = r.ink_outside_a + r.ink_outside_b;
  r.pixels = std::int64_t(r.overlap_width_px) * r.overlap_height_px + outside;
  r.c.pixels_differing += outside;
  r.c.pixels_over += outside;
  r.c.percent_over = 100.0 * double(r.c.pixels_over) / double(r.pixels);
  r.c.identical = r.c.identical && outside == 0;
  return r;
}

Image8 alignedDifferenceImage(const Image16& a, const CanvasPlacement& pa, const Image16& b,
                              const CanvasPlacement& pb, double gain) {
  const Frames f = framesOf(a, pa, b, pb);
  const Paper paper_a = borderPaperColour(a), paper_b = borderPaperColour(b);
  // Both images over the union; where one of them has no pixel, it gets the
  // other's pixel when that is bare paper (no difference) and its own paper
  // colour when it is ink (a difference); where neither has one, both are black.
  const int w = f.both.width(), h = f.both.height();
  // Two canvases far apart would make a vast image of nothing: the limit of
  // any image bristle reads or writes holds for this one too.
  constexpr std::int64_t kMaxDiffPixels = kMaxCanvasPixels;
  if (std::int64_t(w) * h > kMaxDiffPixels)
    throw Error(ExitCode::kDataError,
                "--diff: the two canvases together span " + std::to_string(w) + " x " +
                    std::to_string(h) + " px, over the limit of " +
                    std::to_string(kMaxDiffPixels) + " px (64 Mpx) of a difference image");
  Image16 ua{w, h, 4, std::vector<std::uint16_t>(std::size_t(w) * h * 4, 0)}, ub = ua;
  const auto paper16 = [](const Paper& p, std::uint16_t* o) {
    for (int ch = 0; ch < 3; ++ch) o[ch] = static_cast<std::uint16_t>(p[ch] * 257);
    o[3] = 65535;
  };
  for (int y = f.both.y0; y < f.both.y1; ++y) {
    for (int x = f.both.x0; x < f.both.x1; ++x) {
      const std::size_t i = 4 * (std::size_t(f.both.y1 - 1 - y) * w + (x - f.both.x0));
      std::uint16_t* oa = &ua.pixels[i];
      std::uint16_t* ob = &ub.pixels[i];
      const bool in_a = f.a.contains(x, y), in_b = f.b.contains(x, y);
      if (in_a) std::copy_n(pixelAt(a, f.a, x, y), 4, oa);
      if (in_b) std::copy_n(pixelAt(b, f.b, x, y), 4, ob);
      if (in_a && !in_b) {
        if (isInk16(oa, paper_a)) paper16(paper_b, ob);
        else std::copy_n(oa, 4, ob);
      } else if (in_b && !in_a) {
        if (isInk16(ob, paper_b)) paper16(paper_a, oa);
        else std::copy_n(ob, 4, oa);
      }
    }
  }
  return differenceImage(ua, ub, gain);
}

}  // namespace bristle::render

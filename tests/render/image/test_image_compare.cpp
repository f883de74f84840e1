// The metrics of `bristle compare` (render/image/image_compare.h) on hand-made images
// whose differences are known: hash, channel differences, RMSE/PSNR by hand,
// SSIM in closed form (Wang et al. 2004, eq. 13), bit-depth normalisation.

#include <catch2/catch.hpp>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <string>
#include <utility>

#include "render/image/image_compare.h"
#include "render/image/png_io.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using namespace bristle::render;

namespace {

// Sums of a few hundred doubles: agreement to 1e-12 is far above their
// rounding error (~1e-16 per operation) and far below any real difference.
constexpr double kArithmeticTol = 1e-12;
// SSIM sums ~100 windows of products of weighted means: 1e-9 absorbs the
// cancellation in var = E[x^2] - E[x]^2 (terms ~0.2, 1e-16 relative) many
// times over, and is 4 orders below the SSIM differences the tests look for.
constexpr double kSsimTol = 1e-9;

// 16-bit value of an 8-bit level (the normalisation of readPngRgba16).
constexpr std::uint16_t level16(int v8) { return static_cast<std::uint16_t>(v8 * 257); }

// An opaque RGBA16 image, every pixel (r, g, b) in 8-bit levels.
Image16 flat(int w, int h, int r, int g, int b) {
  Image16 im{w, h, 4, {}};
  for (int i = 0; i < w * h; ++i) {
    for (const int v : {r, g, b}) im.pixels.push_back(level16(v));
    im.pixels.push_back(65535);
  }
  return im;
}

// A deterministic texture with full-range structure (xorshift levels).
Image16 texture(int w, int h) {
  Image16 im = flat(w, h, 0, 0, 0);
  std::uint32_t s = 2463534242u;
  for (int i = 0; i < w * h; ++i) {
    s ^= s << 13;
    s ^= s >> 17;
    s ^= s << 5;
    const int v = static_cast<int>(s % 256);
    for (int c = 0; c < 3; ++c) im.pixels[4 * i + c] = level16(v);
  }
  return im;
}

using bristle::testing::TempDir;

}  // namespace

TEST_CASE("compare: an image against itself is exact", "[compare]") {
  const Image16 a = texture(23, 17);
  const ImageComparison c = compareImages(a, a, 1);
  CHECK(c.identical);
  CHECK(c.hash_a == c.hash_b);
  for (const double m : c.max_abs) CHECK(m == 0);
  CHECK(c.pixels_differing == 0);
  CHECK(c.pixels_over == 0);
  CHECK(c.rmse == 0);
  CHECK(std::isinf(c.psnr_db));
  CHECK(c.ssim == 1);
  CHECK(ssim(a, a) == Approx(1).margin(kSsimTol));
  for (const char* preset : {"exact", "strict", "loose"}) {
    CHECK(allPass(checkTolerance(c, tolerancePreset(preset))));
  }
}

TEST_CASE("compare: one pixel off by 10 in one channel", "[compare]") {
  const int w = 12, h = 8, n = w * h;
  const Image16 a = flat(w, h, 200, 120, 40);
  Image16 b = a;
  b.pixels[4 * (3 * w + 5) + 1] = level16(130);  // G of pixel (5, 3): 120 -> 130
  const ImageComparison c = compareImages(a, b, 1);
  CHECK_FALSE(c.identical);
  CHECK(c.hash_a != c.hash_b);
  CHECK(c.max_abs[0] == 0);
  CHECK(c.max_abs[1] == Approx(10).margin(kArithmeticTol));
  CHECK(c.max_abs[2] == 0);
  CHECK(c.max_abs[3] == 0);
  CHECK(c.pixels_differing == 1);
  CHECK(c.pixels_over == 1);
  CHECK(c.percent_over == Approx(100.0 / n).epsilon(kArithmeticTol));
  // By hand: one squared difference of 10^2 among 3 * 96 colour samples.
  const double rmse = std::sqrt(100.0 / (3 * n));  // 0.58926 steps
  CHECK(c.rmse == Approx(rmse).epsilon(kArithmeticTol));
  CHECK(c.psnr_db == Approx(20 * std::log10(255 / rmse)).epsilon(kArithmeticTol));  // 52.72 dB
  CHECK(c.ssim < 1);
  CHECK(c.ssim == Approx(ssim(b, a)).margin(kSsimTol));  // SSIM is symmetric

  // A threshold of 10 steps does not count a difference of exactly 10.
  CHECK(compareImages(a, b, 10).pixels_over == 0);
  CHECK(compareImages(a, b, 9.5).pixels_over == 1);

  // exact fails on the hash alone; strict fails on max abs 10 > 2 and on 1/96
  // of the pixels (1.04%) > 0.1% over 1 step.
  const auto exact = checkTolerance(c, tolerancePreset("exact"));
  REQUIRE(exact.size() == 1);
  CHECK(exact[0].metric == "hash");
  CHECK_FALSE(exact[0].pass);
  const auto strict = checkTolerance(compareImages(a, b, tolerancePreset("strict").pixel_threshold),
                                     tolerancePreset("strict"));
  REQUIRE(strict.size() == 2);
  CHECK(strict[0].metric == "max_abs");
  CHECK_FALSE(strict[0].pass);
  CHECK(strict[1].metric == "percent_over");
  CHECK_FALSE(strict[1].pass);
  // loose: 1 pixel of 96 over 8 steps is 1.04% > 1%. SSIM fails too: on a
  // flat image the structure term is C2 / (var + C2), and the one pixel (luma
  // +0.023, Gaussian weight up to 0.07 in a window) gives var ~4e-5 against
  // C2 = 9e-4: ~0.96 in the windows that see it, most of the 2 x 1 here.
  const CompareTolerance loose = tolerancePreset("loose");
  const auto lc = checkTolerance(compareImages(a, b, loose.pixel_threshold), loose);
  REQUIRE(lc.size() == 2);
  CHECK(lc[0].metric == "percent_over");
  CHECK_FALSE(lc[0].pass);
  CHECK(lc[1].metric == "ssim");
  CHECK(lc[1].value < 0.99);
  CHECK_FALSE(lc[1].pass);
}

TEST_CASE("compare: SSIM of flat images in closed form", "[compare][ssim]") {
  // Flat images have no variance and no covariance: eq. 13 reduces to the
  // luminance term (2 mx my + C1) / (mx^2 + my^2 + C1), the same in every
  // window. Grey levels have luma = level (the BT.601 weights sum to 1).
  const double mx = 100 / 255.0, my = 110 / 255.0, c1 = 0.01 * 0.01;
  const double expected = (2 * mx * my + c1) / (mx * mx + my * my + c1);
  CHECK(expected == Approx(0.9954764).margin(1e-7));  // by hand: 0.338431 / 0.339969
  int window = 0;
  CHECK(ssim(flat(30, 20, 100, 100, 100), flat(30, 20, 110, 110, 110), &window) ==
        Approx(expected).margin(kSsimTol));
  CHECK(window == 11);
  // Smaller than the 11 px window: the window shrinks to the image.
  CHECK(ssim(flat(4, 6, 100, 100, 100), flat(4, 6, 110, 110, 110), &window) ==
        Approx(expected).margin(kSsimTol));
  CHECK(window == 4);
}

TEST_CASE("compare: SSIM sees structure, not only brightness", "[compare][ssim]") {
  const Image16 a = texture(40, 30);
  // A brightness shift keeps the structure: covariance = variances, so only
  // the luminance term (close to 1 for a shift of 4 levels) drops.
  Image16 shifted = a, negative = a;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) {
    if (i % 4 == 3) continue;
    shifted.pixels[i] = static_cast<std::uint16_t>(std::min(65535, a.pixels[i] + level16(4)));
    negative.pixels[i] = static_cast<std::uint16_t>(65535 - a.pixels[i]);
  }
  const double s_shift = ssim(a, shifted);
  CHECK(s_shift > 0.99);
  CHECK(s_shift < 1);
  // The negative has the same mean (~0.5) and variance but covariance -var:
  // the structure term is (-2 var + C2) / (2 var + C2), near -1 for a texture
  // of variance ~0.08.
  CHECK(ssim(a, negative) < -0.9);
  // More noise, lower SSIM.
  Image16 mild = a, strong = a;
  for (std::size_t i = 0; i < a.pixels.size(); i += 4) {
    const int sign = (i / 4) % 2 == 0 ? 1 : -1;
    for (int c = 0; c < 3; ++c) {
      mild.pixels[i + c] = static_cast<std::uint16_t>(
          std::clamp(int(a.pixels[i + c]) + sign * level16(8), 0, 65535));
      strong.pixels[i + c] = static_cast<std::uint16_t>(
          std::clamp(int(a.pixels[i + c]) + sign * level16(40), 0, 65535));
    }
  }
  CHECK(ssim(a, mild) > ssim(a, strong));
}

TEST_CASE("compare: 8- and 16-bit, RGB and RGBA files of one picture are identical",
          "[compare][png]") {
  TempDir dir;
  Image8 rgb8{5, 3, 3, {}};
  Image16 rgba16{5, 3, 4, {}};
  for (int i = 0; i < 15; ++i) {
    const int r = 17 * i, g = 255 - 13 * i, b = (i * 91) % 256;
    for (const int v : {r, g, b}) {
      rgb8.pixels.push_back(static_cast<std::uint8_t>(v));
      rgba16.pixels.push_back(level16(v));
    }
    rgba16.pixels.push_back(65535);
  }
  writePng(dir.file("rgb8.png"), rgb8);
  writePng(dir.file("rgba16.png"), rgba16);
  PngFormat f8, f16;
  const Image16 a = readPngRgba16(dir.file("rgb8.png"), &f8);
  const Image16 b = readPngRgba16(dir.file("rgba16.png"), &f16);
  CHECK(f8.bit_depth == 8);
  CHECK(f8.channels == 3);
  CHECK(f16.bit_depth == 16);
  CHECK(f16.channels == 4);
  CHECK(a.pixels == rgba16.pixels);
  const ImageComparison c = compareImages(a, b, 1);
  CHECK(c.identical);
  CHECK(pixelHash(a) == pixelHash(b));

  // One 16-bit step is 1/257 of an 8-bit step: measured, and under every
  // pixel threshold of the presets.
  rgba16.pixels[5] += 1;  // G of pixel 1
  writePng(dir.file("rgba16b.png"), rgba16);
  const ImageComparison d = compareImages(a, readPngRgba16(dir.file("rgba16b.png")), 1);
  CHECK_FALSE(d.identical);
  CHECK(d.max_abs[1] == Approx(1.0 / 257).epsilon(kArithmeticTol));
  CHECK(d.pixels_differing == 1);
  CHECK(d.pixels_over == 0);

  // Alpha is compared: a half-transparent pixel differs by 127.5 steps in A.
  Image16 translucent = a;
  translucent.pixels[3] = 32767;
  CHECK(compareImages(a, translucent, 1).max_abs[3] == Approx(32768 * 255.0 / 65535).epsilon(kArithmeticTol));
}

TEST_CASE("compare: the pixel hash is FNV-1a 64 of the documented bytes", "[compare]") {
  // 1x1 RGBA (1, 2, 3, 65535): bytes 01 00 00 00 | 01 00 00 00 | 00 01 00 02 00 03
  // ff ff; FNV-1a 64 of them computed independently (Python, offset basis
  // 0xcbf29ce484222325, prime 0x100000001b3).
  const Image16 one{1, 1, 4, {1, 2, 3, 65535}};
  CHECK(pixelHash(one) == 0x6be1cdb26cd91cabULL);
}

TEST_CASE("compare: the hash depends on the size, not only the samples", "[compare]") {
  const Image16 wide = flat(4, 2, 9, 9, 9), tall = flat(2, 4, 9, 9, 9);
  CHECK(wide.pixels == tall.pixels);
  CHECK(pixelHash(wide) != pixelHash(tall));
  CHECK_THROWS_AS(compareImages(wide, tall, 1), std::invalid_argument);
}

TEST_CASE("compare: the difference image shows where and how much", "[compare]") {
  const int w = 12, h = 9;
  const Image16 a = flat(w, h, 100, 100, 100);
  Image16 b = a;
  b.pixels[4 * (4 * w + 5) + 0] = level16(110);  // pixel (5, 4): R off by 10 steps
  const double gain = 16;
  const Image8 d = differenceImage(a, b, gain);
  REQUIRE(d.width == w);
  REQUIRE(d.height == h);
  REQUIRE(d.channels == 3);
  const auto at = [&](int x, int y) { return &d.pixels[3 * (std::size_t(y) * w + x)]; };
  // The differing pixel: red 64 + 191 * min(1, 16 * 10/255) = 183.85 -> 184.
  CHECK(int(at(5, 4)[0]) == 184);
  CHECK(int(at(5, 4)[1]) == 0);
  CHECK(int(at(5, 4)[2]) == 0);
  // Equal pixels up to 3 px away (a square) carry the yellow marker ...
  for (const auto& [x, y] : {std::pair{2, 1}, std::pair{8, 7}, std::pair{5, 1}, std::pair{6, 5}}) {
    CHECK(int(at(x, y)[0]) == 255);
    CHECK(int(at(x, y)[1]) == 200);
    CHECK(int(at(x, y)[2]) == 0);
  }
  // ... and beyond, luma 100/255 dimmed to 30% -> 30 (of 255), grey.
  for (const auto& [x, y] : {std::pair{1, 4}, std::pair{9, 4}, std::pair{5, 0}, std::pair{0, 0}}) {
    CHECK(int(at(x, y)[0]) == 30);
    CHECK(int(at(x, y)[1]) == 30);
    CHECK(int(at(x, y)[2]) == 30);
  }
  // A gain that saturates: full red.
  CHECK(int(differenceImage(a, b, 1000).pixels[3 * (4 * w + 5)]) == 255);
  // Equal images: all grey.
  const Image8 same = differenceImage(a, a, gain);
  CHECK(std::all_of(same.pixels.begin(), same.pixels.end(), [](std::uint8_t v) { return v == 30; }));
}

TEST_CASE("compare: tolerance presets are what the docs say", "[compare]") {
  const CompareTolerance exact = tolerancePreset("exact");
  CHECK(exact.require_identical);
  const CompareTolerance strict = tolerancePreset("strict");
  CHECK(*strict.max_abs == 2);
  CHECK(strict.pixel_threshold == 1);
  CHECK(*strict.max_percent_over == 0.1);
  const CompareTolerance loose = tolerancePreset("loose");
  CHECK(*loose.min_ssim == 0.99);
  CHECK(loose.pixel_threshold == 8);
  CHECK(*loose.max_percent_over == 1.0);
  CHECK_THROWS_AS(tolerancePreset("fuzzy"), std::invalid_argument);
}

TEST_CASE("aligned compare: the canvas text, the pixel grid and the paper colour", "[compare][align]") {
  CanvasPlacement p;
  REQUIRE(parseCanvasPlacement(
      "x0_mm=-11.750000 y0_mm=-2.750000 px_per_mm=8.000000 width_px=1068 height_px=684", &p));
  CHECK(p.x0_mm == -11.75);
  CHECK(p.y0_mm == -2.75);
  CHECK(p.px_per_mm == 8);
  CHECK(p.width_px == 1068);
  CHECK(p.height_px == 684);
  // Anything else is not a placement: missing or extra fields, junk after
  // them, a scale or size that is not positive, a value that is not finite.
  for (const char* bad :
       {"", "x0_mm=0 y0_mm=0 px_per_mm=8 width_px=4", "x0_mm=0 y0_mm=0 px_per_mm=8 width_px=4 "
        "height_px=4 z=1", "x0_mm=0 y0_mm=0 px_per_mm=0 width_px=4 height_px=4",
        "x0_mm=0 y0_mm=0 px_per_mm=8 width_px=-4 height_px=4",
        "x0_mm=nan y0_mm=0 px_per_mm=8 width_px=4 height_px=4",
        "y0_mm=0 x0_mm=0 px_per_mm=8 width_px=4 height_px=4"}) {
    INFO(bad);
    CHECK_FALSE(parseCanvasPlacement(bad, &p));
  }

  const CanvasPlacement a{-11.75, -2.75, 8, 100, 50};
  int dx = 0, dy = 0;
  REQUIRE(canvasOffsetPx(a, CanvasPlacement{-10.5, -3.0, 8, 10, 10}, &dx, &dy));
  CHECK(dx == 10);
  CHECK(dy == -2);
  // 6 px/mm corners printed with 6 decimals still land on the grid.
  REQUIRE(canvasOffsetPx(CanvasPlacement{0, 0, 6, 1, 1},
                         CanvasPlacement{0.166667, -0.333333, 6, 1, 1}, &dx, &dy));
  CHECK(dx == 1);
  CHECK(dy == -2);
  CHECK_FALSE(canvasOffsetPx(a, CanvasPlacement{-11.75, -2.75, 6, 10, 10}, &dx, &dy));
  CHECK_FALSE(canvasOffsetPx(a, CanvasPlacement{-11.6875, -2.75, 8, 10, 10}, &dx, &dy));  // 0.5 px

  // The paper is the commonest colour of the outermost ring, whatever lies inside.
  Image16 im{5, 4, 4, {}};
  for (int i = 0; i < 5 * 4; ++i)
    for (const std::uint16_t v : {std::uint16_t(246 * 257), std::uint16_t(241 * 257),
                                  std::uint16_t(230 * 257), std::uint16_t(65535)})
      im.pixels.push_back(v);
  for (const int i : {6, 7, 8, 11, 12, 13, 0})  // the inside, and one corner
    for (int c = 0; c < 3; ++c) im.pixels[4 * i + c] = 0;
  CHECK(borderPaperColour(im) == std::array<std::uint8_t, 3>{246, 241, 230});
}

// The footprint measures of `bristle measure` (render/brush_measure.h) on
// footprints of a known shape: Wang et al.'s parabola, widest `offset` behind
// the handle and closing `drag` behind that.

#include <catch2/catch.hpp>
#include <cmath>

#include "render/brush_measure.h"

using bristle::render::FootprintImage;
using bristle::render::FootprintShape;
using bristle::render::measureFootprintShape;

namespace {

constexpr double kPxPerMm = 10;
// A measure reads pixel centres and adds one pixel for the extent: within a
// pixel of the drawn shape's true size.
constexpr double kPixelMm = 1 / kPxPerMm;

// A 40 x 30 mm window from (0, 0), touched inside the parabola whose front
// edge is `offset` behind x = handle_x and which closes `drag` behind that:
// at s mm behind the front edge, |y - 15| <= width / 2 * sqrt(1 - s / drag).
FootprintImage parabola(double handle_x, double width, double offset, double drag) {
  FootprintImage img;
  img.window = {0, 0, static_cast<int>(40 * kPxPerMm), static_cast<int>(30 * kPxPerMm), kPxPerMm};
  img.texels.assign(static_cast<size_t>(img.window.width_px) * img.window.height_px * 4, 0.f);
  for (int r = 0; r < img.window.height_px; ++r)
    for (int c = 0; c < img.window.width_px; ++c) {
      const double x = (c + 0.5) / kPxPerMm, y = 30 - (r + 0.5) / kPxPerMm;
      const double s = (handle_x - offset) - x;  // behind the front edge
      if (s < 0 || s > drag) continue;
      if (std::abs(y - 15) > 0.5 * width * std::sqrt(1 - s / drag)) continue;
      img.texels[(static_cast<size_t>(r) * img.window.width_px + c) * 4 + 3] = 1.f;
    }
  return img;
}

}  // namespace

TEST_CASE("measure: width, offset and drag of a parabolic footprint are its own",
          "[render][measure]") {
  const auto [width, offset, drag] = GENERATE(table<double, double, double>(
      {{4.0, 3.0, 5.0}, {9.0, 0.5, 12.0}, {2.0, 6.0, 1.5}}));
  INFO("width " << width << ", offset " << offset << ", drag " << drag);
  const FootprintShape m = measureFootprintShape(parabola(30, width, offset, drag), 30);
  REQUIRE(m.touched);
  CHECK(std::abs(m.width_mm - width) <= kPixelMm);
  CHECK(std::abs(m.offset_mm - offset) <= kPixelMm);
  CHECK(std::abs(m.drag_mm - drag) <= kPixelMm);
}

TEST_CASE("measure: a footprint ahead of the handle has a negative offset, none is untouched",
          "[render][measure]") {
  const FootprintShape ahead = measureFootprintShape(parabola(20, 4, -2, 3), 20);
  REQUIRE(ahead.touched);
  CHECK(std::abs(ahead.offset_mm + 2) <= kPixelMm);
  const FootprintShape none = measureFootprintShape(parabola(20, 4, 50, 3), 20);
  CHECK_FALSE(none.touched);
  CHECK(none.width_mm == 0);
}

// The measurement tooling of tests/support: mark measures against synthetic
// images with closed-form answers, and the press matrix's trajectories.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "tests/support/mark_measure.h"
#include "tests/support/press_matrix.h"
#include "tests/support/build_paths.h"

using namespace bristle;
using namespace bristle::testsupport;

namespace {

// Ink where inside(x, y) holds at the pixel centre (x = c + 0.5, y = r + 0.5).
template <class F>
Coverage paint(int w, int h, F inside, double ppm = 8) {
  Coverage img(w, h, ppm);
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c)
      if (inside(c + 0.5, r + 0.5)) img.at(c, r) = 1.0f;
  return img;
}

// Inside the triangle a, b, c (either winding).
bool inTriangle(double x, double y, const double (&t)[3][2]) {
  auto side = [&](int i, int j) {
    return (t[j][0] - t[i][0]) * (y - t[i][1]) - (t[j][1] - t[i][1]) * (x - t[i][0]);
  };
  const double s0 = side(0, 1), s1 = side(1, 2), s2 = side(2, 0);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

}  // namespace

TEST_CASE("mark_measure: a filled disc is one blot of fill ~1", "[mark]") {
  constexpr double R = 40, cx = 100, cy = 100;
  const Coverage img = paint(200, 200, [&](double x, double y) {
    return (x - cx) * (x - cx) + (y - cy) * (y - cy) <= R * R;
  });
  const BlotStats b = blotStats(img);
  CHECK(b.components == 1);
  CHECK(b.specks == 0);
  // Tolerance: every pixel within R - sqrt(2)/2 of the centre has its centre
  // within R, so the inked squares cover the disc of radius R - 0.71; every hull
  // corner is a corner of a pixel whose centre is within R, so the hull lies in
  // the disc of radius R + 0.71. Hence ((R - 0.71) / (R + 0.71))^2 = 0.931 <=
  // fill <= 1 (the hull contains the squares), whatever the pixelisation.
  const double h = std::sqrt(0.5);
  CHECK(b.fill <= 1.0);
  CHECK(b.fill >= std::pow((R - h) / (R + h), 2));
  CHECK(b.largest_area_px >= std::numbers::pi * (R - h) * (R - h));
  CHECK(b.largest_area_px <= std::numbers::pi * (R + h) * (R + h));
  CHECK(b.largest_area_mm2 == Approx(b.largest_area_px / 64.0));
}

TEST_CASE("mark_measure: a blot's pale share is the part of its hull under half its median ink",
          "[mark]") {
  // A disc of radius 40 px at ink 0.8 with a pale ring (ink 0.3, under half
  // of 0.8) from 20 to 25 px: the median is 0.8 (the ring is 14 % of the
  // disc), and the hull is the disc, so the pale share is the ring's area
  // over the disc's, (25^2 - 20^2) / 40^2 = 0.1406.
  constexpr double R = 40, r0 = 20, r1 = 25, cx = 100, cy = 100;
  auto blot = [&](bool ring) {
    Coverage img(200, 200);
    for (int r = 0; r < 200; ++r)
      for (int c = 0; c < 200; ++c) {
        const double d = std::hypot(c + 0.5 - cx, r + 0.5 - cy);
        if (d <= R) img.at(c, r) = ring && d >= r0 && d <= r1 ? 0.3f : 0.8f;
      }
    return blotStats(img);
  };
  const BlotStats even = blot(false), ringed = blot(true);
  CHECK(even.median_ink == Approx(0.8));
  CHECK(ringed.median_ink == Approx(0.8));
  // The even disc's hull (of pixel corners) reaches up to 0.71 px past the
  // inked pixels' centres: the uninked centres inside it are at most
  // pi ((R + 0.71)^2 - R^2) over pi (R - 0.71)^2 of it, 3.7 %.
  CHECK(even.pale_share <= 0.037);
  // Both blots have the same pixels, so the same hull: the ring adds its
  // own pixels. Tolerance: each of the three circles moves by <= 0.71 px
  // with the pixels: the ring's area by 2 pi 22.5 x 0.71 of its 707 px^2
  // (14 %), the hull's by 2 pi 40 x 0.71 of 5027 (3.5 %): 0.1406 (1 +- 0.18).
  CHECK(ringed.pale_share - even.pale_share == Approx(0.1406).epsilon(0.18));
}

TEST_CASE("mark_measure: a blot's principal axes and its ink's centroid", "[mark]") {
  // An ellipse with semi-axes a and b turned by 30 degrees, centred at pixel
  // (cx, cy): its pixels' covariance has eigenvalues a^2 / 4 and b^2 / 4 (those
  // of a filled ellipse), so the ratio is a / b. Pixelisation at a = 40 px
  // moves it by a few thousandths; 0.02 allows that.
  constexpr double a = 40, cx = 90.5, cy = 110.25, ppm = 8;
  constexpr double kAxisTol = 0.02;
  for (const double b : {40.0, 20.0}) {
    const double t = std::numbers::pi / 6;
    const Coverage img = paint(200, 200, [&](double x, double y) {
      const double u = (x - cx) * std::cos(t) + (y - cy) * std::sin(t);
      const double v = -(x - cx) * std::sin(t) + (y - cy) * std::cos(t);
      return (u / a) * (u / a) + (v / b) * (v / b) <= 1;
    }, ppm);
    INFO("b = " << b);
    CHECK(principalAxisRatio(img) == Approx(a / b).margin(kAxisTol));
    // The centroid in canvas mm (row 0 at the top, x0 = y0 = 0): within a
    // tenth of a pixel of the centre, which the ellipse's symmetry puts there
    // but for the pixels its edge cuts.
    double x = 0, y = 0;
    REQUIRE(inkCentroidMm(img, 0.1, &x, &y));
    CHECK(x == Approx(cx / ppm).margin(0.1 / ppm));
    CHECK(y == Approx((200 - cy) / ppm).margin(0.1 / ppm));
  }
  // Ink weighs: a pixel of ink 1 and one of 0.5 two pixels to its right sit
  // at a third of the way between them.
  Coverage two(10, 10, 1);
  two.at(2, 5) = 1.0f;
  two.at(4, 5) = 0.5f;
  double x = 0, y = 0;
  REQUIRE(inkCentroidMm(two, 0.1, &x, &y));
  CHECK(x == Approx(2.5 + 2.0 / 3));
  CHECK(y == Approx(4.5));
  CHECK_FALSE(inkCentroidMm(Coverage(10, 10, 1), 0.1, &x, &y));
}

TEST_CASE("mark_measure: a six-pointed star fills two thirds of its hull", "[mark]") {
  // Two equilateral triangles of circumradius R: the star's area is sqrt(3) R^2,
  // its hull the regular hexagon of area 3 sqrt(3) / 2 R^2, so fill = 2/3.
  constexpr double R = 60, cx = 100, cy = 100;
  double up[3][2], down[3][2];
  for (int k = 0; k < 3; ++k) {
    const double a = std::numbers::pi / 2 + k * 2 * std::numbers::pi / 3;
    up[k][0] = cx + R * std::cos(a);
    up[k][1] = cy + R * std::sin(a);
    down[k][0] = cx - R * std::cos(a);
    down[k][1] = cy - R * std::sin(a);
  }
  const Coverage img = paint(200, 200, [&](double x, double y) {
    return inTriangle(x, y, up) || inTriangle(x, y, down);
  });
  const BlotStats b = blotStats(img);
  CHECK(b.components == 1);
  // Tolerance: pixelisation moves each boundary by <= 0.71 px. The star's
  // perimeter is 12 R / sqrt(3) = 416 px on 6235 px^2 (<= 4.7%), the hexagon's
  // 6 R = 360 px on 9353 px^2 (<= 2.7%): 2/3 * 0.953 / 1.027 = 0.619 <= fill <=
  // 2/3 * 1.047 / 0.973 = 0.717.
  CHECK(b.fill > 0.619);
  CHECK(b.fill < 0.717);
  CHECK(b.fill < 0.85);
}

TEST_CASE("mark_measure: a ring with gaps is several blots or a poorly filled one", "[mark]") {
  constexpr double r_in = 30, r_out = 40, cx = 100, cy = 100;
  auto ring = [&](double x, double y) {
    const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
    return d2 >= r_in * r_in && d2 <= r_out * r_out;
  };
  SECTION("four gaps: four blots") {
    const Coverage img = paint(200, 200, [&](double x, double y) {
      return ring(x, y) && std::abs(x - cx) > 3 && std::abs(y - cy) > 3;
    });
    const BlotStats b = blotStats(img);
    CHECK(b.components == 4);
    CHECK(b.fill < 0.85);
  }
  SECTION("one gap: one blot of low fill") {
    // Hull ~ the disc of r_out: fill ~ (r_out^2 - r_in^2) / r_out^2 = 0.44.
    const Coverage img = paint(200, 200, [&](double x, double y) {
      return ring(x, y) && !(x > cx && std::abs(y - cy) < 3);
    });
    const BlotStats b = blotStats(img);
    CHECK(b.components == 1);
    CHECK(b.fill == Approx(0.44).margin(0.05));
  }
  SECTION("specks under 4 px are ignored") {
    Coverage img = paint(200, 200, ring);
    img.at(2, 2) = 1;                          // 1 px
    img.at(190, 5) = img.at(191, 6) = 1;       // 2 px, diagonal (8-connected)
    img.at(5, 190) = img.at(6, 190) = img.at(7, 190) = 1;  // 3 px
    img.at(180, 180) = img.at(181, 180) = img.at(180, 181) = img.at(181, 181) = 1;  // 4 px
    const BlotStats b = blotStats(img);
    CHECK(b.components == 2);
    CHECK(b.specks == 3);
    // All four lie outside the ring's hull, the disc of r_out: satellites,
    // whatever their size.
    CHECK(b.satellites == 4);
  }
  SECTION("a crumb in the blot's hull is no satellite") {
    // One gap, as above; a 2 px crumb in the hole of the ring and one in the
    // gap lie in its hull; a pixel just outside it does not.
    Coverage img = paint(200, 200, [&](double x, double y) {
      return ring(x, y) && !(x > cx && std::abs(y - cy) < 3);
    });
    img.at(100, 100) = img.at(101, 100) = 1;
    img.at(135, 100) = 1;
    img.at(100, 145) = 1;
    const BlotStats b = blotStats(img, 0.1, 1);
    CHECK(b.components == 4);
    CHECK(b.satellites == 1);
  }
}

TEST_CASE("mark_measure: the 10-90 % edge ramp of a step and of linear ramps", "[mark]") {
  constexpr double kPpm = 8;
  // A band along x, rows 20..59, ink 1: a step edge, no ramp at all.
  Coverage step = paint(100, 80, [](double, double y) { return y > 20 && y < 60; }, kPpm);
  const EdgeRamp s = edgeRamp(crossProfile(step, Axis::kX, 10, 90), kPpm);
  CHECK(s.plateau == Approx(1));
  // Interpolated between the outside lane (0) and the first inked one (1):
  // 0.1 to 0.9 of a lane, 0.8 px.
  CHECK(s.low_side_mm == Approx(0.8 / kPpm));
  CHECK(s.high_side_mm == Approx(0.8 / kPpm));
  // Linear ramps of 16 px up (rows 10..26) and 8 px down (rows 90..98) around
  // a plateau of 0.5: 10-90 % is 0.8 of each ramp, exact under interpolation.
  Coverage ramp(100, 120, kPpm);
  for (int r = 0; r < 120; ++r) {
    const double y = r + 0.5;
    const double v = y < 10 ? 0 : y < 26 ? (y - 10) / 16 : y < 90 ? 1 : y < 98 ? (98 - y) / 8 : 0;
    for (int c = 0; c < 100; ++c) ramp.at(c, r) = static_cast<float>(0.5 * v);
  }
  const EdgeRamp e = edgeRamp(crossProfile(ramp, Axis::kX, 0, 100), kPpm);
  CHECK(e.plateau == Approx(0.5));
  CHECK(e.low_side_mm == Approx(0.8 * 16 / kPpm).margin(1e-6));
  CHECK(e.high_side_mm == Approx(0.8 * 8 / kPpm).margin(1e-6));
  // The same across a stroke running along y: the profile's lanes are columns.
  Coverage turned(120, 100, kPpm);
  for (int r = 0; r < 100; ++r)
    for (int c = 0; c < 120; ++c) turned.at(c, r) = ramp.at(r, c);
  CHECK(edgeRamp(crossProfile(turned, Axis::kY, 0, 100), kPpm).low_side_mm ==
        Approx(e.low_side_mm));
  CHECK(edgeRamp({}, kPpm).meanMm() == 0);
}

TEST_CASE("mark_measure: a rectangle's width is exact to one pixel", "[mark]") {
  // Columns 20..179, rows 10..46: 37 px = 4.625 mm tall at 8 px/mm.
  const Coverage img = paint(200, 60, [](double x, double y) {
    return x > 20 && x < 180 && y > 10 && y < 47;
  });
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  CHECK(p.first == 20);
  CHECK(p.last == 179);
  CHECK(std::abs(meanWidthMm(p) - 4.625) <= 1 / 8.0);
  CHECK(widthCv(p) == Approx(0).margin(1e-12));
  // Its centre across the stroke: rows 10..46 of 60 are y 13/8..50/8 mm
  // up from the bottom edge, columns 20..179 x 20/8..180/8 mm.
  CHECK(p.centre_mm[100] == Approx(63.0 / 16).margin(1e-12));
  CHECK(p.centre_mm[5] == 0);
  const WidthProfile py = widthProfile(img, 0.1, Axis::kY);
  CHECK(std::abs(meanWidthMm(py) - 20.0) <= 1 / 8.0);
  CHECK(py.centre_mm[30] == Approx(12.5).margin(1e-12));
  // An axis-aligned rectangle of pixel squares is its own hull.
  const BlotStats b = blotStats(img);
  CHECK(b.fill == Approx(1.0).margin(1e-12));
  CHECK(b.largest_area_px == 160 * 37);
}

TEST_CASE("mark_measure: a linearly narrowing wedge has the closed-form CV", "[mark]") {
  // Width 120 px at x = 50 down to 20 px at x = 450, centred on y = 100. The
  // middle 60% of the span (x = 130..370) has widths uniform on [40, 100] px:
  // mean 70, std 60 / sqrt(12), CV = (100 - 40) / (sqrt(3) (100 + 40)).
  auto width = [](double x) { return 120 - 100 * (x - 50) / 400; };
  const Coverage img = paint(500, 200, [&](double x, double y) {
    return x > 50 && x < 450 && std::abs(y - 100) <= width(x) / 2;
  });
  const WidthProfile p = widthProfile(img);
  CHECK(p.first == 50);
  CHECK(p.last == 449);
  const SpanRange r = middleRange(p);
  CHECK(r.lo == 130);
  CHECK(r.hi == 370);
  const double cv = (100.0 - 40.0) / (std::sqrt(3.0) * (100.0 + 40.0));
  // Tolerance: each column's pixel count is within 1 px of width(x), so the
  // mean (70 px) moves by <= 1 px and the std (17.3 px) by <= 1 px: the CV by
  // <= (17.3 + 1) / (70 - 1) - 0.2474 = 0.018.
  CHECK(widthCv(p) == Approx(cv).margin(0.02));
  CHECK(meanWidthMm(p) == Approx(70.0 / 8).margin(1 / 8.0));
}

TEST_CASE("mark_measure: ink beyond a canvas x", "[mark]") {
  Coverage img = paint(200, 60, [](double x, double y) {
    return x > 20 && x < 180 && y > 10 && y < 47;
  });
  img.x0_mm = -10;  // column c spans x = -10 + c / 8 .. -10 + (c + 1) / 8
  double lo = 0, hi = 0;
  REQUIRE(inkXRangeMm(img, 0.1, &lo, &hi));
  CHECK(lo == Approx(-10 + 20 / 8.0));
  CHECK(hi == Approx(-10 + 180 / 8.0));
  CHECK(inkBeyondMm(img, 10.0, -1) == Approx(10 - (-7.5)));
  CHECK(inkBeyondMm(img, 10.0, +1) == Approx(12.5 - 10));
  CHECK(inkBeyondMm(img, 20.0, +1) == 0);
  CHECK(inkBeyondMm(Coverage(10, 10), 0.0, -1) == 0);
}

TEST_CASE("mark_measure: lines down a column, with one-pixel breaks bridged", "[mark]") {
  // Rows 2-4, 6-7 (one uninked row between: the same line), 10 (two rows
  // after: a new line) and 14-15 of column 3 are inked, every other column not.
  Coverage img(8, 20);
  for (int r : {2, 3, 4, 6, 7, 10, 14, 15}) img.at(3, r) = 1.0f;
  CHECK(lineCount(img, 3) == 3);
  CHECK(lineCount(img, 3, 0.1, 0) == 4);  // no bridging: 2-4 and 6-7 are two
  CHECK(lineCount(img, 3, 0.1, 2) == 2);  // 6-7 and 10 are two rows apart: one line
  CHECK(lineCount(img, 3, 0.1, 3) == 1);  // and 10 and 14 three
  CHECK(lineCount(img, 2) == 0);
  CHECK(lineCount(img, -1) == 0);
  CHECK(lineCount(img, 8) == 0);
  CHECK(inkedPixels(img) == 8);
  CHECK(inkedPixels(img, 1.0) == 0);  // inked means above the threshold
}

TEST_CASE("mark_measure: streaks along travel by the structure tensor", "[mark]") {
  // Stripes that vary only across x: every dv/dy is 0 exactly, so the measure
  // is exactly +1 for travel along y and -1 for travel along x.
  Coverage stripes(40, 40);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) stripes.at(c, r) = (c / 2) % 2 ? 1.0f : 0.2f;
  CHECK(streakAnisotropy(stripes, 0, 40, 0, 40, Axis::kY) == 1.0);
  CHECK(streakAnisotropy(stripes, 0, 40, 0, 40, Axis::kX) == -1.0);
  // A checkerboard of square cells changes as much along x as along y: 0, up
  // to the window's edges (a 38 x 38 window of 4-pixel cells is symmetric, so
  // exactly 0 but for float sums: 1e-12).
  Coverage checks(40, 40);
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) checks.at(c, r) = ((c / 4) + (r / 4)) % 2 ? 1.0f : 0.0f;
  CHECK(std::fabs(streakAnisotropy(checks, 0, 40, 0, 40, Axis::kY)) < 1e-12);
  // Even ink: no streaks at all.
  Coverage even(20, 20);
  for (float& v : even.v) v = 0.7f;
  CHECK(streakAnisotropy(even, 0, 20, 0, 20, Axis::kY) == 0.0);
  // Out-of-image windows are clipped, not read past the edge.
  CHECK(streakAnisotropy(stripes, -5, 100, -5, 100, Axis::kY) == 1.0);
}

TEST_CASE("mark_measure: the spread of a stroke's ends", "[mark]") {
  // A stroke along x over columns 10..49 and rows 5..24, at 8 px/mm; row 5
  // (its edge) starts 4 px late and row 12 stops 2 px early.
  Coverage img(60, 30, 8);
  for (int r = 5; r < 25; ++r)
    for (int c = 10; c < 50; ++c) img.at(c, r) = 1;
  for (int c = 10; c < 14; ++c) img.at(c, 5) = 0;
  img.at(48, 12) = img.at(49, 12) = 0;
  const EndSpread e = endSpread(img, Axis::kX);
  CHECK(e.lanes == 20);
  CHECK(e.start_mm == Approx(4.0 / 8));
  CHECK(e.stop_mm == Approx(2.0 / 8));
  // Trimming 5 % of the 20-row width drops one row on each side: row 5 goes.
  const EndSpread t = endSpread(img, Axis::kX, 0.05);
  CHECK(t.lanes == 18);
  CHECK(t.start_mm == 0.0);
  CHECK(t.stop_mm == Approx(2.0 / 8));
  // The same stroke turned to run along y.
  Coverage turned(30, 60, 8);
  for (int r = 0; r < 60; ++r)
    for (int c = 0; c < 30; ++c) turned.at(c, r) = img.at(r, c);
  const EndSpread u = endSpread(turned, Axis::kY);
  CHECK(u.start_mm == Approx(4.0 / 8));
  CHECK(u.stop_mm == Approx(2.0 / 8));
  // No ink: nothing measured.
  CHECK(endSpread(Coverage(10, 10), Axis::kX).lanes == 0);
}

TEST_CASE("mark_measure: how far a stroke lays paint before it runs dry", "[mark]") {
  // At 4 px/mm: 4 mm of blank, then a stroke of ink 0.8 for 20 mm that fades
  // linearly to 0.2 over the next 20 mm and stops there.
  constexpr double ppm = 4;
  std::vector<double> along(200, 0.0);
  for (int i = 16; i < 96; ++i) along[static_cast<size_t>(i)] = 0.8;
  for (int i = 96; i < 176; ++i) along[static_cast<size_t>(i)] = 0.8 - 0.6 * (i - 96) / 80.0;
  // Half the start level, 0.4, is reached 20 + 13.3 mm in; the 2 mm running
  // mean falls under it 1 mm (half its window) before that.
  CHECK(inkRunMm(along, ppm, 0.5) == Approx(20 + 40.0 / 3 - 1).margin(0.3));
  // A share it never falls under: the whole stroke, 40 mm.
  CHECK(inkRunMm(along, ppm, 0.1) == Approx(40.0));
  // No ink: no run.
  CHECK(inkRunMm(std::vector<double>(50, 0.0), ppm, 0.5) == 0.0);
}

TEST_CASE("mark_measure: a blot's outline, its lobes and its edge", "[mark]") {
  // 8 px/mm, 240 px square, centre (120, 120). ink(x, y) fills each image.
  auto image = [](auto ink) {
    Coverage img(240, 240, 8);
    for (int r = 0; r < img.h; ++r)
      for (int c = 0; c < img.w; ++c) img.at(c, r) = static_cast<float>(ink(c + 0.5, r + 0.5));
    return img;
  };
  // A disc of radius 80 px (10 mm), ink 0.6 with a hard edge: one lobe (its
  // largest radius), the radius, a ramp of at most a pixel.
  const BlotOutline disc = blotOutline(
      image([](double x, double y) { return std::hypot(x - 120, y - 120) < 80 ? 0.6 : 0.0; }));
  CHECK(disc.lobes == 1);
  CHECK(disc.mean_radius_mm == Approx(10).margin(0.15));
  CHECK(disc.radius_cv < 0.01);
  CHECK(disc.edge_ramp_mm <= 1.0 / 8);
  CHECK(disc.level == Approx(0.6));
  CHECK(disc.centre_ink == Approx(0.6).margin(0.01));
  // Six discs of radius 4 mm on a ring of radius 6 mm over a disc of 6 mm:
  // six lobes, each 10 mm out with the notches between them 7.84 mm out,
  // and but one, the largest radius, that stands out by 3 mm.
  const Coverage petals = image([](double x, double y) {
    if (std::hypot(x - 120, y - 120) < 48) return 0.6;
    for (int k = 0; k < 6; ++k) {
      const double a = k * std::numbers::pi / 3;
      if (std::hypot(x - 120 - 48 * std::cos(a), y - 120 - 48 * std::sin(a)) < 32) return 0.6;
    }
    return 0.0;
  });
  CHECK(blotOutline(petals).lobes == 6);
  CHECK(blotOutline(petals, 0.1, 1.0).lobes == 6);
  CHECK(blotOutline(petals, 0.1, 3.0).lobes == 1);
  // A disc with a soft edge: ink 0.6 within 8 mm, falling linearly to 0 at
  // 10 mm. Its 10-90 % ramp is 0.8 of the 2 mm fall, 1.6 mm; its edge lies
  // where the ink crosses 0.1, 10 - 1/3 mm out.
  const BlotOutline soft = blotOutline(image([](double x, double y) {
    const double d = std::hypot(x - 120, y - 120) / 8;
    return 0.6 * std::clamp((10 - d) / 2, 0.0, 1.0);
  }));
  CHECK(soft.edge_ramp_mm == Approx(1.6).margin(0.1));
  CHECK(soft.mean_radius_mm == Approx(10 - 1.0 / 3).margin(0.15));
  CHECK(soft.lobes == 1);
  CHECK(soft.centre_ink > soft.outer_ink);
  // No ink: nothing.
  CHECK(blotOutline(image([](double, double) { return 0.0; })).lobes == 0);
}

TEST_CASE("mark_measure: coverage from RGBA, against the paper or from alpha", "[mark]") {
  // Paper #f6f1e6 at the top-left, black paint, and paint at half the paper's luminance.
  std::vector<std::uint8_t> px = {0xf6, 0xf1, 0xe6, 255, 0, 0, 0, 255, 0x7b, 0x79, 0x73, 255};
  const Coverage c = coverageFromRgba8(3, 1, px.data());
  CHECK(c.v[0] == 0);
  CHECK(c.v[1] == 1);
  CHECK(c.v[2] == Approx(0.5).margin(0.01));
  std::vector<std::uint8_t> alpha = {9, 9, 9, 0, 9, 9, 9, 255, 9, 9, 9, 51};
  const Coverage a = coverageFromRgba8(3, 1, alpha.data());
  CHECK(a.v[0] == 0);
  CHECK(a.v[1] == 1);
  CHECK(a.v[2] == Approx(0.2));
}

TEST_CASE("press_matrix: case trajectories hover, press to depth and keep the ferrule up",
          "[press_matrix]") {
  for (const char* name : {"round", "flat", "fan", "badger"}) {
    const Brush brush =
        loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json");
    const double hair = hairLengthMm(brush);
    for (double tilt : {0.0, 30.0, 60.0}) {
      for (double f : {0.0, 0.4, 0.8}) {
        CAPTURE(name, tilt, f);
        Case c;
        c.press_fraction = f;
        c.tilt_deg = tilt;
        c.speed_mm_s = 100;
        const CaseTrajectory ct = makeCaseTrajectoryDetailed(brush, c);
        const Trajectory& t = ct.trajectory;
        REQUIRE(t.samples.size() == 5);
        CHECK_NOTHROW(validateTrajectoryForBrush(t, brush));
        // Hovering 2 mm above first contact, touching at depth 0.
        CHECK(restLowestZMm(brush, t.samples[0].pose) == Approx(kHoverMm).margin(1e-9));
        CHECK(restLowestZMm(brush, t.samples[1].pose) == Approx(-ct.depth_mm).margin(1e-9));
        CHECK(t.samples[2].pose.position_mm.x() - t.samples[1].pose.position_mm.x() == Approx(30));
        CHECK(t.samples[2].t_s - t.samples[1].t_s == Approx(0.3));
        CHECK(restLowestZMm(brush, t.samples[4].pose) == Approx(kLiftClearMm).margin(1e-9));
        CHECK(ct.asked_depth_mm == Approx(f * hair));
        double lowest_root = 1e9;
        for (const SpineSpec& s : brush.spines)
          lowest_root = std::min(lowest_root, t.samples[1].pose.apply(s.root_mm).z());
        if (ct.clamped) {
          CHECK(ct.depth_mm < ct.asked_depth_mm);
          CHECK(lowest_root == Approx(kMinRootZMm));
        } else {
          CHECK(ct.depth_mm == Approx(ct.asked_depth_mm));
          CHECK(lowest_root >= kMinRootZMm - 1e-9);
        }
      }
    }
  }
}

TEST_CASE("press_matrix: positive tilt leans the handle towards +x, the hairs towards -x",
          "[press_matrix]") {
  const Eigen::Quaterniond q = tiltRotation(30);
  CHECK((q * Eigen::Vector3d::UnitZ()).x() > 0.49);
  CHECK((q * -Eigen::Vector3d::UnitZ()).x() < -0.49);
}

// A round lifted while it is still moving tapers to a point, as a real round
// does: the hairs' load fades as the handle rises,
// and a bundle that only just touches leaves a thin line (kBundleFlatLoadN,
// engine/geometry/spine_bundles.h), not a blunt tail ending in a blob. Rendered end to
// end by the bristle executable and measured on the PNG
// (tests/support/mark_measure.h).

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "tests/support/mark_measure.h"
#include "tests/support/mark_png.h"
#include "tests/support/press_matrix.h"

using namespace bristle;
using namespace bristle::testing;
using namespace bristle::testsupport;

namespace {

// One pixel at the 8 px/mm rendered here: the resolution of every width.
constexpr double kTaperPxPerMm = 8;
constexpr double kPixelMm = 1.0 / kTaperPxPerMm;

// The pull that lifts off while moving (tilted 20 degrees so the hairs trail,
// as the marks tests pull): hover, press straight down in 0.4 s, pull 40 mm
// along +x at 40 mm/s, then rise 9.5 mm over the next 20 mm of the pull (0.5 s,
// still at 40 mm/s). The round first touches with its handle at ~18.8 mm, so
// the press is ~6.3 mm (a third of its hair) and the lift ends ~3 mm clear.
constexpr double kTiltDeg = 20;
constexpr double kHoverZMm = 24, kPressZMm = 12.5, kEndZMm = 22;
constexpr double kStartXMm = 12, kPullEndXMm = 52, kEndXMm = 72, kYMm = 20;
constexpr double kDescendS = 0.4, kPullS = 1.0, kLiftS = 0.5, kDtS = 0.01;

std::string liftWhileMovingCsv() {
  const Eigen::Quaterniond q = tiltRotation(kTiltDeg);
  std::ostringstream f;
  f << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n" << std::setprecision(10);
  auto row = [&](double t, double x, double z) {
    f << t << ',' << x << ',' << kYMm << ',' << z << ',' << q.w() << ',' << q.x() << ','
      << q.y() << ',' << q.z() << '\n';
  };
  const int descend = static_cast<int>(std::lround(kDescendS / kDtS));
  const int pull = static_cast<int>(std::lround(kPullS / kDtS));
  const int lift = static_cast<int>(std::lround(kLiftS / kDtS));
  for (int i = 0; i <= descend; ++i)
    row(i * kDtS, kStartXMm, kHoverZMm + (kPressZMm - kHoverZMm) * i / descend);
  for (int i = 1; i <= pull; ++i)
    row(kDescendS + i * kDtS, kStartXMm + (kPullEndXMm - kStartXMm) * i / pull, kPressZMm);
  for (int i = 1; i <= lift; ++i)
    row(kDescendS + kPullS + i * kDtS, kPullEndXMm + (kEndXMm - kPullEndXMm) * i / lift,
        kPressZMm + (kEndZMm - kPressZMm) * i / lift);
  return f.str();
}

double mean(const std::vector<double>& w, int lo, int hi) {
  double s = 0;
  for (int i = lo; i < hi; ++i) s += w[i];
  return s / (hi - lo);
}

}  // namespace

TEST_CASE("taper: a round lifted while moving narrows to a point", "[marks][taper]") {
  const std::string brush_path = sourcePath("scenes/brushes/round.json");
  const Brush brush = loadBrush(brush_path);
  // The trajectory really presses and really lifts off.
  const double contact_z = spineContactHeightMm(brush, tiltRotation(kTiltDeg));
  REQUIRE(kPressZMm < contact_z - 5);
  REQUIRE(kEndZMm > contact_z + 1);

  TempDir dir;
  const std::string csv = dir.write("liftmove.csv", liftWhileMovingCsv());
  const std::string png = dir.file("liftmove.png");
  // Ipopt, the reference for a brush with hair volume (tests/cli/test_cli_marks.cpp).
  const RunResult r = runBristle("render -q --solver ipopt --px-per-mm 8 --brush '" + brush_path +
                                 "' --trajectory '" + csv + "' -o '" + png + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.find("failed solve") == std::string::npos);

  // Width across the stroke per column along it (the pull runs along +x).
  const WidthProfile p = widthProfile(loadCoveragePng(png, kTaperPxPerMm));
  REQUIRE_FALSE(p.empty());
  std::vector<double> span(p.width_mm.begin() + p.first, p.width_mm.begin() + p.last + 1);
  const int n = static_cast<int>(span.size());
  const int two_mm = static_cast<int>(std::lround(2 * kTaperPxPerMm));
  REQUIRE(n > 10 * two_mm);  // a stroke, not a dab
  std::vector<double> sorted = span;
  std::nth_element(sorted.begin(), sorted.begin() + n / 2, sorted.end());
  const double median = sorted[n / 2];
  const double tail_mean = mean(span, n - two_mm, n);
  const double tail_max = *std::max_element(span.end() - two_mm, span.end());
  const double before_tail = mean(span, n - 2 * two_mm, n - two_mm);
  INFO("median width " << median << " mm; last 2 mm: mean " << tail_mean << ", widest "
                       << tail_max << "; the 2 mm before them: mean " << before_tail);

  // The body is the pressed round's (5.6 mm at this 6.3 mm press): the taper
  // must not come from a thinner stroke.
  CHECK(median > 4.5);
  // The bar (the acceptance figure): the last 2 mm are narrower than a third of
  // the stroke's median width. Edge pixels flip with sub-pixel shifts of the
  // hair, so the mean must clear the bar by one pixel of measurement
  // (kTaperClearanceMm): a blunt tail measures 1.9 mm against a bar of
  // 1.87 mm, the taper 0.9 mm.
  constexpr double kTaperClearanceMm = kPixelMm;
  CHECK(tail_mean + kTaperClearanceMm <= median / 3);
  // And it comes to a point rather than ending in a blob: nowhere in the last
  // 2 mm is the stroke as wide as it is, on average, in the 2 mm before them
  // (a blunt tail's spring-back blob is 2.4 mm wide after 2.1 mm).
  CHECK(tail_max < before_tail);
}

// The strokes of the 永 painting (scenes/paintings/calligraphy.json, written by
// scenes/paintings/generate.py, YONG) measured as a calligrapher judges them
// (docs/fidelity.md, "Entries and blots"): a dot's weight at its pressed end,
// a left-falling stroke that enters without a ball, a square turn without a
// lump. Each stroke is rendered alone, as the painting places it (its canvas,
// paper, ink and solver), by the bristle executable.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "tests/support/mark_measure.h"
#include "tests/support/mark_png.h"

using namespace bristle::testing;
using namespace bristle::testsupport;

namespace {

// The painting's key points are in a 100-unit box placed at (8, 6) mm, 0.8 mm
// a unit (generate.py, calligraphy()).
struct YongPoint {
  double x, y;  // canvas mm
};
YongPoint yongUnits(double ux, double uy) { return {8 + 0.8 * ux, 6 + 0.8 * uy}; }

// Renders stroke `index` (0-based, in the painting's order) of the painting
// alone and returns its coverage.
Coverage renderYongStroke(int index, const TempDir& dir) {
  const std::string folder = sourcePath("scenes/paintings/");
  std::ifstream in(folder + "calligraphy.json");
  nlohmann::json scene = nlohmann::json::parse(in);
  nlohmann::json stroke = scene.at("strokes").at(index);
  stroke["brush"] = folder + stroke.at("brush").get<std::string>();
  stroke["trajectory"] = folder + stroke.at("trajectory").get<std::string>();
  scene["strokes"] = nlohmann::json::array({stroke});
  const std::string tag = "yong-" + std::to_string(index + 1);
  const std::string scene_path = dir.file(tag + ".json");
  std::ofstream(scene_path) << scene.dump();
  const std::string png = dir.file(tag + ".png");
  const std::string stats = dir.file(tag + "-stats.json");
  const RunResult r =
      runBristle("render -q '" + scene_path + "' -o '" + png + "' --stats '" + stats + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream st_in(stats);
  CHECK(nlohmann::json::parse(st_in).at("failed_steps").get<int>() == 0);
  return loadCoveragePng(png);
}

// The mark's width along the line from a to b (canvas mm): its inked area in
// each bin_mm of that line's length, divided by bin_mm, from the first inked
// bin to the last. Area per length, not the extent across, so that the pixel
// staircase of a slanted edge averages out.
std::vector<double> yongWidthsAlong(const Coverage& img, YongPoint a, YongPoint b,
                                    double bin_mm) {
  const double len = std::hypot(b.x - a.x, b.y - a.y);
  const double dx = (b.x - a.x) / len, dy = (b.y - a.y) / len;
  std::vector<double> along;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      if (img.at(c, r) <= 0.1f) continue;
      const double x = img.x0_mm + (c + 0.5) / img.px_per_mm;
      const double y = img.y0_mm + (img.h - r - 0.5) / img.px_per_mm;
      along.push_back((x - a.x) * dx + (y - a.y) * dy);
    }
  std::vector<double> widths;
  if (along.empty()) return widths;
  const double lo = *std::min_element(along.begin(), along.end());
  const double hi = *std::max_element(along.begin(), along.end());
  widths.assign(static_cast<size_t>(std::floor((hi - lo) / bin_mm)) + 1, 0.0);
  const double px_area = 1 / (img.px_per_mm * img.px_per_mm);
  for (double s : along) widths[static_cast<size_t>((s - lo) / bin_mm)] += px_area / bin_mm;
  return widths;
}

std::string yongList(const std::vector<double>& v) {
  std::ostringstream out;
  for (double w : v) out << ' ' << std::round(w * 100) / 100;
  return out.str();
}

// The inked rows of column x_mm between y0_mm and y1_mm: the top edge's height
// (canvas mm, NAN without ink) and the inked length.
struct YongColumn {
  double top_mm = NAN, inked_mm = 0;
};
YongColumn yongColumn(const Coverage& img, double x_mm, double y0_mm, double y1_mm) {
  YongColumn out;
  const int c = static_cast<int>(std::floor((x_mm - img.x0_mm) * img.px_per_mm));
  for (int r = 0; r < img.h; ++r) {
    const double y = img.y0_mm + (img.h - r - 0.5) / img.px_per_mm;
    if (y < y0_mm || y > y1_mm || img.at(c, r) <= 0.1f) continue;
    if (std::isnan(out.top_mm)) out.top_mm = y + 0.5 / img.px_per_mm;
    out.inked_mm += 1 / img.px_per_mm;
  }
  return out;
}

// The inked columns of row y_mm between x0_mm and x1_mm: the right edge
// (canvas mm, NAN without ink), the inked length and the ink's middle.
struct YongRow {
  double right_mm = NAN, inked_mm = 0, middle_mm = NAN;
};
YongRow yongRow(const Coverage& img, double y_mm, double x0_mm, double x1_mm) {
  YongRow out;
  const int r = img.h - 1 - static_cast<int>(std::floor((y_mm - img.y0_mm) * img.px_per_mm));
  double sum = 0;
  for (int c = 0; c < img.w; ++c) {
    const double x = img.x0_mm + (c + 0.5) / img.px_per_mm;
    if (x < x0_mm || x > x1_mm || img.at(c, r) <= 0.1f) continue;
    out.right_mm = x + 0.5 / img.px_per_mm;
    out.inked_mm += 1 / img.px_per_mm;
    sum += x;
  }
  if (out.inked_mm > 0) out.middle_mm = sum / (out.inked_mm * img.px_per_mm);
  return out;
}

double yongMedian(std::vector<double> v) {
  REQUIRE_FALSE(v.empty());
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

}  // namespace

TEST_CASE("yong: the dot gathers its weight at its pressed lower end", "[marks][yong]") {
  // 点: the brush enters light and fast, presses as it slows at the lower
  // right, and turns back up as it lifts; the dot is blunt and heavy there and
  // light where it came down. Along the line from its entry to its press (the
  // key points (45, 93) and (54.5, 83.5)), in kBinMm bins: the half of its
  // length nearer the press holds at least kMinPressedHalf of its ink, and its
  // widest bin lies in that half. Entering at 1.5 mm and pressing 5.5 mm
  // while still travelling, the pressed belly printed where the brush came
  // down (it trails the handle by 5-8 mm at such presses): a tadpole with
  // 0.30 of its ink in that half, widest at 0.31 of its length.
  constexpr double kBinMm = 2, kMinPressedHalf = 0.5;
  TempDir dir;
  const std::vector<double> w =
      yongWidthsAlong(renderYongStroke(0, dir), yongUnits(45, 93), yongUnits(54.5, 83.5), kBinMm);
  REQUIRE(w.size() >= 4);
  double total = 0, pressed = 0;
  const double half = w.size() / 2.0;
  for (size_t i = 0; i < w.size(); ++i) {
    total += w[i];
    pressed += w[i] * std::clamp(i + 1 - half, 0.0, 1.0);  // a bin astride the middle: its part
  }
  const double widest =
      (std::max_element(w.begin(), w.end()) - w.begin() + 0.5) / static_cast<double>(w.size());
  INFO("widths (mm) every " << kBinMm << " mm:" << yongList(w) << "; pressed half "
                            << pressed / total << ", widest at " << widest << " of its length");
  CHECK(pressed / total >= kMinPressedHalf);
  CHECK(widest >= 0.5);
}

TEST_CASE("yong: the left-falling stroke enters without a ball", "[marks][yong]") {
  // 撇 comes down along its own line and presses to its body's depth as it
  // travels: its head (the first 2 bins of kBinMm along the line from (85, 67)
  // to (70, 52)) at most kMaxHeadToBody of its body (the mean of bins 4-6, 6 to
  // 12 mm from where its ink begins),
  // the bound of the entry test in test_cli_marks.cpp. Pressed 4 mm over its
  // first 1.8 mm, deeper than its body, it began with a ball 1.5 times the
  // body's width.
  constexpr double kBinMm = 2, kMaxHeadToBody = 1.35;
  TempDir dir;
  const std::vector<double> w =
      yongWidthsAlong(renderYongStroke(3, dir), yongUnits(85, 67), yongUnits(70, 52), kBinMm);
  REQUIRE(w.size() >= 6);
  const double head = std::max(w[0], w[1]), body = (w[3] + w[4] + w[5]) / 3;
  INFO("widths (mm) every " << kBinMm << " mm:" << yongList(w) << "; head " << head << ", body "
                            << body);
  CHECK(head <= kMaxHeadToBody * body);
}

TEST_CASE("yong: the turn of the horizontal into the long vertical is square", "[marks][yong]") {
  // 横折钩's turn: the horizontal keeps its body's depth to the corner, the
  // brush lifts and presses again down the vertical's way (顿笔), leaving a
  // shoulder, not a lump. The corner's ink may rise above the horizontal's
  // top edge, and stand out right of the vertical's right edge, by at most
  // kMaxShoulder of that stroke's width; and the vertical's top is not bowed
  // by hair still trailing from the horizontal: the middle of its ink, row by
  // row down to y = 30 units, stays within kMaxBow of its width of its median.
  // Pressed to 4.5 mm as the handle slowed before the turn and 4.6 mm standing
  // after it, the corner was a lump rising 0.85 of the horizontal's width
  // above it and 0.85 of the vertical's right of it, and the vertical's top
  // bowed by 0.35 of its width; lifting only to 0.5 mm at the corner bowed it
  // by 0.43.
  constexpr double kMaxShoulder = 0.6, kMaxBow = 0.3;
  TempDir dir;
  const Coverage img = renderYongStroke(1, dir);
  const double band0 = yongUnits(0, 65).y, band1 = yongUnits(0, 85).y;
  std::vector<double> tops, widths;
  for (double u = 38; u < 48; u += 0.5) {
    const YongColumn c = yongColumn(img, yongUnits(u, 0).x, band0, band1);
    if (std::isnan(c.top_mm)) continue;
    tops.push_back(c.top_mm);
    widths.push_back(c.inked_mm);
  }
  const double h_top = yongMedian(tops), h_width = yongMedian(widths);
  double corner_top = -1e9;
  for (double u = 50; u < 62; u += 0.25) {
    const YongColumn c = yongColumn(img, yongUnits(u, 0).x, band0, band1);
    if (!std::isnan(c.top_mm)) corner_top = std::max(corner_top, c.top_mm);
  }
  const double x0 = yongUnits(50, 0).x, x1 = yongUnits(70, 0).x;
  std::vector<double> rights, v_widths, middles;
  for (double u = 35; u < 55; u += 1) {
    const YongRow r = yongRow(img, yongUnits(0, u).y, x0, x1);
    if (std::isnan(r.right_mm)) continue;
    rights.push_back(r.right_mm);
    v_widths.push_back(r.inked_mm);
  }
  const double v_right = yongMedian(rights), v_width = yongMedian(v_widths);
  double corner_right = -1e9;
  for (double u = 60; u < 80; u += 0.25) {
    const YongRow r = yongRow(img, yongUnits(0, u).y, x0, x1);
    if (!std::isnan(r.right_mm)) corner_right = std::max(corner_right, r.right_mm);
  }
  for (double u = 30; u <= 70; u += 1) {
    const YongRow r = yongRow(img, yongUnits(0, u).y, x0, x1);
    if (!std::isnan(r.middle_mm)) middles.push_back(r.middle_mm);
  }
  const double mid = yongMedian(middles);
  double bow = 0;
  for (double m : middles) bow = std::max(bow, std::fabs(m - mid));
  INFO("horizontal " << h_width << " mm wide, the corner " << corner_top - h_top
                     << " mm above it; vertical " << v_width << " mm wide, the corner "
                     << corner_right - v_right << " mm right of it; its top bowed by " << bow
                     << " mm");
  CHECK(corner_top - h_top <= kMaxShoulder * h_width);
  CHECK(corner_right - v_right <= kMaxShoulder * v_width);
  CHECK(bow <= kMaxBow * v_width);
}

// The round's marks where its hair meets the paper on end (docs/fidelity.md,
// "Artefacts of the marks"): a stroke that lifts off leaves no disc ahead of
// its end, and the round pressed straight down leaves one round blot round
// the handle with no speck beside it. Rendered end to end by the bristle
// executable and measured on the PNG (tests/support/mark_measure.h).

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string>

#include "cli_runner.h"
#include "tests/support/mark_measure.h"
#include "tests/support/mark_png.h"

using namespace bristle::testing;
using namespace bristle::testsupport;

namespace {

// The SVG line of docs/input.md pulled by `bristle import` (upright, 40 mm/s,
// pressed `depth_frac` of the hair, lifted where the line ends): it lands at
// (10, 10) and lifts off at (40, 10) in canvas mm, on a canvas whose corner
// is the origin.
constexpr double kLiftXMm = 40, kLiftYMm = 10;

// The mean ink of the half annulus kAheadFromMm..kAheadToMm ahead (x > the
// lift-off point) of where the handle lifted: past the tapering end's last
// pixels (its tip ends under the handle) and within the 2.5 mm disc the
// centre spine laid when it stood on its own tip there.
constexpr double kAheadFromMm = 0.6, kAheadToMm = 1.5;
double roundInkAhead(const Coverage& img) {
  double sum = 0;
  int n = 0;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      const double x = img.x0_mm + (c + 0.5) / img.px_per_mm;
      const double y = img.y0_mm + (img.h - r - 0.5) / img.px_per_mm;
      const double d = std::hypot(x - kLiftXMm, y - kLiftYMm);
      if (x <= kLiftXMm || d < kAheadFromMm || d > kAheadToMm) continue;
      sum += img.at(c, r);
      ++n;
    }
  return n > 0 ? sum / n : 0.0;
}

Coverage renderRoundLift(const std::string& solver, double depth_frac, const TempDir& dir) {
  const std::string svg = dir.file("line.svg"), csv = dir.file("line.csv");
  std::ofstream(svg) << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"60mm\" height=\"30mm\" "
                        "viewBox=\"0 0 60 30\"><path d=\"M 10 15 L 40 15\"/></svg>\n";
  const RunResult imp = runBristle("import -q '" + svg + "' -o '" + csv + "' --brush '" + kRound +
                                   "' --max-depth-frac " + std::to_string(depth_frac));
  INFO(imp.err);
  REQUIRE(imp.code == 0);
  const nlohmann::json scene = {
      {"format", "bristle-scene/1"},
      {"name", "lift-off"},
      {"canvas", {{"size_mm", {60, 25}}, {"px_per_mm", 8}}},
      {"solver", solver},
      {"strokes",
       {{{"brush", kRound}, {"trajectory", csv}, {"paint", {{"paints", {"#1a1e2e"}}, {"amount", 1.0}}}}}}};
  const std::string scene_path = dir.file("lift.json"), png = dir.file("lift.png");
  std::ofstream(scene_path) << scene.dump();
  const RunResult r = runBristle("render -q '" + scene_path + "' -o '" + png + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  return loadCoveragePng(png);
}

// The brush pressed straight down 8 mm past first contact, held and lifted
// (press-lift.csv, the handle at x-y 30, 30) with `solver`: its mark, every
// step solved.
Coverage renderRoundPress(const std::string& brush, const std::string& solver,
                          const TempDir& dir) {
  const std::string png = dir.file("press.png"), stats = dir.file("press.json");
  const RunResult r = runBristle("render -q --solver " + solver + " --brush '" + brush +
                                 "' --trajectory '" + sourcePath("scenes/trajectories/press-lift.csv") +
                                 "' -o '" + png + "' --stats '" + stats + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(nlohmann::json::parse(std::ifstream(stats)).at("failed_steps").get<int>() == 0);
  return loadCoveragePng(png);
}

}  // namespace

TEST_CASE("marks: no disc after lift-off: a round pulled and lifted leaves nothing ahead of its end",
          "[marks][round]") {
  const std::string solver = GENERATE("slsqp", "ipopt");
  INFO(solver);
  TempDir dir;
  // Pressed from 0.3 to 0.45 of the hair: whether a lifting tip lands ahead
  // of the others turns on the press, so one depth alone could pass by luck.
  const double depths[] = {0.3, 0.35, 0.4, 0.45};
  double sum = 0, most = 0;
  for (double f : depths) {
    const Coverage img = renderRoundLift(solver, f, dir);
    const double ahead = roundInkAhead(img);
    INFO("pressed " << f << " of the hair: ink ahead of the lift-off " << ahead);
    CHECK(inkedPixels(img) > 1000);  // the line itself was painted
    sum += ahead;
    most = std::max(most, ahead);
  }
  const double mean = sum / std::size(depths);
  INFO("mean " << mean << ", most " << most);
  // The disc the centre spine laid standing on its own tip averaged 0.12-0.17
  // there at every depth with SLSQP (mean 0.15) and 0.16-0.19 at three of
  // the four with Ipopt (mean 0.13); a clean end tapers under the handle and
  // leaves 0. Asked: a mean of at most 0.03, a fifth of the disc's, and no
  // depth over 0.1, under the smallest disc measured (Ipopt still leaves a
  // 0.6 mm dot at 0.4 of the hair, 0.08: docs/fidelity.md).
  constexpr double kMaxMeanInkAhead = 0.03, kMaxInkAhead = 0.1;
  CHECK(mean <= kMaxMeanInkAhead);
  CHECK(most <= kMaxInkAhead);
}

TEST_CASE("marks: the round pressed straight down leaves one round blot round the handle",
          "[marks][round]") {
  // Pressed straight down 8 mm past first contact (press-lift.csv, the handle
  // at x-y 30, 30), the round's squashed hair spreads round the handle
  // (volume.spread_n_per_mm, docs/dynamics.md "A squashed bundle spreads").
  // Without the rule its belly buckled over to one side: axes 1.98 (Ipopt)
  // and 1.93 (SLSQP), the ink's centroid 4.2 mm off the handle; with it 1.07
  // and 1.08, 0.35 mm off (docs/fidelity.md, "The round's press blot").
  // Ipopt, the reference: SLSQP's block solve lays the same blot (1.08, 0.35
  // mm) in ten times the CPU (17 s against 1.3 s).
  TempDir dir;
  const Coverage img = renderRoundPress(kRound, "ipopt", dir);
  // Every inked component counts (no speck allowance): a satellite is one.
  const BlotStats b = blotStats(img, 0.1, 1);
  const double ratio = principalAxisRatio(img, 0.1);
  double cx = 0, cy = 0;
  REQUIRE(inkCentroidMm(img, 0.1, &cx, &cy));
  constexpr double kHandleXMm = 30, kHandleYMm = 30;
  const double offset = std::hypot(cx - kHandleXMm, cy - kHandleYMm);
  INFO("components " << b.components << ", fill " << b.fill << ", axis ratio " << ratio
       << ", ink centroid " << offset << " mm from the handle");
  CHECK(b.components == 1);
  // Filled: the acceptance figure of "a straight press-and-lift leaves one
  // filled blot".
  CHECK(b.fill >= 0.85);
  // Round: axes at most 1.3, a blot a painter calls round (the laid-over one
  // fails by far); round the handle: its centroid within 1.5 mm of the
  // handle's x-y, a sixth of the blot's 9.8 mm.
  constexpr double kMaxRatio = 1.3, kMaxOffsetMm = 1.5;
  CHECK(ratio <= kMaxRatio);
  CHECK(offset <= kMaxOffsetMm);
}

// The parts of `bristle fit` that need no simulation (render/brush_fit.h;
// docs/fit.md): the measurement table's rules, the reach and row checks, the
// free parameters applied to a brush file, and the data's scatter.

#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "engine/base/error.h"
#include "engine/formats/brush_reader.h"
#include "render/brush_fit.h"
#include "temp_dir.h"
#include "tests/support/build_paths.h"

using namespace bristle;
using namespace bristle::render;

namespace {

const std::vector<FitColumn> kWidthDrag = {FitColumn::kWidth, FitColumn::kDrag};

// The one-line message of the table's refusal, checked to be a data error.
std::string refusal(const std::string& text) {
  try {
    parseMeasurementTable(text, "m.csv", kWidthDrag);
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::kDataError);
    return e.what();
  }
  FAIL("the table was accepted: " << text);
  return "";
}

std::string brushText(const std::string& name) {
  std::ifstream in(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("fit table: comments, depth-0 rows and measure's failed_steps are read past",
          "[render][fit]") {
  const MeasurementTable t = parseMeasurementTable(
      "# a source\ndepth_mm,width_mm,drag_mm,offset_mm,failed_steps\n0,0,0,0,0\n"
      "2,2.5,1,0.5,0\n\n2,3.5,1.5,1,0\n4, 5 ,2,1,0\n",
      "m.csv", kWidthDrag);
  CHECK(t.zero_depth_rows == 1);
  REQUIRE(t.rows.size() == 3);
  CHECK(t.rows[0].line == 4);
  CHECK(t.rows[2].value[size_t(FitColumn::kWidth)] == 5);
  CHECK(t.depths() == std::vector<double>{2, 4});
  CHECK(t.has[size_t(FitColumn::kOffset)]);
}

TEST_CASE("fit table: each broken rule is one line naming the file, the line and the rule",
          "[render][fit]") {
  CHECK(refusal("depth_mm,widht_mm,drag_mm\n1,2,3\n") ==
        "m.csv: line 1, column 2 (widht_mm): unknown column 'widht_mm'; did you mean width_mm?");
  CHECK(refusal("# note\ndepth_mm,width_mm\n1,2\n") ==
        "m.csv: line 2: missing column drag_mm (the header must name depth_mm, width_mm, "
        "drag_mm)");
  CHECK(refusal("depth_mm,width_mm,drag_mm\n1,2,3\n2,wide,3\n") ==
        "m.csv: line 3, column 2 (width_mm): 'wide' is not a number");
  CHECK(refusal("depth_mm,width_mm,drag_mm\n1,2,-3\n") ==
        "m.csv: line 2, column 3 (drag_mm): -3 must be >= 0 (a length in mm)");
  CHECK(refusal("depth_mm,width_mm,drag_mm\n1,2,nan\n") ==
        "m.csv: line 2, column 3 (drag_mm): 'nan': must be finite");
  CHECK(refusal("depth_mm,width_mm,drag_mm\n1,2,0x1p3\n") ==
        "m.csv: line 2, column 3 (drag_mm): '0x1p3' is not a number");
  CHECK(refusal("depth_mm,width_mm,drag_mm\n1,\"2,5\",3\n") ==
        "m.csv: line 2, column 2 (width_mm): '2,5' is not a number");
  CHECK(refusal("depth_mm,width_mm,drag_mm\n1,2\n") ==
        "m.csv: line 2: 2 fields where the header names 3");
  CHECK(refusal("# only a comment\n") ==
        "m.csv: line 1: no header (expected depth_mm,width_mm,drag_mm,offset_mm)");
}

TEST_CASE("fit table: too few rows for the parameters, or a depth past the ferrule, is refused",
          "[render][fit]") {
  const Brush round = parseBrush(brushText("round"), "round.json");
  const std::vector<FitParam> three = defaultFitParams(round);
  REQUIRE(three.size() == 3);
  const MeasurementTable two = parseMeasurementTable(
      "depth_mm,width_mm,drag_mm\n0,0,0\n1,1,1\n2,2,2\n", "m.csv", kWidthDrag);
  REQUIRE_THROWS_WITH(checkTableForFit(two, round, three),
                      "m.csv: line 4: 2 rows with a depth above 0, fewer than the 3 free "
                      "parameters (stiffness_scale, stiffness_taper, tip_spread): a fit "
                      "needs a row per parameter at least");
  // The round's hair is about 20 mm long: its ferrule reaches the paper
  // before a 25 mm press.
  const double deepest = deepestPressMm(round);
  CHECK(deepest > 15);
  CHECK(deepest < 25);
  const MeasurementTable deep = parseMeasurementTable(
      "depth_mm,width_mm,drag_mm\n1,1,1\n2,2,2\n25,9,9\n", "m.csv", kWidthDrag);
  REQUIRE_THROWS_WITH(checkTableForFit(deep, round, three),
                      Catch::Matchers::StartsWith("m.csv: line 4, column 1 (depth_mm): 25 mm is "
                                                  "deeper than 'round' can press"));
}

TEST_CASE("fit parameters: stiffness scale and taper, tip spread, rounded to 4 digits",
          "[render][fit]") {
  const std::string text = brushText("round");
  const Brush round = parseBrush(text, "round.json");
  std::vector<FitParam> params = defaultFitParams(round);
  REQUIRE(params.size() == 3);
  CHECK(params[2].name == "tip_spread");
  const std::string out = applyFitParams(text, params, {1.5, 2.0, 0.5}, "r2", "a test brush");
  const Brush fitted = parseBrush(out, "fitted");  // a valid brush: parseBrush throws otherwise
  CHECK(fitted.name == "r2");
  CHECK(fitted.description == "a test brush");
  const std::vector<double>& k0 = round.spines[0].stiffness_nmm_per_rad;
  const std::vector<double>& k1 = fitted.spines[0].stiffness_nmm_per_rad;
  REQUIRE(k1.size() == k0.size());
  // Root: the scale alone; tip: scale times taper (4 significant digits, so
  // exact for these values).
  CHECK(k1.front() == k0.front() * 1.5);
  CHECK(k1.back() == Approx(k0.back() * 1.5 * 2.0).epsilon(5e-4));
  CHECK(fitted.volume.tip_spread == 0.5);
  CHECK(fitted.friction.mu_static == round.friction.mu_static);  // not a free parameter here
  // Friction, from a --params file: both coefficients times the factor.
  const FitParam friction{"friction_scale", 0.25, 2, 1, true};
  const Brush slippery = parseBrush(applyFitParams(text, {friction}, {0.5}, "", ""), "f");
  CHECK(slippery.friction.mu_static == Approx(round.friction.mu_static * 0.5).epsilon(5e-4));
  CHECK(slippery.friction.mu_kinetic == Approx(round.friction.mu_kinetic * 0.5).epsilon(5e-4));
  CHECK(slippery.name == round.name);
  // The same values give the same bytes.
  CHECK(applyFitParams(text, params, {1.5, 2.0, 0.5}, "r2", "a test brush") == out);
}

TEST_CASE("fit parameters: a --params file is checked, one line per rule", "[render][fit]") {
  const Brush round = parseBrush(brushText("round"), "round.json");
  bristle::testing::TempDir dir;
  const std::string p = dir.file("p.json");
  auto refused = [&](const std::string& json) -> std::string {
    dir.write("p.json", json);
    try {
      readFitParams(p, round);
    } catch (const Error& e) {
      CHECK(e.code() == ExitCode::kDataError);
      return std::string(e.what()).substr(p.size() + 2);  // after "PATH: "
    }
    return "accepted";
  };
  dir.write("p.json", R"({"tip_spread": [0.2, 0.9], "stiffness_scale": [0.5, 2]})");
  const std::vector<FitParam> ok = readFitParams(p, round);
  REQUIRE(ok.size() == 2);
  CHECK(ok[0].name == "stiffness_scale");  // the documented order, not the file's
  CHECK(ok[1].start == Approx(round.volume.tip_spread).margin(1e-12));
  CHECK(refused(R"({"stifness_scale": [0.5, 2]})") ==
        "/stifness_scale: unknown key 'stifness_scale'; did you mean /stiffness_scale?");
  CHECK(refused(R"({"stiffness_scale": [2, 0.5]})") ==
        "/stiffness_scale = [2,0.5]: must be [min, max] with min < max");
  CHECK(refused(R"({"stiffness_scale": [0, 2]})") ==
        "/stiffness_scale = [0,2]: must lie within [0.01, 100]");
  CHECK(refused(R"({"tip_spread": 0.5})") == "/tip_spread = 0.5: must be [min, max], two numbers");
  CHECK(refused("{}").rfind("/: must be an object naming each free parameter", 0) == 0);
}

TEST_CASE("fit: the data's scatter is the pooled spread of repeated depths", "[render][fit]") {
  // Depth 2: 1 and 3 (mean 2, squares 1 + 1); depth 4: 5, 6, 7 (squares 1 +
  // 0 + 1); depth 6 alone. Pooled: sqrt(4 / (1 + 2)); floor: sqrt(4 / 6).
  const MeasurementTable t = parseMeasurementTable(
      "depth_mm,width_mm,drag_mm\n2,1,0\n2,3,0\n4,5,0\n4,6,0\n4,7,0\n6,9,0\n", "m.csv",
      kWidthDrag);
  const Scatter s = dataScatter(t, FitColumn::kWidth);
  CHECK(s.repeated_depths == 2);
  CHECK(s.pooled_sd == Approx(std::sqrt(4.0 / 3)));
  CHECK(s.floor_rmse == Approx(std::sqrt(4.0 / 6)));
  CHECK(dataScatter(t, FitColumn::kDrag).pooled_sd == 0);
}

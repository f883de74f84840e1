// `bristle fit` and `bristle measure --plot` end to end (render/brush_fit.h,
// docs/fit.md): a fit recovers a stiffness it was measured with, a second run
// is all cache hits and writes the same bytes, an evaluation limit writes the
// best brush found with exit 75, and the plots are PNGs.
//
// Cheap on purpose (CI's time is at its limit): one spine of the round brush
// (no surface, strips or hair volume), pulls of 12 mm at 4 px/mm, two depths,
// one free parameter.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "cli_runner.h"

using namespace bristle::testing;

namespace {

// The protocol of every run here: short pulls, coarse pixels.
const std::string kProtocol = " --px-per-mm 4 --pull-mm 12 ";
// The stiffness profile of the measured copy: its tip joint this many times
// stiffer than the brush's, its root as stiff (the stiffness_taper parameter).
// A uniform stiffness scale would not do: pressed to a depth and pulled
// steadily, a brush of stiffness and Coulomb friction alone takes the same
// shape at any scale of its stiffness (docs/fit.md, "Free parameters").
constexpr double kTrueTaper = 2;

// One spine of the round brush, its joint i of n stiffer by taper^(i/(n-1)),
// made here (not by the code under test).
std::string oneSpine(double taper) {
  nlohmann::ordered_json b = nlohmann::ordered_json::parse(readAll(kRound));
  b.erase("surface");
  b.erase("strips");
  b.erase("volume");
  b["spines"] = nlohmann::ordered_json::array({b["spines"][0]});
  auto& k = b["spines"][0]["stiffness_nmm_per_rad"];
  for (size_t i = 0; i < k.size(); ++i)
    k[i] = k[i].get<double>() * std::pow(taper, double(i) / double(k.size() - 1));
  b["name"] = "one-spine";
  return b.dump(1);
}

// The fitted brush's tip stiffness over the one-spine brush's: its taper.
double taperOf(const std::string& fitted_path) {
  const nlohmann::json fitted = nlohmann::json::parse(readAll(fitted_path));
  const nlohmann::json one = nlohmann::json::parse(oneSpine(1));
  return fitted["spines"][0]["stiffness_nmm_per_rad"].back().get<double>() /
         one["spines"][0]["stiffness_nmm_per_rad"].back().get<double>();
}

const char* kTaperParams = R"({"stiffness_taper": [0.25, 4]})";

int simulatedStrokes(const std::string& report) {
  std::smatch m;
  REQUIRE(std::regex_search(report, m, std::regex("- simulated strokes: ([0-9]+)")));
  return std::stoi(m[1]);
}

bool isPng(const std::string& path) { return readAll(path).rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

}  // namespace

TEST_CASE("fit: recovers the stiffness profile a brush was measured with, and a second run is all "
          "cache hits and the same bytes",
          "[cli][fit]") {
  TempDir dir;
  const std::string brush = dir.write("one.json", oneSpine(1));
  const std::string stiff = dir.write("stiff.json", oneSpine(kTrueTaper));
  const std::string table = dir.file("table.csv");
  const RunResult m =
      runBristle("measure '" + stiff + "' --depths 3,6 -q" + kProtocol + "-o '" + table + "'");
  INFO(m.err);
  REQUIRE(m.code == 0);
  const std::string params = dir.write("p.json", kTaperParams);
  const std::string fit = "fit '" + brush + "' '" + table + "' --params '" + params +
                          "' --columns width_mm,drag_mm,offset_mm --cache '" + dir.file("cache") +
                          "' -q" + kProtocol;
  const RunResult first =
      runBristle(fit + "-o '" + dir.file("a.json") + "' --report '" + dir.file("a.md") + "'");
  INFO(first.err);
  REQUIRE(first.code == 0);
  // The measures move by one 0.25 mm pixel for about 19 % of taper (the
  // offset at 3 mm grows 1 mm, four pixels, from taper 1 to 2), so every
  // taper within about that of the truth reproduces the table to the pixel
  // and BOBYQA may stop anywhere on that plateau: 25 % holds it.
  constexpr double kTaperTolerance = 0.25;
  CHECK(taperOf(dir.file("a.json")) == Approx(kTrueTaper).epsilon(kTaperTolerance));
  CHECK(simulatedStrokes(readAll(dir.file("a.md"))) > 0);
  CHECK(runBristle("validate '" + dir.file("a.json") + "'").code == 0);

  const RunResult second = runBristle(fit + "-o '" + dir.file("b.json") + "' --report '" +
                                      dir.file("b.md") + "' --plot '" + dir.file("b.png") + "'");
  INFO(second.err);
  REQUIRE(second.code == 0);
  CHECK(simulatedStrokes(readAll(dir.file("b.md"))) == 0);
  CHECK(readAll(dir.file("b.json")) == readAll(dir.file("a.json")));
  CHECK(isPng(dir.file("b.png")));
}

TEST_CASE("fit: an evaluation limit writes the best brush found, says so, and exits 75",
          "[cli][fit]") {
  TempDir dir;
  const std::string table =
      dir.write("t.csv", "depth_mm,width_mm,drag_mm\n3,2.5,3\n3,2.75,3.25\n6,3.5,6\n");
  const RunResult r =
      runBristle("fit '" + dir.write("one.json", oneSpine(1)) + "' '" + table +
                 "' --max-evals 2 --no-cache" + kProtocol + "--params '" +
                 dir.write("p.json", kTaperParams) +
                 "' -q -o '" + dir.file("best.json") + "'");
  CHECK(r.code == 75);
  CHECK_THAT(r.err, Catch::Matchers::StartsWith(
                        "bristle: warning: fit: stopped by the evaluation limit before "
                        "converging; wrote the best brush found to "));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK(runBristle("validate '" + dir.file("best.json") + "'").code == 0);
}

TEST_CASE("fit: the time limit stops the search, writes the best brush found and says so",
          "[cli][fit]") {
  TempDir dir;
  // Three depths: each evaluation is three pulls, about half a second, and
  // BOBYQA needs at least five evaluations for one parameter (its 2n + 1
  // starting points and a step), so 1 s cannot hold a converged search.
  const std::string table = dir.write(
      "t.csv", "depth_mm,width_mm,drag_mm\n2,1.5,1.5\n4,3,3\n6,5,5\n");
  const RunResult r =
      runBristle("fit '" + dir.write("one.json", oneSpine(1)) + "' '" + table +
                 "' --time-limit-s 1 --no-cache" + kProtocol + "--params '" +
                 dir.write("p.json", kTaperParams) + "' -q -o '" + dir.file("best.json") + "'");
  CHECK(r.code == 75);
  CHECK_THAT(r.err, Catch::Matchers::StartsWith(
                        "bristle: warning: fit: stopped by the time limit before converging; "
                        "wrote the best brush found to "));
  CHECK(runBristle("validate '" + dir.file("best.json") + "'").code == 0);
}

TEST_CASE("fit: a corrupt cache entry is measured again, never trusted", "[cli][fit]") {
  TempDir dir;
  const std::string table = dir.write("t.csv", "depth_mm,width_mm,drag_mm\n4,3,3\n");
  const std::string cache = dir.file("cache");
  const std::string fit = "fit '" + dir.write("one.json", oneSpine(1)) + "' '" + table +
                          "' --max-evals 1 --cache '" + cache + "'" + kProtocol + "--params '" +
                          dir.write("p.json", kTaperParams) + "' -q -o '" +
                          dir.file("f.json") + "' --report '" + dir.file("r.md") + "'";
  REQUIRE(runBristle(fit).code == 75);  // one evaluation: the limit
  CHECK(simulatedStrokes(readAll(dir.file("r.md"))) == 1);
  // Every entry garbled: the next run measures again, and gets the same brush.
  const std::string before = readAll(dir.file("f.json"));
  int entries = 0;
  for (const auto& e : std::filesystem::directory_iterator(cache)) {
    std::ofstream(e.path()) << "{\"format\": \"bristle-fit-cache/1\", \"rows\": [[4, true, 99";
    ++entries;
  }
  CHECK(entries == 1);
  REQUIRE(runBristle(fit).code == 75);
  CHECK(simulatedStrokes(readAll(dir.file("r.md"))) == 1);
  CHECK(readAll(dir.file("f.json")) == before);
  // ...and rewrote the entry: a third run is a hit.
  REQUIRE(runBristle(fit).code == 75);
  CHECK(simulatedStrokes(readAll(dir.file("r.md"))) == 0);
}

TEST_CASE("measure --plot draws the measures, --compare a table beside them", "[cli][measure]") {
  TempDir dir;
  const std::string table = dir.write("t.csv", "# x\ndepth_mm,width_mm,drag_mm,offset_mm\n"
                                               "3,2.5,3,1\n");
  const RunResult r = runBristle("measure round --depths 3 -q" + kProtocol + "--plot '" +
                                 dir.file("p.png") + "' --compare '" + table + "' -o '" +
                                 dir.file("m.csv") + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(isPng(dir.file("p.png")));
  // Without gnuplot on PATH: one line saying so, exit 69, nothing written.
  const RunResult none = runCaptured("env PATH=/nonexistent '" + std::string(BRISTLE_BIN) +
                                         "' measure round --depths 3 --plot '" +
                                         dir.file("q.png") + "'",
                                     dir.file("out"), dir.file("err"));
  CHECK(none.code == 69);
  CHECK(none.err ==
        "bristle: --plot: gnuplot not found on PATH (Debian: apt install gnuplot-nox; "
        "scripts/install-deps installs it)\n");
  CHECK_FALSE(std::filesystem::exists(dir.file("q.png")));
}

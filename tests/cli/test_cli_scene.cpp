// `bristle render SCENE.json` and `bristle validate SCENE.json` end to end: a
// small scene renders, twice to the same pixels, with the inputs hash; a brush
// dragged through wet paint carries it on (and does not when the canvas dried
// first); every bad input exits with its code and a one-line message, and
// leaves no PNG behind (docs/scene-format.md).

#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"
#include "engine/base/fnv1a64.h"
#include "render/image/image_compare.h"
#include "render/image/png_io.h"
#include "tests/support/mark_png.h"

using namespace bristle;
using bristle::testsupport::pngText;
using namespace bristle::testing;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using nlohmann::json;

namespace {

const std::string kPull = sourcePath("scenes/trajectories/straight-pull.csv");
constexpr double kPxPerMm = 4;
constexpr double kHeightMm = 70;

// Two round-brush pulls on an 80 x 70 mm canvas: red along y = 20 mm, then a
// blue one turned 90 degrees that crosses it at x = 40 mm going up (+y).
json crossingScene() {
  json s = {{"format", "bristle-scene/1"},
            {"name", "crossing"},
            {"canvas", {{"size_mm", {80, kHeightMm}}, {"px_per_mm", kPxPerMm},
                        {"background", "#f5f1e6"}}},
            {"sim", {{"rate_hz", 60}, {"max_step_mm", 0.5}}},
            {"solver", "ipopt"}};
  s["strokes"] = json::array();
  s["strokes"].push_back({{"brush", kRound}, {"trajectory", kPull},
                          {"paint", {{"paints", {"cadmium-red"}}}}});
  // The pull runs x 12 -> 67 at y 20; turned by 90 degrees and shifted it runs
  // x = 60 - 20 = 40, y = -5 + (12 -> 67) = 7 -> 62.
  s["strokes"].push_back({{"brush", kRound}, {"trajectory", kPull},
                          {"paint", {{"paints", {"ultramarine"}}}},
                          {"placement", {{"offset_mm", {60, -5}}, {"rotate_deg", 90}}}});
  return s;
}

std::string writeScene(const TempDir& dir, const std::string& name, const json& scene) {
  return dir.write(name, scene.dump(1));
}

bool exists(const std::string& path) { return std::filesystem::exists(path); }

// Mean (R - B) over the painted pixels of a box of the canvas (mm): how red the
// paint there is compared to blue. Painted = clearly darker than the paper.
struct BoxStats {
  double red_minus_blue = 0;
  int painted = 0;
};
BoxStats boxStats(const render::Image8& img, double x0, double x1, double y0, double y1) {
  BoxStats s;
  double sum = 0;
  for (int r = int((kHeightMm - y1) * kPxPerMm); r < int((kHeightMm - y0) * kPxPerMm); ++r)
    for (int c = int(x0 * kPxPerMm); c < int(x1 * kPxPerMm); ++c) {
      const std::uint8_t* p = &img.pixels[(size_t(r) * img.width + c) * 4];
      // 24 levels below the paper's 0xf5/0xf1/0xe6 summed: paint, not grain.
      if (int(p[0]) + p[1] + p[2] > 0xf5 + 0xf1 + 0xe6 - 24) continue;
      sum += int(p[0]) - int(p[2]);
      ++s.painted;
    }
  if (s.painted > 0) s.red_minus_blue = sum / s.painted;
  return s;
}


}  // namespace

TEST_CASE("a scene renders: canvas size, paint on it, inputs hash, determinism",
          "[cli][scene]") {
  TempDir dir;
  const std::string scene = writeScene(dir, "s.json", crossingScene());
  const RunResult a = runBristle("render -q '" + scene + "' -o '" + dir.file("a.png") + "'");
  INFO(a.err);
  REQUIRE(a.code == 0);
  const render::Image8 img = render::readPngRgba8(dir.file("a.png"));
  CHECK(img.width == 320);
  CHECK(img.height == 280);
  // Both strokes left paint: red along y = 20 left of the crossing, blue along
  // x = 40 above it.
  const BoxStats red = boxStats(img, 14, 30, 14, 26);
  const BoxStats blue = boxStats(img, 34, 46, 40, 55);
  CHECK(red.painted > 100);
  CHECK(red.red_minus_blue > 60);
  CHECK(blue.painted > 100);
  CHECK(blue.red_minus_blue < 0);

  // The hash covers the scene, then each brush and trajectory once.
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx",
                static_cast<unsigned long long>(fnv1a64Files({scene, kRound, kPull})));
  CHECK(pngText(dir.file("a.png"), "bristle:inputs-fnv1a64") == hex);
  CHECK(pngText(dir.file("a.png"), "bristle:scene") == "crossing");

  // Same scene, same pixels (and the trace names each line's stroke).
  const RunResult b = runBristle("render -q '" + scene + "' -o '" + dir.file("b.png") +
                                 "' --trace '" + dir.file("t.jsonl") + "'");
  REQUIRE(b.code == 0);
  CHECK(render::readPngRgba8(dir.file("b.png")).pixels == img.pixels);
  const std::string trace = readAll(dir.file("t.jsonl"));
  CHECK_THAT(trace, Contains("\"stroke\":0"));
  CHECK_THAT(trace, Contains("\"stroke\":1"));
}

TEST_CASE("a brush dragged through wet paint carries it on, and dry_before stops that",
          "[cli][scene]") {
  TempDir dir;
  json wet = crossingScene();
  json dry = crossingScene();
  dry["strokes"][1]["dry_before"] = true;
  REQUIRE(runBristle("render -q '" + writeScene(dir, "wet.json", wet) + "' -o '" +
                     dir.file("wet.png") + "'").code == 0);
  REQUIRE(runBristle("render -q '" + writeScene(dir, "dry.json", dry) + "' -o '" +
                     dir.file("dry.png") + "'").code == 0);
  // The blue stroke just after it crossed the red one (which lies within
  // y 17..23 mm): x 36..44 mm, y 25..34 mm; and further on, y 43..52 mm.
  const render::Image8 wet_img = render::readPngRgba8(dir.file("wet.png"));
  const render::Image8 dry_img = render::readPngRgba8(dir.file("dry.png"));
  const BoxStats w = boxStats(wet_img, 36, 44, 25, 34);
  const BoxStats d = boxStats(dry_img, 36, 44, 25, 34);
  const BoxStats w_far = boxStats(wet_img, 36, 44, 43, 52);
  const BoxStats d_far = boxStats(dry_img, 36, 44, 43, 52);
  REQUIRE(w.painted > 50);
  REQUIRE(d.painted > 50);
  INFO("R - B after the crossing: wet " << w.red_minus_blue << ", dry " << d.red_minus_blue
                                        << "; further on: wet " << w_far.red_minus_blue
                                        << ", dry " << d_far.red_minus_blue);
  // Picked-up red shifts the blue towards violet: R - B rises (by ~30 levels
  // here). 15 levels is far above anything but paint carried over: both runs
  // are deterministic and share the paper's grain, and differ only in whether
  // the red was still wet.
  constexpr double kCarriedLevels = 15;
  CHECK(w.red_minus_blue > d.red_minus_blue + kCarriedLevels);
  // The carried red is laid down as the brush goes: less of it further on.
  CHECK(w.red_minus_blue - d.red_minus_blue > w_far.red_minus_blue - d_far.red_minus_blue);
}

TEST_CASE("validate reports a scene's summary, and its problems with exit codes",
          "[cli][scene]") {
  TempDir dir;
  const std::string good = writeScene(dir, "good.json", crossingScene());
  RunResult r = runBristle("validate '" + good + "'");
  CHECK(r.code == 0);
  CHECK(r.out == good + ": ok (scene 'crossing', 2 strokes, 1 brush, 80 x 70 mm at 4 px/mm)\n");

  json bad = crossingScene();
  bad["strokes"][1]["paint"]["paints"][0] = "ultramarin";
  r = runBristle("validate '" + writeScene(dir, "bad.json", bad) + "' '" + good + "'");
  CHECK(r.code == 65);
  CHECK_THAT(r.err, StartsWith("bristle: " + dir.file("bad.json") +
                               ": /strokes/1/paint/paints/0: unknown pigment 'ultramarin'"));
  CHECK_THAT(r.out, Contains(good + ": ok"));  // the other file is still checked

  // The library's paintings are sound.
  r = runBristle("validate '" + sourcePath("scenes/paintings/petals.json") + "' '" +
                 sourcePath("scenes/paintings/calligraphy.json") + "' '" +
                 sourcePath("scenes/paintings/landscape.json") + "'");
  CHECK(r.code == 0);
  CHECK(r.err.empty());
}

TEST_CASE("bad scenes exit with their code and one line, and leave no PNG", "[cli][scene]") {
  TempDir dir;
  struct Case {
    const char* what;
    std::function<void(json&)> edit;
    int code;
    std::string message;  // after "bristle: <scene>: "
  };
  const std::vector<Case> cases = {
      {"unknown pigment", [](json& j) { j["strokes"][0]["paint"]["paints"][0] = "cadmium-rde"; },
       65, "/strokes/0/paint/paints/0: unknown pigment 'cadmium-rde'"},
      {"bad colour", [](json& j) { j["canvas"]["background"] = "#f5f1e"; }, 65,
       "/canvas/background: colour '#f5f1e' does not parse"},
      {"negative amount", [](json& j) { j["strokes"][1]["paint"]["amount"] = -1; }, 65,
       "/strokes/1/paint/amount = -1: must be in (0, 1]"},
      {"canvas too large", [](json& j) { j["canvas"]["size_mm"] = {5000, 5000}; }, 65,
       "/canvas/size_mm: 5000 x 5000 mm at 4 px/mm is 20000 x 20000 px: larger than the limit"},
      {"missing trajectory", [](json& j) { j["strokes"][1]["trajectory"] = "gone.csv"; }, 66,
       "/strokes/1/trajectory: cannot read '"},
      {"missing brush", [](json& j) { j["strokes"][0]["brush"] = "gone.json"; }, 66,
       "/strokes/0/brush: cannot read '"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    json j = crossingScene();
    c.edit(j);
    const std::string scene = writeScene(dir, "bad.json", j);
    const std::string png = dir.file("bad.png");
    const RunResult r = runBristle("render -q '" + scene + "' -o '" + png + "'");
    CHECK(r.code == c.code);
    CHECK_THAT(r.err, StartsWith("bristle: " + scene + ": " + c.message));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(exists(png));
  }
}

TEST_CASE("with a scene, options the scene sets are usage errors naming them",
          "[cli][scene]") {
  TempDir dir;
  const std::string scene = writeScene(dir, "s.json", crossingScene());
  for (const char* opt : {"--px-per-mm 3", "--brush x.json", "--solver ipopt", "--paint viridian"}) {
    INFO(opt);
    const RunResult r =
        runBristle("render '" + scene + "' -o '" + dir.file("x.png") + "' " + opt);
    CHECK(r.code == 64);
    CHECK_THAT(r.err, Contains(std::string(opt).substr(0, std::string(opt).find(' ')) +
                               " cannot be used with a scene"));
    CHECK_FALSE(exists(dir.file("x.png")));
  }
  // The iteration limit is not the scene's to set: it is taken, and checked.
  const RunResult zero = runBristle("render '" + scene + "' -o '" + dir.file("x.png") +
                                    "' --solver-max-iterations 0");
  CHECK(zero.code == 64);
  CHECK_THAT(zero.err, Contains("--solver-max-iterations"));
  CHECK(std::count(zero.err.begin(), zero.err.end(), '\n') == 1);
  CHECK_FALSE(exists(dir.file("x.png")));
  // Neither a scene nor a brush and trajectory.
  const RunResult r = runBristle("render -o '" + dir.file("x.png") + "'");
  CHECK(r.code == 64);
  CHECK_THAT(r.err, Contains("give a SCENE.json, or --brush and --trajectory"));
  // An output that cannot be created fails before the run: 73, no file.
  const RunResult o = runBristle("render -q '" + scene + "' -o '" + dir.file("no/such/dir/x.png") + "'");
  CHECK(o.code == 73);
}

TEST_CASE("render SCENE --solver-max-iterations limits every stroke's solves, and --threads is "
          "taken",
          "[cli][scene]") {
  TempDir dir;
  json one = crossingScene();
  one["strokes"].erase(1);
  // The pull's press and first 2.5 mm (its first 0.6 s): trajectoryHead.
  one["strokes"][0]["trajectory"] = dir.write("short.csv", trajectoryHead(kPull, 0.6));
  const std::string scene = writeScene(dir, "s.json", one);
  auto run = [&](const std::string& name, const std::string& extra) {
    const RunResult r = runBristle("render -q '" + scene + "' -o '" + dir.file(name + ".png") +
                                   "' --stats '" + dir.file(name + ".json") + "' " + extra);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return json::parse(readAll(dir.file(name + ".json")));
  };
  const json full = run("full", "");
  CHECK(full["failed_steps"] == 0);
  // One SLSQP evaluation, one Ipopt iteration: no solve can converge.
  const json starved = run("starved", "--solver-max-iterations 1");
  CHECK(starved["failed_steps"].get<int>() > 0);
  CHECK(render::readPngRgba8(dir.file("starved.png")).pixels !=
        render::readPngRgba8(dir.file("full.png")).pixels);
  // --threads is taken as well, and changes the time, not the pixels.
  const json turns = run("turns", "--threads 1");
  CHECK(turns["failed_steps"] == 0);
  CHECK(render::readPngRgba8(dir.file("turns.png")).pixels ==
        render::readPngRgba8(dir.file("full.png")).pixels);
}

TEST_CASE("a stroke that never touches the canvas is a warning naming the stroke",
          "[cli][scene]") {
  TempDir dir;
  json j = crossingScene();
  // Shifted 300 mm to the right: nowhere near the 80 mm canvas.
  j["strokes"][1]["placement"]["offset_mm"] = {360, -5};
  const std::string scene = writeScene(dir, "s.json", j);
  const RunResult r = runBristle("render -q '" + scene + "' -o '" + dir.file("s.png") + "'");
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("warning: " + scene + ": /strokes/1: the brush never comes within "
                             "reach of the canvas"));
  CHECK(exists(dir.file("s.png")));
}

TEST_CASE("a scene, a sheet and a render that name no paper colour share one paper",
          "[cli][scene][paper]") {
  // kDefaultPaperColour (engine/paint/paint_spec.h): the same stroke as a one-stroke
  // scene, a one-cell sheet or a render lands on the same paper.
  TempDir dir;
  std::string dab = "# bristle-trajectory/1\nt_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz\n";
  for (int i = 0; i <= 10; ++i)
    dab += std::to_string(0.03 * i) + ",20,20," + std::to_string(i <= 5 ? 0.4 * i : 4 - 0.4 * i) +
           ",1,0,0,0\n";
  dir.write("dab.csv", dab);
  const json scene = {{"format", "bristle-scene/1"},
                      {"name", "dab"},
                      {"canvas", {{"size_mm", {40, 40}}, {"px_per_mm", 2}}},
                      {"solver", "ipopt"},
                      {"strokes",
                       {{{"brush", kRound},
                         {"trajectory", "dab.csv"},
                         {"paint", {{"paints", {"#1c2433"}}}}}}}};
  const json sheet = {{"format", "bristle-sheet/1"}, {"name", "dab"},
                      {"brushes", {kRound}},       {"trajectories", {"dab.csv"}},
                      {"px_per_mm", 2},            {"solver", "ipopt"}};
  const std::string q = " -q -o '";
  REQUIRE(runBristle("render '" + dir.write("s.json", scene.dump()) + "'" + q +
                     dir.file("scene.png") + "'").code == 0);
  REQUIRE(runBristle("sheet '" + dir.write("sh.json", sheet.dump()) + "'" + q +
                     dir.file("sheet.png") + "'").code == 0);
  REQUIRE(runBristle("render --solver ipopt --px-per-mm 2 --brush '" + kRound +
                     "' --trajectory '" + dir.file("dab.csv") + "'" + q + dir.file("render.png") +
                     "'").code == 0);
  const std::array<std::uint8_t, 3> paper{0xf6, 0xf1, 0xe6};
  for (const char* png : {"scene.png", "sheet.png", "render.png"}) {
    INFO(png);
    CHECK(render::borderPaperColour(render::readPngRgba16(dir.file(png))) == paper);
  }
}

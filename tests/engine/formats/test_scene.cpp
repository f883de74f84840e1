// The scene reader (`bristle-scene/1`, engine/formats/scene.h): what a good scene turns
// into, placement, and every bad input with its exit code and a message that
// names the file, the JSON pointer and the rule (docs/scene-format.md).

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "engine/base/error.h"
#include "engine/formats/scene.h"
#include "test_helpers.h"
#include "temp_dir.h"

using namespace bristle;
using bristle::testing::Caught;
using bristle::testing::kSourceDir;
using bristle::testing::catchError;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using nlohmann::json;

namespace {

namespace fs = std::filesystem;

// BRISTLE_SOURCE_DIR, not __FILE__: ccache with CCACHE_BASEDIR makes __FILE__
// relative to the build folder, and paths written into scene files then break.
const std::string kFlat = (kSourceDir / "scenes/brushes/flat.json").string();
const std::string kPull = (kSourceDir / "scenes/trajectories/straight-pull.csv").string();

// Positions and quaternions are compared after a rotation by 90 degrees: a
// few ulps of sin/cos, far below any millimetre that matters.
constexpr double kPoseTol = 1e-12;

// A small, sound scene: two strokes of the library's flat along the demo pull.
json goodScene() {
  return json::parse(R"({
    "format": "bristle-scene/1",
    "name": "test",
    "canvas": {"size_mm": [80, 40], "px_per_mm": 4, "background": "#f4efe2",
               "paper": {"tooth_depth_mm": 0.05, "tooth_scale_mm": 0.5, "seed": 9}},
    "sim": {"rate_hz": 100, "max_step_mm": 0.3, "steady_step_mm": 0.8},
    "mix": "rgb",
    "solver": "slsqp",
    "strokes": [
      {"brush": ")" + kFlat + R"(", "trajectory": ")" + kPull + R"(",
       "paint": {"mode": "across", "paints": ["cadmium-red", "#ffffff"], "amount": 0.5}},
      {"brush": ")" + kFlat + R"(", "trajectory": ")" + kPull + R"(",
       "paint": {"mode": "tip", "paints": ["ultramarine", "cadmium-yellow"], "tip_length": 0.2,
                 "dilution": 0.3},
       "placement": {"offset_mm": [40, -10], "rotate_deg": 90}, "dry_before": true}
    ]})");
}

Scene parse(const json& j) { return parseScene(j.dump(), "scene.json", ""); }

Caught parseError(const json& j) {
  return catchError([&] { parse(j); });
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

using bristle::testing::TempDir;

}  // namespace

TEST_CASE("a sound scene parses into canvas, paper, paint loadings and placements",
          "[scene]") {
  const Scene s = parse(goodScene());
  CHECK(s.name == "test");
  CHECK(s.canvas.width_mm == 80);
  CHECK(s.canvas.height_mm == 40);
  const CanvasGrid g = s.canvas.grid();
  CHECK(g.width_px == 320);
  CHECK(g.height_px == 160);
  CHECK(g.x0_mm == 0);
  CHECK(g.y0_mm == 0);
  CHECK(s.canvas.paper.colour == "#f4efe2");
  CHECK(s.canvas.paper.tooth_depth_mm == 0.05);
  CHECK(s.canvas.paper.tooth_scale_mm == 0.5);
  CHECK(s.canvas.paper.seed == 9);
  CHECK(s.sim.min_rate_hz == 100);
  CHECK(s.sim.max_step_mm == 0.3);
  CHECK(s.sim.steady_step_mm == 0.8);
  CHECK(s.mix == MixModel::kLinearRgb);
  CHECK(s.solver == SolverKind::kSlsqp);
  REQUIRE(s.strokes.size() == 2);
  const PaintLoad& a = s.strokes[0].paint;
  CHECK(a.mode == PaintLoad::Mode::kAcross);
  CHECK(a.paints == std::vector<std::string>{"cadmium-red", "#ffffff"});
  CHECK(a.amount == 0.5);
  CHECK_FALSE(s.strokes[0].dry_before);
  CHECK(s.strokes[0].placement.identity());
  const PaintLoad& b = s.strokes[1].paint;
  CHECK(b.mode == PaintLoad::Mode::kTip);
  CHECK(b.tip_length == 0.2);
  CHECK(b.dilution == 0.3);
  CHECK(s.strokes[1].dry_before);
  CHECK(s.strokes[1].placement.offset_x_mm == 40);
  CHECK(s.strokes[1].placement.offset_y_mm == -10);
  CHECK(s.strokes[1].placement.rotate_deg == 90);
  CHECK(s.strokes[1].pointer == "/strokes/1");
}

TEST_CASE("omitted optional keys take the documented defaults", "[scene]") {
  json j = goodScene();
  j.erase("sim");
  j.erase("mix");
  j.erase("solver");
  j["canvas"].erase("paper");
  j["canvas"].erase("background");
  j["canvas"].erase("px_per_mm");
  j["strokes"][0]["paint"] = json::parse(R"({"paints": ["sumi-ink"]})");
  const Scene s = parse(j);
  CHECK(s.canvas.px_per_mm == 8);
  CHECK(s.canvas.paper.colour == PaperSpec().colour);
  CHECK(s.canvas.paper.tooth_depth_mm == PaperSpec().tooth_depth_mm);
  CHECK(s.mix == MixModel::kKubelkaMunk);
  CHECK(s.solver == SolverKind::kIpopt);
  CHECK(s.sim.max_step_mm == SimOptions().max_step_mm);
  CHECK(s.sim.min_rate_hz == SimOptions().min_rate_hz);
  const PaintLoad& p = s.strokes[0].paint;
  CHECK(p.mode == PaintLoad::Mode::kSolid);
  CHECK(p.amount == 1.0);
  CHECK(p.dilution == 0.0);
}

TEST_CASE("placement turns about the trajectory's origin, then shifts, and heights stay",
          "[scene]") {
  Placement pl;
  pl.rotate_deg = 90;
  pl.offset_x_mm = 10;
  pl.offset_y_mm = -2;
  Pose p;
  p.position_mm = Eigen::Vector3d(3, 0, 7);
  // The handle tilted 20 degrees towards +x: after the turn it leans towards +y.
  p.rotation = Eigen::AngleAxisd(20 * std::numbers::pi / 180, Eigen::Vector3d::UnitY());
  const Pose q = pl.apply(p);
  CHECK(std::fabs(q.position_mm.x() - 10) < kPoseTol);
  CHECK(std::fabs(q.position_mm.y() - 1) < kPoseTol);
  CHECK(q.position_mm.z() == 7);
  // Where the hairs point (-z of the brush) turns with the trajectory.
  const Eigen::Vector3d hair_before = p.rotation * Eigen::Vector3d(0, 0, -1);
  const Eigen::Vector3d hair_after = q.rotation * Eigen::Vector3d(0, 0, -1);
  CHECK(std::fabs(hair_after.x() - -hair_before.y()) < kPoseTol);
  CHECK(std::fabs(hair_after.y() - hair_before.x()) < kPoseTol);
  CHECK(std::fabs(hair_after.z() - hair_before.z()) < kPoseTol);
  // Identity placement is exact.
  const Pose same = Placement{}.apply(p);
  CHECK(same.position_mm == p.position_mm);
  CHECK(same.rotation.coeffs() == p.rotation.coeffs());
}

TEST_CASE("bad values are 65 naming the JSON pointer and the rule", "[scene]") {
  struct Case {
    const char* what;
    std::function<void(json&)> edit;
    const char* where;
    const char* rule;
  };
  const std::vector<Case> cases = {
      {"unknown pigment", [](json& j) { j["strokes"][0]["paint"]["paints"][1] = "ultramarin"; },
       "scene.json: /strokes/0/paint/paints/1: ", "unknown pigment 'ultramarin'"},
      {"bad paint colour", [](json& j) { j["strokes"][1]["paint"]["paints"][0] = "#12345g"; },
       "scene.json: /strokes/1/paint/paints/0: ", "colour '#12345g' does not parse"},
      {"short background", [](json& j) { j["canvas"]["background"] = "#fff"; },
       "scene.json: /canvas/background: ", "colour '#fff' does not parse"},
      {"negative amount", [](json& j) { j["strokes"][0]["paint"]["amount"] = -0.5; },
       "scene.json: /strokes/0/paint/amount = -0.5: ", "must be in (0, 1]"},
      {"amount above 1", [](json& j) { j["strokes"][0]["paint"]["amount"] = 1.5; },
       "scene.json: /strokes/0/paint/amount = 1.5: ", "must be in (0, 1]"},
      {"negative dilution", [](json& j) { j["strokes"][1]["paint"]["dilution"] = -1; },
       "scene.json: /strokes/1/paint/dilution = -1: ", "must be in [0, 1]"},
      {"negative tooth", [](json& j) { j["canvas"]["paper"]["tooth_depth_mm"] = -0.1; },
       "scene.json: /canvas/paper/tooth_depth_mm = -0.1: ", "must be in [0, 1] mm"},
      {"unknown mode", [](json& j) { j["strokes"][0]["paint"]["mode"] = "double"; },
       "scene.json: /strokes/0/paint/mode = \"double\": ", "must be \"solid\", \"across\" or \"tip\""},
      {"across with one paint", [](json& j) { j["strokes"][0]["paint"]["paints"] = {"viridian"}; },
       "scene.json: /strokes/0/paint/paints = [\"viridian\"]: ", "takes 2..3 paints"},
      {"tip_length without tip", [](json& j) { j["strokes"][0]["paint"]["tip_length"] = 0.2; },
       "scene.json: /strokes/0/paint/tip_length = 0.2: ", "applies only to mode \"tip\""},
      // A tip over the whole hair, or none of it, is a solid load (engine/paint/paint_spec.h).
      {"tip_length 1", [](json& j) { j["strokes"][1]["paint"]["tip_length"] = 1; },
       "scene.json: /strokes/1/paint/tip_length = 1: ", "must be in (0, 1) (a fraction"},
      {"tip_length 0", [](json& j) { j["strokes"][1]["paint"]["tip_length"] = 0; },
       "scene.json: /strokes/1/paint/tip_length = 0: ", "must be in (0, 1)"},
      {"tip with one paint", [](json& j) { j["strokes"][1]["paint"]["paints"] = {"viridian"}; },
       "scene.json: /strokes/1/paint/paints = [\"viridian\"]: ",
       "mode \"tip\" takes 2 paints (body, then tip)"},
      {"a paint that is not a string", [](json& j) { j["strokes"][1]["paint"]["paints"][1] = 3; },
       "scene.json: /strokes/1/paint/paints/1 = 3: ", "must be a pigment name or a colour"},
      {"paints not a list", [](json& j) { j["strokes"][1]["paint"]["paints"] = "viridian"; },
       "scene.json: /strokes/1/paint/paints = \"viridian\": ", "mode \"tip\" takes 2 paints"},
      {"unknown stroke key", [](json& j) { j["strokes"][1]["speed"] = 2; },
       "scene.json: /strokes/1/speed: ", "unknown key 'speed'"},
      {"unknown top key", [](json& j) { j["outputs"] = json::object(); },
       "scene.json: /outputs: ", "unknown key 'outputs'"},
      {"misspelt optional key", [](json& j) { j["strokes"][0]["dry_befor"] = true; },
       "scene.json: /strokes/0/dry_befor: ",
       "unknown key 'dry_befor'; did you mean /strokes/0/dry_before?"},
      {"misspelt required key",
       [](json& j) {
         j["strokes"][0]["trajectry"] = j["strokes"][0]["trajectory"];
         j["strokes"][0].erase("trajectory");
       },
       "scene.json: /strokes/0/trajectry: ",
       "unknown key 'trajectry'; did you mean /strokes/0/trajectory?"},
      {"format version", [](json& j) { j["format"] = "bristle-scene/2"; },
       "scene.json: /format = \"bristle-scene/2\": ", "unknown format version"},
      {"no strokes", [](json& j) { j["strokes"] = json::array(); },
       "scene.json: /strokes = []: ", "must have 1..10000 strokes"},
      {"zero width", [](json& j) { j["canvas"]["size_mm"][0] = 0; },
       "scene.json: /canvas/size_mm/0 = 0.0: ", "must be > 0"},
      {"dry_before not a bool", [](json& j) { j["strokes"][0]["dry_before"] = "yes"; },
       "scene.json: /strokes/0/dry_before = \"yes\": ", "must be true or false"},
      {"offset of three", [](json& j) { j["strokes"][1]["placement"]["offset_mm"] = {1, 2, 3}; },
       "scene.json: /strokes/1/placement/offset_mm = [1,2,3]: ", "must be [x, y] in mm"},
      {"mix", [](json& j) { j["mix"] = "cmyk"; },
       "scene.json: /mix = \"cmyk\": ", "must be \"km\""},
      {"solver", [](json& j) { j["solver"] = "newton"; },
       "scene.json: /solver = \"newton\": ", "must be \"ipopt\" or \"slsqp\""},
      {"rate", [](json& j) { j["sim"]["rate_hz"] = 0; },
       "scene.json: /sim/rate_hz = 0: ", "must be in [1, 10000]"},
      {"steady step", [](json& j) { j["sim"]["steady_step_mm"] = -1; },
       "scene.json: /sim/steady_step_mm = -1: ", "must be in [0, 5] mm"},
      {"empty brush path", [](json& j) { j["strokes"][0]["brush"] = ""; },
       "scene.json: /strokes/0/brush = \"\": ", "must name a brush file"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    json j = goodScene();
    c.edit(j);
    const Caught e = parseError(j);
    REQUIRE(e.thrown);
    CHECK(e.code == 65);
    CHECK_THAT(e.message, StartsWith(c.where));
    CHECK_THAT(e.message, Contains(c.rule));
    CHECK(e.message.find('\n') == std::string::npos);
  }
}

TEST_CASE("a canvas beyond the pixel limit is refused before allocating", "[scene]") {
  json j = goodScene();
  // 2100 mm at 8 px/mm = 16800 px, above 16384 px a side.
  j["canvas"]["size_mm"] = {2100, 10};
  j["canvas"]["px_per_mm"] = 8;
  Caught e = parseError(j);
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith("scene.json: /canvas/size_mm: "));
  CHECK_THAT(e.message, Contains("16800 x 80 px: larger than the limit"));
  // Each side within the limit, 9000 x 9000 = 81 Mpx above 64 Mpx in all.
  j["canvas"]["size_mm"] = {900, 900};
  j["canvas"]["px_per_mm"] = 10;
  e = parseError(j);
  CHECK(e.code == 65);
  CHECK_THAT(e.message, Contains("9000 x 9000 px"));
  // Absurd sizes do not overflow the check.
  j["canvas"]["size_mm"] = {1e300, 1e300};
  CHECK(parseError(j).code == 65);
  // The largest side that fits is accepted.
  j["canvas"]["size_mm"] = {1638.4, 10};
  CHECK_FALSE(parseError(j).thrown);
}

TEST_CASE("malformed JSON is 65 with line and column", "[scene]") {
  const Caught e = catchError([] { parseScene("{\"format\": \"bristle-scene/1\",\n ]", "s.json", ""); });
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith("s.json: line 2, column 2: malformed JSON"));
}

TEST_CASE("scenes are recognised by their format key", "[scene]") {
  CHECK(looksLikeScene(goodScene().dump()));
  CHECK(looksLikeScene(R"({"format": "bristle-scene/7"})"));
  CHECK_FALSE(looksLikeScene(R"({"format": "bristle-brush/1"})"));
  CHECK_FALSE(looksLikeScene("{ not json"));
  CHECK_FALSE(looksLikeScene("[1, 2]"));
}

TEST_CASE("loadScene resolves paths against the scene's folder and reads each file once",
          "[scene]") {
  TempDir dir;
  dir.write("brushes/flat.json", slurp(kFlat));
  dir.write("paths/pull.csv", slurp(kPull));
  json j = goodScene();
  for (json& s : j["strokes"]) {
    s["brush"] = "../brushes/flat.json";
    s["trajectory"] = "../paths/pull.csv";
  }
  const std::string path = dir.write("scenes/s.json", j.dump());
  const Scene s = loadScene(path);
  REQUIRE(s.brushes.size() == 1);
  CHECK(s.brushes[0].name == "flat");
  CHECK(s.strokes[0].brush == 0);
  CHECK(s.strokes[1].brush == 0);
  CHECK(s.strokes[0].trajectory_path == dir.file("paths/pull.csv"));
  // The scene, then each distinct file once, in order of first mention.
  CHECK(s.inputs ==
        std::vector<std::string>{path, dir.file("brushes/flat.json"), dir.file("paths/pull.csv")});
  // The second stroke's poses are placed: turned 90 degrees, shifted by (40, -10).
  const Pose& raw = s.strokes[0].trajectory.samples[5].pose;
  const Pose& moved = s.strokes[1].trajectory.samples[5].pose;
  CHECK(std::fabs(moved.position_mm.x() - (40 - raw.position_mm.y())) < kPoseTol);
  CHECK(std::fabs(moved.position_mm.y() - (-10 + raw.position_mm.x())) < kPoseTol);
  CHECK(moved.position_mm.z() == raw.position_mm.z());
}

TEST_CASE("a missing referenced file is 66 naming the scene field", "[scene]") {
  TempDir dir;
  dir.write("flat.json", slurp(kFlat));
  dir.write("pull.csv", slurp(kPull));
  json j = goodScene();
  for (json& s : j["strokes"]) {
    s["brush"] = "flat.json";
    s["trajectory"] = "pull.csv";
  }
  j["strokes"][1]["trajectory"] = "nope.csv";
  Caught e = catchError([&] { loadScene(dir.write("s.json", j.dump())); });
  CHECK(e.code == 66);
  CHECK_THAT(e.message, StartsWith(dir.file("s.json") + ": /strokes/1/trajectory: cannot read '" +
                                   dir.file("nope.csv") + "'"));
  j["strokes"][1]["trajectory"] = "pull.csv";
  j["strokes"][0]["brush"] = "missing/flat.json";
  e = catchError([&] { loadScene(dir.write("s.json", j.dump())); });
  CHECK(e.code == 66);
  CHECK_THAT(e.message, Contains(": /strokes/0/brush: cannot read '"));
  // A folder is not a file.
  j["strokes"][0]["brush"] = ".";
  e = catchError([&] { loadScene(dir.write("s.json", j.dump())); });
  CHECK(e.code == 66);
  CHECK_THAT(e.message, Contains("is a directory"));
  // The scene itself missing.
  e = catchError([&] { loadScene(dir.file("none.json")); });
  CHECK(e.code == 66);
  CHECK_THAT(e.message, StartsWith(dir.file("none.json") + ": cannot read"));
}

TEST_CASE("a bad brush or trajectory keeps naming its own file", "[scene]") {
  TempDir dir;
  json brush = json::parse(slurp(kFlat));
  brush["spines"][0]["width_mm"][2] = -1;
  dir.write("bad.json", brush.dump());
  dir.write("pull.csv", slurp(kPull));
  dir.write("bad.csv", "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,1,2,3,1,0,0,0\n"
                       "0,1,2,3,1,0,0,0\n");
  json j = goodScene();
  j["strokes"] = json::array({j["strokes"][0]});
  j["strokes"][0]["brush"] = "bad.json";
  j["strokes"][0]["trajectory"] = "pull.csv";
  Caught e = catchError([&] { loadScene(dir.write("s.json", j.dump())); });
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith(dir.file("bad.json") + ": /spines/0/width_mm/2"));
  j["strokes"][0]["brush"] = kFlat;
  j["strokes"][0]["trajectory"] = "bad.csv";
  e = catchError([&] { loadScene(dir.write("s.json", j.dump())); });
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith(dir.file("bad.csv") + ": line 4"));
}

TEST_CASE("a trajectory that drives the brush's ferrule into the canvas names the stroke", "[scene]") {
  TempDir dir;
  // Sound on its own (a CSV knows no brush), but the flat's ferrule would go
  // 1 mm into the paper on the second sample: the message names the stroke
  // that pairs them as well as the trajectory's line.
  std::string low = "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                    "0,10,10,20,1,0,0,0\n1,20,10,-1,1,0,0,0\n";
  dir.write("low.csv", low);
  json j = goodScene();
  j["strokes"][1]["trajectory"] = dir.file("low.csv");
  const Caught e = catchError([&] { loadScene(dir.write("s.json", j.dump())); });
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith(dir.file("s.json") + ": /strokes/1: with brush 'flat': " +
                                   dir.file("low.csv") + ": line 4"));
  CHECK_THAT(e.message, Contains("ferrule goes below the canvas"));
}

TEST_CASE("a stroke placed beyond the brush's reach of the canvas is warned about",
          "[scene]") {
  json j = goodScene();
  j["strokes"][1]["placement"]["offset_mm"] = {500, 0};
  TempDir dir;
  const Scene s = loadScene(dir.write("s.json", j.dump()));
  const std::vector<std::string> w = sceneWarnings(s);
  REQUIRE(w.size() == 1);
  CHECK_THAT(w[0], StartsWith(dir.file("s.json") + ": /strokes/1: the brush never comes within reach"));
  j["strokes"][1]["placement"]["offset_mm"] = {40, -10};
  CHECK(sceneWarnings(loadScene(dir.write("s.json", j.dump()))).empty());
}

TEST_CASE("the three paintings load", "[scene]") {
  for (const char* name : {"petals", "calligraphy", "landscape"}) {
    INFO(name);
    const Scene s = loadScene((kSourceDir / "scenes/paintings" / (std::string(name) + ".json")).string());
    CHECK(s.strokes.size() >= 5);
    CHECK(sceneWarnings(s).empty());
  }
}

TEST_CASE("the annotated example of docs/scene-format.md is a sound scene", "[scene]") {
  const std::string doc = slurp((kSourceDir / "docs/scene-format.md").string());
  const size_t open = doc.find("```jsonc");
  REQUIRE(open != std::string::npos);
  const size_t start = doc.find('\n', open) + 1;
  const size_t end = doc.find("```", start);
  // Without its // comments (the page says so).
  std::string text;
  std::istringstream lines(doc.substr(start, end - start));
  for (std::string line; std::getline(lines, line);)
    text += line.substr(0, line.find("//")) + "\n";
  const std::string dir = (kSourceDir / "scenes/paintings").string();
  const Scene s = parseScene(text, "example.json", dir);
  CHECK(s.name == "two petals");
  REQUIRE(s.strokes.size() == 2);
  CHECK(s.strokes[1].dry_before);
  // The files it names are where the page says (relative to scenes/paintings/).
  for (const SceneStroke& st : s.strokes) {
    CHECK(fs::exists(st.brush_path));
    CHECK(fs::exists(st.trajectory_path));
  }
}

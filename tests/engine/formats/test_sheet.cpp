// The stroke-sheet reader (`bristle-sheet/1`, engine/formats/sheet.h): what a good sheet
// turns into, its defaults, and every bad input with its exit code and a message
// naming the file, the JSON pointer and the rule (docs/sheet-format.md); the
// inputs it lists and their hash.

#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/sheet.h"
#include "engine/base/text_file.h"
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


json goodSheet() {
  return json::parse(R"({
    "format": "bristle-sheet/1",
    "name": "two by two",
    "title": "Round and badger",
    "brushes": ["brushes/round.json", {"path": "brushes/badger.json", "lift_mm": 6}],
    "trajectories": ["trajectories/straight-pull.csv", "/abs/press-lift.csv"],
    "layout": "brushes-in-columns",
    "cell_mm": [60, 30],
    "px_per_mm": 5,
    "paint": {"mode": "tip", "paints": ["ultramarine", "cadmium-yellow"], "amount": 0.5},
    "background": "#ffffff",
    "paper": {"tooth_depth_mm": 0.05, "seed": 3},
    "mix": "rgb",
    "sim": {"rate_hz": 60, "max_step_mm": 0.5},
    "solver": "slsqp",
    "labels": {"font_px": 20}
  })");
}

Sheet sheetFrom(const json& j) { return parseSheet(j.dump(), "sheet.json", "base"); }

Caught sheetError(const json& j) {
  return catchError([&] { sheetFrom(j); });
}

// A fresh folder with a sheet and copies of the files it lists.
struct SheetDir {
  bristle::testing::TempDir tmp{"bristle-sheet"};
  const fs::path& dir = tmp.path();
  SheetDir() {
    fs::create_directories(dir / "b");
    fs::create_directories(dir / "t");
    for (const char* b : {"round", "flat"})
      fs::copy_file(kSourceDir / "scenes/brushes" / (std::string(b) + ".json"),
                    dir / "b" / (std::string(b) + ".json"));
    for (const char* t : {"straight-pull", "press-lift"})
      fs::copy_file(kSourceDir / "scenes/trajectories" / (std::string(t) + ".csv"),
                    dir / "t" / (std::string(t) + ".csv"));
  }
  std::string write(const json& j) const {
    const std::string p = (dir / "sheet.json").string();
    std::ofstream(p) << j.dump(1);
    return p;
  }
  static json sheet() {
    return {{"format", "bristle-sheet/1"},
            {"name", "copy"},
            {"brushes", {"b/round.json", "b/flat.json"}},
            {"trajectories", {"t/straight-pull.csv", "t/press-lift.csv"}}};
  }
};

}  // namespace

TEST_CASE("a sound sheet parses into files, lifts, layout, cell, paint and labels", "[sheet]") {
  const Sheet s = sheetFrom(goodSheet());
  CHECK(s.name == "two by two");
  CHECK(s.title == "Round and badger");
  REQUIRE(s.brush_paths.size() == 2);
  CHECK(s.brush_paths[0] == "base/brushes/round.json");  // relative to the sheet
  CHECK(s.brush_paths[1] == "base/brushes/badger.json");
  CHECK(s.brush_lift_mm == std::vector<double>{0, 6});
  REQUIRE(s.trajectory_paths.size() == 2);
  CHECK(s.trajectory_paths[0] == "base/trajectories/straight-pull.csv");
  CHECK(s.trajectory_paths[1] == "/abs/press-lift.csv");  // absolute stays
  CHECK(s.brushes_in_columns);
  CHECK_FALSE(s.autoCell());
  CHECK(s.cell_width_mm == 60);
  CHECK(s.cell_height_mm == 30);
  CHECK(s.px_per_mm == 5);
  CHECK(s.paint.mode == PaintLoad::Mode::kTip);
  CHECK(s.paint.paints == std::vector<std::string>{"ultramarine", "cadmium-yellow"});
  CHECK(s.paint.amount == 0.5);
  CHECK(s.paper.colour == "#ffffff");
  CHECK(s.background.r == 1.0);
  CHECK(s.paper.tooth_depth_mm == 0.05);
  CHECK(s.paper.seed == 3);
  CHECK(s.mix == MixModel::kLinearRgb);
  CHECK(s.sim.min_rate_hz == 60);
  CHECK(s.sim.max_step_mm == 0.5);
  CHECK(s.solver == SolverKind::kSlsqp);
  CHECK(s.label_px == 20);
  // Labels: the brush's file stem until the brush is read, with its lift.
  CHECK(s.brushLabel(1) == "badger +6 mm");
  CHECK(s.trajectoryLabel(0) == "straight-pull");
}

TEST_CASE("omitted keys take the defaults of `bristle render --brush --trajectory`", "[sheet]") {
  const Sheet s = sheetFrom({{"format", "bristle-sheet/1"},
                         {"name", "n"},
                         {"brushes", {"a.json"}},
                         {"trajectories", {"t.csv"}}});
  CHECK(s.title.empty());
  CHECK_FALSE(s.brushes_in_columns);
  CHECK(s.autoCell());
  CHECK(s.px_per_mm == 8);
  // cli/paint_options.h: --paint #1c2433 --load solid --amount 1, --background #f6f1e6.
  CHECK(s.paint.mode == PaintLoad::Mode::kSolid);
  CHECK(s.paint.paints == std::vector<std::string>{"#1c2433"});
  CHECK(s.paint.amount == 1.0);
  CHECK(s.paper.colour == "#f6f1e6");
  CHECK(s.paper.tooth_depth_mm == PaperSpec{}.tooth_depth_mm);
  CHECK(s.mix == MixModel::kKubelkaMunk);
  CHECK(s.sim.min_rate_hz == SimOptions{}.min_rate_hz);
  CHECK(s.sim.max_step_mm == SimOptions{}.max_step_mm);
  CHECK(s.solver == SolverKind::kIpopt);
  CHECK(s.label_px == 14);
  CHECK(s.brush_lift_mm == std::vector<double>{0});

  json j = goodSheet();
  j["cell_mm"] = "auto";
  CHECK(sheetFrom(j).autoCell());
}

TEST_CASE("bad sheet values are 65 naming the JSON pointer and the rule", "[sheet]") {
  struct Case {
    const char* what;
    std::function<void(json&)> edit;
    const char* where;
    const char* rule;
  };
  const std::vector<Case> cases = {
      {"format version", [](json& j) { j["format"] = "bristle-sheet/2"; },
       "sheet.json: /format = \"bristle-sheet/2\": ", "unknown format version"},
      {"empty name", [](json& j) { j["name"] = ""; }, "sheet.json: /name = \"\": ",
       "must not be empty"},
      {"unknown top key", [](json& j) { j["colour"] = "red"; }, "sheet.json: /colour: ",
       "unknown key 'colour'"},
      {"no brushes", [](json& j) { j["brushes"] = json::array(); }, "sheet.json: /brushes = []: ",
       "must be a list of 1..64 brush file paths"},
      {"trajectories not a list", [](json& j) { j["trajectories"] = "a.csv"; },
       "sheet.json: /trajectories = \"a.csv\": ", "must be a list of 1..64 trajectory"},
      {"no trajectories", [](json& j) { j.erase("trajectories"); }, "sheet.json: /trajectories",
       "required key is missing"},
      {"number as a path", [](json& j) { j["trajectories"][1] = 3; },
       "sheet.json: /trajectories/1 = 3: ", "must be a trajectory file path"},
      {"object as a trajectory", [](json& j) { j["trajectories"][0] = {{"path", "a.csv"}}; },
       "sheet.json: /trajectories/0 = ", "must be a trajectory file path"},
      {"empty brush path", [](json& j) { j["brushes"][0] = ""; }, "sheet.json: /brushes/0 = \"\": ",
       "must be a brush file path"},
      {"brush twice", [](json& j) { j["brushes"][1] = "brushes/../brushes/round.json"; },
       "sheet.json: /brushes/1: ", "is listed already at /brushes/0"},
      {"unknown brush entry key", [](json& j) { j["brushes"][1]["lift"] = 2; },
       "sheet.json: /brushes/1/lift: ", "unknown key 'lift'"},
      {"misspelt required key",
       [](json& j) {
         j["trajectorys"] = j["trajectories"];
         j.erase("trajectories");
       },
       "sheet.json: /trajectorys: ", "unknown key 'trajectorys'; did you mean /trajectories?"},
      {"misspelt label key", [](json& j) { j["labels"] = {{"fontpx", 12}}; },
       "sheet.json: /labels/fontpx: ", "unknown key 'fontpx'; did you mean /labels/font_px?"},
      {"lift too large", [](json& j) { j["brushes"][1]["lift_mm"] = 150; },
       "sheet.json: /brushes/1/lift_mm = 150: ", "must be within +-100 mm"},
      {"layout", [](json& j) { j["layout"] = "diagonal"; }, "sheet.json: /layout = \"diagonal\": ",
       "must be \"brushes-in-rows\" or \"brushes-in-columns\""},
      {"cell word", [](json& j) { j["cell_mm"] = "big"; }, "sheet.json: /cell_mm = \"big\": ",
       "must be \"auto\" or [width, height] in mm"},
      {"cell of one", [](json& j) { j["cell_mm"] = {40}; }, "sheet.json: /cell_mm = [40]: ",
       "must be \"auto\" or [width, height] in mm"},
      {"zero cell", [](json& j) { j["cell_mm"][1] = 0; }, "sheet.json: /cell_mm/1 = 0.0: ",
       "must be in (0, 1000] mm"},
      {"px_per_mm", [](json& j) { j["px_per_mm"] = 0; }, "sheet.json: /px_per_mm = 0: ",
       "must be in (0, 100]"},
      {"unknown pigment", [](json& j) { j["paint"]["paints"][0] = "ultramarin"; },
       "sheet.json: /paint/paints/0: ", "unknown pigment 'ultramarin'"},
      {"unknown paint key", [](json& j) { j["paint"]["colour"] = "#000000"; },
       "sheet.json: /paint/colour: ", "unknown key 'colour'"},
      {"background", [](json& j) { j["background"] = "white"; }, "sheet.json: /background: ",
       "colour 'white' does not parse"},
      {"paper tooth", [](json& j) { j["paper"]["tooth_depth_mm"] = 2; },
       "sheet.json: /paper/tooth_depth_mm = 2: ", "must be in [0, 1] mm"},
      {"mix", [](json& j) { j["mix"] = "cmyk"; }, "sheet.json: /mix = \"cmyk\": ",
       "must be \"km\""},
      {"rate", [](json& j) { j["sim"]["rate_hz"] = 0; }, "sheet.json: /sim/rate_hz = 0: ",
       "must be in [1, 10000]"},
      {"solver", [](json& j) { j["solver"] = "newton"; }, "sheet.json: /solver = \"newton\": ",
       "must be \"ipopt\" or \"slsqp\""},
      {"label too small", [](json& j) { j["labels"]["font_px"] = 5; },
       "sheet.json: /labels/font_px = 5: ", "must be in [8, 96] px"},
      {"unknown label key", [](json& j) { j["labels"]["colour"] = "#000000"; },
       "sheet.json: /labels/colour: ", "unknown key 'colour'"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    json j = goodSheet();
    c.edit(j);
    const Caught e = sheetError(j);
    REQUIRE(e.thrown);
    CHECK(e.code == 65);
    CHECK_THAT(e.message, StartsWith(c.where));
    CHECK_THAT(e.message, Contains(c.rule));
    CHECK(e.message.find('\n') == std::string::npos);
  }
}

TEST_CASE("malformed sheet JSON is 65 with line and column, and sheets are recognised", "[sheet]") {
  const Caught e = catchError([] { parseSheet("{\n\"format\": ,}", "s.json", ""); });
  REQUIRE(e.thrown);
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith("s.json: line 2"));

  CHECK(looksLikeSheet(goodSheet().dump()));
  CHECK_FALSE(looksLikeSheet(R"({"format": "bristle-scene/1"})"));
  CHECK_FALSE(looksLikeSheet(R"({"name": "round"})"));
  CHECK_FALSE(looksLikeSheet("{ not json"));
}

TEST_CASE("loadSheet reads every listed file, in order, into the inputs", "[sheet]") {
  const SheetDir d;
  const std::string path = d.write(SheetDir::sheet());
  const Sheet s = loadSheet(path);
  REQUIRE(s.brushes.size() == 2);
  CHECK(s.brushes[0].name == "round");
  CHECK(s.brushes[1].name == "flat");
  REQUIRE(s.trajectories.size() == 2);
  CHECK(s.brushLabel(0) == "round");  // the brush's name, now that it is read
  CHECK(s.trajectoryLabel(1) == "press-lift");
  const std::string b = (d.dir / "b").string(), t = (d.dir / "t").string();
  CHECK(s.inputs == std::vector<std::string>{path, b + "/round.json", b + "/flat.json",
                                             t + "/straight-pull.csv", t + "/press-lift.csv"});
  CHECK(sheetInputsHash(s) == fnv1a64Files(s.inputs));
}

TEST_CASE("the inputs hash changes when any listed file changes", "[sheet]") {
  const SheetDir d;
  const std::string path = d.write(SheetDir::sheet());
  const std::uint64_t before = sheetInputsHash(loadSheet(path));
  CHECK(sheetInputsHash(loadSheet(path)) == before);  // stable
  // One comment line more in a trajectory: same stroke, other bytes.
  std::ofstream(d.dir / "t/press-lift.csv", std::ios::app) << "# edited\n";
  const std::uint64_t after = sheetInputsHash(loadSheet(path));
  CHECK(after != before);
}

TEST_CASE("a missing listed file is 66 naming the sheet's pointer", "[sheet]") {
  const SheetDir d;
  json j = SheetDir::sheet();
  j["brushes"][1] = "b/gone.json";
  Caught e = catchError([&] { loadSheet(d.write(j)); });
  REQUIRE(e.thrown);
  CHECK(e.code == 66);
  CHECK_THAT(e.message, StartsWith((d.dir / "sheet.json").string() + ": /brushes/1: cannot read '" +
                                   (d.dir / "b/gone.json").string() + "'"));

  j = SheetDir::sheet();
  j["trajectories"][0] = "t";  // a folder
  e = catchError([&] { loadSheet(d.write(j)); });
  REQUIRE(e.thrown);
  CHECK(e.code == 66);
  CHECK_THAT(e.message, Contains(": /trajectories/0: cannot read '"));
  CHECK_THAT(e.message, Contains("is a directory"));

  e = catchError([&] { loadSheet((d.dir / "nothing.json").string()); });
  REQUIRE(e.thrown);
  CHECK(e.code == 66);
}

TEST_CASE("a brush held too low for a trajectory names both pointers", "[sheet]") {
  const SheetDir d;
  fs::copy_file(kSourceDir / "scenes/brushes/badger.json", d.dir / "b/badger.json");
  json j = SheetDir::sheet();
  j["brushes"][1] = "b/badger.json";  // 25 mm of hair on a 20 mm round's pull
  const Caught e = catchError([&] { loadSheet(d.write(j)); });
  REQUIRE(e.thrown);
  CHECK(e.code == 65);
  CHECK_THAT(e.message, StartsWith((d.dir / "sheet.json").string() +
                                   ": /brushes/1 with /trajectories/0: brush 'badger': "));
  CHECK_THAT(e.message, Contains("starts below the canvas"));

  // Held 6 mm higher, as the library sheet holds it, it is sound.
  j["brushes"][1] = {{"path", "b/badger.json"}, {"lift_mm", 6}};
  const Sheet s = loadSheet(d.write(j));
  const Trajectory lifted = s.cellTrajectory(1, 0), plain = s.cellTrajectory(0, 0);
  REQUIRE(lifted.samples.size() == plain.samples.size());
  // Exactly 6 mm higher (one addition of 6 to each z: a few ulps at most).
  constexpr double kLiftTol = 1e-12;
  for (size_t i = 0; i < plain.samples.size(); ++i) {
    CHECK(std::abs(lifted.samples[i].pose.position_mm.z() - plain.samples[i].pose.position_mm.z() -
                   6) < kLiftTol);
    CHECK(lifted.samples[i].pose.position_mm.x() == plain.samples[i].pose.position_mm.x());
  }
}

TEST_CASE("the shipped sheets are sound", "[sheet]") {
  for (const char* name : {"library", "small"}) {
    INFO(name);
    const Sheet s = loadSheet((kSourceDir / "scenes/sheets" / (std::string(name) + ".json")).string());
    CHECK(s.inputs.size() == 1 + s.brushes.size() + s.trajectories.size());
  }
  const Sheet lib = loadSheet((kSourceDir / "scenes/sheets/library.json").string());
  CHECK(lib.brushes.size() == 7);
  CHECK(lib.trajectories.size() == 4);
}

TEST_CASE("the annotated example of docs/sheet-format.md is a sound sheet", "[sheet]") {
  const std::string doc = readTextFile((kSourceDir / "docs/sheet-format.md").string());
  const size_t open = doc.find("```jsonc");
  REQUIRE(open != std::string::npos);
  const size_t start = doc.find('\n', open) + 1;
  const size_t end = doc.find("```", start);
  // Without its // comments (the page says so).
  std::string text;
  std::istringstream lines(doc.substr(start, end - start));
  for (std::string line; std::getline(lines, line);) text += line.substr(0, line.find("//")) + "\n";
  // Saved in scenes/sheets/, as the page says: then it loads with every file.
  const fs::path saved = kSourceDir / "scenes/sheets" / ("doc-example-" + std::to_string(::getpid()) + ".json");
  std::ofstream(saved) << text;
  const Caught e = catchError([&] {
    const Sheet s = loadSheet(saved.string());
    CHECK(s.name == "rounds and flats");
    CHECK(s.brush_lift_mm == std::vector<double>{0, 5});
    CHECK(s.trajectories.size() == 2);
    CHECK(s.label_px == 14);
  });
  fs::remove(saved);
  CHECK(e.message.empty());
  CHECK_FALSE(e.thrown);
}

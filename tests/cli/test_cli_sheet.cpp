// `bristle sheet SHEET.json -o sheet.png` and `bristle validate SHEET.json` end
// to end: a small sheet renders to the picture the renderer makes, with the
// inputs hash of engine/formats/sheet.h that changes when a listed file does; a cell is
// the very stroke `bristle render --brush --trajectory` paints; every bad input
// exits with its code and one line, and leaves no PNG (docs/sheet-format.md).

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/sheet.h"
#include "render/image/png_io.h"
#include "tests/support/mark_png.h"
#include "render/sheet_renderer.h"

using namespace bristle;
using bristle::testsupport::pngText;
using namespace bristle::testing;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
using nlohmann::json;

namespace {

namespace fs = std::filesystem;

// The small sheet's settings (scenes/sheets/small.json): quick to render.
json smallSheet(const std::string& brushes_dir, const std::string& trajectories_dir) {
  return {{"format", "bristle-sheet/1"},
          {"name", "test"},
          {"title", "test sheet"},
          {"brushes", {brushes_dir + "/round.json", brushes_dir + "/flat.json"}},
          {"trajectories",
           {trajectories_dir + "/straight-pull.csv", trajectories_dir + "/press-lift.csv"}},
          {"px_per_mm", 4},
          {"solver", "ipopt"},
          {"sim", {{"rate_hz", 60}, {"max_step_mm", 0.5}}}};
}

json librarySmallSheet() {
  return smallSheet(sourcePath("scenes/brushes"), sourcePath("scenes/trajectories"));
}

std::string writeJson(const TempDir& dir, const std::string& name, const json& j) {
  return dir.write(name, j.dump(1));
}


}  // namespace

TEST_CASE("a sheet renders: the renderer's picture, its name and inputs hash", "[cli][sheet]") {
  TempDir dir;
  const std::string sheet = writeJson(dir, "s.json", librarySmallSheet());
  const std::string png = dir.file("s.png");
  const RunResult r = runBristle("sheet '" + sheet + "' -o '" + png + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out == png + "\n");
  CHECK_THAT(r.err, Contains("4 cells (2 x 2)"));

  // The PNG is exactly what render/sheet_renderer.h makes of the sheet.
  const Sheet loaded = loadSheet(sheet);
  const render::SheetImage expected = render::renderSheet(loaded);
  const render::Image8 img = render::readPngRgba8(png);
  REQUIRE(img.width == expected.layout.width_px);
  REQUIRE(img.height == expected.layout.height_px);
  bool same = true;
  for (size_t i = 0; i < size_t(img.width) * img.height && same; ++i)
    same = img.pixels[4 * i] == expected.image.pixels[3 * i] &&
           img.pixels[4 * i + 1] == expected.image.pixels[3 * i + 1] &&
           img.pixels[4 * i + 2] == expected.image.pixels[3 * i + 2];
  CHECK(same);

  CHECK(pngText(png, "bristle:sheet") == "test");
  CHECK(pngText(png, "bristle:inputs-fnv1a64") == hex64(sheetInputsHash(loaded)));
  // The sheet, then the brushes and trajectories in the order listed.
  CHECK(sheetInputsHash(loaded) ==
        fnv1a64Files({sheet, sourcePath("scenes/brushes/round.json"),
                      sourcePath("scenes/brushes/flat.json"),
                      sourcePath("scenes/trajectories/straight-pull.csv"),
                      sourcePath("scenes/trajectories/press-lift.csv")}));
  char grid[128];
  std::snprintf(grid, sizeof grid, "2 x 2 (brushes x trajectories), cells %.4g x %.4g mm at 4 px/mm",
                expected.cell_width_mm, expected.cell_height_mm);
  CHECK(pngText(png, "bristle:sheet-grid") == grid);
}

TEST_CASE("the PNG's inputs hash changes when a listed trajectory changes", "[cli][sheet]") {
  TempDir dir;
  fs::create_directories(dir.path() / "b");
  fs::create_directories(dir.path() / "t");
  for (const char* b : {"round", "flat"})
    fs::copy_file(sourcePath("scenes/brushes/") + b + ".json", dir.path() / "b" / (std::string(b) + ".json"));
  for (const char* t : {"straight-pull", "press-lift"})
    fs::copy_file(sourcePath("scenes/trajectories/") + t + ".csv",
                  dir.path() / "t" / (std::string(t) + ".csv"));
  // Relative paths: resolved against the sheet's folder.
  const std::string sheet = writeJson(dir, "s.json", smallSheet("b", "t"));
  REQUIRE(runBristle("sheet -q '" + sheet + "' -o '" + dir.file("a.png") + "'").code == 0);
  const std::string before = pngText(dir.file("a.png"), "bristle:inputs-fnv1a64");
  CHECK(before.size() == 16);

  std::ofstream(dir.path() / "t/press-lift.csv", std::ios::app) << "# a comment more\n";
  REQUIRE(runBristle("sheet -q '" + sheet + "' -o '" + dir.file("b.png") + "'").code == 0);
  const std::string after = pngText(dir.file("b.png"), "bristle:inputs-fnv1a64");
  CHECK(after != before);
  CHECK(after == hex64(sheetInputsHash(loadSheet(sheet))));
}

TEST_CASE("a sheet cell is the stroke `bristle render` paints, pixel for pixel", "[cli][sheet]") {
  TempDir dir;
  json j = librarySmallSheet();
  j["brushes"] = {sourcePath("scenes/brushes/round.json")};
  j["trajectories"] = {sourcePath("scenes/trajectories/press-lift.csv")};
  const Sheet sheet = loadSheet(writeJson(dir, "one.json", j));
  const render::SheetImage s = render::renderSheet(sheet);
  REQUIRE(s.cells.size() == 1);
  const render::SheetCell& cell = s.cells[0];
  const render::PixelRect& at = s.layout.cells[0];

  // The same pair, paint, paper and settings through the single-stroke command.
  const RunResult r = runBristle(
      "render -q --brush '" + sourcePath("scenes/brushes/round.json") + "' --trajectory '" +
      sourcePath("scenes/trajectories/press-lift.csv") + "' --solver ipopt --px-per-mm 4 " +
      "--max-step-mm 0.5 --min-rate-hz 60 -o '" + dir.file("r.png") + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  const render::Image8 single = render::readPngRgba8(dir.file("r.png"));
  // The window the cell shows lies on that canvas (the stroke is small).
  REQUIRE(cell.window.x >= 0);
  REQUIRE(cell.window.y >= 0);
  REQUIRE(cell.window.x + cell.window.width <= single.width);
  REQUIRE(cell.window.y + cell.window.height <= single.height);
  long differing = 0;
  for (int y = 0; y < at.height; ++y)
    for (int x = 0; x < at.width; ++x) {
      const std::uint8_t* a = &s.image.pixels[(size_t(at.y + y) * s.image.width + at.x + x) * 3];
      const std::uint8_t* b =
          &single.pixels[(size_t(cell.window.y + y) * single.width + cell.window.x + x) * 4];
      differing += a[0] != b[0] || a[1] != b[1] || a[2] != b[2];
    }
  CHECK(differing == 0);
  CHECK(cell.ink.width > 0);
}

TEST_CASE("bad sheets exit with their code and one line, and leave no PNG", "[cli][sheet]") {
  TempDir dir;
  struct Case {
    const char* what;
    std::function<void(json&)> edit;
    int code;
    std::string message;  // after "bristle: <sheet>: "
  };
  const std::vector<Case> cases = {
      {"missing brush", [](json& j) { j["brushes"][1] = "gone.json"; }, 66,
       "/brushes/1: cannot read '"},
      {"missing trajectory", [](json& j) { j["trajectories"][0] = "gone.csv"; }, 66,
       "/trajectories/0: cannot read '"},
      {"unknown key", [](json& j) { j["rows"] = 2; }, 65, "/rows: unknown key 'rows'"},
      {"empty brushes", [](json& j) { j["brushes"] = json::array(); }, 65,
       "/brushes = []: must be a list of 1..64 brush file paths"},
      {"empty trajectories", [](json& j) { j["trajectories"] = json::array(); }, 65,
       "/trajectories = []: must be a list of 1..64 trajectory file paths"},
      {"unknown pigment", [](json& j) { j["paint"] = {{"paints", {"cadmium-rde"}}}; }, 65,
       "/paint/paints/0: unknown pigment 'cadmium-rde'"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    json j = librarySmallSheet();
    c.edit(j);
    const std::string sheet = writeJson(dir, "bad.json", j);
    const std::string png = dir.file("bad.png");
    const RunResult r = runBristle("sheet -q '" + sheet + "' -o '" + png + "'");
    CHECK(r.code == c.code);
    CHECK_THAT(r.err, StartsWith("bristle: " + sheet + ": " + c.message));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(fs::exists(png));
  }

  // Malformed JSON: 65 with line and column.
  const std::string broken = dir.write("broken.json", "{\n  \"format\": \"bristle-sheet/1\",,\n}");
  RunResult r = runBristle("sheet -q '" + broken + "' -o '" + dir.file("x.png") + "'");
  CHECK(r.code == 65);
  CHECK_THAT(r.err, StartsWith("bristle: " + broken + ": line 2"));

  // A missing sheet: 66.
  r = runBristle("sheet -q '" + dir.file("none.json") + "' -o '" + dir.file("x.png") + "'");
  CHECK(r.code == 66);
  CHECK_THAT(r.err, StartsWith("bristle: " + dir.file("none.json")));

  // An output that cannot be created: 73, before anything is rendered.
  const std::string good = writeJson(dir, "good.json", librarySmallSheet());
  const std::string nowhere = dir.file("no/such/dir/s.png");
  r = runBristle("sheet -q '" + good + "' -o '" + nowhere + "'");
  CHECK(r.code == 73);
  CHECK_THAT(r.err, StartsWith("bristle: "));
  CHECK_THAT(r.err, Contains(nowhere));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(nowhere));

  // Usage: the output is required, the overrides are checked.
  r = runBristle("sheet '" + good + "'");
  CHECK(r.code == 64);
  r = runBristle("sheet '" + good + "' -o '" + dir.file("x.png") + "' --px-per-mm 0");
  CHECK(r.code == 64);
  CHECK_THAT(r.err, Contains("--px-per-mm"));
  r = runBristle("sheet '" + good + "' -o '" + dir.file("x.png") + "' --solver newton");
  CHECK(r.code == 64);
  r = runBristle("sheet '" + good + "' -o '" + dir.file("x.png") + "' --solver-max-iterations 0");
  CHECK(r.code == 64);
  CHECK_THAT(r.err, Contains("--solver-max-iterations"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(dir.file("x.png")));
}

TEST_CASE("sheet --solver-max-iterations limits every solve, as render's does", "[cli][sheet]") {
  TempDir dir;
  json j = librarySmallSheet();
  j["brushes"] = {sourcePath("scenes/brushes/round.json")};
  // The pull's press and first 2.5 mm: trajectoryHead.
  j["trajectories"] = {dir.write(
      "pull.csv", trajectoryHead(sourcePath("scenes/trajectories/straight-pull.csv"), 0.6))};
  const std::string sheet = writeJson(dir, "s.json", j);
  // The summary line's "N solver iterations".
  auto iterations = [](const std::string& err) {
    const size_t end = err.find(" solver iterations");
    REQUIRE(end != std::string::npos);
    const size_t start = err.rfind(' ', end - 1) + 1;
    return std::stol(err.substr(start, end - start));
  };
  const RunResult full = runBristle("sheet '" + sheet + "' -o '" + dir.file("a.png") + "'");
  INFO(full.err);
  REQUIRE(full.code == 0);
  CHECK_THAT(full.err, !Contains("failed solve"));
  // One SLSQP evaluation, one Ipopt iteration: no solve can converge, and the
  // spines are carried along frozen (a warning, not an error).
  const RunResult starved = runBristle("sheet '" + sheet + "' -o '" + dir.file("b.png") +
                                       "' --solver-max-iterations 1");
  INFO(starved.err);
  REQUIRE(starved.code == 0);
  CHECK_THAT(starved.err, Contains("failed solve"));
  CHECK(iterations(starved.err) != iterations(full.err));
  CHECK(render::readPngRgba8(dir.file("b.png")).pixels !=
        render::readPngRgba8(dir.file("a.png")).pixels);
}

TEST_CASE("validate reports a sheet's summary and its problems", "[cli][sheet]") {
  TempDir dir;
  const std::string good = writeJson(dir, "good.json", librarySmallSheet());
  RunResult r = runBristle("validate '" + good + "'");
  CHECK(r.code == 0);
  CHECK(r.out == good + ": ok (sheet 'test', 2 brushes x 2 trajectories)\n");

  json bad = librarySmallSheet();
  bad["brushes"][0] = "gone.json";
  const std::string bad_path = writeJson(dir, "bad.json", bad);
  r = runBristle("validate '" + bad_path + "' '" + good + "'");
  CHECK(r.code == 66);
  CHECK_THAT(r.err, StartsWith("bristle: " + bad_path + ": /brushes/0: cannot read '"));
  CHECK_THAT(r.out, Contains(good + ": ok"));  // the other file is still checked

  // The shipped sheets are sound.
  r = runBristle("validate '" + sourcePath("scenes/sheets/library.json") + "' '" +
                 sourcePath("scenes/sheets/small.json") + "'");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("library.json: ok (sheet 'library', 7 brushes x 4 trajectories)"));
  CHECK(r.err.empty());
}

TEST_CASE("sheet --help explains with a real example", "[cli][sheet]") {
  const RunResult r = runBristle("sheet --help");
  CHECK(r.code == 0);
  CHECK_THAT(r.out, Contains("bristle sheet scenes/sheets/library.json -o"));
  CHECK_THAT(r.out, Contains("--px-per-mm"));
  CHECK_THAT(r.out, Contains("docs/sheet-format.md"));
  const RunResult h = runBristle("help sheet");
  CHECK(h.code == 0);
  CHECK_THAT(h.out, Contains("bristle sheet scenes/sheets/library.json -o"));
}

TEST_CASE("a clipped cell and a brush that never paints are warnings naming the cell",
          "[cli][sheet]") {
  TempDir dir;
  json j = librarySmallSheet();
  // 30 x 20 mm: the 55 mm pulls do not fit; the flat held 30 mm higher never
  // reaches the paper.
  j["cell_mm"] = {30, 20};
  j["brushes"][1] = {{"path", sourcePath("scenes/brushes/flat.json")}, {"lift_mm", 30}};
  const std::string sheet = writeJson(dir, "s.json", j);
  const std::string png = dir.file("s.png");
  const RunResult r = runBristle("sheet -q '" + sheet + "' -o '" + png + "'");
  INFO(r.err);
  CHECK(r.code == 0);  // warnings, not errors: the sheet shows what happened
  CHECK(fs::exists(png));
  CHECK_THAT(r.err, Contains("bristle: warning: " + sheet +
                             ": brush 'round' on trajectory 'straight-pull': the stroke ("));
  CHECK_THAT(r.err, Contains("is larger than the cell; its middle is shown (/cell_mm)"));
  CHECK_THAT(r.err, Contains("bristle: warning: " + sheet +
                             ": brush 'flat +30 mm' on trajectory 'press-lift': the brush left "
                             "no visible paint"));
  // The round's press-lift fits: no warning names it.
  CHECK(r.err.find("brush 'round' on trajectory 'press-lift'") == std::string::npos);
}

TEST_CASE("a fixed cell size past the picture limits is 65 naming /cell_mm, and no PNG",
          "[cli][sheet]") {
  TempDir dir;
  json j = librarySmallSheet();
  j["cell_mm"] = {1000, 100};  // two columns of 4000 px at 4 px/mm: 8003 px, fine ...
  j["px_per_mm"] = 10;         // ... at 10 px/mm two columns are 20003 px wide
  const std::string sheet = writeJson(dir, "big.json", j);
  const std::string png = dir.file("big.png");
  const RunResult r = runBristle("sheet -q '" + sheet + "' -o '" + png + "'");
  CHECK(r.code == 65);
  CHECK_THAT(r.err, StartsWith("bristle: " + sheet + ": /cell_mm: the sheet would be 20003 x "));
  CHECK_THAT(r.err, Contains("above the limit of 16384 px a side"));
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(png));
}

// The command line as a Unix tool's user expects it: brushes by
// library name, `bristle pigments`, "-" for standard input and output, and
// `replay` taking its brush from the session's header.

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_runner.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/first_contact.h"
#include "engine/paint/pigments.h"
#include "render/image/png_io.h"

using namespace bristle;
using namespace bristle::testing;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;
namespace fs = std::filesystem;

namespace {

const std::string kBin = BRISTLE_BIN;

// Runs a shell command line (pipes and redirections allowed, stdin /dev/null
// unless it redirects it) in `dir`, capturing stdout and stderr.
RunResult runShell(const TempDir& dir, const std::string& command) {
  std::ofstream(dir.file(".command.sh")) << "cd '" << dir.path().string() << "' || exit 99\n{\n"
                                         << command << "\n} </dev/null\n";
  return runCaptured("env -u GALLIUM_DRIVER sh '" + dir.file(".command.sh") + "'",
                     dir.file(".stdout"), dir.file(".stderr"));
}

// The first 60 lines of the straight pull: a short stroke (about a second to render).
std::string shortTrajectory(const TempDir& dir) {
  std::ifstream in(sourcePath("scenes/trajectories/straight-pull.csv"));
  std::ofstream out(dir.file("short.csv"));
  std::string line;
  for (int i = 0; i < 60 && std::getline(in, line); ++i) out << line << "\n";
  return dir.file("short.csv");
}

std::string bytesOf(const std::string& path) { return readAll(path); }

}  // namespace

TEST_CASE("a brush by library name is the library's file", "[cli][names]") {
  TempDir d;
  shortTrajectory(d);
  const std::string b = "'" + kBin + "'";
  const RunResult by_name = runShell(d, b + " render -q --brush round --trajectory short.csv -o n.png");
  REQUIRE(by_name.code == 0);
  const RunResult by_path =
      runShell(d, b + " render -q --brush '" + kRound + "' --trajectory short.csv -o p.png");
  REQUIRE(by_path.code == 0);
  // The same pixels and the same provenance (the inputs' hash): byte for byte.
  CHECK(bytesOf(d.file("n.png")) == bytesOf(d.file("p.png")));

  const RunResult v = runShell(d, b + " validate round");
  CHECK(v.code == 0);
  CHECK(v.out == kRound + ": ok (brush 'round', 7 spines, surface)\n");

  // A path is used as given, never looked up: round.json here does not exist.
  const RunResult rel = runShell(d, b + " validate round.json");
  CHECK(rel.code == 66);
  CHECK(rel.err == "bristle: round.json: cannot read: No such file or directory\n");
}

TEST_CASE("brush names: BRISTLE_BRUSH_PATH and the install's share folder", "[cli][names]") {
  TempDir d;
  fs::create_directories(d.path() / "mine");
  fs::copy_file(kRound, d.path() / "mine/house.json");
  const std::string b = "'" + kBin + "'";
  // Empty entries and missing folders are skipped; the first hit wins.
  const RunResult env = runShell(d, "BRISTLE_BRUSH_PATH=:nowhere:mine " + b + " validate house");
  CHECK(env.code == 0);
  CHECK(env.out == "mine/house.json: ok (brush 'round', 7 spines, surface)\n");
  const RunResult unset = runShell(d, "env -u BRISTLE_BRUSH_PATH " + b + " validate house");
  CHECK(unset.code == 66);
  CHECK_THAT(unset.err, Contains("no brush named 'house'") &&
                            Contains("BRISTLE_BRUSH_PATH is not set"));

  // A copy of the executable in PREFIX/bin finds PREFIX/share/bristle/brushes.
  fs::create_directories(d.path() / "prefix/bin");
  fs::create_directories(d.path() / "prefix/share/bristle/brushes");
  fs::copy_file(kBin, d.path() / "prefix/bin/bristle");
  fs::copy_file(kRound, d.path() / "prefix/share/bristle/brushes/shared.json");
  const RunResult share = runShell(d, "env -u BRISTLE_BRUSH_PATH prefix/bin/bristle validate shared");
  CHECK(runShell(d, "prefix/bin/bristle validate nope").err.find(sourcePath("scenes")) ==
        std::string::npos);
  CHECK(share.code == 0);
  CHECK(share.out == (d.path() / "prefix/share/bristle/brushes/shared.json").string() +
                         ": ok (brush 'round', 7 spines, surface)\n");
  // The build's own executable looks in the source tree first; a copy elsewhere
  // (an install) never does: its `round` is its share folder's.
  fs::copy_file(kRound, d.path() / "prefix/share/bristle/brushes/round.json");
  const RunResult copy = runShell(d, "prefix/bin/bristle validate round");
  CHECK(copy.out == (d.path() / "prefix/share/bristle/brushes/round.json").string() +
                        ": ok (brush 'round', 7 spines, surface)\n");
  const RunResult build = runShell(d, b + " validate round");
  CHECK(build.out == kRound + ": ok (brush 'round', 7 spines, surface)\n");
}

TEST_CASE("brush names: `brushes` lists exactly the names lookup finds, from one variable",
          "[cli][names]") {
  TempDir d;
  fs::create_directories(d.path() / "mine");
  fs::copy_file(kRound, d.path() / "mine/house.json");
  // A library name found again in BRISTLE_BRUSH_PATH is shadowed, as in lookup.
  fs::copy_file(kRound, d.path() / "mine/flat.json");
  const std::string b = "'" + kBin + "'";
  const RunResult list = runShell(d, "BRISTLE_BRUSH_PATH=mine " + b + " brushes");
  REQUIRE(list.code == 0);
  std::vector<std::string> names;
  std::istringstream lines(list.out);
  for (std::string line; std::getline(lines, line);) names.push_back(line.substr(0, line.find(' ')));
  // The eight library brushes and the house brush, each once, by the name that
  // finds it (the file's, whatever the brush calls itself), in the order of
  // the file names ("calligraphy-wang2020.json" sorts before "calligraphy.json").
  CHECK(names == std::vector<std::string>{"badger", "bright", "calligraphy-wang2020", "calligraphy",
                                          "fan", "filbert", "flat", "round", "house"});
  // Every name listed resolves, from the folder listed first (the library's flat).
  const RunResult flat = runShell(d, "BRISTLE_BRUSH_PATH=mine " + b + " validate flat");
  CHECK(flat.out == sourcePath("scenes/brushes/flat.json") + ": ok (brush 'flat', 5 spines, surface, 120 strips)\n");
  CHECK(runShell(d, "BRISTLE_BRUSH_PATH=mine " + b + " validate house").code == 0);
  // --library lists that folder alone.
  const RunResult one = runShell(d, b + " brushes --library mine");
  CHECK(std::count(one.out.begin(), one.out.end(), '\n') == 2);

  // The old variable is not read, and says so in one line.
  const RunResult old = runShell(d, "BRISTLE_BRUSHES=mine " + b + " validate house");
  CHECK(old.code == 66);
  CHECK_THAT(old.err, StartsWith("bristle: warning: BRISTLE_BRUSHES is no longer read; put the "
                                 "folder in BRISTLE_BRUSH_PATH (colon-separated), which `bristle "
                                 "brushes` and every brush name use\n"));
}

TEST_CASE("pigments: the table, with swatches only on a terminal", "[cli][pigments]") {
  TempDir d;
  const std::string b = "'" + kBin + "'";
  const RunResult plain = runShell(d, b + " pigments");
  REQUIRE(plain.code == 0);
  CHECK(plain.out.find('\x1b') == std::string::npos);  // a pipe: no escapes
  size_t lines = 0;
  for (char c : plain.out) lines += c == '\n';
  CHECK(lines == pigmentTable().size());
  for (const Pigment& p : pigmentTable()) CHECK_THAT(plain.out, Contains("\n" + p.name + " ") || StartsWith(p.name + " "));
  // Titanium white shows light, ivory black dark.
  auto colour = [&](const std::string& name) {
    const size_t at = plain.out.find(name + " ");
    REQUIRE(at != std::string::npos);
    const size_t hash = plain.out.find('#', at);
    return std::stoi(plain.out.substr(hash + 1, 2), nullptr, 16);
  };
  CHECK(colour("titanium-white") > 0xd0);
  CHECK(colour("ivory-black") < 0x40);

  const RunResult always = runShell(d, b + " pigments --swatches always");
  CHECK_THAT(always.out, StartsWith("\x1b[48;2;"));
  size_t swatches = 0;
  for (size_t at = 0; (at = always.out.find("\x1b[48;2;", at)) != std::string::npos; ++at)
    ++swatches;
  CHECK(swatches == pigmentTable().size());
  // On a terminal (script(1) gives the command one) the default shows swatches.
  const RunResult tty = runShell(d, "script -qec \"" + kBin + " pigments\" /dev/null");
  CHECK_THAT(tty.out, Contains("\x1b[48;2;"));
  CHECK(runShell(d, "script -qec \"" + kBin + " pigments --swatches never\" /dev/null")
            .out.find("\x1b[48;2;") == std::string::npos);
}

TEST_CASE("'-': a trajectory from stdin, the PNG to stdout", "[cli][stdio]") {
  TempDir d;
  shortTrajectory(d);
  const std::string b = "'" + kBin + "'";
  REQUIRE(runShell(d, b + " render -q --brush round --trajectory short.csv -o file.png").code == 0);
  // Progress and the summary stay on stderr: stdout is the PNG alone.
  const RunResult piped =
      runShell(d, "cat short.csv | " + b + " render --brush round --trajectory - -o - > piped.png");
  REQUIRE(piped.code == 0);
  CHECK(piped.out.empty());
  CHECK_THAT(piped.err, Contains(" planned steps; ") && Contains(" simulation steps ("));
  CHECK(bytesOf(d.file("piped.png")) == bytesOf(d.file("file.png")));
  CHECK_FALSE(fs::exists(d.path() / "-"));
  // ... and straight into compare, which reads "-" from stdin.
  const RunResult cmp = runShell(d, b + " render -q --brush round --trajectory - -o - < short.csv | " +
                                        b + " compare file.png -");
  CHECK(cmp.code == 0);
  CHECK_THAT(cmp.out, Contains("file.png and -: identical pixels"));
  const RunResult cmp_bad = runShell(d, "echo not a png | " + b + " compare file.png -");
  CHECK(cmp_bad.code == 65);
  CHECK(cmp_bad.err == "bristle: stdin: not a PNG file\n");

  // A bad trajectory on stdin: the error names stdin, and stdout stays empty.
  std::ofstream(d.file("bad.csv")) << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                                      "0,nan,0,20,1,0,0,0\n1,0,0,20,1,0,0,0\n";
  const RunResult bad = runShell(d, b + " render --brush round --trajectory - -o - < bad.csv > out.png");
  CHECK(bad.code == 65);
  CHECK(bad.err == "bristle: stdin: line 3, column 2 (x_mm): 'nan': must be finite\n");
  CHECK(bytesOf(d.file("out.png")).empty());

  // preview and sheet write to stdout too.
  const RunResult pv = runShell(d, b + " preview round -o - > pv.png");
  CHECK(pv.code == 0);
  CHECK(render::readPngRgba8(d.file("pv.png")).width == 800);
  CHECK_FALSE(fs::exists(d.path() / "-"));
}

TEST_CASE("replay takes the brush from the session's header", "[cli][replay]") {
  TempDir d;
  shortTrajectory(d);
  fs::copy_file(kRound, d.path() / "mine.json");
  const std::string b = "'" + kBin + "'";
  // Recorded by name and by path, each replayed without --brush: the live --png's pixels.
  for (const std::string& brush : {std::string("round"), std::string("mine.json")}) {
    INFO(brush);
    const RunResult rec = runShell(d, b + " record -q --device none --brush " + brush +
                                          " --trajectory short.csv -o s.csv --png live.png");
    REQUIRE(rec.code == 0);
    const std::string header = readAll(d.file("s.csv"));
    CHECK_THAT(header, Contains("# brush: " + (brush == "round"
                                                   ? brush
                                                   : (d.path() / "mine.json").string()) + "\n"));
    fs::create_directories(d.path() / "elsewhere");
    const RunResult rep = runShell(d, "cd elsewhere && " + b + " replay ../s.csv -o r.png");
    REQUIRE(rep.code == 0);
    CHECK(rep.err.empty());
    CHECK(runShell(d, b + " compare live.png elsewhere/r.png").code == 0);
  }
  // The recorded file changed: refused; --brush overrides it with a warning.
  std::ofstream(d.file("mine.json"), std::ios::app) << "\n";
  const RunResult changed = runShell(d, b + " replay s.csv -o r2.png");
  CHECK(changed.code == 65);
  CHECK_THAT(changed.err, Contains("it changed since the recording; give --brush"));
  CHECK_FALSE(fs::exists(d.path() / "r2.png"));
  const RunResult over = runShell(d, b + " replay s.csv --brush mine.json -o r2.png");
  CHECK(over.code == 0);
  CHECK_THAT(over.err, Contains("warning:") && Contains("differs from the brush given"));
  CHECK(runShell(d, b + " compare live.png r2.png").code == 0);
}

TEST_CASE("record without a device names --device none --trajectory", "[cli][record]") {
  TempDir d;
  const RunResult r = runShell(d, "BRISTLE_HD_LIBRARY=/nonexistent/libHD.so '" + kBin +
                                      "' record --brush round -o s.csv");
  CHECK(r.code == 69);
  CHECK_THAT(r.err, Contains("--device none --trajectory T.csv"));
  CHECK_FALSE(fs::exists(d.path() / "s.csv"));
}

TEST_CASE("render --stats: the figures and the warnings as JSON", "[cli][stats]") {
  TempDir d;
  shortTrajectory(d);
  d.write("air.csv", "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                     "0,10,10,60,1,0,0,0\n1,40,10,60,1,0,0,0\n");
  const std::string b = "'" + kBin + "'";
  REQUIRE(runShell(d, b + " render -q --brush round --trajectory short.csv -o s.png --stats s.json")
              .code == 0);
  const std::string painted = readAll(d.file("s.json"));
  CHECK_THAT(painted, Contains("\"warnings\":[]"));
  CHECK_THAT(painted, Contains("\"failed_steps\":0"));
  CHECK(painted.find("\"painted_pixels\":0,") == std::string::npos);
  // The solver's work, as the summary line on stderr gives it.
  const RunResult loud =
      runShell(d, b + " render --brush round --trajectory short.csv -o s.png --stats s.json");
  REQUIRE(loud.code == 0);
  const nlohmann::json figures = nlohmann::json::parse(readAll(d.file("s.json")));
  const long iterations = figures.at("solver_iterations").get<long>();
  CHECK(iterations > 0);
  CHECK_THAT(loud.err, Contains(", " + std::to_string(iterations) + " solver iterations"));
  const std::string solved = std::string(1, '(')
                                 .append(std::to_string(figures.at("solved_steps").get<long>()))
                                 .append(" solved, ")
                                 .append(std::to_string(figures.at("settled_steps").get<long>()))
                                 .append(" at rest, ")
                                 .append(std::to_string(figures.at("stiction_resolves").get<long>()))
                                 .append(" stiction re-solves");
  CHECK_THAT(loud.err, Contains(solved));
  // The plan's step count leads the summary, as progress counted it; the steps
  // simulated are as many or more (a step redone in halves counts its pieces).
  const long planned = figures.at("planned_steps").get<long>();
  CHECK(planned > 0);
  CHECK(figures.at("steps").get<long>() >= planned);
  CHECK_THAT(loud.err, Contains("bristle: " + std::to_string(planned) + " planned steps; " +
                                std::to_string(figures.at("steps").get<long>()) +
                                " simulation steps ("));
  // A blot held still: the steps at rest are counted apart, and solve nothing.
  REQUIRE(runShell(d, b + " render -q --brush round --trajectory '" +
                          sourcePath("scenes/trajectories/depth/press-hold-lift.csv") +
                          "' -o h.png --stats h.json")
              .code == 0);
  const nlohmann::json held = nlohmann::json::parse(readAll(d.file("h.json")));
  // Observed: 264 of the 1.5 s hold's steps at rest.
  CHECK(held.at("settled_steps").get<long>() > 100);
  CHECK(held.at("solved_steps").get<long>() + held.at("settled_steps").get<long>() <=
        held.at("steps").get<long>());
  const RunResult air =
      runShell(d, b + " render -q --brush round --trajectory air.csv -o a.png --stats a.json");
  CHECK(air.code == 0);
  const std::string blank = readAll(d.file("a.json"));
  CHECK_THAT(blank, Contains("\"painted_pixels\":0,") && Contains("\"paint_laid_mm3\":0.0"));
  CHECK_THAT(blank, Contains("\"warnings\":[\"the brush never touched the canvas (air.csv): "
                             "the image is blank\"]"));
  CHECK(air.err == "bristle: warning: the brush never touched the canvas (air.csv): the image is "
                   "blank\n");
}

TEST_CASE("help per command: its own description and examples", "[cli][help]") {
  for (const std::string cmd : {"render", "validate", "brushes", "pigments", "preview", "record",
                                "replay", "sheet", "batch", "compare"}) {
    INFO(cmd);
    const RunResult h = runBristle("help " + cmd), dash = runBristle(cmd + " --help");
    CHECK(h.code == 0);
    CHECK(dash.code == 0);
    CHECK(h.out == dash.out);
    // Its examples are its own: each example line runs this command.
    const size_t at = h.out.find("Examples:\n");
    REQUIRE(at != std::string::npos);
    std::istringstream lines(h.out.substr(at + 10));
    int own = 0;
    for (std::string line; std::getline(lines, line) && line.rfind("  ", 0) == 0;) {
      if (line.rfind("  bristle ", 0) != 0) continue;
      CHECK_THAT(line + " ", StartsWith("  bristle " + cmd + " "));
      ++own;
    }
    CHECK(own >= 1);
  }
  const RunResult v = runBristle("help validate");
  CHECK_THAT(v.out, StartsWith("Check brush and scene"));
  CHECK_THAT(v.out, Contains("bristle validate round\n"));
  CHECK(v.out.find("bristle render") == std::string::npos);
}

TEST_CASE("validate BRUSH TRAJ refuses the pair render refuses, with the same message",
          "[cli][validate]") {
  TempDir d;
  // Held with the ferrule 5 mm up: the 20 mm hairs start in the paper.
  d.write("low.csv", "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                     "0,15,40,5,1,0,0,0\n1,30,40,25,1,0,0,0\n");
  d.write("high.csv", "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                      "0,15,40,80,1,0,0,0\n1,30,40,80,1,0,0,0\n");
  const std::string b = "'" + kBin + "'";
  const RunResult render = runShell(d, b + " render -q --brush round --trajectory low.csv -o o.png");
  const RunResult validate = runShell(d, b + " validate round low.csv");
  CHECK(render.code == 65);
  CHECK(validate.code == 65);
  CHECK_THAT(render.err, StartsWith("bristle: low.csv: line 3: the brush starts below the canvas"));
  // It names the joint to raise the start past, the lowest: upright at 5 mm,
  // the tip of an outer spine of the round, 19.8 mm of hair below the ferrule
  // (its centre spine ends 1 mm inside the point), not the first joint found
  // under the paper (joint 1 at -1 mm).
  CHECK_THAT(render.err, Contains("(spine 1 joint 4 at z = -14.79 mm at rest, its lowest)"));
  CHECK(validate.err == render.err);
  // Each file alone is fine; only the pair is refused.
  CHECK(runShell(d, b + " validate round").code == 0);
  CHECK(runShell(d, b + " validate low.csv").code == 0);

  // Never within reach: render's image would be blank, and validate says so.
  const RunResult high = runShell(d, b + " validate round high.csv");
  CHECK(high.code == 0);
  CHECK(high.err == "bristle: warning: high.csv: the brush 'round' never comes within reach of "
                    "the paper: render's image would be blank\n");
  CHECK_THAT(high.out, Contains("round with high.csv: ok (starts above the paper, never reaches it)"));
  const RunResult good = runShell(d, b + " validate round '" +
                                         sourcePath("scenes/trajectories/s-curve.csv") + "'");
  CHECK(good.code == 0);
  CHECK(good.err.empty());
  CHECK_THAT(good.out, Contains("comes within reach of it"));
}

TEST_CASE("brush names in scenes, sheets and batch manifests", "[cli][names]") {
  TempDir d;
  shortTrajectory(d);
  d.write("s.json", R"({"format": "bristle-scene/1", "name": "named",
    "canvas": {"size_mm": [120, 90], "px_per_mm": 2},
    "strokes": [{"brush": "round", "trajectory": "short.csv", "paint": {"paints": ["sumi-ink"]}}]})");
  d.write("p.json", R"({"format": "bristle-scene/1", "name": "named",
    "canvas": {"size_mm": [120, 90], "px_per_mm": 2},
    "strokes": [{"brush": ")" + kRound + R"(", "trajectory": "short.csv",
                 "paint": {"paints": ["sumi-ink"]}}]})");
  d.write("sh.json", R"({"format": "bristle-sheet/1", "name": "named", "px_per_mm": 2,
    "brushes": ["round", {"path": "flat", "lift_mm": 1}], "trajectories": ["short.csv"]})");
  d.write("m.json", R"({"format": "bristle-batch/1",
    "jobs": [{"id": "one", "brush": "round", "trajectory": "short.csv"}]})");
  const std::string b = "'" + kBin + "'";
  const RunResult v = runShell(d, b + " validate s.json sh.json");
  CHECK(v.code == 0);
  CHECK_THAT(v.out, Contains("s.json: ok (scene 'named', 1 stroke, 1 brush") &&
                        Contains("sh.json: ok (sheet 'named', 2 brushes x 1 trajectory)"));
  // The name is the library's file: the same painting, pixel for pixel.
  REQUIRE(runShell(d, b + " render -q s.json -o s.png").code == 0);
  REQUIRE(runShell(d, b + " render -q p.json -o p.png").code == 0);
  CHECK(runShell(d, b + " compare s.png p.png").code == 0);
  const RunResult batch = runShell(d, b + " batch m.json --out out --json");
  CHECK(batch.code == 0);
  CHECK_THAT(batch.out, Contains("\"status\":\"rendered\""));
}

TEST_CASE("brushes: each brush's hair length and first contact held upright", "[cli][brushes]") {
  TempDir d;
  fs::create_directories(d.path() / "lib");
  for (const char* name : {"round", "bright"})
    fs::copy_file(sourcePath("scenes/brushes/" + std::string(name) + ".json"),
                  d.path() / "lib" / (std::string(name) + ".json"));
  const RunResult r = runShell(d, "'" + kBin + "' brushes --library lib");
  REQUIRE(r.code == 0);
  // The listing prints one decimal, as engine/geometry/first_contact.h computes it:
  // the round's 20 mm of hair touch at 20.0 mm (its bundles reach below the
  // tips), the bright's 11 mm at 12.0 (its slabs' half solids, 1 mm deep).
  for (const char* name : {"round", "bright"}) {
    const Brush b = loadBrush(sourcePath("scenes/brushes/" + std::string(name) + ".json"));
    char expected[64];
    std::snprintf(expected, sizeof expected, "touches at %4.1f mm upright",
                  firstContactHeightMm(b));
    INFO(r.out);
    const size_t line = r.out.find(std::string(name) + " ");
    REQUIRE(line != std::string::npos);
    const std::string text = r.out.substr(line, r.out.find('\n', line) - line);
    CHECK_THAT(text, Contains(expected));
  }
  CHECK_THAT(r.out, Contains("round        20.0 mm long, touches at 20.0 mm upright"));
  CHECK_THAT(r.out, Contains("bright       11.0 mm long, touches at 12.0 mm upright"));
}

TEST_CASE("a number option given nan or inf is a usage error naming it", "[cli][errors]") {
  // CLI11's ranges compare, and every comparison with NaN is false: before
  // requireFiniteNumbers (cli/options.h), --sample-mm nan asked for 2^63
  // samples, --lead-s nan wrote a trajectory of NaN times, and --px-per-mm nan
  // a canvas of -2^31 px.
  auto quoted = [](const std::string& path) { return std::string(1, '\'').append(path).append("'"); };
  const std::string svg = quoted(sourcePath("scenes/recordings/three-strokes.svg"));
  const std::string pull = quoted(sourcePath("scenes/trajectories/straight-pull.csv"));
  TempDir dir;
  const struct {
    std::string args, option;
  } cases[] = {
      {"import " + svg + " --brush round -o '" + dir.file("a.csv") + "' --sample-mm nan",
       "--sample-mm"},
      {"import " + svg + " --brush round -o '" + dir.file("b.csv") + "' --lead-s NaN",
       "--lead-s"},
      {"import " + svg + " --brush round -o '" + dir.file("c.csv") + "' --smooth-ms -nan",
       "--smooth-ms"},
      {"render --brush round --trajectory " + pull + " -o '" + dir.file("d.png") +
           "' --px-per-mm nan",
       "--px-per-mm"},
      {"render --brush round --trajectory " + pull + " -o '" + dir.file("e.png") +
           "' --offset-mm 0 inf 0",
       "--offset-mm"},
      {"preview round -o '" + dir.file("f.png") + "' --px-per-mm -NaN", "--px-per-mm"},
  };
  for (const auto& c : cases) {
    INFO(c.args);
    const RunResult r = runBristle(c.args);
    CHECK(r.code == 64);
    CHECK_THAT(r.err, Contains(c.option) && Contains("is not a finite number"));
  }
  CHECK_FALSE(std::filesystem::exists(dir.file("b.csv")));
  CHECK_FALSE(std::filesystem::exists(dir.file("d.png")));
}

TEST_CASE("a PNG output named for another image format is refused (64), naming the option",
          "[cli][errors]") {
  TempDir d;
  // Checked before any input is read: the inputs here do not exist.
  const struct {
    std::string args, line;
  } cases[] = {
      {"render --brush round --trajectory t.csv -o x.jpg",
       "render: -o x.jpg: bristle writes PNG only; use a .png name (or - for standard output)"},
      {"render s.json -o x.JPEG",
       "render: -o x.JPEG: bristle writes PNG only; use a .png name (or - for standard output)"},
      {"sheet sh.json -o x.gif",
       "sheet: -o x.gif: bristle writes PNG only; use a .png name (or - for standard output)"},
      {"preview round -o x.webp",
       "preview: -o x.webp: bristle writes PNG only; use a .png name (or - for standard output)"},
      {"record --device none --brush round --trajectory t.csv -o r.csv --png x.tiff",
       "record: --png x.tiff: bristle writes PNG only; use a .png name (or - for standard "
       "output)"},
      {"replay r.csv -o x.bmp",
       "replay: -o x.bmp: bristle writes PNG only; use a .png name (or - for standard output)"},
      {"compare a.png b.png --diff x.exr",
       "compare: --diff x.exr: bristle writes PNG only; use a .png name"},
  };
  for (const auto& c : cases) {
    INFO(c.args);
    const RunResult r = runShell(d, "'" + kBin + "' " + c.args);
    CHECK(r.code == 64);
    CHECK(r.err == "bristle: " + c.line + "\n");
  }
  // Nothing written but runShell's own files (.command.sh, .stdout, .stderr).
  for (const auto& entry : fs::directory_iterator(d.path()))
    CHECK(entry.path().filename().string()[0] == '.');
  // A name with no extension, or with one that names no other image format, is
  // written as given (a PNG).
  for (const std::string name : {"brush", "brush.PNG", "brush.out"}) {
    INFO(name);
    REQUIRE(runShell(d, "'" + kBin + "' preview -q round --width 64 --height 64 -o " + name).code ==
            0);
    CHECK(bytesOf(d.file(name)).rfind("\x89PNG", 0) == 0);
  }
}

namespace {

// A trajectory of the handle held upright at height z, at x = 15 then 40 mm,
// over the times given: in the air (z = 60) it renders in a moment.
void writeUpright(const TempDir& d, const std::string& name, const std::vector<double>& t,
                  const std::vector<double>& x, double z) {
  std::ofstream out(d.file(name));
  out << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  for (size_t i = 0; i < t.size(); ++i) out << t[i] << ',' << x[i] << ",40," << z << ",1,0,0,0\n";
}

// The round brush with its spines in metres (roots, lengths and widths a
// thousandth) and its surface left in millimetres.
void writeBrushInMetres(const TempDir& d, const std::string& name) {
  nlohmann::json doc = nlohmann::json::parse(readAll(kRound));
  for (auto& spine : doc["spines"])
    for (const char* key : {"root_mm", "segment_lengths_mm", "width_mm", "thickness_mm"})
      if (spine.contains(key))
        for (auto& v : spine[key]) v = v.get<double>() / 1000;
  std::ofstream(d.file(name)) << doc.dump();
}

const char* const kMsWarning =
    "ms.csv: t_s spans 5350 s (89 min%s); were the times in milliseconds?";
const char* const kMetresWarning =
    "m.json: /spines span 0.02 mm but /surface/cage_vertices_mm spans 19.9 mm (996 times "
    "larger); both are in mm: were they written in different units?";

std::string msWarning(const std::string& steps) {
  char buf[200];
  std::snprintf(buf, sizeof buf, kMsWarning, steps.c_str());
  return buf;
}

}  // namespace

TEST_CASE("a trajectory in milliseconds and a brush in metres are warned of, in --stats too",
          "[cli][warnings]") {
  TempDir d;
  // A 5.35 s stroke written in milliseconds, in the air; at 1 step a second
  // it plans 5351 steps (642,001 at the default 120 Hz).
  writeUpright(d, "ms.csv", {0, 5350}, {15, 40}, 60);
  writeBrushInMetres(d, "m.json");
  const std::string b = "'" + kBin + "'";
  const RunResult r = runShell(d, b + " render -q --brush m.json --trajectory ms.csv -o o.png "
                                      "--stats s.json --min-rate-hz 1 --px-per-mm 1 --solver slsqp");
  REQUIRE(r.code == 0);
  const std::string blank = "the brush never touched the canvas (ms.csv): the image is blank";
  const std::string ms = msWarning(", 5351 simulation steps");
  CHECK(r.err == "bristle: warning: " + std::string(kMetresWarning) + "\nbristle: warning: " + ms +
                     "\nbristle: warning: " + blank + "\n");
  const nlohmann::json stats = nlohmann::json::parse(readAll(d.file("s.json")));
  CHECK(stats.at("warnings") == nlohmann::json({kMetresWarning, ms, blank}));
  // validate says the same before any run: the brush alone, the trajectory
  // alone (no brush, no steps); the pair then adds only what is news.
  const RunResult v = runShell(d, b + " validate m.json ms.csv");
  CHECK(v.code == 0);
  CHECK(v.err == "bristle: warning: " + std::string(kMetresWarning) + "\nbristle: warning: " +
                     msWarning("") +
                     "\nbristle: warning: ms.csv: the brush 'round' never comes within reach of "
                     "the paper: render's image would be blank\n");
  // preview, for people designing brushes, names the brush's.
  const RunResult p = runShell(d, b + " preview -q m.json --width 64 --height 64 -o p.png");
  CHECK(p.code == 0);
  CHECK(p.err == "bristle: warning: " + std::string(kMetresWarning) + "\n");
  // record --device none plays the trajectory in real time: it says so before
  // it begins (here for a fifth of a second).
  const RunResult rec = runShell(d, b + " record -q --device none --brush m.json --trajectory "
                                        "ms.csv -o r.csv --duration 0.2");
  CHECK(rec.code == 0);
  CHECK(rec.err == "bristle: warning: " + msWarning(", 642001 simulation steps") +
                       "\nbristle: warning: " + kMetresWarning + "\n");
  // Ten minutes is not a mistake.
  writeUpright(d, "long.csv", {0, 600}, {15, 40}, 60);
  const RunResult ok = runShell(d, b + " validate long.csv");
  CHECK(ok.code == 0);
  CHECK(ok.err.empty());
}

TEST_CASE("validate warns of a pair planning over a million steps, and of a scene's and a "
          "sheet's trajectory in milliseconds",
          "[cli][warnings]") {
  TempDir d;
  const std::string b = "'" + kBin + "'";
  // 300 m of travel in 15 s: 1,200,001 steps of 0.25 mm.
  writeUpright(d, "far.csv", {0, 5, 10, 15}, {0, 100000, 0, 100000}, 60);
  const RunResult far = runShell(d, b + " validate round far.csv");
  CHECK(far.code == 0);
  CHECK_THAT(far.err,
             StartsWith("bristle: warning: far.csv: the trajectory plans 1200001 simulation steps, "
                        "over 1000000 (an hour or more of solving): the spine roots travel 300000 "
                        "mm at most 0.25 mm a step; were x_mm, y_mm and z_mm in micrometres?\n"));
  // A scene and a sheet plan at their own rates (120 and 60 steps a second).
  writeUpright(d, "ms.csv", {0, 5350}, {15, 40}, 25);
  std::ofstream(d.file("s.json")) << R"({"format": "bristle-scene/1", "name": "s",
      "canvas": {"size_mm": [60, 60]},
      "strokes": [{"brush": "round", "trajectory": "ms.csv", "paint": {"paints": ["sumi-ink"]}}]})";
  const RunResult scene = runShell(d, b + " validate s.json");
  CHECK(scene.code == 0);
  CHECK_THAT(scene.err, StartsWith("bristle: warning: " +
                                   msWarning(", 642001 simulation steps") + "\n"));
  std::ofstream(d.file("sh.json")) << R"({"format": "bristle-sheet/1", "name": "sh",
      "brushes": ["round", "flat"], "trajectories": ["ms.csv"], "sim": {"rate_hz": 60}})";
  const RunResult sheet = runShell(d, b + " validate sh.json");
  CHECK(sheet.code == 0);
  // One line for both brushes: the trajectory and its steps are the same.
  CHECK(sheet.err == "bristle: warning: " + msWarning(", 321001 simulation steps") + "\n");
}

TEST_CASE("a render writes nothing outside its outputs: no Mesa shader cache", "[cli][outputs]") {
  // Mesa caches compiled shaders under XDG_CACHE_HOME, or the home of the
  // password file; bristle turns the cache off (render/gl/gl_context.cpp), so
  // with both pointing at empty folders they stay empty, and the working
  // folder holds the PNG alone (docs/errors.md, "Outputs").
  TempDir dir;
  for (const char* sub : {"home", "cache", "work"}) fs::create_directories(dir.path() / sub);
  const RunResult r = runCaptured(
      "cd '" + dir.file("work") + "' && env -u GALLIUM_DRIVER -u MESA_SHADER_CACHE_DISABLE "
      "-u MESA_SHADER_CACHE_DIR HOME='" + dir.file("home") + "' XDG_CACHE_HOME='" +
          dir.file("cache") + "' '" + BRISTLE_BIN + "' render -q --brush round --trajectory '" +
          sourcePath("scenes/trajectories/s-curve.csv") + "' -o o.png",
      dir.file("stdout"), dir.file("stderr"));
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(fs::is_empty(dir.path() / "home"));
  CHECK(fs::is_empty(dir.path() / "cache"));
  std::vector<std::string> work;
  for (const auto& e : fs::directory_iterator(dir.path() / "work")) work.push_back(e.path().filename());
  CHECK(work == std::vector<std::string>{"o.png"});
}

TEST_CASE("'-o -' with a trace that fails: nothing on stdout, no file", "[cli][stdio][outputs]") {
  // The PNG goes to standard output only after the run's files are in place
  // (docs/errors.md, "Outputs"): with every file limited to 1 MB (as a full
  // disk; SIGXFSZ ignored, so the write fails with EFBIG) the 4 MB trace
  // fails, and the run is exit 74 with nothing written anywhere.
  TempDir dir;
  const RunResult r = runCaptured(
      "cd '" + dir.path().string() + "' && (ulimit -f 1024; trap '' XFSZ; env -u GALLIUM_DRIVER '" +
          BRISTLE_BIN + "' render -q --brush round --trajectory '" +
          sourcePath("scenes/trajectories/s-curve.csv") + "' -o - --trace t.jsonl)",
      dir.file("stdout"), dir.file("stderr"));
  CHECK(r.code == 74);
  CHECK(r.err == "bristle: t.jsonl: write failed: File too large\n");
  CHECK(r.out.empty());
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename());
  std::sort(left.begin(), left.end());
  CHECK(left == std::vector<std::string>{"stderr", "stdout"});
}

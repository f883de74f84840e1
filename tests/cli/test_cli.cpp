// End to end through the command line: a stroke from the demo files, the trace,
// determinism, and the exit codes and messages of bad input (docs/design.md,
// "Exit codes").

#include <catch2/catch.hpp>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unordered_map>

#include "bristle/version.h"
#include "cli_runner.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/geometry/spine_bundles.h"
#include "engine/model/brush.h"
#include "engine/model/trajectory.h"
#include "engine/dynamics/stepper.h"
#include "render/image/png_io.h"
#include "render/stroke_renderer.h"

using namespace bristle;
using namespace bristle::testing;
using Catch::Matchers::Contains;

namespace {

const std::string kBrush = sourcePath("scenes/brushes/round.json");
const std::string kSCurve = sourcePath("scenes/trajectories/s-curve.csv");

struct Placement {
  double x0_mm = 0, y0_mm = 0, px_per_mm = 0;
};
Placement placementOf(const std::string& png) {
  Placement p;
  for (const auto& [key, value] : render::readPngText(png))
    if (key == "bristle:canvas")
      std::sscanf(value.c_str(), "x0_mm=%lf y0_mm=%lf px_per_mm=%lf", &p.x0_mm, &p.y0_mm,
                  &p.px_per_mm);
  return p;
}

// A pixel carries paint when it is clearly darker than the paper (#f6f1e6):
// the compositing maps opacity 1/255 to at most a 1-level change, so 8 levels
// is paint, not rounding.
bool painted(const render::Image8& img, int c, int r) {
  const std::uint8_t* px = &img.pixels[(size_t(r) * img.width + c) * 4];
  return px[0] < 0xf6 - 8 || px[1] < 0xf1 - 8 || px[2] < 0xe6 - 8;
}

// Points of the brush that could touch the canvas in some step of the trace,
// hashed on a 1 mm grid: (x, y, radius of the geometry there).
struct Touchable {
  std::unordered_map<long, std::vector<Eigen::Vector3d>> cells;
  static long key(int i, int j) { return long(i) * 100003L + j; }
  void add(double x, double y, double r) {
    cells[key(int(std::floor(x)), int(std::floor(y)))].push_back({x, y, r});
  }
  // Within its radius plus slack of some point?
  bool near(double x, double y, double slack) const {
    const int ci = int(std::floor(x)), cj = int(std::floor(y));
    for (int di = -3; di <= 3; ++di)
      for (int dj = -3; dj <= 3; ++dj) {
        auto it = cells.find(key(ci + di, cj + dj));
        if (it == cells.end()) continue;
        for (const Eigen::Vector3d& p : it->second)
          if (std::hypot(p.x() - x, p.y() - y) <= p.z() + slack) return true;
      }
    return false;
  }
};

}  // namespace

TEST_CASE("render: the stroke lies where the brush touched, and the trace has every step",
          "[cli]") {
  TempDir dir;
  const std::string png = dir.file("s.png"), trace = dir.file("s.jsonl");
  // Smooth paper: this test checks where the brush touches, not the paper's grain
  // (on a toothy paper a joint that barely touches may meet a valley and leave no
  // paint, tests/render/test_paint_render.cpp).
  const RunResult run = runBristle("render --brush '" + kBrush + "' --trajectory '" + kSCurve +
                                   "' -o '" + png + "' --trace '" + trace + "' --paper-tooth 0");
  INFO(run.err);
  REQUIRE(run.code == 0);
  CHECK_THAT(run.out, Contains(png));

  // The canvas is the one the library computes for these inputs.
  const Brush brush = loadBrush(kBrush);
  const Trajectory traj = loadTrajectory(kSCurve);
  const CanvasGrid grid = render::canvasForStroke(brush, traj, render::StrokeOptions{});
  const render::Image8 img = render::readPngRgba8(png);
  REQUIRE(img.width == grid.width_px);
  REQUIRE(img.height == grid.height_px);
  const Placement place = placementOf(png);
  REQUIRE(place.px_per_mm == Approx(8));

  // Trace: one line per step, numbered from 0, with the keys of docs/design.md, "Formats".
  std::istringstream lines(readAll(trace));
  std::string line;
  int count = 0;
  double last_t = -1;
  Touchable touchable;
  std::vector<Eigen::Vector2d> contacts;
  int stuck_joints = 0;
  const double contact_band_mm = 0.1;
  while (std::getline(lines, line)) {
    const nlohmann::json j = nlohmann::json::parse(line);
    REQUIRE(j.at("step").get<int>() == count);
    REQUIRE(j.at("t_s").get<double>() >= last_t);
    last_t = j.at("t_s").get<double>();
    REQUIRE(j.at("handle").at("position_mm").size() == 3);
    REQUIRE(j.at("handle").at("quaternion_wxyz").size() == 4);
    REQUIRE(j.at("force_n").size() == 3);
    REQUIRE(j.at("spines").size() == brush.spines.size());
    for (size_t s = 0; s < brush.spines.size(); ++s) {
      const nlohmann::json& sp = j["spines"][s];
      const size_t n = brush.spines[s].segment_lengths_mm.size();
      REQUIRE(sp.at("joints_mm").size() == n + 1);
      REQUIRE(sp.at("angles_rad").size() == n);
      REQUIRE(sp.at("contact").size() == n);
      REQUIRE(sp.at("normal_force_n").size() == n);
      REQUIRE(sp.at("sliding").size() == n);
      // A sticking contact joint is held within slip_mm of where it stuck
      // (else it would have slipped); the others have no such point.
      REQUIRE(sp.at("stuck_xy_mm").size() == n);
      for (size_t k = 0; k < n; ++k) {
        const nlohmann::json& held = sp["stuck_xy_mm"][k];
        const bool sticking = sp["contact"][k].get<bool>() && !sp["sliding"][k].get<bool>();
        REQUIRE(held.is_null() == !sticking);
        if (!sticking) continue;
        const Eigen::Vector2d at(sp["joints_mm"][k + 1][0].get<double>(),
                                 sp["joints_mm"][k + 1][1].get<double>());
        ++stuck_joints;
        CHECK((at - Eigen::Vector2d(held[0].get<double>(), held[1].get<double>())).norm() <=
              SimOptions{}.slip_mm);
      }
      for (const char* k : {"spring", "friction", "damping"})
        REQUIRE(sp.at("energy_nmm").contains(k));
      REQUIRE(sp.at("solver").at("status").is_string());
      REQUIRE(sp.at("solver").at("iterations").is_number_integer());
      // Sample the geometry along each segment: the radius is half the brush
      // width there; a point can touch when it is within its radius of the band.
      const std::vector<double>& w = brush.spines[s].width_mm;
      for (size_t k = 0; k < n; ++k) {
        const auto& a = sp["joints_mm"][k];
        const auto& b = sp["joints_mm"][k + 1];
        for (int i = 0; i <= 20; ++i) {
          const double u = i / 20.0;
          const double x = (1 - u) * a[0].get<double>() + u * b[0].get<double>();
          const double y = (1 - u) * a[1].get<double>() + u * b[1].get<double>();
          const double z = (1 - u) * a[2].get<double>() + u * b[2].get<double>();
          const double rad = 0.5 * ((1 - u) * w[k] + u * w[k + 1]);
          // Pressed onto the paper a bundle spreads across the hair, by at most
          // bundleSpread(rad, z) (its reach to the canvas is z or more).
          if (z - rad <= contact_band_mm) touchable.add(x, y, rad * bundleSpread(rad, z));
        }
        if (sp["contact"][k].get<bool>())
          contacts.emplace_back(sp["joints_mm"][k + 1][0].get<double>(),
                                sp["joints_mm"][k + 1][1].get<double>());
      }
    }
    ++count;
  }
  CHECK(count >= static_cast<int>(planStepTimes(traj, brush, SimOptions{}).size()));
  CHECK(last_t == Approx(traj.endTime()));
  REQUIRE(!contacts.empty());
  CHECK(stuck_joints > 0);  // the S-curve's turns hold some joints still

  // Every painted pixel lies under brush geometry that could reach the canvas
  // (slack: 1.5 px for the pixel's extent and rasterisation).
  const double slack_mm = 1.5 / place.px_per_mm;
  long painted_count = 0, stray = 0;
  for (int r = 0; r < img.height; ++r)
    for (int c = 0; c < img.width; ++c) {
      if (!painted(img, c, r)) continue;
      ++painted_count;
      const double x = place.x0_mm + (c + 0.5) / place.px_per_mm;
      const double y = place.y0_mm + (img.height - r - 0.5) / place.px_per_mm;
      if (!touchable.near(x, y, slack_mm)) ++stray;
    }
  CHECK(painted_count > 10000);  // a real stroke, not a few specks
  CHECK(stray == 0);
  // ... and every joint the solver reported in contact left paint within 1.5 px.
  long bare = 0;
  for (const Eigen::Vector2d& p : contacts) {
    const int c = int(std::floor((p.x() - place.x0_mm) * place.px_per_mm));
    const int r = img.height - 1 - int(std::floor((p.y() - place.y0_mm) * place.px_per_mm));
    bool found = false;
    for (int dr = -1; dr <= 1 && !found; ++dr)
      for (int dc = -1; dc <= 1 && !found; ++dc)
        if (c + dc >= 0 && c + dc < img.width && r + dr >= 0 && r + dr < img.height)
          found = painted(img, c + dc, r + dr);
    if (!found) {
      ++bare;
      if (bare < 10) UNSCOPED_INFO("bare contact at " << p.transpose() << " px " << c << "," << r);
    }
  }
  // A hair's tip that the whole stroke has drained may graze the paper at
  // lift-off without leaving paint enough to see (measured: 1 or 2 contacts of
  // ~8,700, all at t = 2.99 s of 3 s); a brush that leaves real gaps misses
  // hundreds. 0.1 % of the contacts leaves room for those grazes.
  CHECK(bare <= static_cast<long>(contacts.size()) / 1000);
}

TEST_CASE("render: same inputs give the same pixels", "[cli][determinism]") {
  // The second run also rasterises on 4 llvmpipe threads where the first uses
  // bristle's choice (none besides the caller's, render/gl/gl_context.cpp), and
  // simulates and draws in turns on one thread where the first simulates
  // ahead on a second (--threads): the pixels may not depend on the machine's
  // core count either.
  TempDir dir;
  const std::string traj = sourcePath("scenes/trajectories/straight-pull.csv");
  const std::string args = "render -q --brush '" + kBrush + "' --trajectory '" + traj + "' -o ";
  REQUIRE(runCaptured("env -u GALLIUM_DRIVER -u LP_NUM_THREADS '" + std::string(BRISTLE_BIN) +
                          "' " + args + "'" + dir.file("a.png") + "' --threads 2",
                      dir.file("a.out"), dir.file("a.err"))
              .code == 0);
  REQUIRE(runCaptured("env -u GALLIUM_DRIVER LP_NUM_THREADS=4 '" + std::string(BRISTLE_BIN) +
                          "' " + args + "'" + dir.file("b.png") + "' --threads 1",
                      dir.file("b.out"), dir.file("b.err"))
              .code == 0);
  const render::Image8 a = render::readPngRgba8(dir.file("a.png"));
  const render::Image8 b = render::readPngRgba8(dir.file("b.png"));
  CHECK(a.width == b.width);
  CHECK(a.pixels == b.pixels);
}

// An allowed Ipopt option reaches the solve: the iteration limit Ipopt already
// had (--solver-max-iterations' 200) changes no pixel, a looser tolerance
// changes the solves and so the stroke; and the list is `bristle help ipopt-option`.
TEST_CASE("render: an allowed --ipopt-option reaches the solver", "[cli][ipopt]") {
  TempDir dir;
  const std::string traj = sourcePath("scenes/trajectories/straight-pull.csv");
  const std::string args = "render -q --brush '" + kBrush + "' --trajectory '" + traj + "' -o ";
  const auto pixels = [&](const std::string& name, const std::string& more) {
    const RunResult r = runBristle(args + "'" + dir.file(name) + "'" + more);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return render::readPngRgba8(dir.file(name)).pixels;
  };
  const auto plain = pixels("plain.png", "");
  CHECK(pixels("max-iter.png", " --ipopt-option max_iter=200") == plain);
  CHECK(pixels("loose.png", " --ipopt-option tol=1e-2 --ipopt-option acceptable_tol=1e-1") !=
        plain);
  const RunResult help = runBristle("help ipopt-option");
  CHECK(help.code == 0);
  CHECK_THAT(help.out, Contains("  max_iter                     an integer in [1, 100000]"));
  CHECK_THAT(help.out, !Contains("output_file"));
}

TEST_CASE("render: a trajectory that never touches the canvas gives a blank image and says so",
          "[cli]") {
  TempDir dir;
  const std::string traj = dir.write("air.csv",
                                     "# bristle-trajectory/1\n"
                                     "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                                     "0,10,10,30,1,0,0,0\n"
                                     "1,40,10,30,1,0,0,0\n");
  const RunResult r = runBristle("render -q --brush '" + kBrush + "' --trajectory '" + traj +
                                 "' -o '" + dir.file("air.png") + "'");
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("never touched the canvas"));
  const render::Image8 img = render::readPngRgba8(dir.file("air.png"));
  for (int row = 0; row < img.height; ++row)
    for (int c = 0; c < img.width; ++c) REQUIRE_FALSE(painted(img, c, row));
}

TEST_CASE("render: failed solves are counted, traced and reported, and the run goes on", "[cli]") {
  TempDir dir;
  const std::string trace = dir.file("t.jsonl");
  // The press-lift's first 0.5 s: the round (first contact at 20.0 mm) comes
  // 2 mm past first contact, a dozen planned steps on the paper, going down.
  // Each failed step gets every rescue (a re-centred start, the spines alone
  // with each solver, halves), dozens of solves: the whole press-lift, 130
  // steps on the paper, shows nothing more for ten times the time.
  std::istringstream whole(readAll(sourcePath("scenes/trajectories/press-lift.csv")));
  std::string excerpt, line;
  while (std::getline(whole, line) && (line.empty() || !std::isdigit(line[0]) ||
                                       std::stod(line) <= 0.5 + 1e-9))
    excerpt += line + "\n";
  const std::string press = dir.write("press.csv", excerpt);
  // Two iterations (Ipopt) or evaluations (SLSQP, the fallback) cannot converge a
  // contact step: every such solve fails with both solvers.
  const RunResult r = runBristle("render -q --solver-max-iterations 2 --brush '" + kBrush +
                                 "' --trajectory '" + press + "' -o '" + dir.file("f.png") +
                                 "' --trace '" + trace + "'");
  CHECK(r.code == 0);
  CHECK_THAT(r.err, Contains("solve failed (Maximum_Iterations_Exceeded)"));
  CHECK_THAT(r.err, Contains("steps had a failed solve"));
  // The warning says how long a spine was carried frozen.
  CHECK_THAT(r.err, Contains("carried along frozen"));
  CHECK_THAT(r.err, Contains("steps in a row"));
  CHECK_THAT(readAll(trace), Contains("\"status\":\"failed\""));
  CHECK(std::filesystem::exists(dir.file("f.png")));
}

TEST_CASE("bad input gets its exit code and a one-line message naming the field", "[cli][errors]") {
  TempDir dir;
  const std::string good_traj = kSCurve;
  const std::string out = dir.file("o.png");
  auto render = [&](const std::string& brush, const std::string& traj, const std::string& o) {
    return runBristle("render -q --brush '" + brush + "' --trajectory '" + traj + "' -o '" + o +
                      "'");
  };
  auto oneLine = [](const RunResult& r) {
    return !r.err.empty() && r.err.find('\n') == r.err.size() - 1;
  };
  const std::string brush_text = readAll(kBrush);

  SECTION("missing file: 66") {
    const RunResult r = render(dir.file("nope.json"), good_traj, out);
    CHECK(r.code == 66);
    CHECK_THAT(r.err, Contains("nope.json"));
    CHECK(oneLine(r));
  }
  SECTION("malformed JSON: 65 with line and column") {
    const std::string b = dir.write("bad.json", "{\n  \"format\": \"bristle-brush/1\",\n  \"name\" \"x\"\n}\n");
    const RunResult r = render(b, good_traj, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("bad.json: line 3, column"));
    CHECK(oneLine(r));
  }
  SECTION("unknown key: 65 naming it") {
    std::string t = brush_text;
    t.replace(t.find("\"friction\""), 10, "\"fricton\"");
    const RunResult r = render(dir.write("typo.json", t), good_traj, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("/fricton") && Contains("unknown key"));
  }
  SECTION("unknown format version: 65 naming it") {
    std::string t = brush_text;
    t.replace(t.find("bristle-brush/1"), 15, "bristle-brush/9");
    const RunResult r = render(dir.write("v9.json", t), good_traj, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("/format") && Contains("bristle-brush/9"));
  }
  SECTION("non-positive length: 65 naming the JSON pointer") {
    std::string t = brush_text;
    t.replace(t.find("[6.0, 5.5"), 9, "[-6.0, 5.5");
    const RunResult r = render(dir.write("neg.json", t), good_traj, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("/spines/0/segment_lengths_mm/0") && Contains("must be > 0"));
  }
  SECTION("malformed CSV and time going backwards: 65 naming the line") {
    const std::string t1 = dir.write("nan.csv",
                                     "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                                     "0,10,10,30,1,0,0,0\n0.1,10,abc,30,1,0,0,0\n");
    RunResult r = render(kBrush, t1, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("nan.csv: line 4, column 3 (y_mm)"));
    const std::string t2 = dir.write("back.csv",
                                     "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                                     "0,10,10,30,1,0,0,0\n0.2,10,10,30,1,0,0,0\n"
                                     "0.1,10,10,30,1,0,0,0\n");
    r = render(kBrush, t2, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("back.csv: line 5") && Contains("increase"));
  }
  SECTION("a brush that starts inside the canvas: 65 naming the line") {
    const std::string t = dir.write("low.csv",
                                    "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
                                    "0,10,10,5,1,0,0,0\n1,20,10,5,1,0,0,0\n");
    const RunResult r = render(kBrush, t, out);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("low.csv: line 3") && Contains("below the canvas"));
  }
  SECTION("unwritable output: 73 and no file left behind") {
    const std::string o = dir.file("no-such-dir/out.png");
    const std::string tr = dir.file("trace.jsonl");
    const RunResult r = runBristle("render -q --brush '" + kBrush + "' --trajectory '" +
                                   good_traj + "' -o '" + o + "' --trace '" + tr + "'");
    CHECK(r.code == 73);
    CHECK_THAT(r.err, Contains("out.png: cannot create output"));
    CHECK_FALSE(std::filesystem::exists(tr));
    CHECK(std::filesystem::is_empty(dir.path()));
  }
  SECTION("a non-manifold cage: 65 naming /surface (validate and render)") {
    nlohmann::json doc = nlohmann::json::parse(brush_text);
    doc["surface"]["faces"].push_back({0, 1, 11});  // a third face on edge (0, 1)
    const std::string b = dir.write("nm.json", doc.dump());
    RunResult r = runBristle("validate '" + b + "'");
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("nm.json: /surface/faces/") && Contains("non-manifold"));
    r = render(b, good_traj, out);
    CHECK(r.code == 65);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  SECTION("validate lists every problem of a brush at once") {
    nlohmann::json doc = nlohmann::json::parse(brush_text);
    doc["spines"][1]["segment_lengths_mm"][0] = -1;
    doc["spines"][3]["stiffness_nmm_per_rad"][2] = 0;
    doc["friction"]["mu_kinetic"] = 0.9;
    doc["colour"] = "red";
    const RunResult r = runBristle("validate '" + dir.write("many.json", doc.dump()) + "'");
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("/spines/1/segment_lengths_mm/0") &&
                          Contains("/spines/3/stiffness_nmm_per_rad/2") &&
                          Contains("/friction/mu_kinetic") && Contains("/colour"));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 4);
  }
  SECTION("usage errors: 64") {
    CHECK(runBristle("render --brush x.json").code == 64);
    CHECK(runBristle("render --brush a --trajectory b -o c --px-per-mm -3").code == 64);
    CHECK(runBristle("frobnicate").code == 64);
  }
}

TEST_CASE("help and version", "[cli]") {
  const RunResult v = runBristle("--version");
  CHECK(v.code == 0);
  CHECK_THAT(v.out, Contains("bristle 0."));
  const RunResult h = runBristle("help render");
  CHECK(h.code == 0);
  CHECK_THAT(h.out, Contains("bristle render --brush round"));
  const RunResult top = runBristle("--help");
  CHECK(top.code == 0);
  CHECK_THAT(top.out, Contains("Examples:"));
}

TEST_CASE("render: paint options, 16-bit output and the inputs hash", "[cli][paint]") {
  TempDir dir;
  const std::string traj = sourcePath("scenes/trajectories/press-lift.csv");
  auto render = [&](const std::string& name, const std::string& extra) {
    const std::string png = dir.file(name);
    const RunResult r = runBristle("render -q --brush '" + kBrush + "' --trajectory '" + traj +
                                   "' -o '" + png + "' " + extra);
    INFO(r.err);
    REQUIRE(r.code == 0);
    return png;
  };
  const std::string km = render("km.png", "--paint phthalo-blue,hansa-yellow --load tip");
  const std::string rgb =
      render("rgb.png", "--paint phthalo-blue,hansa-yellow --load tip --mix rgb");
  const std::string deep = render("deep.png", "--paint phthalo-blue,hansa-yellow --load tip "
                                              "--bits 16 --impasto");
  // The PNG header's bit depth (byte 24: after the signature, IHDR length, type,
  // width and height).
  auto bitDepth = [](const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::string head(25, '\0');
    in.read(head.data(), 25);
    return int(static_cast<unsigned char>(head[24]));
  };
  CHECK(bitDepth(km) == 8);
  CHECK(bitDepth(deep) == 16);
  // The two mix models paint different colours from the same strokes.
  CHECK(render::readPngRgba8(km).pixels != render::readPngRgba8(rgb).pixels);
  // Provenance: the version and FNV-1a 64 of the brush's and trajectory's bytes.
  std::map<std::string, std::string> text;
  for (const auto& [k, v] : render::readPngText(deep)) text[k] = v;
  CHECK(text["bristle:version"] == kVersion);
  CHECK(text["bristle:inputs-fnv1a64"] == hex64(fnv1a64Files({kBrush, traj})));
  CHECK(text["bristle:inputs-fnv1a64"].size() == 16);
}

TEST_CASE("render: bad paint input is a one-line data error (65), no PNG", "[cli][paint]") {
  TempDir dir;
  const std::string out = dir.file("out.png");
  auto render = [&](const std::string& extra) {
    return runBristle("render -q --brush '" + kBrush + "' --trajectory '" + kSCurve + "' -o '" +
                      out + "' " + extra);
  };
  struct Case {
    std::string args, message;
  };
  for (const Case& c : {
           Case{"--paint unobtainium", "--paint unobtainium: unknown pigment 'unobtainium'"},
           Case{"--paint '#12g456'", "--paint #12g456: colour '#12g456' does not parse"},
           Case{"--paint ultramarine,sumi-ink", "--paint ultramarine,sumi-ink: --load solid takes 1 paint"},
           // The rules of a scene's paint (engine/paint/paint_spec.h): a tip load has two
           // paints, and a tip_length of 0 or 1 would make it a solid load.
           Case{"--paint ultramarine --load tip", "--load tip takes 2 paints (body, then tip)"},
           Case{"--paint ultramarine,sumi-ink --load tip --tip-length 1",
                "--tip-length 1.000000: must be in (0, 1) (a fraction of the hair length"},
           Case{"--paint ultramarine,sumi-ink --load tip --tip-length 0",
                "--tip-length 0.000000: must be in (0, 1)"},
           Case{"--amount -0.5", "--amount -0.500000: must be in (0, 1]"},
           Case{"--background cream", "--background cream: must be a colour"},
           Case{"--paper-tooth -1", "--paper-tooth: must be in [0, 1] mm"},
       }) {
    INFO(c.args);
    const RunResult r = render(c.args);
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains(c.message));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(out));
  }
  // Choices the command line knows are usage errors (64).
  CHECK(render("--mix cmyk").code == 64);
  CHECK(render("--load sideways").code == 64);
  CHECK(render("--bits 12").code == 64);
}

// The public API (include/bristle/, docs/api.md): its in-memory render is
// `bristle render`'s PNG pixel for pixel, its Simulation steps the engine's,
// and bad input raises bristle::api::Error with a one-line message naming the
// argument and the rule.
#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "bristle/brush.h"
#include "bristle/error.h"
#include "bristle/png.h"
#include "bristle/render.h"
#include "bristle/simulation.h"
#include "bristle/trajectory.h"
#include "bristle/version.h"
#include "cli_runner.h"
#include "engine/dynamics/simulation.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/trajectory.h"
#include "engine/paint/paint_spec.h"
#include "engine/solvers/solver_pair.h"
#include "render/image/png_io.h"
#include "temp_dir.h"

namespace {

namespace api = bristle::api;
using bristle::testing::runBristle;
using bristle::testing::sourcePath;
using bristle::testing::TempDir;

// The first 40 samples of the straight pull (0.39 s): press in and the start
// of the pull, a short stroke that still lays paint.
std::string shortStroke(const TempDir& dir) {
  const bristle::Trajectory full = bristle::loadTrajectory(sourcePath("scenes/trajectories/straight-pull.csv"));
  std::string csv = "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  char line[256];
  for (size_t i = 0; i < 40; ++i) {
    const bristle::TrajectorySample& s = full.samples[i];
    const Eigen::Quaterniond& q = s.pose.rotation;
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", s.t_s,
                  s.pose.position_mm.x(), s.pose.position_mm.y(), s.pose.position_mm.z(), q.w(),
                  q.x(), q.y(), q.z());
    csv += line;
  }
  return dir.write("short.csv", csv);
}

// The pixels of an API image against a PNG's, read as RGBA: same size, the
// same R, G, B bytes and an opaque alpha.
void requireSamePixels(const api::Image& image, const bristle::render::Image8& png) {
  REQUIRE(image.channels == 3);
  REQUIRE(image.width_px == png.width);
  REQUIRE(image.height_px == png.height);
  REQUIRE(png.channels == 4);
  long differing = 0;
  for (size_t p = 0; p < size_t(png.width) * png.height; ++p)
    for (int c = 0; c < 4; ++c)
      differing += (c < 3 ? image.pixels[3 * p + c] : 255) != png.pixels[4 * p + c];
  CHECK(differing == 0);  // byte for byte: one path from options to pixels (api/stroke_setup.h)
}

// The message of the Error fn throws, with its category checked.
template <class F>
std::string errorOf(F&& fn, api::ErrorCategory category) {
  try {
    fn();
  } catch (const api::Error& e) {
    CHECK(e.category() == category);
    const std::string message = e.what();
    CHECK(message.find('\n') == std::string::npos);  // one line
    return message;
  }
  FAIL("no bristle::api::Error");
  return {};
}

const api::Trajectory::Quaternions kUpright(3, {1, 0, 0, 0});

}  // namespace

TEST_CASE("api: renderStroke paints bristle render's pixels byte for byte", "[api]") {
  unsetenv("GALLIUM_DRIVER");  // OSMesa's default (llvmpipe), as the CLI runs here
  TempDir dir("bristle-api");
  const std::string csv = shortStroke(dir);
  const std::string png = dir.file("cli.png");
  // Options off their defaults, so a field the API drops or maps wrongly shows.
  const auto cli = runBristle("render -q --brush round --trajectory '" + csv + "' -o '" + png +
                              "' --px-per-mm 6 --paint burnt-umber --amount 0.6 --paper-seed 7");
  REQUIRE(cli.code == 0);
  api::RenderOptions options;
  options.px_per_mm = 6;
  options.paint = "burnt-umber";
  options.amount = 0.6;
  options.paper_seed = 7;
  api::setBrushLibraryDirs({sourcePath("scenes/brushes")});
  const api::Brush round = api::Brush::load("round");
  const api::RenderResult from_file = api::renderStroke(round, api::Trajectory::load(csv), options);
  CHECK(from_file.touched);
  CHECK(from_file.ink_pixels > 0);
  requireSamePixels(from_file.image, bristle::render::readPngRgba8(png));

  SECTION("the same samples as arrays paint the same pixels") {
    const bristle::Trajectory t = bristle::loadTrajectory(csv);
    std::vector<double> t_s;
    std::vector<std::array<double, 3>> xyz;
    api::Trajectory::Quaternions q;
    for (const bristle::TrajectorySample& s : t.samples) {
      t_s.push_back(s.t_s);
      xyz.push_back({s.pose.position_mm.x(), s.pose.position_mm.y(), s.pose.position_mm.z()});
      q.push_back({s.pose.rotation.w(), s.pose.rotation.x(), s.pose.rotation.y(),
                   s.pose.rotation.z()});
    }
    const api::RenderResult from_arrays =
        api::renderStroke(round, api::Trajectory::fromArrays(t_s, xyz, q), options);
    CHECK(from_arrays.image.pixels == from_file.image.pixels);
  }
  SECTION("writePng writes those pixels") {
    api::writePng(dir.file("api.png"), from_file.image);
    requireSamePixels(from_file.image, bristle::render::readPngRgba8(dir.file("api.png")));
  }
}

// Pixels of an image unlike its corner (bare paper): kInkLevels's rule
// (render/image/compose.h), more than 6 levels summed over R, G, B.
long inkedPixels(const api::Image& image) {
  const auto& px = image.pixels;
  long n = 0;
  for (size_t i = 0; i < px.size(); i += 3)
    n += std::abs(px[i] - px[0]) + std::abs(px[i + 1] - px[1]) + std::abs(px[i + 2] - px[2]) > 6;
  return n;
}

TEST_CASE("api: a Canvas paints renderStroke's pixels, and a second stroke adds to them",
          "[api]") {
  unsetenv("GALLIUM_DRIVER");
  TempDir dir("bristle-api");
  const bristle::Trajectory t = bristle::loadTrajectory(shortStroke(dir));
  std::vector<double> t_s;
  std::vector<std::array<double, 3>> xyz, shifted;
  api::Trajectory::Quaternions q;
  for (const bristle::TrajectorySample& s : t.samples) {
    const Eigen::Vector3d& p = s.pose.position_mm;
    t_s.push_back(s.t_s);
    xyz.push_back({p.x(), p.y(), p.z()});
    shifted.push_back({p.x(), p.y() + 3, p.z()});  // 3 mm up the canvas: inside its margin
    q.push_back({s.pose.rotation.w(), s.pose.rotation.x(), s.pose.rotation.y(),
                 s.pose.rotation.z()});
  }
  const api::Brush round = api::Brush::load(sourcePath("scenes/brushes/round.json"));
  api::RenderOptions options;
  options.px_per_mm = 4;
  const api::RenderResult alone =
      api::renderStroke(round, api::Trajectory::fromArrays(t_s, xyz, q), options);
  api::Canvas canvas(alone.image.x0_mm, alone.image.y0_mm, alone.image.width_px,
                     alone.image.height_px, options);
  const api::StrokeFacts first =
      canvas.addStroke(round, api::Trajectory::fromArrays(t_s, xyz, q), options);
  CHECK(first.touched);
  const api::Image one = canvas.image();
  CHECK(one.pixels == alone.image.pixels);  // one stroke: the same path to the same pixels
  canvas.addStroke(round, api::Trajectory::fromArrays(t_s, shifted, q), options);
  const long after_two = inkedPixels(canvas.image());
  CHECK(after_two > inkedPixels(one));  // the second stroke laid paint where the first had none
  CHECK_THROWS_AS(api::Canvas(0, 0, 0, 10), api::Error);
}

TEST_CASE("api: RenderOptions' defaults are bristle render's", "[api]") {
  const api::RenderOptions o;
  const bristle::SimOptions sim;
  CHECK(o.paper_colour == bristle::kDefaultPaperColour);
  CHECK(o.max_step_mm == sim.max_step_mm);
  CHECK(o.min_rate_hz == sim.min_rate_hz);
  CHECK(o.steady_step_mm == sim.steady_step_mm);
  CHECK(o.solver_max_iterations == bristle::kDefaultSolverMaxIterations);
}

TEST_CASE("api: a Simulation lowered onto the paper touches it and is pushed back", "[api]") {
  const api::Brush round = api::Brush::load(sourcePath("scenes/brushes/round.json"));
  REQUIRE(round.name() == "round");
  REQUIRE(round.spineCount() == 7);
  CHECK(round.hairLengthMm() > 0);
  CHECK(round.reachMm() >= round.hairLengthMm());  // reach includes the ferrule's radius
  api::Simulation sim(round);
  const double top = round.hairLengthMm() + 1;
  sim.reset({{0, 0, top}}, 0);
  CHECK_FALSE(sim.state().contact());
  // 0.25 mm a step (SimOptions::max_step_mm), 3 mm past the hair's length.
  for (int k = 1; k <= 16; ++k) sim.step({{0, 0, top - 0.25 * k}}, 0.01 * k);
  const api::StepResult& s = sim.state();
  CHECK(s.contact());
  CHECK(s.force_n[2] > 0);  // the paper pushes up (Baxter & Lin 2004, §3.1)
  REQUIRE(s.spines.size() == 7);
  for (const api::SpineState& spine : s.spines) CHECK(spine.solved);
  // Joints rest on the paper, never below it past the solver's tolerance.
  constexpr double kPenetrationToleranceMm = 1e-3;
  for (const api::SpineState& spine : s.spines)
    for (const auto& j : spine.joints_mm) CHECK(j[2] >= -kPenetrationToleranceMm);
}

TEST_CASE("api: a Simulation made from a temporary Brush keeps the brush it needs", "[api]") {
  // simulation.h's own example: the Brush is gone when the constructor
  // returns, and the engine's simulation refers to its model. The Simulation
  // keeps a copy (its model is shared), so stepping it reads nothing freed.
  api::Simulation sim(api::Brush::load(sourcePath("scenes/brushes/round.json")));
  sim.reset({{0, 0, 25}}, 0);
  for (int k = 1; k <= 30; ++k) sim.step({{0, 0, 25 - 0.25 * k}}, 0.01 * k);
  const api::StepResult& s = sim.state();
  REQUIRE(s.spines.size() == 7);
  CHECK(s.contact());  // 25 - 7.5 mm: pressed past the round's 20 mm of hair
  for (const api::SpineState& spine : s.spines) CHECK(spine.solved);
}

TEST_CASE("api: a pen recording loads for a brush as bristle render --trajectory reads it",
          "[api]") {
  // An SVG's paths (docs/input.md) become a depth trajectory for the brush:
  // its depths are placed when rendered, and what the import notes (the
  // <text> it skips) comes back as a warning, not on stderr.
  const api::Brush round = api::Brush::load(sourcePath("scenes/brushes/round.json"));
  const std::string svg = sourcePath("scenes/recordings/three-strokes.svg");
  std::vector<std::string> warnings;
  const api::Trajectory t = api::Trajectory::load(svg, round, &warnings);
  CHECK(t.hasDepths());
  CHECK(t.sampleCount() > 2);
  REQUIRE(warnings.size() == 1);
  CHECK(warnings[0].find("skipped 1 <text>") != std::string::npos);
  // Without a brush only bristle's own CSV is read, refused at its first line.
  try {
    api::Trajectory::load(svg);
    FAIL("an SVG loaded without a brush");
  } catch (const api::Error& e) {
    CHECK(e.category() == api::ErrorCategory::kDataError);
    CHECK(std::string(e.what()).find("line 1: the first line must be '# bristle-trajectory/1'") !=
          std::string::npos);
  }
}

TEST_CASE("api: bad input raises Error naming the argument and the rule", "[api]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  using C = api::ErrorCategory;
  api::setBrushLibraryDirs({sourcePath("scenes/brushes")});
  CHECK_THAT(errorOf([] { api::Brush::load("no-such-brush"); }, C::kNoInput),
             Catch::StartsWith("Brush::load no-such-brush: no brush named 'no-such-brush'"));
  CHECK(errorOf([&] { api::Trajectory::fromArrays({0, 0.1, 0.2}, {{0, 0, 1}, {0, nan, 1}, {0, 0, 1}}, kUpright); },
                C::kDataError) == "Trajectory::fromArrays: xyz_mm[1]: must be finite");
  CHECK(errorOf([&] { api::Trajectory::fromArrays({0, 0.2, 0.2}, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}, kUpright); },
                C::kDataError) ==
        "Trajectory::fromArrays: t_s[2]: is not after t_s[1] (time must increase strictly)");
  api::Trajectory::Quaternions zero = kUpright;
  zero[1] = {0, 0, 0, 0};
  CHECK(errorOf([&] { api::Trajectory::fromArrays({0, 0.1, 0.2}, {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}, zero); },
                C::kDataError) == "Trajectory::fromArrays: quaternion_wxyz[1]: has near-zero norm");
  CHECK(errorOf([&] { api::Trajectory::fromArrays({0, 0.1}, {{0, 0, 1}}, kUpright); },
                C::kDataError) ==
        "Trajectory::fromArrays: xyz_mm has 1 samples, t_s has 2 (they must be equal)");
  const api::Brush round = api::Brush::load("round");
  const api::Trajectory t = api::Trajectory::fromArrays({0, 0.1, 0.2}, {{0, 0, 30}, {1, 0, 30}, {2, 0, 30}}, kUpright);
  api::RenderOptions bad_px;
  bad_px.px_per_mm = 0;
  CHECK(errorOf([&] { api::renderStroke(round, t, bad_px); }, C::kUsage) ==
        "RenderOptions.px_per_mm 0: must be in [0.5, 100]");
  api::RenderOptions bad_amount;
  bad_amount.amount = nan;
  CHECK_THAT(errorOf([&] { api::renderStroke(round, t, bad_amount); }, C::kDataError),
             Catch::StartsWith("RenderOptions.amount nan: "));
  api::RenderOptions bad_paint;
  bad_paint.paint = "no-such-pigment";
  CHECK_THAT(errorOf([&] { api::renderStroke(round, t, bad_paint); }, C::kDataError),
             Catch::StartsWith("RenderOptions.paint no-such-pigment: "));
  api::Simulation sim(round);
  sim.reset({{0, 0, 30}}, 0);
  CHECK(errorOf([&] { sim.step({{0, 0, 30}, {0, 0, 0, 0}}, 0.1); }, C::kUsage) ==
        "Simulation::step: ferrule.quaternion_wxyz: has near-zero norm");
  CHECK_THAT(errorOf([&] { sim.step({{0, 0, 30}}, 0); }, C::kUsage),
             Catch::StartsWith("Simulation::step: t_s = 0.000000: must be after the last step's"));
}

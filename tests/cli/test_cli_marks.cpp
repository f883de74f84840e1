// Marks of the library brushes measured as a painter would judge them
// (docs/fidelity.md): a steady pull keeps its width, a deeper press leaves a
// wider stroke, and a straight press-and-lift leaves one filled blot. Each
// stroke is rendered end to end by the bristle executable and measured on the
// PNG (tests/support/mark_measure.h).

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "render/image/png_io.h"
#include "tests/support/mark_measure.h"
#include "tests/support/mark_png.h"
#include "tests/cli/scene_render.h"
#include "tests/support/press_matrix.h"

using namespace bristle;
using namespace bristle::testing;
using namespace bristle::testsupport;

namespace {

// One pixel at the default 8 px/mm: the resolution of every width measured here.
constexpr double kMarkPixelMm = 1.0 / 8;

// A brush whose spine roots lie in a row (flat, bright, filbert) is turned a
// quarter about its axis, so that the pull along +x is broadside, as a painter
// lays a flat stroke.
bool rowBrush(const Brush& b) {
  double xs = 0, ys = 0;
  for (const SpineSpec& s : b.spines) {
    xs = std::max(xs, std::fabs(s.root_mm.x()));
    ys = std::max(ys, std::fabs(s.root_mm.y()));
  }
  return xs > 3 * ys + 1e-9;
}

void writeCsv(const Trajectory& t, const std::string& path) {
  std::ofstream f(path);
  f << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n" << std::setprecision(10);
  for (const TrajectorySample& s : t.samples) {
    const Eigen::Quaterniond& q = s.pose.rotation;
    f << s.t_s << ',' << s.pose.position_mm.x() << ',' << s.pose.position_mm.y() << ','
      << s.pose.position_mm.z() << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z()
      << '\n';
  }
}

// Renders one case of the press matrix with the brush and returns the mark's
// coverage. Unless told, a brush with hair volume is solved by Ipopt, which
// solves its spines together as the reference does; any other by SLSQP, the
// fast solver (bench_matrix covers both): with hair volume the spines push on
// each other, and the coupled NLP is the paper's formulation.
Coverage renderCase(const std::string& name, Case c, const TempDir& dir, const std::string& tag,
                    std::string solver = "", const std::string& extra = "") {
  c.brush_path = sourcePath("scenes/brushes/" + name + ".json");
  const Brush brush = loadBrush(c.brush_path);
  if (solver.empty()) solver = brush.volume.present() ? "ipopt" : "slsqp";
  Trajectory t = makeCaseTrajectory(brush, c);
  if (rowBrush(brush)) {
    // Turn about the handle's own axis: the same contact height (the rest shape
    // turns with it about the vertical before the tilt).
    const Eigen::Quaterniond yaw(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
    for (TrajectorySample& s : t.samples) s.pose.rotation = s.pose.rotation * yaw;
    const double shift =
        spineContactHeightMm(brush, tiltRotation(c.tilt_deg) * yaw) -
        spineContactHeightMm(brush, tiltRotation(c.tilt_deg));
    for (TrajectorySample& s : t.samples) s.pose.position_mm.z() += shift;
  }
  std::string stem = name;  // (built up with +=: GCC 12 warns falsely on a + chain)
  stem += '-';
  stem += tag;
  const std::string csv = dir.file(stem + ".csv");
  const std::string png = dir.file(stem + ".png");
  writeCsv(t, csv);
  const RunResult r = runBristle("render -q --solver " + solver + " --brush '" + c.brush_path +
                                 "' --trajectory '" + csv + "' -o '" + png + "' " + extra);
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.find("failed solve") == std::string::npos);
  return loadCoveragePng(png);
}

// The handle upright, pressed straight down to `fraction` of the hair, held
// and lifted.
Case pressLiftCase(double fraction) {
  Case c;
  c.kind = CaseKind::kPressLift;
  c.press_fraction = fraction;
  c.tilt_deg = 0;
  return c;
}

Case pullCase(double fraction) {
  Case c;
  c.kind = CaseKind::kPull;
  c.press_fraction = fraction;
  c.tilt_deg = 20;  // the hairs trail behind the pull
  c.speed_mm_s = 30;
  return c;
}

}  // namespace

TEST_CASE("marks: a steady pull keeps its width (CV <= 15 % over the middle 60 %)",
          "[marks]") {
  // The fan's width is the spread of its lines, from the first to the last.
  const char* name =
      GENERATE("round", "flat", "bright", "filbert", "badger", "fan", "calligraphy");
  INFO(name);
  TempDir dir;
  const Coverage img = renderCase(name, pullCase(0.3), dir, "pull");
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  const double cv = widthCv(p);
  INFO("mean width " << meanWidthMm(p) << " mm, CV " << cv);
  // 15 %: what a steady hand achieves (the acceptance figure); without hair
  // volume the calligraphy brush's pull at half its hair length reached 12 %
  // and narrowed from 19 to 10 mm along a 60 mm pull.
  CHECK(cv <= 0.15);
}

TEST_CASE("marks: a deeper press leaves a wider stroke", "[marks]") {
  // The fan's width is the spread of its lines: pressed harder, its splayed
  // hairs lay down over more of their length. The badger's dome already spans
  // most of its width at a light press, and grows slowly from there. A
  // square-cut flat pulled broadside is the exception: its stroke is as wide
  // as the brush at any press, as a real flat's is (its slabs of hair lie
  // side by side and only flare a little at the row's edges, kSlabFlare).
  const char* name =
      GENERATE("round", "flat", "bright", "filbert", "badger", "fan", "calligraphy");
  INFO(name);
  TempDir dir;
  std::vector<double> widths;
  for (double f : {0.1, 0.25, 0.4, 0.6}) {
    std::string tag = "d";
    tag += std::to_string(f);
    const Coverage img = renderCase(name, pullCase(f), dir, tag);
    widths.push_back(meanWidthMm(widthProfile(img)));
  }
  INFO("widths " << widths[0] << " " << widths[1] << " " << widths[2] << " " << widths[3]);
  // Monotone to within two pixels of measurement: a stroke's edge pixels flip
  // with sub-pixel shifts of the hair.
  for (size_t i = 1; i < widths.size(); ++i) CHECK(widths[i] >= widths[i - 1] - 2 * kMarkPixelMm);
  const Brush brush = loadBrush(sourcePath("scenes/brushes/" + std::string(name) + ".json"));
  if (!brush.spines.front().thickness_mm.empty()) {
    // The row's width: its outer slabs' outer edges.
    double lo = 1e300, hi = -1e300;
    for (const SpineSpec& s : brush.spines) {
      lo = std::min(lo, s.root_mm.x() - 0.5 * s.width_mm.front());
      hi = std::max(hi, s.root_mm.x() + 0.5 * s.width_mm.front());
    }
    INFO("the row is " << hi - lo << " mm wide");
    // From the row's width (less two pixels of edge) to a tenth more: a
    // 12 mm flat pressed flat flares to about 13 mm.
    for (double w : widths) {
      CHECK(w >= hi - lo - 2 * kMarkPixelMm);
      CHECK(w <= 1.1 * (hi - lo));
    }
    return;
  }
  // And it does grow: the deepest press is wider than the lightest by more
  // than the pixel noise.
  CHECK(widths.back() > widths.front() + 2 * kMarkPixelMm);
}

TEST_CASE("marks: the calligraphy brush widens about linearly with press depth", "[marks]") {
  // Published robot-calligraphy measurements of a 30 mm brush: ~2 mm of width
  // at 1 mm of press, ~17 mm at 15 mm, close to a line of 1.1 mm per mm. The
  // acceptance bar: a least-squares line through the sweep from 1.5 to 15 mm
  // (5 to 50 % of the 30 mm hair) explains at least 90 % of the variance, and
  // its slope is within a factor 1.5 of 1.1.
  constexpr double kRealSlope = 1.1, kSlopeFactor = 1.5, kMinR2 = 0.9;
  const Brush brush = loadBrush(sourcePath("scenes/brushes/calligraphy.json"));
  const double hair = brush.spines[0].lengthMm();
  TempDir dir;
  std::vector<double> depth, width;
  for (double f : {0.05, 0.1, 0.2, 0.3, 0.4, 0.5}) {
    const Coverage img = renderCase("calligraphy", pullCase(f), dir, "lin" + std::to_string(f));
    depth.push_back(f * hair);
    width.push_back(meanWidthMm(widthProfile(img)));
  }
  const double n = static_cast<double>(depth.size());
  double mx = 0, my = 0;
  for (size_t i = 0; i < depth.size(); ++i) mx += depth[i] / n, my += width[i] / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < depth.size(); ++i) {
    sxy += (depth[i] - mx) * (width[i] - my);
    sxx += (depth[i] - mx) * (depth[i] - mx);
    syy += (width[i] - my) * (width[i] - my);
  }
  const double slope = sxy / sxx, r2 = sxy * sxy / (sxx * syy);
  std::ostringstream widths;
  for (double w : width) widths << ' ' << w;
  INFO("widths (mm):" << widths.str() << "; slope " << slope << " mm/mm, R^2 " << r2);
  CHECK(r2 >= kMinR2);
  CHECK(slope >= kRealSlope / kSlopeFactor);
  CHECK(slope <= kRealSlope * kSlopeFactor);
}

TEST_CASE("marks: a straight press-and-lift leaves one filled blot", "[marks]") {
  // Filled: the blot covers >= 85 % of its convex hull (the acceptance figure; a
  // six-pointed star covers 2/3). Hair volume's cohesion fills the badger's
  // ring and the round's star; graded stiffness lays the round's and the
  // calligraphy brush's bellies down into one teardrop. The fan is left out:
  // its mark is a row of separate hair lines by design (docs/fidelity.md).
  const char* name = GENERATE("round", "flat", "bright", "filbert", "badger", "calligraphy");
  INFO(name);
  TempDir dir;
  const Case c = pressLiftCase(0.3);
  // Ipopt, the reference: SLSQP can stall on the straight centre spine of a
  // round pressed straight down, a buckling point (docs/dynamics.md).
  // A speck under 20 px (0.3 mm^2 at 8 px/mm: one hair tip's dot beside a
  // blot of 2,000-6,000 px) is not a second blot to a painter. (The
  // calligraphy brushes' blots are held to no speck at all below.)
  constexpr int kSpeckPx = 20;
  const BlotStats b = blotStats(renderCase(name, c, dir, "blot", "ipopt"), 0.1, kSpeckPx);
  INFO("components " << b.components << ", fill " << b.fill);
  CHECK(b.components == 1);
  CHECK(b.fill >= 0.85);
}

namespace {

// The ink of `img` within r_mm of (x_mm, y_mm) (canvas mm); nothing outside.
Coverage inkWithinMm(const Coverage& img, double x_mm, double y_mm, double r_mm) {
  Coverage out = img;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      const double x = img.x0_mm + (c + 0.5) / img.px_per_mm;
      const double y = img.y0_mm + (img.h - r - 0.5) / img.px_per_mm;
      if (std::hypot(x - x_mm, y - y_mm) > r_mm) out.at(c, r) = 0;
    }
  return out;
}

// A calligraphy stroke's entry as the 永 painting writes it
// (scenes/paintings/generate.py, YONG): the handle upright comes down while
// travelling along +x, from 2.5 mm above the paper 8 mm back, onto (20, 15)
// at 1.5 mm past first contact, presses on to the body's 3 mm at x = 26 and
// pulls on to x = 39.5 at 3 mm, and lifts. In sumi ink on the painting's
// paper, on a canvas whose origin is the paper's corner, so that the
// stroke's line (y = 15) and where it touches down are known in canvas mm.
constexpr double kEntryXMm = 20, kEntryYMm = 15, kPressedXMm = 26;
Coverage renderCalligraphyEntry(const std::string& name, const TempDir& dir) {
  const std::string csv = dir.file(name + "-entry.csv");
  std::ofstream(csv) << "# bristle-trajectory/1\nt_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz\n"
                        "0,12,15,-2.5,1,0,0,0\n0.25,20,15,1.5,1,0,0,0\n"
                        "0.45,26,15,3,1,0,0,0\n0.9,39.5,15,3,1,0,0,0\n"
                        "1,41,15,-2.5,1,0,0,0\n";
  nlohmann::json scene = {
      {"format", "bristle-scene/1"},
      {"name", "entry"},
      {"canvas",
       {{"size_mm", {60, 30}},
        {"px_per_mm", 8},
        {"background", "#f3ecdc"},
        {"paper", {{"tooth_depth_mm", 0.03}, {"tooth_scale_mm", 0.3}, {"seed", 3}}}}},
      {"solver", "ipopt"},
      {"strokes",
       {{{"brush", sourcePath("scenes/brushes/" + name + ".json")},
         {"trajectory", csv},
         {"paint", {{"paints", {"sumi-ink"}}, {"amount", 1.0}}}}}}};
  return renderSceneChecked(scene, dir, name + "-entry");
}

}  // namespace

TEST_CASE("marks: a calligraphy stroke enters with one full rounded head", "[marks]") {
  // A calligrapher's entry is one rounded head. Pressed 4 mm while barely
  // moving, a brush whose tips fan out paints a splat: fingers of ink round a
  // hollow core and specks beside them (the hand-tuned brush before its hair
  // held together filled 0.79 of the hull of its ink within 4 mm of the press
  // point, the fitted one 0.66 in two pieces). Within kHeadMm of where the
  // brush touches down the head must fill at least kMinHeadFill of its
  // convex hull (a rounded head fills it but for the pixel staircase of its
  // edge: the hand-tuned brush's pressed head measured 0.93), and within
  // kSatelliteMm no other piece of ink of kSpeckPx or more may lie apart
  // from it. Smaller ones are the point's hair touching first as the brush
  // comes down travelling: dots of 1-4 px (1/64 mm^2 each) a quarter of a
  // millimetre before the head. (The test of every brush's blot above lets
  // pass specks of up to 20 px.)
  constexpr double kHeadMm = 4, kMinHeadFill = 0.88, kSatelliteMm = 8;
  constexpr int kSpeckPx = 8;
  const char* name = GENERATE("calligraphy", "calligraphy-wang2020");
  INFO(name);
  TempDir dir;
  const Coverage img = renderCalligraphyEntry(name, dir);
  const BlotStats head =
      blotStats(inkWithinMm(img, kEntryXMm, kEntryYMm, kHeadMm), 0.1, kSpeckPx);
  const BlotStats near =
      blotStats(inkWithinMm(img, kEntryXMm, kEntryYMm, kSatelliteMm), 0.1, kSpeckPx);
  INFO("head: fill " << head.fill << ", " << head.largest_area_mm2 << " mm^2; within "
                     << kSatelliteMm << " mm: " << near.components << " pieces and " << near.specks
                     << " specks");
  CHECK(head.components == 1);
  CHECK(head.fill >= kMinHeadFill);
  CHECK(near.components == 1);
}

TEST_CASE("marks: a calligraphy stroke's head is about as wide as its body and on its line",
          "[marks]") {
  // A calligrapher's entry leaves a head about as wide as the body that
  // follows it, or a little wider, centred on the stroke's line; not a bead
  // beside it. The head is the ink before kPressedXMm + 2 (where the press
  // reaches the body's depth, and the bundle's reach beyond the handle), the
  // body the kBodyMm after kPressedXMm + 4. Its width: at most kMaxHeadToBody
  // of the body's mean (a bead fails it: the brush with its point in one
  // segment and a leaning centre spine measures 1.45 on this entry, 2.7
  // pressed to 4 mm while barely moving). On the line: every column of the
  // head at least half its width wide has its ink's middle within kMaxOffset
  // of the head's width of y = 15 (that brush measures 0.34: its bundle lays
  // over to +y by the centre spine's rest angle, whatever the stroke's
  // direction).
  constexpr double kMaxHeadToBody = 1.35, kMaxOffset = 0.15, kBodyMm = 4;
  const char* name = GENERATE("calligraphy", "calligraphy-wang2020");
  INFO(name);
  TempDir dir;
  const WidthProfile p = widthProfile(renderCalligraphyEntry(name, dir));
  REQUIRE_FALSE(p.empty());
  const auto column = [&](double x_mm) { return static_cast<int>(std::floor(x_mm * 8)); };
  double head = 0, body = 0;
  for (int c = p.first; c < column(kPressedXMm + 2); ++c) head = std::max(head, p.width_mm[c]);
  const int b0 = column(kPressedXMm + 4), b1 = column(kPressedXMm + 4 + kBodyMm);
  for (int c = b0; c < b1; ++c) body += p.width_mm[c] / (b1 - b0);
  double offset = 0;
  for (int c = p.first; c < column(kPressedXMm + 2); ++c)
    if (p.width_mm[c] >= 0.5 * head)
      offset = std::max(offset, std::fabs(p.centre_mm[c] - kEntryYMm));
  INFO("head " << head << " mm, body " << body << " mm, head off the line by up to " << offset
               << " mm");
  CHECK(head <= kMaxHeadToBody * body);
  CHECK(offset <= kMaxOffset * head);
}

TEST_CASE("marks: the calligraphy brush widens smoothly through its point's lie-down",
          "[marks]") {
  // Pulled upright, as the 永 painting holds it, at 2 to 5 mm of press, where
  // the point's last 4 mm lie down: a real 30 mm brush widens by about
  // kRealSlope mm per mm there (data/real-brushes/wang2020-calligraphy.csv:
  // 2.2, 3.0, 3.5 and 5.2 mm wide at 2, 3, 4 and 5 mm). No half millimetre of
  // press may widen the stroke by more than kSlopeFactor times that rate
  // (the factor of the linearity test above): with the point one rigid 4 mm
  // segment it lay down at once, and the stroke went from 2.4 to 3.6 mm wide
  // between 3.5 and 4 mm (2.4 mm per mm), the step behind the 永 painting's
  // bead-like heads.
  constexpr double kRealSlope = 1.1, kSlopeFactor = 1.5;
  TempDir dir;
  std::vector<double> depths, widths;
  for (double d = 2; d <= 5 + 1e-9; d += 0.5) {
    Case c = pullCase(d / 30);
    c.tilt_deg = 0;
    const Coverage img = renderCase("calligraphy", c, dir, "smooth" + std::to_string(d));
    depths.push_back(d);
    widths.push_back(meanWidthMm(widthProfile(img)));
  }
  std::ostringstream seen;
  for (size_t i = 0; i < widths.size(); ++i) seen << ' ' << depths[i] << ':' << widths[i];
  INFO("depth:width (mm):" << seen.str());
  for (size_t i = 1; i < widths.size(); ++i)
    CHECK((widths[i] - widths[i - 1]) / (depths[i] - depths[i - 1]) <=
          kSlopeFactor * kRealSlope);
}

TEST_CASE("marks: the calligraphy brushes pressed straight down leave one smooth blot",
          "[marks]") {
  // Pressed straight down to 0.4 of its hair (12 mm, the golden's press),
  // held and lifted, a wet calligraphy brush lays its belly over as one body
  // and leaves one rounded blot. Every speck counts (no size below which ink
  // is ignored, unlike the test of every brush above): a tip that sticks out
  // of the bundle prints apart from it. Filled: >= kMinFill of its convex
  // hull, where a teardrop with a spike or a lobed edge (the hand-tuned
  // brush's 0.92 before its hair held together, the fitted one's 0.91) falls
  // short; the hand-tuned brush's rounded blot measures 0.97.
  constexpr double kMinFill = 0.95;
  const char* name = GENERATE("calligraphy", "calligraphy-wang2020");
  INFO(name);
  TempDir dir;
  const BlotStats b =
      blotStats(renderCase(name, pressLiftCase(0.4), dir, "smooth-blot", "ipopt"), 0.1, 1);
  INFO("components " << b.components << ", fill " << b.fill);
  CHECK(b.components == 1);
  CHECK(b.fill >= kMinFill);
}

TEST_CASE("marks: the calligraphy brush pressed straight down leaves a round blot under the handle",
          "[marks]") {
  // Pressed straight down past its point, a full round brush's belly is
  // squashed and spreads all round the handle (docs/dynamics.md, "The point
  // lies down before the belly squashes"): a round blot centred under the
  // handle, not the bundle laid over to one side as one body, a lozenge
  // whose ink sat 3.9-6.0 mm off the handle (axes 1.18-1.43). At 0.35, 0.4 and
  // 0.45 of the hair (10.5-13.5 mm): whether a straight press lays over or
  // spreads is a buckling branch, and one depth alone could pass by luck.
  // Ipopt, the reference (SLSQP's blot at 0.4 is as round: axes 1.17,
  // 0.8 mm off). Limits as the round's blot test (tests/cli/test_cli_round.cpp):
  // axes at most kMaxRatio, a blot a painter calls round; the ink's
  // centroid within kMaxOffsetMm of the handle (at x-y 0, 0), a sixth of
  // the blot's ~19 mm.
  constexpr double kMaxRatio = 1.3, kMaxOffsetMm = 1.5;
  const double fraction = GENERATE(0.35, 0.4, 0.45);
  INFO("pressed " << fraction << " of the hair");
  TempDir dir;
  const Coverage img =
      renderCase("calligraphy", pressLiftCase(fraction), dir, "round-blot", "ipopt");
  const BlotStats b = blotStats(img, 0.1, 1);
  const double ratio = principalAxisRatio(img, 0.1);
  double cx = 0, cy = 0;
  REQUIRE(inkCentroidMm(img, 0.1, &cx, &cy));
  const double offset = std::hypot(cx, cy);
  INFO("components " << b.components << ", fill " << b.fill << ", axis ratio " << ratio
                     << ", ink centroid " << offset << " mm from the handle");
  CHECK(b.components == 1);
  CHECK(ratio <= kMaxRatio);
  CHECK(offset <= kMaxOffsetMm);
}

TEST_CASE("marks: the calligraphy brush's spreading press walks its point out instead of throwing it",
          "[marks]") {
  // Where the squash starts, the point laid down across the axis is inside
  // the spread's target by millimetres. The push ramps in with the squash
  // (volume.spread_ramp, docs/dynamics.md "The spread ramps in") so that it
  // grows from nothing between steps and moves the hair out over several
  // steps; switched on whole, it threw the point round the axis within a
  // step, more than a step may move the touching hair, and the stepper
  // halved 960 steps of this press (8 mm past contact, 3 px/mm) where the
  // ramp halves 64 and the brush laid over, with no spread, 30. At most
  // kMaxSplitSteps: twice the ramp's, an eighth of the switch's.
  constexpr int kMaxSplitSteps = 128;
  TempDir dir;
  const std::string stats = dir.file("press.json");
  const RunResult r = runBristle(
      "render -q --solver ipopt --px-per-mm 3 --brush '" +
      sourcePath("scenes/brushes/calligraphy.json") + "' --trajectory '" +
      sourcePath("scenes/trajectories/depth/press-lift.csv") + "' -o '" + dir.file("press.png") +
      "' --stats '" + stats + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream f(stats);
  const nlohmann::json j = nlohmann::json::parse(f);
  const int splits = j.at("jump_split_steps").get<int>();
  INFO("split steps " << splits << ", solver iterations " << j.at("solver_iterations"));
  CHECK(j.at("failed_steps").get<int>() == 0);
  CHECK(splits <= kMaxSplitSteps);
}

TEST_CASE("marks: a fan's pull draws a few distinct lines on the default paper", "[marks]") {
  // The grass stroke: wet hair gathers into bunches, and each bunch draws a
  // line. Broadside at 30 % of the hair, on bristle's default paper (tooth
  // 0.03 mm) and on paper with no tooth.
  TempDir dir;
  const Brush fan = loadBrush(sourcePath("scenes/brushes/fan.json"));
  REQUIRE(fan.strips.clumps > 0);
  const Coverage toothy = renderCase("fan", pullCase(0.3), dir, "toothy");
  const Coverage smooth = renderCase("fan", pullCase(0.3), dir, "smooth", "", "--paper-tooth 0");
  // Cross-sections at 30, 50 and 70 % of the inked span along the pull.
  double lo = 0, hi = 0;
  REQUIRE(inkXRangeMm(toothy, 0.1, &lo, &hi));
  for (double f : {0.3, 0.5, 0.7}) {
    const int col = static_cast<int>(std::floor(((lo + f * (hi - lo)) - toothy.x0_mm) *
                                                toothy.px_per_mm));
    const int lines = lineCount(toothy, col);
    INFO("cross-section at " << f << " of the span: " << lines << " lines");
    // At least 3 distinct lines (the acceptance figure) ...
    CHECK(lines >= 3);
    // ... and no more than two per bunch (a bunch straddling a pixel boundary
    // or broken by the grain can show as two): a few lines, not the 36-47
    // separate hairlines the 160 strips draw unclumped.
    CHECK(lines <= 2 * fan.strips.clumps);
  }
  // Visible: the default tooth keeps at least 25 % of the coverage the same
  // pull has on paper with no tooth (the acceptance figure). Single hairs that
  // did not follow the grain (docs/paint.md) would keep 13 %: dust.
  const long toothy_px = inkedPixels(toothy), smooth_px = inkedPixels(smooth);
  INFO("inked pixels: " << toothy_px << " with the default tooth, " << smooth_px << " without");
  REQUIRE(smooth_px > 0);
  CHECK(static_cast<double>(toothy_px) >= 0.25 * static_cast<double>(smooth_px));
}

TEST_CASE("marks: a fan pulled along its own row draws a continuous fine line", "[marks]") {
  // Edge-on, every hair tip runs along one line about 0.1 mm wide, finer than
  // a pixel: a painter's fan then draws a thin line (twigs, grass blades). The
  // footprint sampled pixel centres only and, with the line between two rows
  // of them, kept nothing: the library sheet's fan on the straight pull was
  // blank (docs/paint.md, "Hair finer than a pixel").
  TempDir dir;
  const std::string png = dir.file("fan-edge-on.png");
  const RunResult r = runBristle(
      "render -q --solver slsqp --brush '" + sourcePath("scenes/brushes/fan.json") +
      "' --trajectory '" + sourcePath("scenes/trajectories/depth/straight-pull.csv") +
      "' -o '" + png + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.find("no visible paint") == std::string::npos);
  const Coverage img = loadCoveragePng(png);
  double x0 = 0, x1 = 0;
  REQUIRE(inkXRangeMm(img, 0.1, &x0, &x1));
  INFO("ink from x = " << x0 << " to " << x1 << " mm");
  // At least the handle's 55 mm of travel (the tips trail and lead it).
  CHECK(x1 - x0 >= 55);
  // Continuous: at least 90 % of the columns along it hold ink (measured
  // 99 %; the gaps are where the grain's valleys take a whole column).
  const int c0 = static_cast<int>(std::floor((x0 - img.x0_mm) * img.px_per_mm));
  const int c1 = static_cast<int>(std::floor((x1 - img.x0_mm) * img.px_per_mm));
  int inked = 0;
  std::vector<int> rows;
  for (int c = c0; c <= c1; ++c) {
    bool any = false;
    for (int row = 0; row < img.h; ++row)
      if (img.at(c, row) >= 0.1f) {
        any = true;
        if (std::find(rows.begin(), rows.end(), row) == rows.end()) rows.push_back(row);
      }
    inked += any;
  }
  const double share = double(inked) / (c1 - c0 + 1);
  INFO("inked columns: " << share << ", rows with ink: " << rows.size());
  CHECK(share >= 0.9);
  // Fine: a line, not a band. At most 3 rows (0.375 mm) of ink; measured 2.
  CHECK(rows.size() <= 3u);
}

TEST_CASE("marks: paint laid down converges as the steps shrink", "[marks][transfer]") {
  // Transfer rates are per unit of contact time, not per step (docs/paint.md,
  // "Transfer per unit of contact time"). The round's straight pull at
  // --max-step-mm 0.1 and 0.05 leaves the same paint on the paper to 5 % (the
  // acceptance figure; measured 1.1 %, where per-step rates laid 111 against
  // 204 mm^3), and the two images agree to an SSIM of 0.99 (the "loose" golden
  // tolerance of docs/golden-tests.md: saturated strokes differ only at their
  // edges). What stays on the paper is what the brush laid down less what it
  // picked back up: the wet paint it lays and lifts again under the same pass
  // churns by a step-dependent amount (gross 50.7 against 53.3 mm^3, 4.9 %).
  // Both solvers: SLSQP converges as Ipopt does only because it solves the
  // spines that hair volume couples as one block (docs/dynamics.md).
  const std::string solver = GENERATE("slsqp", "ipopt");
  INFO(solver);
  TempDir dir;
  auto onPaper = [&](const std::string& step) {
    const std::string png = dir.file("pull-" + step + ".png");
    const std::string stats = dir.file("pull-" + step + ".json");
    const RunResult r = runBristle(
        "render -q --solver " + solver + " --brush '" + sourcePath("scenes/brushes/round.json") +
        "' --trajectory '" + sourcePath("scenes/trajectories/straight-pull.csv") +
        "' --max-step-mm " + step + " -o '" + png + "' --stats '" + stats + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    std::ifstream f(stats);
    const nlohmann::json j = nlohmann::json::parse(f);
    return j.at("paint_laid_mm3").get<double>() - j.at("paint_picked_up_mm3").get<double>();
  };
  const double coarse = onPaper("0.1"), fine = onPaper("0.05");
  INFO("on the paper: " << coarse << " mm^3 at 0.1 mm steps, " << fine << " at 0.05");
  REQUIRE(fine > 0);
  CHECK(std::abs(coarse - fine) <= 0.05 * fine);
  const RunResult cmp = runBristle("compare '" + dir.file("pull-0.1.png") + "' '" +
                                   dir.file("pull-0.05.png") + "' --min-ssim 0.99");
  INFO(cmp.out << cmp.err);
  CHECK(cmp.code == 0);
}

TEST_CASE("marks: a flat's broadside pull has square ends", "[marks]") {
  // A flat's hairs end together in a straight edge, so its stroke starts and
  // stops square: where the ink starts, and where it stops, varies by under
  // 1 mm across the stroke's whole width (the acceptance figure).
  //
  // When the spines' bundles were round and ended in domes, each spine left a
  // bump: the start varied by 1.9 mm (flat) and 1.8 mm (bright), the stop by
  // 1.5 and 1.9 mm. Cut tips (kTipCapDepth) squared the start; slab sections
  // (SpineSpec::thickness_mm) and a surface that is pressed no deeper than
  // its bundles squared the stop to 1.0 mm (flat) and 0.5 mm (bright); square
  // corners (kSlabSectionExponent 24) and a surface that rises with its
  // bundles (bundlePlacement) to 0.75 and 0.375 mm. The start varies by
  // 0.375 mm for both. What is left of the flat's stop is its outermost
  // pixel row each side: the row's flare recedes as it lifts.
  const char* name = GENERATE("flat", "bright");
  INFO(name);
  TempDir dir;
  const Coverage img = renderCase(name, pullCase(0.3), dir, "pull");
  const EndSpread e = endSpread(img, Axis::kX);
  INFO("over the whole width the ends vary by " << e.start_mm << " mm (start) and " << e.stop_mm
                                                << " mm (stop)");
  REQUIRE(e.lanes > 0);
  CHECK(e.start_mm < 1.0);
  CHECK(e.stop_mm < 1.0);
}

namespace {

// Streak measure over the body of a stroke along x: the middle 60 % of its
// length, and its width less 1 mm at each side (the edges are a step in ink
// across the stroke, which would count as a streak).
double bodyAnisotropy(const Coverage& img) {
  double lo = 0, hi = 0;
  REQUIRE(inkXRangeMm(img, 0.1, &lo, &hi));
  const int c0 = static_cast<int>((lo + 0.2 * (hi - lo) - img.x0_mm) * img.px_per_mm);
  const int c1 = static_cast<int>((lo + 0.8 * (hi - lo) - img.x0_mm) * img.px_per_mm);
  int r0 = img.h, r1 = -1;
  for (int r = 0; r < img.h; ++r)
    for (int c = c0; c < c1; c += 4)
      if (img.at(c, r) > 0.1) {
        r0 = std::min(r0, r);
        r1 = std::max(r1, r);
      }
  const int edge = static_cast<int>(std::ceil(img.px_per_mm));
  return streakAnisotropy(img, c0, c1, r0 + edge, r1 - edge, Axis::kX);
}

}  // namespace

TEST_CASE("marks: a flat's paint streaks along the stroke", "[marks]") {
  // The hairs differ in the paint they hold and lay (BrushTexelMap::
  // hairNoise) and keep their place in the bundle, so the film is thicker
  // under some hairs than others all along the stroke: streaks along travel.
  // Measured by the structure tensor of the ink over the stroke's body
  // (streakAnisotropy: +1 streaks exactly along, 0 no direction).
  TempDir dir;
  // A glaze (ultramarine, whose colour shows the film's thickness) at full
  // load. Before hairs differed the fill was even: 0.0 (the paper's grain
  // dots only).
  const Coverage glaze = renderCase("flat", pullCase(0.3), dir, "glaze", "", "--paint ultramarine");
  const double a_glaze = bodyAnisotropy(glaze);
  // Dry brush: little paint on toothy paper. The best-loaded hairs keep
  // drawing lines that the grain breaks; before, the grain's dots: 0.02.
  const Coverage dry = renderCase("flat", pullCase(0.3), dir, "dry", "",
                                  "--amount 0.15 --paper-tooth 0.06");
  const double a_dry = bodyAnisotropy(dry);
  INFO("anisotropy: glaze " << a_glaze << ", dry brush " << a_dry);
  // Measured 0.99 and 0.23 (and 0.98 and 0.21 on the broadside-pull scene of
  // docs/paint.md). The thresholds sit at about half of those, well above
  // what the grain alone gives (|a| <= 0.02, the "before" figures above).
  CHECK(a_glaze > 0.5);
  CHECK(a_dry > 0.1);
}

TEST_CASE("marks: a double-loaded flat blends its two paints where they meet", "[marks]") {
  // Cadmium red on the brush's -x half, titanium white on its +x half, worked
  // into each other over the middle 30 % of the width on the palette
  // (docs/paint.md, "Loading"). Pulled broadside, the stroke is red along
  // one side and white along the other, with a pink zone between that
  // changes gradually: no hard stripe at a spine's edge.
  TempDir dir;
  (void)renderCase("flat", pullCase(0.3), dir, "double", "",
                   "--paint cadmium-red,titanium-white --load across");
  const render::Image8 png = render::readPngRgba8(dir.file("flat-double.png"));
  const int w = png.width, h = png.height;
  auto px = [&](int c, int r) { return &png.pixels[(static_cast<size_t>(r) * w + c) * 4]; };
  // Redness (R - B) per row across the stroke, averaged over the middle 40 %
  // of its inked length.
  const std::uint8_t* paper = px(0, 0);
  int c_lo = w, c_hi = -1, r_lo = h, r_hi = -1;
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const std::uint8_t* p = px(c, r);
      if (std::abs(p[0] - paper[0]) + std::abs(p[1] - paper[1]) + std::abs(p[2] - paper[2]) > 30) {
        c_lo = std::min(c_lo, c);
        c_hi = std::max(c_hi, c);
        r_lo = std::min(r_lo, r);
        r_hi = std::max(r_hi, r);
      }
    }
  REQUIRE(c_hi > c_lo);
  const int c0 = c_lo + (c_hi - c_lo) * 3 / 10, c1 = c_lo + (c_hi - c_lo) * 7 / 10;
  // The stroke's own edges are a step from paint to paper (their pixels
  // partly covered): the profile leaves out 2 rows (0.25 mm) at each side.
  std::vector<double> red;
  for (int r = r_lo + 2; r <= r_hi - 2; ++r) {
    double sum = 0;
    for (int c = c0; c < c1; ++c) sum += px(c, r)[0] - px(c, r)[2];
    red.push_back(sum / (c1 - c0));
  }
  const auto [mn, mx] = std::minmax_element(red.begin(), red.end());
  const double range = *mx - *mn;
  REQUIRE(range > 50);  // red against white: R - B differs by ~150 of 255
  double biggest_step = 0;
  int blended = 0;
  for (size_t i = 0; i < red.size(); ++i) {
    const double f = (red[i] - *mn) / range;
    blended += f > 0.15 && f < 0.85;
    if (i > 0) biggest_step = std::max(biggest_step, std::fabs(red[i] - red[i - 1]) / range);
  }
  const double px_per_mm = loadCoveragePng(dir.file("flat-double.png")).px_per_mm;
  const double blended_mm = blended / px_per_mm;
  INFO("blended zone " << blended_mm << " mm; the largest step between neighbouring rows is "
                       << biggest_step << " of the red-white range");
  // The palette's blend is 30 % of the 13 mm width, 3.9 mm; the stroke
  // shows at least 1.5 mm of it ...
  CHECK(blended_mm >= 1.5);
  // ... with no hard edge: no single row-to-row step of more than 0.4 of the
  // whole change. A stripe's edge was a step of 0.6; the blend, sampled by
  // the brush texture's 32 columns (0.4 mm, 3 rows, each) and drawn by five
  // spines whose bundles meet in seams, moves in steps of up to 0.28
  // (measured).
  CHECK(biggest_step < 0.4);
}

namespace {

// A pull in press depths past first contact (docs/formats.md, "Heights
// relative to the paper"): from `hover_mm`, down to `press_mm` in 0.3 s, 20 mm
// along +x in 0.6 s, back up to `hover_mm` in 0.3 s, the handle held at `q`.
std::string depthPullCsv(double hover_mm, double press_mm, const Eigen::Quaterniond& q) {
  std::ostringstream f;
  f << "# bristle-trajectory/1\nt_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz\n" << std::setprecision(10);
  auto row = [&](double t, double x, double depth) {
    f << t << ',' << x << ",0," << depth << ',' << q.w() << ',' << q.x() << ',' << q.y() << ','
      << q.z() << '\n';
  };
  for (int i = 0; i <= 30; ++i) row(0.01 * i, 0, hover_mm + (press_mm - hover_mm) * i / 30.0);
  for (int i = 1; i <= 60; ++i) row(0.3 + 0.01 * i, 20.0 * i / 60, press_mm);
  for (int i = 1; i <= 30; ++i) row(0.9 + 0.01 * i, 20, press_mm + (hover_mm - press_mm) * i / 30.0);
  return f.str();
}

}  // namespace

TEST_CASE("marks: one depth trajectory presses every library brush alike and a hover not at all",
          "[marks][depth]") {
  // The same file for every brush, no lift per brush: 4 mm past first contact.
  // In ferrule heights made for the 20 mm round, the same pull would leave
  // the 11 mm bright (first contact at 13 mm, tilted 20 degrees) no mark and
  // start the 30 mm calligraphy brush (28.4 mm) with its hairs in the paper.
  const char* name = GENERATE("round", "flat", "bright", "filbert", "badger", "fan", "calligraphy");
  INFO(name);
  TempDir dir;
  const std::string brush = sourcePath("scenes/brushes/" + std::string(name) + ".json");
  const Brush loaded = loadBrush(brush);
  const std::string solver = loaded.volume.present() ? "ipopt" : "slsqp";
  // Tilted 20 degrees back from the pull (the hairs trail); a brush whose hair
  // lies in a row is turned a quarter about its axis to be pulled broadside,
  // as renderCase does, and its first contact follows it with no shift by hand.
  Eigen::Quaterniond q = tiltRotation(20);
  if (rowBrush(loaded))
    q = q * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  auto render = [&](const std::string& stem, double hover_mm, double press_mm) {
    const std::string csv = dir.write(stem + ".csv", depthPullCsv(hover_mm, press_mm, q));
    const std::string png = dir.file(stem + ".png");
    RunResult r = runBristle("render -q --solver " + solver + " --brush '" + brush +
                             "' --trajectory '" + csv + "' -o '" + png + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("failed solve") == std::string::npos);
    r.out = png;
    return r;
  };
  const RunResult pressed = render("pressed", -3, 4);
  const Coverage img = loadCoveragePng(pressed.out);
  double x0 = 0, x1 = 0;
  REQUIRE(inkXRangeMm(img, 0.1, &x0, &x1));
  INFO("ink from x = " << x0 << " to " << x1 << " mm");
  // Every brush touches all along the 20 mm pull: the mark is the contact
  // patch swept 20 mm, so at least that long, less a pixel at each end
  // (measured: 25.1 to 29.6 mm over the seven brushes).
  CHECK(x1 - x0 >= 20 - 2 * kMarkPixelMm);

  // Held 1 mm above first contact all the way, it never touches: a blank image
  // and render's warning saying so.
  const RunResult hover = render("hover", -3, -1);
  CHECK_THAT(hover.err, Catch::Matchers::Contains("never touched the canvas"));
  CHECK(inkedPixels(loadCoveragePng(hover.out)) == 0);
}

TEST_CASE("marks: the paint laid does not depend on the resolution past a large footprint",
          "[marks][footprint]") {
  // The fan pressed down on depth/press-lift.csv has a footprint window over
  // 2,048 px a side at 60 px/mm, more than the GL target holds: it is drawn in
  // tiles (render/stroke_renderer.cpp), so the paint laid at 60 px/mm is the
  // paint laid at 40 px/mm to within the discretisation (measured 1.245
  // against 1.224 mm^3, 1.7 %). The tolerance, 5 %, is over twice the spread
  // the discretisation alone gives where every window fits the target (1.250,
  // 1.224 and 1.233 mm^3 at 30, 40 and 50 px/mm: 2.1 %), and far from what a
  // dropped footprint costs (0.066 mm^3 at 60 px/mm when windows over 2,048
  // px were skipped).
  constexpr double kTolerance = 0.05;
  TempDir dir;
  auto laid = [&](const std::string& px_per_mm) {
    const std::string stats = dir.file("fan-" + px_per_mm + ".json");
    const RunResult r = runBristle(
        "render -q --brush '" + sourcePath("scenes/brushes/fan.json") + "' --trajectory '" +
        sourcePath("scenes/trajectories/depth/press-lift.csv") + "' --px-per-mm " + px_per_mm +
        " -o '" + dir.file("fan-" + px_per_mm + ".png") + "' --stats '" + stats + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    std::ifstream f(stats);
    return nlohmann::json::parse(f).at("paint_laid_mm3").get<double>();
  };
  const double at40 = laid("40"), at60 = laid("60");
  INFO("paint laid: " << at40 << " mm^3 at 40 px/mm, " << at60 << " at 60 px/mm");
  REQUIRE(at40 > 0);
  CHECK(std::abs(at60 - at40) <= kTolerance * at40);
}

namespace {

// The badger's marks are measured in ultramarine, a glaze: its colour deepens
// with the film's thickness, so a thinner film at the rim shows as a lighter
// edge (the default paint, an opaque near-black, is black at any film that
// can be seen and would hide it). 4 px/mm keeps each render to a few seconds.
constexpr double kBadgerPpm = 4;
const char* const kGlazeAt4 = "--paint ultramarine --px-per-mm 4";

// The mean 10-90 % ramp of both edges of a pull along +x, over the middle
// 60 % of its length.
EdgeRamp pullEdgeRamp(const Coverage& img) {
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  const SpanRange mid = middleRange(p);
  return edgeRamp(crossProfile(img, Axis::kX, mid.lo, mid.hi), img.px_per_mm);
}

// The profile along a stroke that runs along +x: the mean ink of each column
// over the stroke's rows (those whose mean over the whole image is at least
// 10 % of the darkest row's).
std::vector<double> alongProfile(const Coverage& img) {
  const std::vector<double> rows = crossProfile(img, Axis::kX, 0, img.w);
  const double peak = *std::max_element(rows.begin(), rows.end());
  int r0 = 0, r1 = img.h;
  while (r0 < r1 && rows[static_cast<size_t>(r0)] < 0.1 * peak) ++r0;
  while (r1 > r0 && rows[static_cast<size_t>(r1 - 1)] < 0.1 * peak) --r1;
  return crossProfile(img, Axis::kY, r0, r1);
}

// The q-quantile of the ink of the inked pixels (ink > kInked) in columns
// [c0, c1) of a mark; 0 when none is inked.
constexpr float kInked = 0.1f;
double inkedQuantile(const Coverage& img, int c0, int c1, double q) {
  std::vector<float> ink;
  for (int r = 0; r < img.h; ++r)
    for (int c = std::max(c0, 0); c < std::min(c1, img.w); ++c)
      if (img.at(c, r) > kInked) ink.push_back(img.at(c, r));
  if (ink.empty()) return 0;
  const size_t k = std::min(ink.size() - 1, static_cast<size_t>(q * ink.size()));
  std::nth_element(ink.begin(), ink.begin() + static_cast<std::ptrdiff_t>(k), ink.end());
  return ink[k];
}

// A golden's badger stroke (golden/golden.json): scenes/trajectories'
// `trajectory` in burnt umber (a glaze), SLSQP, 8 px/mm, the brush raised by
// `lift_mm` as its golden holds it. Returns the mark's coverage.
struct GoldenStroke {
  const char* trajectory;
  const char* lift_mm;
};
Coverage renderBadgerGolden(const GoldenStroke& k, const TempDir& dir) {
  const std::string png = dir.file(std::string(k.trajectory) + ".png");
  const RunResult run = runBristle(
      "render -q --solver slsqp --paint burnt-umber --offset-mm 0 0 " + std::string(k.lift_mm) +
      " --brush '" + sourcePath("scenes/brushes/badger.json") + "' --trajectory '" +
      sourcePath("scenes/trajectories/" + std::string(k.trajectory) + ".csv") + "' -o '" + png +
      "'");
  INFO(k.trajectory << ": " << run.err);
  REQUIRE(run.code == 0);
  return loadCoveragePng(png);
}

}  // namespace

TEST_CASE("marks: a loaded badger lays its pull to the end, as the round does",
          "[marks][badger]") {
  // The library sheet's pull (depth/straight-pull.csv: 6.5 mm of press,
  // 55 mm along +x), each brush with its default load. A loaded softener lays
  // a long, soft stroke: its belly feeds the tips that touch as they run
  // drier than it (docs/paint.md, "Unabsorbent hair"). With no flow at all
  // in its hair, its tips ran dry and the pull faded into dry-brush dots.
  TempDir dir;
  auto pull = [&](const std::string& name) {
    const std::string png = dir.file(name + "-long.png");
    const RunResult run = runBristle(
        "render -q --solver slsqp " + std::string(kGlazeAt4) + " --brush '" +
        sourcePath("scenes/brushes/" + name + ".json") + "' --trajectory '" +
        sourcePath("scenes/trajectories/depth/straight-pull.csv") + "' -o '" + png + "'");
    INFO(run.err);
    REQUIRE(run.code == 0);
    return alongProfile(loadCoveragePng(png));
  };
  const std::vector<double> badger = pull("badger"), round = pull("round");
  // How far each lays paint before its ink along the path falls under a
  // share of its start (inkRunMm: its mean 2-10 mm past where it starts).
  const double b50 = inkRunMm(badger, kBadgerPpm, 0.5), r50 = inkRunMm(round, kBadgerPpm, 0.5);
  const double b30 = inkRunMm(badger, kBadgerPpm, 0.3), r30 = inkRunMm(round, kBadgerPpm, 0.3);
  INFO("run to half its start: badger " << b50 << " mm, round " << r50 << " mm; to 30 %: badger "
       << b30 << " mm, round " << r30 << " mm");
  // Half its start: where a painter sees the stroke fade. The round keeps its
  // level to the lift (61.5 mm); the badger fades on the way, at 44.8 mm
  // (30.5 mm when its tips ran dry). Asked: 0.6 of the round's, the paint the
  // badger holds against the round per mm^2 of hair (paint.capacity 0.6):
  // it may run out sooner by its load, not by starving its tips.
  constexpr double kLoadShare = 0.6;
  CHECK(b50 >= kLoadShare * r50);
  // And it still lays, faint, to the end of the pull as the round does: 30 %
  // of its start is reached at the lift (62.8 mm; 36.5 mm when it ran dry,
  // the rest dry-brush dots). Asked: 0.9 of the round's, the lift's last
  // few mm (the round's own end fades over 5 mm) left to either.
  constexpr double kToTheEnd = 0.9;
  CHECK(b30 >= kToTheEnd * r30);
}

namespace {

// How the ink of a badger pull along +x runs from end to end: the darkest
// tenth of its first 5 mm (the landing), the median of its last 8 mm (the
// end) and of its body (30-70 % of its length), each over its inked pixels.
struct BadgerEnds {
  double landing = 0, end = 0, middle = 0;
};
BadgerEnds badgerEnds(const Coverage& img) {
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  const SpanRange all = middleRange(p, 0.0, 1.0), body = middleRange(p, 0.3, 0.7);
  const int head = static_cast<int>(std::lround(5 * img.px_per_mm)),
            tail = static_cast<int>(std::lround(8 * img.px_per_mm));
  return {inkedQuantile(img, all.lo, all.lo + head, 0.9),
          inkedQuantile(img, all.hi - tail, all.hi, 0.5),
          inkedQuantile(img, body.lo, body.hi, 0.5)};
}

// How far the ink rises again over the lift's stretch: the last 25 mm of the
// mark (the dome's 14 mm and the 8-10 mm its hair springs forward as it
// lifts), in 1 mm bands, each band's median ink (inkedQuantile); the largest
// rise of a band over the lowest band before it.
double liftRebound(const Coverage& img) {
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  const SpanRange all = middleRange(p, 0.0, 1.0);
  const int band = static_cast<int>(std::lround(img.px_per_mm));
  const int from = all.hi - 25 * band;
  double lowest = 1, rise = 0;
  for (int c = from; c + band <= all.hi; c += band) {
    const double ink = inkedQuantile(img, c, c + band, 0.5);
    lowest = std::min(lowest, ink);
    rise = std::max(rise, ink - lowest);
  }
  return rise;
}

// The deepest interior dip of a stroke's cross-profile, as a share of the
// profile's median: the profile is the mean ink of each row over the middle
// 60 % of a pull along +x, trimmed to the rows at 10 % of its peak or more
// (the edges' ramps left out); a dip is how far a row lies below the lower of
// the highest rows on either side of it. A stroke laid as one film has none
// beyond its grain; one laid as parallel tubes, a pale line between each two.
double deepestCrossDip(const Coverage& img) {
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  const SpanRange mid = middleRange(p);
  std::vector<double> prof = crossProfile(img, Axis::kX, mid.lo, mid.hi);
  const double peak = *std::max_element(prof.begin(), prof.end());
  auto inked = [&](double v) { return v >= 0.1 * peak; };
  const auto first = std::find_if(prof.begin(), prof.end(), inked);
  const auto last = std::find_if(prof.rbegin(), prof.rend(), inked);
  prof = std::vector<double>(first, last.base());
  std::vector<double> left(prof.size()), right(prof.size());
  for (size_t i = 0; i < prof.size(); ++i) left[i] = std::max(i ? left[i - 1] : 0.0, prof[i]);
  for (size_t i = prof.size(); i-- > 0;)
    right[i] = std::max(i + 1 < prof.size() ? right[i + 1] : 0.0, prof[i]);
  double dip = 0;
  for (size_t i = 1; i + 1 < prof.size(); ++i)
    dip = std::max(dip, std::min(left[i - 1], right[i + 1]) - prof[i]);
  std::vector<double> sorted = prof;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return dip / sorted[sorted.size() / 2];
}

}  // namespace

TEST_CASE("marks: the badger's pulls fade in and out with no darker patch, one soft film",
          "[marks][badger]") {
  // The goldens' tilted drag and straight pull (burnt umber, a glaze; SLSQP,
  // 8 px/mm): the dome lands and stands 0.1 s, is drawn along +x, stops and
  // lifts. Each is rendered once and measured three ways.
  TempDir dir;
  for (const GoldenStroke& k :
       {GoldenStroke{"tilted-drag", "3"}, GoldenStroke{"straight-pull", "3.1"}}) {
    INFO(k.trajectory);
    const Coverage img = renderBadgerGolden(k, dir);

    // A softener's mark fades in and out. While its hair laid paint at the
    // same rate standing as sliding, the film under the standing dome
    // settled darker than the drawn body's: a blot where it landed
    // (docs/paint.md, "Flags lay as they slide").
    const BadgerEnds e = badgerEnds(img);
    INFO("first 5 mm: 90th percentile of ink " << e.landing << "; last 8 mm: median " << e.end
         << "; body (30-70 % of its length): median " << e.middle);
    // Fades in: the darkest tenth of the first 5 mm no darker than the
    // body's median. Measured 0.48 against 0.70 (tilted drag) and 0.63
    // against 0.69 (straight pull); 0.63 against 0.53 and 0.60 against 0.60
    // while standing hair laid as sliding hair does.
    constexpr double kFadeIn = 1.0;
    CHECK(e.landing <= kFadeIn * e.middle);
    // Fades out: the last 8 mm's median at most three quarters of the
    // body's, a visibly lighter end (0.48 against 0.70, 0.35 against 0.69).
    constexpr double kFadeOut = 0.75;
    CHECK(e.end <= kFadeOut * e.middle);

    // No darker patch at the lift. As the handle lifts, the unloading hair
    // springs forward over the paper at 100-160 mm/s. Hair that bears almost
    // no load only brushes the paper (docs/paint.md, "Pressed hair gives and
    // takes, resting hair barely"); while it laid and took up paint at the
    // full rate, those tips settled the paper they swept to the full
    // balance: the ink along the stroke fell and then rose again before it
    // faded.
    const double rise = liftRebound(img);
    INFO("largest rise of the ink over the last 25 mm: " << rise);
    // A rise of 0.12 (a fifth of the body's median ink, 0.6) is a patch a
    // painter sees darker than the stroke behind it. Measured 0.08 (tilted
    // drag) and 0.11 (straight pull: its hair's tips standing still where the
    // stroke stops, before it lifts); 0.26 and 0.14 while the springing
    // hair laid and took up paint at the full rate.
    constexpr double kNoRebound = 0.12;
    CHECK(rise <= kNoRebound);

    // One film, not a bundle of tubes. A softener's hair is fine and dense:
    // its mark is one haze, darker nowhere in particular across it. With the
    // flagged rim measured on each bundle's outline, every bundle's trailing
    // tip laid little and scrubbed what it slid over, a pale line beside
    // each: the mark read as four or five tubes side by side (docs/paint.md,
    // "The rim is the head's outline").
    const double dip = deepestCrossDip(img);
    INFO("deepest dip across the body " << dip << " of its median");
    // Measured 0.20 (straight pull) and 0.19 (tilted drag); 0.66 and 0.92
    // with the rim on every bundle's outline, and 0.48 and 0.39 while each
    // row's film settled to the deposit of the last texel over it, rationed
    // by how many pixels that texel feeds (pale lanes; docs/paint.md, "The
    // cap on a texel's deposit"); the round's pull, 0.02. Asked: 0.3, half
    // as much again as the worst measured, so that the rim moving by a pixel
    // cannot cross it, and under the lanes' 0.39.
    constexpr double kMaxDip = 0.3;
    CHECK(dip <= kMaxDip);
  }
}

TEST_CASE("marks: the badger's pull has feathered edges, the round's crisp ones",
          "[marks][badger]") {
  TempDir dir;
  const Coverage badger = renderCase("badger", pullCase(0.3), dir, "soft", "slsqp", kGlazeAt4);
  const Coverage round = renderCase("round", pullCase(0.3), dir, "crisp", "slsqp", kGlazeAt4);
  const EdgeRamp b = pullEdgeRamp(badger), r = pullEdgeRamp(round);
  INFO("10-90 % ramps (mm): badger " << b.low_side_mm << " and " << b.high_side_mm
       << " (plateau ink " << b.plateau << "), round " << r.low_side_mm << " and "
       << r.high_side_mm << " (plateau ink " << r.plateau << ")");
  // The badger's 1.5 mm flags feather each edge over about their length
  // (measured 1.5 and 1.6 mm; 0.48 and 0.45 before it had flags); the round
  // lays its film to the last pixel, and its ramps are its edge pixels'
  // partial cover and the hair's streaks (0.2 and 1.0 mm). The means stand
  // 2.6 : 1. Asked: 2.5, so that a pixel more or less on every ramp (0.25 mm
  // at 4 px/mm) cannot cross it either way; and each of the badger's edges
  // at least 1 mm, two thirds of its flags, so a soft edge cannot hide a hard one.
  constexpr double kSofter = 2.5, kMinFeatherMm = 1.0;
  CHECK(b.meanMm() >= kSofter * r.meanMm());
  CHECK(b.low_side_mm >= kMinFeatherMm);
  CHECK(b.high_side_mm >= kMinFeatherMm);
  // Low contrast: a softener lays a thin film (paint.capacity 0.6), so the
  // body of its glaze is lighter than the round's (capacity 1).
  CHECK(b.plateau < r.plateau);
}

TEST_CASE("marks: the badger's light touch lays a broad, faint mark", "[marks][badger]") {
  // Pulled at 0.05 of its hair (1.25 mm of press past first contact, the
  // lightest press of scripts/fidelity's sweep), a softener's domed head
  // meets the paper over a patch and leaves a soft haze about as wide as the
  // dome, lighter than where it is pressed. Its domed cut
  // (scenes/brushes/generate.py, BADGER_DOME_MM) puts six spines on the
  // paper, and their bundles lie down at their light load (flat_load_n).
  TempDir dir;
  const Coverage light = renderCase("badger", pullCase(0.05), dir, "light", "slsqp", kGlazeAt4);
  const Coverage firm = renderCase("badger", pullCase(0.3), dir, "firm", "slsqp", kGlazeAt4);
  // The haze's ink is 0.1-0.15 in this glaze, so the usual 0.1 would cut
  // through the haze itself and measure its grain; 0.05 is half of it and
  // still above the blank paper's 0.
  constexpr double kHazeInk = 0.05;
  const WidthProfile p = widthProfile(light, kHazeInk);
  REQUIRE_FALSE(p.empty());
  const EdgeRamp l = pullEdgeRamp(light), f = pullEdgeRamp(firm);
  INFO("light touch: width " << meanWidthMm(p) << " mm, CV " << widthCv(p) << ", plateau ink "
       << l.plateau << ", ramps " << l.low_side_mm << " and " << l.high_side_mm
       << " mm; pressed to 0.3: plateau ink " << f.plateau);
  // Broad: 12.1 mm measured (0.02 mm when only two spine tips touched).
  // Asked: 6 mm, over a third of the dome's 15 mm and three times the flags'
  // 2 x 1.5 mm of rim, so that it cannot be two bundle tips' lanes.
  constexpr double kBroadMm = 6.0;
  CHECK(meanWidthMm(p) >= kBroadMm);
  // Steady along the pull, as every pull of the sweep (the 15 % of "a steady
  // pull keeps its width").
  CHECK(widthCv(p) <= 0.15);
  // Soft: its edges are ramps (2.2 and 1.7 mm measured, against its own
  // faint level) where the round's crisp side is 0.2 mm. Asked: 0.5 mm, two
  // pixels at 4 px/mm, over twice the round's.
  constexpr double kMinFeatherMm = 0.5;
  CHECK(l.low_side_mm >= kMinFeatherMm);
  CHECK(l.high_side_mm >= kMinFeatherMm);
  // Faint: no darker than the firm pull's body (0.45 against 0.55; 0.24
  // against 0.47 while the gaps between its bundles laid nothing).
  CHECK(l.plateau <= f.plateau);
}

namespace {

// The share of a pull's body that is solid ink (over 0.5): the middle 60 %
// of its length (middleRange), and the middle half of its width, away from
// a feathered edge (the rows whose mean ink there is at least a tenth of
// the darkest row's, less a quarter of them on each side).
double solidShare(const Coverage& img) {
  const WidthProfile p = widthProfile(img);
  REQUIRE_FALSE(p.empty());
  const SpanRange mid = middleRange(p);
  const std::vector<double> rows = crossProfile(img, Axis::kX, mid.lo, mid.hi);
  const double peak = *std::max_element(rows.begin(), rows.end());
  int r0 = 0, r1 = img.h;
  while (r0 < r1 && rows[static_cast<size_t>(r0)] < 0.1 * peak) ++r0;
  while (r1 > r0 && rows[static_cast<size_t>(r1 - 1)] < 0.1 * peak) --r1;
  const int quarter = (r1 - r0) / 4;
  long solid = 0, all = 0;
  for (int r = r0 + quarter; r < r1 - quarter; ++r)
    for (int c = mid.lo; c < mid.hi; ++c) {
      ++all;
      solid += img.at(c, r) > 0.5f;
    }
  return all > 0 ? static_cast<double>(solid) / all : 0;
}

}  // namespace

TEST_CASE("marks: the badger's light touch in an opaque paint is broken, its firm press solid",
          "[marks][badger]") {
  // In the default near-black any film hides the paper, however thin, so a
  // softener's light touch can only read as light by leaving paper bare:
  // under a light load only the flags it lays on the paper touch it, on the
  // grain's peaks and along its best-loaded hairs
  // (TransferParams::flag_cover_n_per_mm2). Pulled 20 mm at 1.3 mm past
  // first contact (depthPullCsv, tilted 20 degrees: the library sheet's
  // lightest pull), and at 6 mm. The round's dense belly covers what it
  // touches at the light press too.
  TempDir dir;
  const Eigen::Quaterniond q = tiltRotation(20);
  auto solid = [&](const std::string& name, double depth_mm) {
    std::ostringstream stem;
    stem << name << '-' << depth_mm;
    const std::string csv = dir.write(stem.str() + ".csv", depthPullCsv(-3, depth_mm, q));
    const std::string png = dir.file(stem.str() + ".png");
    const RunResult r = runBristle("render -q --solver slsqp --px-per-mm 6 --brush '" +
                                   sourcePath("scenes/brushes/" + name + ".json") +
                                   "' --trajectory '" + csv + "' -o '" + png + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("failed solve") == std::string::npos);
    return solidShare(loadCoveragePng(png));
  };
  const double light = solid("badger", 1.3), firm = solid("badger", 6),
               round = solid("round", 1.3);
  INFO("solid share of the body: badger at 1.3 mm " << light << ", at 6 mm " << firm
       << "; round at 1.3 mm " << round);
  // Broken: measured 0.74 of the light pull's body solid, streaks along the
  // pull with paper between them (1.0, a solid bar, while every flag touched
  // at any load). Asked: at most 0.85, so that the grain's seed cannot carry
  // it either way. Firm, and the round: all of it (measured 1); asked 0.95,
  // a crumb of grain allowed.
  constexpr double kBroken = 0.85, kSolid = 0.95;
  CHECK(light <= kBroken);
  CHECK(firm >= kSolid);
  CHECK(round >= kSolid);
}

TEST_CASE("marks: the badger's first touch lays a faint haze that grows with depth",
          "[marks][badger]") {
  // A softener is used with the lightest touch: from its first contact on,
  // its dome lays a haze that grows with the press. Pulled 20 mm in press
  // depths past first contact (depthPullCsv, tilted 20 degrees), its lowest
  // point is hair 1.75 mm below the joint it surrounds. The hair under a
  // joint bears load before the joint reaches the paper (engine/mechanics/
  // spine_energy.h, HairCushion); while only the joints did, the dome passed
  // through the paper unloaded for its first 1.75 mm and laid nothing at 1.0
  // and 1.5 mm (then 12 mm^2 at 2.0, 169 at 2.5: a cliff).
  TempDir dir;
  const std::string brush = sourcePath("scenes/brushes/badger.json");
  const Eigen::Quaterniond q = tiltRotation(20);
  // Visible: bristle's own rule for painted pixels, 6 levels of 255 off the
  // paper (docs/batch.md), is 0.024 of its luminance.
  constexpr double kVisibleInk = 0.025;
  struct Pull {
    double depth_mm;
    double visible_mm2 = 0;  // the area over kVisibleInk
    double ink_mm2 = 0;      // the ink summed over the image, per mm^2 of canvas
    double mean_ink = 0;     // over the visible area
  };
  // The four light pulls, and a firm one.
  std::vector<Pull> pulls = {{1.0}, {1.5}, {2.0}, {2.5}, {4.0}};
  for (Pull& p : pulls) {
    std::ostringstream stem;
    stem << "touch-" << p.depth_mm;
    const std::string csv = dir.write(stem.str() + ".csv", depthPullCsv(-3, p.depth_mm, q));
    const std::string png = dir.file(stem.str() + ".png");
    const RunResult r = runBristle("render -q --solver slsqp " + std::string(kGlazeAt4) +
                                   " --brush '" + brush + "' --trajectory '" + csv + "' -o '" +
                                   png + "'");
    INFO(r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.find("failed solve") == std::string::npos);
    const Coverage img = loadCoveragePng(png);
    const double px_mm2 = 1 / (img.px_per_mm * img.px_per_mm);
    double sum = 0, visible_sum = 0;
    for (float v : img.v) {
      sum += v;
      if (v > kVisibleInk) visible_sum += v;
    }
    const long visible_px = inkedPixels(img, kVisibleInk);
    p.visible_mm2 = visible_px * px_mm2;
    p.ink_mm2 = sum * px_mm2;
    p.mean_ink = visible_px > 0 ? visible_sum / visible_px : 0;
    UNSCOPED_INFO(p.depth_mm << " mm: visible " << p.visible_mm2 << " mm^2, ink " << p.ink_mm2
                             << " mm^2, mean ink " << p.mean_ink);
  }
  // Visible at every depth. Under the lightest load only the flags on the
  // grain's peaks and the best-loaded hairs touch (TransferParams::
  // flag_cover_floor), so the lightest pull, 1.0 mm, is a dotted line:
  // measured 5.4 mm^2 (87 px at 4 px/mm; 49 mm^2 of even faint line while
  // every flag touched at any load). Asked: 2.5 mm^2, 40 px, a row of dots
  // along the pull and not a stray speck, with room for the grain's seed.
  constexpr double kVisibleMm2 = 2.5;
  for (const Pull& p : pulls) CHECK(p.visible_mm2 >= kVisibleMm2);
  // Grows with depth, no cliff: each pull deeper lays more ink over more
  // paper, by at least a fifth. Measured 1.36 and 1.41 at the least (2.0 to
  // 2.5 mm, the area and the ink), 17 and 31 from 1.0 to 1.5 mm, where the
  // dome's tips first lie down side by side.
  constexpr double kGrowth = 1.2;
  for (size_t i = 0; i + 1 < pulls.size(); ++i) {
    INFO("from " << pulls[i].depth_mm << " to " << pulls[i + 1].depth_mm << " mm");
    CHECK(pulls[i + 1].visible_mm2 >= kGrowth * pulls[i].visible_mm2);
    CHECK(pulls[i + 1].ink_mm2 >= kGrowth * pulls[i].ink_mm2);
  }
  // The lightest is a haze: its mean ink at most half the firm pull's
  // (measured 0.03 against 0.39).
  constexpr double kHaze = 0.5;
  CHECK(pulls.front().mean_ink <= kHaze * pulls.back().mean_ink);
}

namespace {

// A badger's pressed blot is one piece with a feathered edge: its flags lay
// a thin, uneven film that the hair in the gaps between its bundles carries
// out to the head's outline (docs/paint.md, "The gaps are hair too"). Where
// that outline has a notch, the 0.1 contour of that film can leave a crumb
// of 1-3 px inside the blot's hull, its ragged edge. A mark beside the blot
// (a bundle's tip, a disc) lies outside its hull, or is larger: 4 px is half
// a millimetre at 8 px/mm, the smallest dot a painter would call a mark.
constexpr int kCrumbPx = 4;

}  // namespace

TEST_CASE("marks: the badger pressed upright to 0.3 of its hair leaves one blot, no specks",
          "[marks][badger]") {
  // scripts/fidelity's press (blot_trajectory: upright, from 2 mm above
  // first contact down to 0.3 of the 25 mm hair in 0.4 s, held 0.2 s, lifted
  // to 8 mm above contact in 0.4 s; Ipopt, 8 px/mm, default paint): every
  // inked pixel counts, so a speck beside the blot is a second mark (the
  // general test above allows specks under 20 px).
  TempDir dir;
  const std::string brush = sourcePath("scenes/brushes/badger.json");
  const double z0 = spineContactHeightMm(loadBrush(brush), Eigen::Quaterniond::Identity());
  const double zd = z0 - 0.3 * 25.0;
  const std::string csv = dir.file("press.csv"), png = dir.file("press.png");
  {
    std::ofstream f(csv);
    f << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
    const double rows[5][2] = {{0.0, z0 + 2}, {0.4, zd}, {0.6, zd}, {1.0, z0 + 8}, {1.2, z0 + 8}};
    for (const auto& r : rows) f << r[0] << ",10,20," << r[1] << ",1,0,0,0\n";
  }
  const RunResult run = runBristle("render -q --brush '" + brush + "' --trajectory '" + csv +
                                   "' -o '" + png + "'");
  INFO(run.err);
  REQUIRE(run.code == 0);
  const Coverage img = loadCoveragePng(png);
  const BlotStats b = blotStats(img, 0.1, 1), pieces = blotStats(img, 0.1, kCrumbPx);
  INFO("components " << b.components << " (" << pieces.components << " of " << kCrumbPx
       << " px or more), outside the blot's hull " << b.satellites << ", fill " << b.fill);
  // Nothing beside the blot, however small; inside its outline only crumbs
  // of its feathered edge (kCrumbPx).
  CHECK(b.satellites == 0);
  CHECK(pieces.components == 1);
  CHECK(b.fill >= 0.85);
}

TEST_CASE("marks: the badger pressed, held and lifted leaves one blot, no satellites",
          "[marks][badger]") {
  // The press-hold-lift of every brush's depth sweep, in the default paint:
  // an opaque near-black, in which any stray tip's dot shows.
  TempDir dir;
  const std::string png = dir.file("blot.png"), stats = dir.file("blot.json");
  const RunResult run = runBristle(
      "render -q --solver slsqp --px-per-mm 8 --brush '" + sourcePath("scenes/brushes/badger.json") +
      "' --trajectory '" + sourcePath("scenes/trajectories/depth/press-hold-lift.csv") + "' -o '" +
      png + "' --stats '" + stats + "'");
  INFO(run.err);
  REQUIRE(run.code == 0);
  const nlohmann::json s = nlohmann::json::parse(std::ifstream(stats));
  CHECK(s.at("failed_steps").get<int>() == 0);
  // Every inked component beside the blot counts, however small: a
  // satellite is one.
  const Coverage img = loadCoveragePng(png);
  const BlotStats b = blotStats(img, 0.1, 1);
  // Inside its outline the edge is broken: the outer bundles press lightly,
  // and their flags touch only the grain's peaks (TransferParams::
  // flag_cover_n_per_mm2), a stipple whose crumbs are pieces of their own.
  // One blot: the largest piece holds nearly all the inked pixels (measured
  // 0.998; asked 0.99, so that the crumbs together are at most a hundredth
  // of the mark, 2.4 mm^2 of this 244 mm^2 dab).
  const long inked = inkedPixels(img, 0.1);
  const double main_share = inked > 0 ? static_cast<double>(b.largest_area_px) / inked : 0;
  INFO("components " << b.components << ", the largest holding " << main_share
       << " of the inked pixels, outside the blot's hull " << b.satellites << ", fill "
       << b.fill << ", area " << b.largest_area_mm2 << " mm^2");
  CHECK(b.satellites == 0);
  CHECK(main_share >= 0.99);
  // Filled: the acceptance figure of "a straight press-and-lift leaves one
  // filled blot".
  CHECK(b.fill >= 0.85);
}

TEST_CASE("marks: the badger pressed and lifted leaves one soft blot, not a cluster of discs",
          "[marks][badger]") {
  // The golden's press (press-lift.csv, 3 mm deeper than the press-hold-lift)
  // in burnt umber, a glaze in which a thinner film shows paler. A dome
  // pressed and lifted leaves one even blot. While the flagged rim picked up
  // in full whatever its motion, the lift printed a disc per bundle: as the
  // unloading bundles drew back, each one's rim, laying little and picking up
  // in full, passed inwards over the blot and lifted a pale ring
  // (docs/paint.md, "Flags scrub only as they slide").
  TempDir dir;
  const std::string png = dir.file("press.png");
  const RunResult run = runBristle(
      "render -q --solver slsqp --paint burnt-umber --px-per-mm 8 --offset-mm 0 0 3 --brush '" +
      sourcePath("scenes/brushes/badger.json") + "' --trajectory '" +
      sourcePath("scenes/trajectories/press-lift.csv") + "' -o '" + png + "'");
  INFO(run.err);
  REQUIRE(run.code == 0);
  const Coverage img = loadCoveragePng(png);
  const BlotStats b = blotStats(img, 0.1, 1);
  INFO("components " << b.components << " (" << blotStats(img, 0.1, kCrumbPx).components
       << " of " << kCrumbPx << " px or more), outside the blot's hull " << b.satellites
       << ", median ink " << b.median_ink << ", hull under half of it " << b.pale_share);
  CHECK(b.satellites == 0);
  CHECK(blotStats(img, 0.1, kCrumbPx).components == 1);
  // The share of the blot's hull under half its median ink. Rings of dense
  // paint round a paler middle, the fault this test is for, measure 28 %; an
  // even blot of unflagged hair 4.2 % (its hull's corners lie outside it).
  // The flagged rim feathers the outline over flag_mm, and the hair bearing
  // load under the joints (HairCushion, engine/mechanics/spine_energy.h)
  // darkens the middle, so the sound soft dab measures 14.1 %. Asked: 15 %,
  // about half the rings' share, and 1 % of the hull (half a pixel's ring
  // round the blot at 8 px/mm) above the sound dab's.
  constexpr double kPaleShare = 0.15;
  CHECK(b.pale_share <= kPaleShare);
}

TEST_CASE("marks: the badger pressed straight down leaves one soft round dab, not a cloud of lobes",
          "[marks][badger]") {
  // The library sheet's press (depth/press-lift.csv: upright, 8 mm past first
  // contact and lifted) in burnt umber, a glaze in which a thinner film shows
  // paler, 8 px/mm, SLSQP; the round beside it. A dome of fine hair pressed
  // into the paper splays into one round dab that feathers out at its edge.
  // Its spines' bundles, pressed flat, are discs 4-5 mm across; while only
  // the pixels under them took paint, the dab's outline was a ring of them,
  // a lobe per outer bundle, each with the hard edge of its disc
  // (docs/paint.md, "The gaps are hair too").
  TempDir dir;
  auto press = [&](const std::string& name) {
    const std::string png = dir.file(name + "-dab.png");
    const RunResult run = runBristle(
        "render -q --solver slsqp --paint burnt-umber --px-per-mm 8 --brush '" +
        sourcePath("scenes/brushes/" + name + ".json") + "' --trajectory '" +
        sourcePath("scenes/trajectories/depth/press-lift.csv") + "' -o '" + png + "'");
    INFO(run.err);
    REQUIRE(run.code == 0);
    return loadCoveragePng(png);
  };
  // A lobe is a bulge of the outline standing 1 mm proud of the notches on
  // either side: a quarter of a bundle's disc, 8 px, well over the pixel
  // staircase and the flags' ragged fringe.
  constexpr double kLobeMm = 1.0;
  const BlotOutline b = blotOutline(press("badger"), 0.1, kLobeMm);
  const BlotOutline r = blotOutline(press("round"), 0.1, kLobeMm);
  INFO("badger: " << b.lobes << " lobes, radius " << b.mean_radius_mm << " mm (CV "
       << b.radius_cv << "), edge ramp " << b.edge_ramp_mm << " mm, ink " << b.centre_ink
       << " in the middle, " << b.outer_ink << " towards the edge; round: " << r.lobes
       << " lobes, edge ramp " << r.edge_ramp_mm << " mm");
  // Round: 2 lobes measured, the round's own press 1; 5 while each outer
  // bundle printed its disc. Asked: 3, between the two.
  constexpr int kMaxLobes = 3;
  CHECK(b.lobes <= kMaxLobes);
  // Soft: the 10-90 % ramp across its edge 1.1 mm, against the round's 0.12
  // (a pixel) and 0.44 mm while the discs' edges made the outline. Asked:
  // half the flags' 1.5 mm (paint.flag_mm), six pixels.
  constexpr double kMinFeatherMm = 0.75;
  CHECK(b.edge_ramp_mm >= kMinFeatherMm);
  // Densest in the middle, where the most hair presses: ink 0.49 within 0.3
  // of its radius against 0.35 over 0.6-0.9 of it.
  CHECK(b.centre_ink > b.outer_ink);
}

TEST_CASE("marks: a nearly clean badger dragged across a wet band softens its edge",
          "[marks][badger]") {
  // A flat lays a band of ultramarine 13 mm wide down the canvas (x 23.5 to
  // 36.5 mm); then, the paint still wet, a badger with a trace of white on it
  // is pulled along +x across it, through the band and out into the clean
  // paper beyond. Measured along the badger's path (y 32 to 38 mm), against
  // the band alone.
  TempDir dir;
  auto scene = [&](bool with_badger) {
    nlohmann::json strokes = nlohmann::json::array();
    strokes.push_back({{"brush", sourcePath("scenes/brushes/flat.json")},
                       {"trajectory", sourcePath("scenes/trajectories/depth/broadside-pull.csv")},
                       {"paint", {{"paints", {"ultramarine"}}}}});
    if (with_badger)
      strokes.push_back(
          {{"brush", sourcePath("scenes/brushes/badger.json")},
           {"trajectory", sourcePath("scenes/trajectories/depth/straight-pull.csv")},
           {"paint", {{"paints", {"titanium-white"}}, {"amount", 0.02}}},
           {"placement", {{"offset_mm", {0, 15}}}}});
    const nlohmann::json j = {{"format", "bristle-scene/1"}, {"name", "band"},
                              {"canvas", {{"size_mm", {80, 60}}, {"px_per_mm", kBadgerPpm}}},
                              {"solver", "slsqp"}, {"strokes", strokes}};
    const std::string name = with_badger ? "softened" : "band";
    std::ofstream(dir.file(name + ".json")) << j.dump();
    const RunResult run = runBristle("render -q '" + dir.file(name + ".json") + "' -o '" +
                                     dir.file(name + ".png") + "'");
    INFO(run.err);
    REQUIRE(run.code == 0);
    return loadCoveragePng(dir.file(name + ".png"));
  };
  const Coverage band = scene(false), softened = scene(true);
  // The rows along the badger's path: y 32..38 mm; row 0 is the canvas's top (y 60).
  const int r0 = static_cast<int>((60 - 38) * kBadgerPpm), r1 = static_cast<int>((60 - 32) * kBadgerPpm);
  const std::vector<double> before = crossProfile(band, Axis::kY, r0, r1),
                            after = crossProfile(softened, Axis::kY, r0, r1);
  const EdgeRamp e0 = edgeRamp(before, kBadgerPpm), e1 = edgeRamp(after, kBadgerPpm);
  // Ink carried past the band's far edge: the mean over the 8 mm of paper
  // beyond it, from 0.5 mm out (x 37 to 45 mm).
  auto beyond = [&](const std::vector<double>& p) {
    double sum = 0;
    const int c0 = static_cast<int>(37 * kBadgerPpm), c1 = static_cast<int>(45 * kBadgerPpm);
    for (int c = c0; c < c1; ++c) sum += p[static_cast<size_t>(c)];
    return sum / (c1 - c0);
  };
  INFO("band's far edge ramp " << e0.high_side_mm << " -> " << e1.high_side_mm
       << " mm, near edge " << e0.low_side_mm << " -> " << e1.low_side_mm << " mm; plateau "
       << e0.plateau << " -> " << e1.plateau << "; ink beyond the band " << beyond(before)
       << " -> " << beyond(after));
  // The badger drags the band's paint out over its far edge: that edge's
  // 10-90 % ramp (against the stroke's own level) widens from the flat's
  // crisp 0.2 mm to 4.5 mm (1.36 mm while the lifted paint wicked away);
  // asked: at least 1 mm, four pixels at 4 px/mm,
  // five times the flat's ...
  constexpr double kCrispRampMm = 0.5, kSoftenedRampMm = 1.0;
  CHECK(e0.high_side_mm < kCrispRampMm);
  CHECK(e1.high_side_mm >= kSoftenedRampMm);
  // ... and the clean paper beyond it takes a tint: a mean ink of 0.31 where
  // there was none, against the band's 0.8. Asked: 0.1, an eighth of the
  // band's ink, plainly visible, and under half of what was measured.
  constexpr double kCarriedInk = 0.1;
  CHECK(beyond(before) < 0.005);
  CHECK(beyond(after) >= kCarriedInk);
  // It moves paint rather than adding any: its trace of white lightens the
  // band where it passed (ink 0.8 to 0.31: the softener's thin film
  // takes up what lies thicker than it holds, docs/brush-format.md,
  // "Flagged hair").
  CHECK(e1.plateau < e0.plateau);
  // ... and lays again most of what it lifts (docs/brush-format.md,
  // "Unabsorbent hair"): the ink along its path over the band and 10 mm
  // either side of it (x 13.5 to 46.5 mm), summed, keeps 99 % of what the
  // band had (66 % when the lifted paint wicked into its dry belly). Ink is
  // not volume (a glaze spread thinner shows more ink per mm^3), so the
  // share asked is a painter's "most", three quarters, not 1.
  auto inkNear = [&](const std::vector<double>& p) {
    double sum = 0;
    for (int c = static_cast<int>(13.5 * kBadgerPpm); c < static_cast<int>(46.5 * kBadgerPpm); ++c)
      sum += p[static_cast<size_t>(c)];
    return sum;
  };
  INFO("ink near the band kept: " << inkNear(after) / inkNear(before));
  constexpr double kKeptInk = 0.75;
  CHECK(inkNear(after) >= kKeptInk * inkNear(before));
}

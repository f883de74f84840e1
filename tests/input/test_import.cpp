// The readers and the mapping of bristle import (input/, docs/input.md), in
// process: formats and their detection, the rules every field follows, the
// pressure-to-depth curve, tilt to the handle's rotation, SVG geometry against
// closed forms, and the sample limit. The renders are in test_import_cli.cpp.

#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/base/text_file.h"
#include "input/import.h"
#include "input/pen_axis.h"
#include "input/pen_mapping.h"
#include "input/recording.h"
#include "input/svg_geometry.h"
#include "tests/support/build_paths.h"

#include <2geom/pathvector.h>
#include <2geom/svg-path-parser.h>

using namespace bristle;
using namespace bristle::input;
using Catch::Matchers::Contains;

namespace {

std::string source(const std::string& rel) { return std::string(BRISTLE_SOURCE_DIR) + "/" + rel; }

// The error a call throws: its exit code and message.
template <class F>
Error errorOf(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  FAIL("no error thrown");
  return Error(ExitCode::kOk, "");
}

// Angles and lengths computed in double precision from closed forms: equal
// to a few ulps of the operands' scale.
constexpr double kExact = 1e-9;

Recording readText(const std::string& text, const std::string& name, Format f) {
  return readRecording(text, name, f);
}

}  // namespace

TEST_CASE("import: the real recording reads as MyPaint events", "[import]") {
  const std::string path = source("scenes/recordings/painting30sec-excerpt.dat");
  const std::string text = readTextFile(path);
  REQUIRE(detectFormat(text, path) == Format::kMyPaint);
  const Recording rec = readRecording(text, path, Format::kMyPaint);
  // 320 lines, each at its own time (the excerpt repeats none).
  CHECK(rec.samples.size() == 320);
  CHECK(rec.merged_duplicates == 0);
  CHECK(rec.samples.front().t_s == 0.0);
  CHECK(rec.samples.back().t_s == Approx(3.233).margin(kExact));
  // Two pen-down runs: lines 52-140 (0.512-1.408 s) and 162-320 (1.632-3.233 s).
  int runs = 0;
  for (std::size_t k = 0; k < rec.samples.size(); ++k)
    if (rec.samples[k].down && (k == 0 || !rec.samples[k - 1].down)) ++runs;
  CHECK(runs == 2);
  CHECK(rec.samples[50].down == false);
  CHECK(rec.samples[51].down == true);
  CHECK(rec.samples[51].line == 52);
  CHECK(rec.samples[51].pressure == Approx(0.043053).margin(kExact));
  CHECK(rec.mm_per_unit == Approx(25.4 / 96).epsilon(kExact));
}

TEST_CASE("import: formats are told apart by content and name", "[import]") {
  CHECK(detectFormat("# bristle-trajectory/1\nt_s,x_mm\n", "t.csv") == Format::kTrajectory);
  CHECK(detectFormat("0 1 2 0.5\n", "r.dat") == Format::kMyPaint);
  CHECK(detectFormat("0 1 2 0.5\n", "-") == Format::kMyPaint);
  CHECK(detectFormat("timeStamp,x,y,pressure\n1,2,3,0\n", "p.csv") == Format::kPointerCsv);
  CHECK(detectFormat("<?xml version=\"1.0\"?><svg/>", "a.svg") == Format::kSvg);
  // An empty file stays the trajectory reader's to report, as before.
  CHECK(detectFormat("", "t.csv") == Format::kTrajectory);

  SECTION("unknown content names every format expected") {
    const Error e = errorOf([] { detectFormat("hello world\n", "x.txt"); });
    CHECK(e.code() == ExitCode::kDataError);
    CHECK_THAT(e.what(), Contains("x.txt: line 1: not a format bristle reads"));
    CHECK_THAT(e.what(), Contains("# bristle-trajectory/1"));
    CHECK_THAT(e.what(), Contains("MyPaint events"));
    CHECK_THAT(e.what(), Contains("Pointer Events CSV"));
    CHECK_THAT(e.what(), Contains("SVG"));
  }
  SECTION("a name that promises another format is ambiguous") {
    const Error e = errorOf([] { detectFormat("timeStamp,x,y,pressure\n", "r.dat"); });
    CHECK(e.code() == ExitCode::kDataError);
    CHECK_THAT(e.what(), Contains("r.dat: line 1: ambiguous"));
    CHECK_THAT(e.what(), Contains("promises MyPaint events"));
    CHECK_THAT(e.what(), Contains("the content is Pointer Events CSV"));
    const Error svg = errorOf([] { detectFormat("0 1 2 0.5\n", "d.svg"); });
    CHECK_THAT(svg.what(), Contains("promises an SVG"));
  }
}

TEST_CASE("import: bad values name their line and column", "[import]") {
  auto message = [](const std::string& text, const std::string& name, Format f) {
    const Error e = errorOf([&] { readText(text, name, f); });
    CHECK(e.code() == ExitCode::kDataError);
    return std::string(e.what());
  };
  CHECK(message("0 1 2 0.1\n0.1 nan 2 0.2\n", "r.dat", Format::kMyPaint) ==
        "r.dat: line 2, column 2 (x): 'nan': must be finite");
  CHECK(message("0 1 2 0.1\n0.1 1 2 1.5\n", "r.dat", Format::kMyPaint) ==
        "r.dat: line 2, column 4 (pressure): pressure = 1.5: a pressure must be in [0, 1]");
  CHECK(message("0 1 2 -0.01\n", "r.dat", Format::kMyPaint) ==
        "r.dat: line 1, column 4 (pressure): pressure = -0.01: a pressure must be in [0, 1]");
  CHECK(message("0 1 2 0.1 7\n", "r.dat", Format::kMyPaint) ==
        "r.dat: line 1: has 5 fields; a MyPaint event line is 't x y pressure' (4 numbers)");
  CHECK(message("0.2 1 2 0.1\n0.1 1 2 0.2\n", "r.dat", Format::kMyPaint) ==
        "r.dat: line 2, column 1 (t): t = 0.1 is before the previous sample's (line 1): "
        "times must not decrease (equal times are merged)");
  const std::string header = "timeStamp,x,y,pressure,tiltX,tiltY\n";
  CHECK(message(header + "0,1,2,0.5,0,0\n8,1,2,0.5,91,0\n", "p.csv", Format::kPointerCsv) ==
        "p.csv: line 3, column 5 (tiltX): tiltX = 91: a tilt must be in [-90, 90] degrees");
  CHECK(message(header + "0,1,2,0.5,0,-90.5\n", "p.csv", Format::kPointerCsv) ==
        "p.csv: line 2, column 6 (tiltY): tiltY = -90.5: a tilt must be in [-90, 90] degrees");
  CHECK(message(header + "0,1,NaN,0.5,0,0\n", "p.csv", Format::kPointerCsv) ==
        "p.csv: line 2, column 3 (y): 'NaN': must be finite");
  CHECK(message("timeStamp,x,y,presure\n", "p.csv", Format::kPointerCsv)
            .rfind("p.csv: line 1, column 4 (presure): unknown column 'presure'", 0) == 0);
  CHECK(message("timeStamp,x,y\n", "p.csv", Format::kPointerCsv)
            .rfind("p.csv: line 1: header lacks the column 'pressure'", 0) == 0);
  CHECK(message("timeStamp,x,y,pressure,pointerId\n0,1,2,0.5,1\n8,1,2,0.5,2\n", "p.csv",
                Format::kPointerCsv) ==
        "p.csv: line 3, column 5 (pointerId): pointerId = 2 is a second pointer (line 2 has "
        "1): record one pointer per file");
  CHECK(message("0 1 2 0\n1 2 3 0\n", "r.dat", Format::kMyPaint) ==
        "r.dat: line 1: the pen never touches (no sample with pressure > 0, or with buttons "
        "bit 0 where a buttons column is given): nothing to paint");
}

TEST_CASE("import: equal time stamps merge into the later sample", "[import]") {
  const Recording rec = readText(
      "timeStamp,x,y,pressure,buttons\n0,0,0,0.5,1\n8,1,0,0.5,1\n8,2,0,0.6,1\n16,3,0,0.5,1\n",
      "p.csv", Format::kPointerCsv);
  REQUIRE(rec.samples.size() == 3);
  CHECK(rec.merged_duplicates == 1);
  CHECK(rec.samples[1].x == 2);  // the later of the two at 8 ms
  CHECK(rec.samples[1].t_s == Approx(0.008).margin(kExact));
  CHECK(rec.warnings.size() == 1);
}

TEST_CASE("import: the sample limit is checked before samples are stored", "[import]") {
  // A limit of 100 stands in for the real one (kMaxRecordingSamples): the
  // count comes first, so no recording over it is ever held in memory.
  std::string text;
  for (int k = 0; k < 101; ++k) text += std::to_string(k) + " 0 0 0.5\n";
  const Error e = errorOf([&] { readRecording(text, "big.dat", Format::kMyPaint, {}, 100); });
  CHECK(e.code() == ExitCode::kDataError);
  CHECK(std::string(e.what()) ==
        "big.dat: size: holds 101 event lines, over the limit of 100 samples per recording "
        "(import a part of it at a time)");
  CHECK(readRecording(text, "ok.dat", Format::kMyPaint, {}, 101).samples.size() == 101);
  // An SVG is measured before it is sampled: a path 1 m long at 0.5 mm steps.
  const std::string svg =
      "<svg xmlns='http://www.w3.org/2000/svg' width='1000mm' height='10mm' "
      "viewBox='0 0 1000 10'><path d='M 0 5 H 1000'/></svg>";
  const Error es = errorOf([&] { readRecording(svg, "big.svg", Format::kSvg, {}, 1000); });
  CHECK_THAT(es.what(), Contains("big.svg: size: holds 1001 samples along its paths, over the "
                                 "limit of 1000 samples per recording"));
}

TEST_CASE("import: pressure becomes depth through the documented curve", "[import]") {
  MappingOptions o;
  o.max_depth_mm = 8;
  o.pressure_gamma = 2;
  o.hover_mm = 1.5;
  CHECK(pressureToDepthMm(1, true, o) == Approx(8).margin(kExact));
  CHECK(pressureToDepthMm(0.5, true, o) == Approx(2).margin(kExact));
  CHECK(pressureToDepthMm(0, true, o) == Approx(0).margin(kExact));  // touching, no press
  CHECK(pressureToDepthMm(0.7, false, o) == Approx(-1.5).margin(kExact));  // pen up hovers
  // The default depth is a fraction of the brush's hair length.
  const Brush round = loadBrush(source("scenes/brushes/round.json"));
  ImportOptions io;
  const std::string rule = resolveMaxDepth(&io, round, "round");
  CHECK(io.mapping.max_depth_mm ==
        Approx(kDefaultMaxDepthFrac * firstContactHeightMm(round)).epsilon(kExact));
  CHECK_THAT(rule, Contains("0.4 x the hair length"));
  io.max_depth_mm = 3;
  resolveMaxDepth(&io, round, "round");
  CHECK(io.mapping.max_depth_mm == 3);
}

TEST_CASE("import: tilt and twist become the handle's rotation", "[import]") {
  // Upright, untwisted: the identity (brush upright, width axis along x).
  CHECK(handleRotation(penAxisFromTilt(0, 0), 0).angularDistance(Eigen::Quaterniond::Identity()) <
        kExact);
  // tiltX 30: the top leans towards +x; the brush's +z goes there.
  const Eigen::Vector3d a = penAxisFromTilt(30, 0);
  CHECK(a.x() == Approx(std::sin(M_PI / 6)).margin(kExact));
  CHECK(a.z() == Approx(std::cos(M_PI / 6)).margin(kExact));
  const Eigen::Quaterniond q = handleRotation(a, 0);
  CHECK((q * Eigen::Vector3d::UnitZ() - a).norm() < kExact);
  // altitude/azimuth agree with tiltX/tiltY for a pen leaning along +y.
  const Eigen::Vector3d b = penAxisFromAltitudeAzimuth(M_PI / 3, M_PI / 2);
  const Eigen::Vector3d c = penAxisFromTilt(0, 30);
  CHECK((b - c).norm() < kExact);
  // Twist 90 clockwise from above turns the width axis from +x to -y.
  const Eigen::Quaterniond t = handleRotation(Eigen::Vector3d::UnitZ(), 90);
  CHECK((t * Eigen::Vector3d::UnitX() - Eigen::Vector3d(0, -1, 0)).norm() < kExact);
  // Flat on the surface at +-90.
  CHECK((penAxisFromTilt(90, 0) - Eigen::Vector3d::UnitX()).norm() < kExact);
}

TEST_CASE("import: placement, y flip and the lead-in hover", "[import]") {
  const Recording rec =
      readText("0 100 200 0.5\n0.1 196 200 0.5\n0.2 196 104 0\n", "r.dat", Format::kMyPaint);
  MappingOptions o;
  o.margin_mm = 5;
  o.mm_per_unit = 0.5;
  const Trajectory t = toTrajectory(rec, o);
  // The first sample is down: a hover sample lead_s before it, at its place.
  REQUIRE(t.samples.size() == 4);
  CHECK(t.samples[0].t_s == 0);
  CHECK(t.samples[0].depth_mm == -o.hover_mm);
  CHECK(t.samples[1].t_s == Approx(o.lead_s).margin(kExact));
  // x: (100 - 100) * 0.5 + 5; y flipped: (200 - 200) * 0.5 + 5 is the bottom.
  CHECK(t.samples[1].pose.position_mm.x() == Approx(5).margin(kExact));
  CHECK(t.samples[1].pose.position_mm.y() == Approx(5).margin(kExact));
  CHECK(t.samples[3].pose.position_mm.y() == Approx(53).margin(kExact));  // screen top
  CHECK(t.samples[3].buttons == 0);
  CHECK(t.samples[1].buttons == 1);
  o.flip_y = false;
  CHECK(toTrajectory(rec, o).samples[3].pose.position_mm.y() == Approx(5).margin(kExact));
  // The CSV reads back as a trajectory with depth_mm.
  const Trajectory back = parseTrajectory(trajectoryCsv(t, {"a note"}), "out.csv");
  CHECK(back.depth_column == 4);
  CHECK(back.samples.size() == 4);
  CHECK(back.samples[2].depth_mm == Approx(t.samples[2].depth_mm).margin(1e-6));
}

TEST_CASE("import: each pen-down run becomes a stroke trajectory", "[import]") {
  const std::string path = source("scenes/recordings/painting30sec-excerpt.dat");
  const Recording rec = readRecording(readTextFile(path), path, Format::kMyPaint);
  const std::vector<Trajectory> strokes = toStrokeTrajectories(rec, MappingOptions{});
  REQUIRE(strokes.size() == 2);
  for (const Trajectory& t : strokes) {
    CHECK(t.samples.front().buttons == 0);  // hovering before
    CHECK(t.samples.back().buttons == 0);   // and after
    CHECK(t.samples.front().t_s == 0);
    for (std::size_t k = 1; k + 1 < t.samples.size(); ++k) CHECK(t.samples[k].buttons == 1);
  }
  // The first stroke: lines 52-140 with the pen-up events on either side.
  CHECK(strokes[0].samples.size() == 89 + 2);
  CHECK(strokes[0].samples.front().line == 51);
  CHECK(strokes[0].samples.back().line == 141);
  // The excerpt ends with the pen down: the hover after is made lead_s on.
  CHECK(strokes[1].samples.back().line == 320);
}

TEST_CASE("import: lib2geom's arc length of a circle is 2 pi r", "[import][svg]") {
  // A circle of radius 25 as two SVG arcs: lib2geom's elliptical arcs,
  // measured by its curve lengths, against the closed form.
  const std::string svg =
      "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 100' width='100mm' "
      "height='100mm'><path d='M 75 50 A 25 25 0 1 1 25 50 A 25 25 0 1 1 75 50'/></svg>";
  // lib2geom measures the circle 1.4e-7 short (157.0796110 against
  // 157.0796327: its polynomial (SBasis) form of an elliptical arc, whatever
  // the integral's tolerance). 1e-6 relative leaves room for that, and
  // catches any mistake in the arcs (a wrong flag draws a different arc, mm off).
  constexpr double kLengthRel = 1e-6;
  const Geom::PathVector pv = Geom::parse_svg_path("M 75 50 A 25 25 0 1 1 25 50 A 25 25 0 1 1 75 50");
  REQUIRE(pv.size() == 1);
  CHECK(pathLength(pv[0]) == Approx(2 * M_PI * 25).epsilon(kLengthRel));
  // Samples at equal arc length lie on the circle, 2 pi r / n apart along it:
  // each chord is 2 r sin(pi / n). Each arc's own table of chord lengths maps
  // length to time, so chords agree to 1e-4 mm.
  constexpr double kChordTolMm = 1e-4;
  const int n = 40;
  const std::vector<Geom::Point> pts = samplePath(pv[0], n);
  REQUIRE(pts.size() == n + 1);
  for (int k = 1; k <= n; ++k) {
    CHECK(Geom::distance(pts[k], Geom::Point(50, 50)) == Approx(25).margin(kChordTolMm));
    CHECK(Geom::distance(pts[k - 1], pts[k]) ==
          Approx(2 * 25 * std::sin(M_PI / n)).margin(kChordTolMm));
  }
  // Imported, the circle is drawn at the default 40 mm/s: 157 mm in 3.93 s.
  const Recording rec = readRecording(svg, "c.svg", Format::kSvg);
  CHECK(rec.mm_per_unit == Approx(1).epsilon(kExact));
  double first_down = -1, last_down = -1;
  for (const PenSample& s : rec.samples)
    if (s.down) {
      if (first_down < 0) first_down = s.t_s;
      last_down = s.t_s;
    }
  CHECK(last_down - first_down == Approx(2 * M_PI * 25 / 40).margin(1e-6));
}

TEST_CASE("import: a circle of any size measures 2 pi r, and beyond the limits is refused",
          "[import][svg][errors]") {
  // lib2geom integrates to absolute tolerances: measured as they are, a
  // circle of radius 3e6 user units made it recurse until the stack ran out,
  // and an arc of radius 1e300 aborted inside GSL. Paths are measured in a
  // unit box (pathLength), so the tolerance is relative at every size.
  for (const double r : {1e-3, 25.0, 3e6, 4e8}) {
    INFO("radius " << r);
    const std::string rs = formatNumber(r), d = formatNumber(2 * r);
    const Geom::PathVector pv = Geom::parse_svg_path(
        ("M " + d + " " + rs + " A " + rs + " " + rs + " 0 1 1 0 " + rs + " A " + rs + " " + rs +
         " 0 1 1 " + d + " " + rs)
            .c_str());
    REQUIRE(pv.size() == 1);
    REQUIRE(pathWithinLimits(pv[0]));
    // As the radius-25 circle above: 1.4e-7 short at every size.
    CHECK(pathLength(pv[0]) == Approx(2 * M_PI * r).epsilon(1e-6));
    const std::vector<Geom::Point> pts = samplePath(pv[0], 8);
    REQUIRE(pts.size() == 9u);
    for (const Geom::Point& p : pts)  // on the circle (lib2geom's own point on each arc)
      CHECK(Geom::distance(p, Geom::Point(r, r)) == Approx(r).margin(4e-6 * r));
  }
  // Past +-1e9 user units (the limit on positions) or not finite: refused
  // with the element and the rule, exit 65, never a crash.
  for (const char* d : {"M0 0 A1e300 1e300 0 0 1 1 0", "M0 0 C2e9 0 0 0 1 0", "M0 0 L1e10 0"}) {
    INFO(d);
    const std::string svg = std::string("<svg xmlns='http://www.w3.org/2000/svg'><path d='") + d +
                            "'/></svg>";
    const Error e = errorOf([&] { readRecording(svg, "big.svg", Format::kSvg); });
    CHECK(e.code() == ExitCode::kDataError);
    CHECK_THAT(e.what(), Contains("<path>") && Contains("beyond +-1e9 user units"));
  }
}

namespace {

// An SVG of one <polyline> through (0, 0), (1, 0), ... (points - 1, 0).
std::string straightPolyline(int points) {
  std::string pts;
  for (int k = 0; k < points; ++k) pts += std::to_string(k) + ",0 ";
  return "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 60'><polyline points='" + pts +
         "'/></svg>";
}

}  // namespace

TEST_CASE("import: straight, collinear, zero-length and long paths sample evenly",
          "[import][svg]") {
  // Each case: path data, its length, and where a sample at arc length s lies
  // (all on y = 0). Samples must be evenly spaced along the length.
  struct Case {
    const char* d;
    double length;
    double (*x_at)(double s);
  };
  const Case cases[] = {
      // Collinear and evenly spaced: lib2geom's global arc-length
      // parametrisation came back empty for 1,001 such segments.
      {"M0 0 L1 0 L2 0 L3 0 L4 0 L5 0 L6 0 L7 0 L8 0 L9 0 L10 0", 10, [](double s) { return s; }},
      // Zero-length segments before, between and after: passed over.
      {"M0 0 L0 0 L4 0 L4 0 L4 0 L10 0 L10 0", 10, [](double s) { return s; }},
      // Turning back along the same line: 10 out, 5 back.
      {"M0 0 L10 0 L5 0", 15, [](double s) { return s <= 10 ? s : 20 - s; }},
      // A cubic whose first control points coincide with its start (no
      // tangent there) and a straight cubic: both still along x.
      {"M0 0 C0 0 0 0 10 0", 10, nullptr},
  };
  for (const Case& c : cases) {
    INFO(c.d);
    const Geom::PathVector pv = Geom::parse_svg_path(c.d);
    REQUIRE(pv.size() == 1);
    CHECK(pathLength(pv[0]) == Approx(c.length).margin(1e-9));
    const int n = 20;
    const std::vector<Geom::Point> pts = samplePath(pv[0], n);
    REQUIRE(pts.size() == n + 1);
    for (int k = 0; k <= n; ++k) {
      INFO("sample " << k);
      CHECK(pts[k].y() == 0);
      if (c.x_at) CHECK(pts[k].x() == Approx(c.x_at(c.length * k / n)).margin(1e-9));
      if (k > 0 && !c.x_at) CHECK(pts[k].x() > pts[k - 1].x());
    }
  }
  // A path of no length at all repeats its start (the reader skips it first).
  const std::vector<Geom::Point> none = samplePath(Geom::parse_svg_path("M3 4 L3 4 L3 4")[0], 4);
  REQUIRE(none.size() == 5u);
  for (const Geom::Point& p : none) CHECK(p == Geom::Point(3, 4));
  // 200,000 unit segments: every sample where its length puts it.
  Geom::Path line(Geom::Point(0, 0));
  for (int k = 1; k <= 200'000; ++k) line.appendNew<Geom::LineSegment>(Geom::Point(k, 0));
  const std::vector<Geom::Point> far = samplePath(line, 1000);
  REQUIRE(far.size() == 1001u);
  for (int k = 0; k <= 1000; ++k) CHECK(far[k].x() == Approx(200.0 * k).margin(1e-6));
}

TEST_CASE("import: a straight polyline of 1002 points imports along x", "[import][svg]") {
  // The 1,001 unit segments of the polyline crashed the import (lib2geom's
  // arc-length parametrisation of the whole path came back empty).
  const Recording rec = readRecording(straightPolyline(1002), "x.svg", Format::kSvg);
  double x0 = 1e300, x1 = -1e300;
  for (const PenSample& s : rec.samples) {
    CHECK(s.y == 0);
    x0 = std::min(x0, s.x);
    x1 = std::max(x1, s.x);
  }
  CHECK(x0 == 0);
  CHECK(x1 == 1001);
  // Evenly spaced along it: 1001 units at 25.4/96 mm a unit, every 0.5 mm.
  std::vector<double> down;
  for (const PenSample& s : rec.samples)
    if (s.down) down.push_back(s.x);
  const double step = 1001.0 / (std::ceil(1001 * 25.4 / 96 / 0.5));
  REQUIRE(down.size() == static_cast<std::size_t>(std::ceil(1001 * 25.4 / 96 / 0.5)) + 1);
  for (std::size_t k = 0; k < down.size(); ++k) CHECK(down[k] == Approx(k * step).margin(1e-9));
}

TEST_CASE("import: an SVG's path segments are limited before they are held",
          "[import][svg][errors]") {
  // A 45 MB path of 5,000,000 segments took 2.4 GB and ended in bad_alloc:
  // segments are counted as the data is read, over all the file's elements.
  SvgOptions options;
  options.max_segments = 10;
  auto refusal = [&](const std::string& body) {
    const std::string svg = "<svg xmlns='http://www.w3.org/2000/svg'>" + body + "</svg>";
    return errorOf([&] { readRecording(svg, "big.svg", Format::kSvg, options); });
  };
  const char* over =
      "the SVG's paths hold more than 10 segments, the limit for an SVG (its paths are held in "
      "memory whole)";
  // 1 move and 10 lines: one over.
  const Error d = refusal("<path id='p' d='M0 0 h1 h1 h1 h1 h1 h1 h1 h1 h1 h1'/>");
  CHECK(d.code() == ExitCode::kDataError);
  CHECK(std::string(d.what()) == std::string("big.svg: <path id=\"p\"> (line 1): d: ") + over);
  // 11 points (each a segment, the first the move).
  const Error pts = refusal("<polyline points='0,0 1,0 2,0 3,0 4,0 5,0 6,0 7,0 8,0 9,0 10,0'/>");
  CHECK(std::string(pts.what()) == std::string("big.svg: <polyline> (line 1): points: ") + over);
  // Counted over the file: 5 lines of 2 segments are 10, a sixth is over.
  const Error lines = refusal("<line x2='1'/><line x2='1'/><line x2='1'/><line x2='1'/>"
                              "<line x2='1'/><line id='l6' x2='1'/>");
  CHECK(std::string(lines.what()) == std::string("big.svg: <line id=\"l6\"> (line 1): ") + over);
  // At the limit it reads: 1 move and 9 lines.
  CHECK_NOTHROW(readRecording("<svg xmlns='http://www.w3.org/2000/svg'><path d='M0 0 h1 h1 h1 h1 "
                              "h1 h1 h1 h1 h1'/></svg>",
                              "ok.svg", Format::kSvg, options));
  CHECK(kMaxSvgSegments == 1'000'000);
}

TEST_CASE("import: SVG transforms, units and pressure profiles", "[import][svg]") {
  // rotate(90) about (10, 10), then translated: (20, 10) -> (10, 20) -> (15, 20).
  const Geom::Affine m = parseTransform("translate(5 0) rotate(90 10 10)", "t.svg", "here");
  const Geom::Point p = Geom::Point(20, 10) * m;
  CHECK(p.x() == Approx(15).margin(kExact));
  CHECK(p.y() == Approx(20).margin(kExact));
  CHECK(lengthMm("210mm") == Approx(210).epsilon(kExact));
  CHECK(lengthMm("2in") == Approx(50.8).epsilon(kExact));
  CHECK(lengthMm("96") == Approx(25.4).epsilon(kExact));
  CHECK(lengthMm("50%") == 0);
  const std::vector<ProfilePoint> prof = parsePressureProfile("0:0.2 0.5:0.8 1:0.2", "s", "w");
  CHECK(profilePressure(prof, 0.25) == Approx(0.5).margin(kExact));
  CHECK(profilePressure(parsePressureProfile("0.3", "s", "w"), 0.9) == Approx(0.3));
  const Error e = errorOf([] { parsePressureProfile("0:0.2 0.5:1.3", "s.svg", "<path> (line 3)"); });
  CHECK_THAT(e.what(), Contains("s.svg: <path> (line 3): '0.5:1.3': the pressure must be in [0, 1]"));
}

TEST_CASE("import: the three-stroke SVG", "[import][svg]") {
  const std::string path = source("scenes/recordings/three-strokes.svg");
  const Recording rec = readRecording(readTextFile(path), path, Format::kSvg);
  CHECK(rec.mm_per_unit == Approx(1).epsilon(kExact));
  // The <text> is reported, not drawn.
  REQUIRE(rec.warnings.size() == 1);
  CHECK_THAT(rec.warnings[0], Contains("skipped 1 <text>"));
  int runs = 0;
  double stem_max_pressure = 0;
  for (std::size_t k = 0; k < rec.samples.size(); ++k) {
    const PenSample& s = rec.samples[k];
    if (s.down && (k == 0 || !rec.samples[k - 1].down)) ++runs;
    // The stem's transform moved it to x = 80, where its own profile applies.
    if (s.down && std::fabs(s.x - 80) < 1e-6) stem_max_pressure = std::max(stem_max_pressure, s.pressure);
  }
  CHECK(runs == 3);
  CHECK(stem_max_pressure == Approx(0.8).margin(1e-3));
}

TEST_CASE("import: SVGs with nothing to draw name the element", "[import][svg]") {
  auto message = [](const std::string& svg) {
    const Error e = errorOf([&] { readRecording(svg, "s.svg", Format::kSvg); });
    CHECK(e.code() == ExitCode::kDataError);
    return std::string(e.what());
  };
  CHECK(message("<svg xmlns='http://www.w3.org/2000/svg'>\n<text>hi</text>\n"
                "<image href='a.png'/></svg>") ==
        "s.svg: <text> (line 2): no drawable path: bristle imports <path>, <polyline>, "
        "<polygon>, <line>, <circle>, <ellipse> and <rect>, and this SVG holds only elements it "
        "does not (1 <image>, 1 <text>)");
  CHECK(message("<svg xmlns='http://www.w3.org/2000/svg'><title>x</title><circle r='0'/></svg>") ==
        "s.svg: <svg> (line 1): no drawable path: no <path>, <polyline>, <polygon>, <line>, "
        "<circle>, <ellipse> or <rect> of any length");
  CHECK_THAT(message("<svg><rect width='-1' height='3'/></svg>"),
             Contains("s.svg: <rect> (line 1): width: must be >= 0"));
  CHECK_THAT(message("<svg><path id='p' d='M 0 0 L 10'/></svg>"),
             Contains("s.svg: <path id=\"p\"> (line 1): d: malformed path data"));
  CHECK_THAT(message("<html><body/></html>"),
             Contains("s.svg: <html> (line 1): the document element must be <svg>"));
  CHECK_THAT(message("<svg><path d='M 0 0'"), Contains("s.svg: line 1: malformed XML"));
  CHECK_THAT(message("<svg><polyline points='0,0 5'/></svg>"),
             Contains("points: holds an odd count of numbers (3)"));
}

// ---- Smoothing (docs/input.md, "Time"): a centred moving average per pen run ----

namespace {

std::vector<PenSample> jitteredLine(int n, double dt_s, bool down) {
  std::vector<PenSample> v(n);
  for (int i = 0; i < n; ++i) {
    v[i].t_s = i * dt_s;
    v[i].x = 100 + i;                   // a straight line along x ...
    v[i].y = 50 + (i % 2 ? 0.5 : -0.5);  // ... jittered by +-0.5 units across it
    v[i].pressure = down ? 0.5 : 0;
    v[i].down = down;
  }
  return v;
}

}  // namespace

TEST_CASE("import: smoothing averages the jitter within a pen run, never across it",
          "[import][smooth]") {
  // 100 Hz samples; a 25 ms window (+-12.5 ms) holds a sample and its two
  // neighbours, 10 ms away, and not the next ones, 20 ms away.
  std::vector<PenSample> pen = jitteredLine(20, 0.01, true);
  const std::vector<PenSample> up = jitteredLine(5, 0.01, false);
  for (PenSample s : up) {  // a lift after the stroke, 10 ms on
    s.t_s += 0.2;
    pen.push_back(s);
  }
  const std::vector<PenSample> out = smoothed(pen, 25);
  REQUIRE(out.size() == pen.size());
  // Exact in closed form: three neighbours of a +-0.5 alternation average to
  // +-0.5 / 3, and a straight line stays where it is. 1e-9: the sums' rounding.
  constexpr double kExact = 1e-9;
  for (int i = 1; i < 19; ++i) {
    CHECK(std::fabs(out[i].y - 50) == Approx(0.5 / 3).margin(kExact));
    CHECK(out[i].x == Approx(pen[i].x).margin(kExact));
  }
  // The last pen-down sample averages only with its down neighbour: the
  // lift's pressure 0 does not leak into it, nor its pressure into the lift.
  CHECK(out[19].pressure == Approx(0.5).margin(kExact));
  CHECK(out[20].pressure == 0);
  CHECK(out[20].down == false);
  // No window, no change.
  const std::vector<PenSample> same = smoothed(pen, 0);
  for (std::size_t i = 0; i < pen.size(); ++i) CHECK(same[i].y == pen[i].y);
}

TEST_CASE("import: smoothing a dense recording over the widest window is linear, not n^2",
          "[import][smooth]") {
  // 200,000 samples 1 us apart and the CLI's widest window (10 s): every
  // window holds every sample. Summed window by window that is 4e10 additions
  // (minutes, the ctest TIMEOUT); with prefix sums it is a pass over the data.
  // No time is asserted: a quadratic version fails by running into the test's
  // timeout, and the answer is checked: each sample becomes the mean of all.
  const int n = 200000;
  const std::vector<PenSample> pen = jitteredLine(n, 1e-6, true);
  const std::vector<PenSample> out = smoothed(pen, 10000);
  REQUIRE(out.size() == pen.size());
  const double mean_x = 100 + (n - 1) / 2.0;
  // Relative 1e-9 of the coordinates (1e5 units): the prefix sums' rounding
  // over 2e5 terms of up to 2e5 units each.
  constexpr double kSums = 1e-9 * 2e5;
  CHECK(out.front().x == Approx(mean_x).margin(kSums));
  CHECK(out[n / 2].x == Approx(mean_x).margin(kSums));
  CHECK(out.back().y == Approx(50).margin(kSums));
}

TEST_CASE("import: a UTF-8 byte-order mark at the head of a file is not data", "[import]") {
  // Spreadsheets save "CSV UTF-8" with a BOM; read as data it makes the
  // header's first column unknown (or the file "not a format bristle reads").
  const std::string csv =
      "timeStamp,clientX,clientY,pressure,buttons\n0,10,10,0,0\n10,11,10,0.5,1\n"
      "20,12,10,0.5,1\n30,13,10,0,0\n";
  const std::string dat = "0 10 10 0\n0.01 11 10 0.5\n0.02 12 10 0.5\n0.03 13 10 0\n";
  for (const std::string& text : {csv, dat}) {
    const Recording plain = readInput(text, "r", ImportOptions{});
    const Recording marked = readInput("\xEF\xBB\xBF" + text, "r", ImportOptions{});
    CHECK(marked.format == plain.format);
    REQUIRE(marked.samples.size() == plain.samples.size());
    for (std::size_t i = 0; i < plain.samples.size(); ++i) {
      CHECK(marked.samples[i].t_s == plain.samples[i].t_s);
      CHECK(marked.samples[i].x == plain.samples[i].x);
      CHECK(marked.samples[i].pressure == plain.samples[i].pressure);
    }
  }
}

TEST_CASE("import: an SVG's size is bounded before it is held", "[import][svg][errors]") {
  // pugixml reads a document whole: a million tags and more is refused
  // before it is parsed (kMaxSvgTags), naming the count and the limit.
  std::string big = "<svg xmlns='http://www.w3.org/2000/svg'>";
  big.reserve(16 * kMaxSvgTags);
  for (std::size_t i = 0; i < kMaxSvgTags; ++i) big += "<line x2='1'/>";
  big += "</svg>";
  const Error tags = errorOf([&] { readRecording(big, "big.svg", Format::kSvg); });
  CHECK(tags.code() == ExitCode::kDataError);
  CHECK_THAT(tags.what(), Contains("big.svg: size") && Contains("1000002 tags") &&
                              Contains("limit of 1000000"));
  // A pressure profile of more than 1000 points is refused at once (a long
  // profile on the root was parsed again for every element).
  std::string profile;
  for (int k = 0; k <= 1000; ++k) profile += formatNumber(k / 1000.0) + ":0.5 ";
  const std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' data-bristle-pressure='" +
                          profile + "'><line x2='10'/></svg>";
  const Error points = errorOf([&] { readRecording(svg, "p.svg", Format::kSvg); });
  CHECK(points.code() == ExitCode::kDataError);
  CHECK_THAT(points.what(), Contains("<line>") && Contains("more than 1000 points"));
  // And the stroke count is bounded by the samples as they are gathered:
  // 300 tiny lines at 4 samples each pass 1000 samples.
  std::string many = "<svg xmlns='http://www.w3.org/2000/svg'>";
  for (int i = 0; i < 300; ++i) many += "<line x2='1'/>";
  many += "</svg>";
  CHECK_THROWS_WITH(readRecording(many, "m.svg", Format::kSvg, SvgOptions{}, 1000),
                    Contains("over the limit of 1000 samples"));
}

TEST_CASE("import: hidden layers, odd numbers and second pointers", "[import][errors]") {
  // Inkscape hides a layer with style="display:none": it is not drawn.
  const std::string svg =
      "<svg xmlns='http://www.w3.org/2000/svg'>"
      "<g style='opacity:1; display : none'><line x1='0' y1='0' x2='50' y2='0'/></g>"
      "<line x1='0' y1='10' x2='10' y2='10'/></svg>";
  const Recording rec = readRecording(svg, "h.svg", Format::kSvg);
  for (const PenSample& s : rec.samples) CHECK(s.y == 10);  // only the visible line
  // A <switch> draws its first child whose conditions hold, not all of them.
  const std::string sw =
      "<svg xmlns='http://www.w3.org/2000/svg'><switch>"
      "<line requiredExtensions='http://example.org/x' x1='0' y1='30' x2='9' y2='30'/>"
      "<line x1='0' y1='20' x2='10' y2='20'/><line x1='0' y1='40' x2='10' y2='40'/>"
      "</switch></svg>";
  for (const PenSample& s : readRecording(sw, "s.svg", Format::kSvg).samples) CHECK(s.y == 20);
  // "+-5" is not a number; a number below the smallest double is 0.
  CHECK_THROWS_WITH(readRecording("0 +-5 10 0.5\n0.01 11 10 0.5\n", "n.dat", Format::kMyPaint),
                    Contains("n.dat: line 1, column 2") && Contains("'+-5' is not a number"));
  const Recording tiny =
      readRecording("0 1e-400 10 0.5\n0.01 11 10 0.5\n", "t.dat", Format::kMyPaint);
  CHECK(tiny.samples.front().x == 0);
  // A second pointer is named as both rows wrote their ids (1e20 cast to an
  // integer would be undefined).
  CHECK_THROWS_WITH(
      readRecording("timeStamp,clientX,clientY,pressure,pointerId\n0,1,1,0.5,1e20\n1,2,2,0.5,2\n",
                    "p.csv", Format::kPointerCsv),
      Contains("pointerId = 2 is a second pointer (line 2 has 1e20)"));
  // Times may not span more than 1e9 s - 10 s: the trajectory written counts
  // from the first sample and has its own limit of 1e9 s.
  CHECK_THROWS_WITH(readRecording("-9e8 1 1 0.5\n9e8 2 2 0.5\n", "s.dat", Format::kMyPaint),
                    Contains("s.dat: line 2, column 1") &&
                        Contains("after the first sample's (line 1)"));
}

TEST_CASE("import: a quoted Pointer Events cell may hold a comma", "[import]") {
  // A quoted cell is one cell, commas and all: the error names its column and
  // its whole text, and the columns after it keep their places.
  CHECK_THROWS_WITH(readRecording("timeStamp,pointerType,clientX,clientY,pressure\n"
                                  "0,\"pen, stylus\",10,20,0.5\n",
                                  "q.csv", Format::kPointerCsv),
                    Contains("q.csv: line 2, column 2 (pointerType): 'pen, stylus'"));
  const Recording rec = readRecording(
      "\"timeStamp\",\"pointerType\",\"clientX\",\"clientY\",\"pressure\"\n"
      "0,\"pen\",10,20,0.5\n10,\"pen\",11,20,0.5\n",
      "q.csv", Format::kPointerCsv);
  REQUIRE(rec.samples.size() == 2);
  CHECK(rec.samples[0].x == 10);
  CHECK(rec.samples[0].y == 20);
  CHECK(rec.samples[1].x == 11);
}

TEST_CASE("import: circles, ellipses and rects are strokes along their outlines",
          "[import][svg]") {
  // 1 mm per user unit; each shape alone, drawn at the default 40 mm/s, so
  // its pen-down time is its perimeter / 40 (the closed forms below).
  auto penDown = [](const std::string& shape, Geom::Point* first) {
    const std::string svg = "<svg xmlns='http://www.w3.org/2000/svg' viewBox='0 0 100 100' "
                            "width='100mm' height='100mm'>" + shape + "</svg>";
    const Recording rec = readRecording(svg, "s.svg", Format::kSvg);
    double t0 = -1, t1 = -1;
    for (const PenSample& s : rec.samples)
      if (s.down) {
        if (t0 < 0) {
          t0 = s.t_s;
          *first = Geom::Point(s.x, s.y);
        }
        t1 = s.t_s;
      }
    return (t1 - t0) * 40;  // mm of outline
  };
  // lib2geom's arcs come out 1.4e-7 short (see the circle test above).
  constexpr double kRel = 1e-6;
  Geom::Point first;
  CHECK(penDown("<circle cx='20' cy='30' r='10'/>", &first) ==
        Approx(2 * M_PI * 10).epsilon(kRel));
  CHECK(first == Geom::Point(30, 30));  // SVG's start of a circle: (cx + r, cy)
  // rx alone sets ry too: a circle again.
  CHECK(penDown("<ellipse cx='50' cy='50' rx='8'/>", &first) ==
        Approx(2 * M_PI * 8).epsilon(kRel));
  CHECK(first == Geom::Point(58, 50));
  // A rect's outline from (x, y) round; with corners of radius 2, from (x + 2, y),
  // its straight sides 4 shorter each and a circle of radius 2 in the corners.
  CHECK(penDown("<rect x='10' y='10' width='30' height='20'/>", &first) ==
        Approx(2 * (30 + 20)).epsilon(kRel));
  CHECK(first == Geom::Point(10, 10));
  CHECK(penDown("<rect x='10' y='10' width='30' height='20' rx='2'/>", &first) ==
        Approx(2 * (26 + 16) + 2 * M_PI * 2).epsilon(kRel));
  CHECK(first == Geom::Point(12, 10));
}

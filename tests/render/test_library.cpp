// The brush library and its footprints (paper §4): what the footprint of each
// kind of brush must look like, and that every brush paints.

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>

#include "engine/formats/brush_reader.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/dynamics/simulation.h"
#include "render/stroke_renderer.h"
#include "tests/support/build_paths.h"

using namespace bristle;

namespace {

Brush library(const std::string& name) {
  return loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json");
}

Pose at(double x, double y, double z, double tilt_about_x_rad = 0) {
  Pose p;
  p.position_mm = Eigen::Vector3d(x, y, z);
  p.rotation = Eigen::AngleAxisd(tilt_about_x_rad, Eigen::Vector3d::UnitX());
  return p;
}

// Longest hair of the brush (mm): with the handle tilted by a, the hairs first
// touch the paper when the ferrule is about length * cos(a) above it.
double hairLength(const Brush& b) {
  double l = 0;
  for (const SpineSpec& s : b.spines) l = std::max(l, s.lengthMm());
  return l;
}

void moveTo(Simulation& sim, const Pose& to, double step_mm = 0.2) {
  const Pose from = sim.state().handle;
  const int n = std::max(1, int(std::ceil((to.position_mm - from.position_mm).norm() / step_mm)));
  for (int i = 1; i <= n; ++i)
    sim.step(interpolatePose(from, to, double(i) / n), sim.state().t_s + 0.01);
}

// A canvas window of 80 x 80 mm at 8 px/mm centred on the origin.
CanvasGrid window() {
  CanvasGrid g;
  g.x0_mm = g.y0_mm = -40;
  g.width_px = g.height_px = 640;
  g.px_per_mm = 8;
  return g;
}

// Covered pixels of the footprint of a state.
long coverage(render::StrokeRenderer& r, BrushGeometry& geo, const BrushState& st) {
  render::FootprintImage fp;
  if (!r.footprint(geo, st, window(), 0.1, &fp)) return 0;
  long n = 0;
  for (size_t i = 3; i < fp.texels.size(); i += 4) n += fp.texels[i] > 0;
  return n;
}

// Connected groups (4-neighbour) of covered footprint pixels.
int marks(const render::FootprintImage& fp) {
  const int w = fp.window.width_px, h = fp.window.height_px;
  std::vector<int> label(size_t(w) * h, 0);
  int count = 0;
  std::vector<int> stack;
  for (int start = 0; start < w * h; ++start) {
    if (label[start] || fp.texels[size_t(start) * 4 + 3] <= 0) continue;
    ++count;
    stack.push_back(start);
    label[start] = count;
    while (!stack.empty()) {
      const int p = stack.back();
      stack.pop_back();
      const int c = p % w, r = p / w;
      for (const auto& [dc, dr] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int cc = c + dc, rr = r + dr;
        if (cc < 0 || rr < 0 || cc >= w || rr >= h) continue;
        const int q = rr * w + cc;
        if (label[q] || fp.texels[size_t(q) * 4 + 3] <= 0) continue;
        label[q] = count;
        stack.push_back(q);
      }
    }
  }
  return count;
}

// The round brush held 0.35 rad from upright just above its reach, with its
// geometry and a footprint renderer (on llvmpipe, GALLIUM_DRIVER unset first).
struct TiltedRound {
  static constexpr double kTiltRad = 0.35;
  bool llvmpipe = (::unsetenv("GALLIUM_DRIVER"), true);
  Brush brush = library("round");
  BrushGeometry geo{brush};
  render::StrokeRenderer r;
  Simulation sim{brush, SimOptions{}, makeSlsqpSolver(), makeIpoptSolver()};
  TiltedRound() { sim.reset(at(0, 0, brush.reachMm() + 1, kTiltRad), 0); }
};

}  // namespace

TEST_CASE("the round brush's footprint grows with press depth", "[library][footprint]") {
  TiltedRound f;
  auto& [llvmpipe, brush, geo, r, sim] = f;
  long last = -1;
  for (double depth : {1.0, 3.0, 5.0, 7.0}) {
    moveTo(sim, at(0, 0, 18.8 - depth, f.kTiltRad));
    const long area = coverage(r, geo, sim.state());
    INFO("depth " << depth << " mm: " << area << " px");
    CHECK(area > last);
    last = area;
  }
  CHECK(last > 400);  // > 6 mm^2 at 8 px/mm: a real blot, not a speck
}

TEST_CASE("a flat dragged broadside is at least three times wider than edge-on",
          "[library][footprint]") {
  ::unsetenv("GALLIUM_DRIVER");
  const Brush brush = library("flat");
  // The flat's hairs lie in a row along the brush's x axis. Dragging along y
  // sweeps the whole row (broadside); along x, only its thickness (edge-on).
  auto strokeWidth = [&](bool broadside) {
    BrushGeometry geo(brush);
    render::StrokeRenderer r;
    Simulation sim(brush, SimOptions{}, makeSlsqpSolver(), makeIpoptSolver());
    // Lean the handle against the motion so the hairs trail.
    Pose start = at(0, 0, brush.reachMm() + 1);
    start.rotation = broadside ? Eigen::AngleAxisd(-0.3, Eigen::Vector3d::UnitX())
                               : Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY());
    sim.reset(start, 0);
    Pose down = start;
    down.position_mm.z() = hairLength(brush) * std::cos(0.3) - 5;
    moveTo(sim, down);
    Pose end = down;
    (broadside ? end.position_mm.y() : end.position_mm.x()) += 10;
    moveTo(sim, end);
    // Width across the motion of the current footprint.
    render::FootprintImage fp;
    REQUIRE(r.footprint(geo, sim.state(), window(), 0.1, &fp));
    double lo = 1e9, hi = -1e9;
    for (int row = 0; row < fp.window.height_px; ++row)
      for (int c = 0; c < fp.window.width_px; ++c) {
        if (fp.at(c, row)[3] <= 0) continue;
        const double x = fp.window.x0_mm + (c + 0.5) / 8.0;
        const double y = fp.window.y0_mm + (fp.window.height_px - row - 0.5) / 8.0;
        const double across = broadside ? x : y;
        lo = std::min(lo, across);
        hi = std::max(hi, across);
      }
    return hi - lo;
  };
  const double broad = strokeWidth(true), edge = strokeWidth(false);
  INFO("broadside " << broad << " mm, edge-on " << edge << " mm");
  CHECK(broad >= 3 * edge);
  CHECK(broad >= 10);  // about the 12 mm of the brush
}

// The fan tilted 0.4 rad and pressed 5 mm past first contact.
static BrushState pressedFan(const Brush& brush) {
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver(), makeIpoptSolver());
  Pose start = at(0, 0, brush.reachMm() + 1);
  start.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX());
  sim.reset(start, 0);
  Pose down = start;
  down.position_mm.z() = hairLength(brush) * std::cos(0.4) - 5;
  moveTo(sim, down);
  return sim.state();
}

TEST_CASE("a fan brush's footprint is many separate marks", "[library][footprint]") {
  ::unsetenv("GALLIUM_DRIVER");
  const Brush brush = library("fan");
  BrushGeometry geo(brush);
  render::StrokeRenderer r;
  render::FootprintImage fp;
  REQUIRE(r.footprint(geo, pressedFan(brush), window(), 0.1, &fp));
  const int n = marks(fp);
  INFO(n << " separate marks");
  CHECK(n >= 10);
}

// Runs of covered pixels down each column of a footprint (lengths in px).
static std::vector<int> columnRuns(const render::FootprintImage& fp) {
  std::vector<int> runs;
  for (int c = 0; c < fp.window.width_px; ++c) {
    int run = 0;
    for (int row = 0; row <= fp.window.height_px; ++row) {
      if (row < fp.window.height_px && fp.at(c, row)[3] > 0) {
        ++run;
      } else if (run > 0) {
        runs.push_back(run);
        run = 0;
      }
    }
  }
  return runs;
}

TEST_CASE("a step's footprint is swept: a hair finer than a pixel draws a line, not dots",
          "[library][footprint]") {
  // The fan's hair tips pressed on the paper, then the whole state moved 1 mm
  // along y (8 px at 8 px/mm, exactly: shifts by whole pixels rasterise the
  // same). Swept, every touched pixel of the end stamp continues in a run of
  // at least the 8 px travelled down its column; 1 px of slack for float
  // rounding at the triangles' edges. One stamp alone leaves mostly short
  // runs: the hair tips are 1-2 px across the motion.
  constexpr double kShiftMm = 1.0;
  constexpr int kTravelPx = 8, kSlackPx = 1;
  ::unsetenv("GALLIUM_DRIVER");
  const Brush brush = library("fan");
  BrushGeometry geo(brush);
  render::StrokeRenderer r;
  const BrushState from = pressedFan(brush);
  BrushState to = from;
  const Eigen::Vector3d shift(0, kShiftMm, 0);
  to.handle.position_mm += shift;
  for (SpineState& s : to.spines)
    for (Eigen::Vector3d& p : s.joints_mm) p += shift;

  render::FootprintImage stamp, swept;
  REQUIRE(r.footprint(geo, to, window(), 0.1, &stamp));
  REQUIRE(r.sweptFootprint(geo, from, to, window(), 0.1, 1.0 / 8, &swept));
  const std::vector<int> one = columnRuns(stamp), many = columnRuns(swept);
  REQUIRE_FALSE(one.empty());
  REQUIRE_FALSE(many.empty());
  const int shortest = *std::min_element(many.begin(), many.end());
  int short_in_stamp = 0;
  for (int run : one) short_in_stamp += run < kTravelPx - kSlackPx;
  INFO("one stamp: " << one.size() << " column runs, " << short_in_stamp
                     << " shorter than the travel; swept: shortest run " << shortest << " px");
  CHECK(shortest >= kTravelPx - kSlackPx);
  // The check bites: most runs of a single stamp are shorter than that.
  CHECK(short_in_stamp * 2 > static_cast<int>(one.size()));
}

TEST_CASE("every library brush presses, drags, lifts and leaves a stroke", "[library]") {
  ::unsetenv("GALLIUM_DRIVER");
  for (const char* name : {"round", "flat", "bright", "filbert", "badger", "fan", "calligraphy"}) {
    INFO(name);
    const Brush brush = library(name);
    BrushGeometry geo(brush);
    render::StrokeRenderer r;
    Simulation sim(brush, SimOptions{}, makeSlsqpSolver(), makeIpoptSolver());
    const double top = brush.reachMm() + 1, down = hairLength(brush) * std::cos(0.3) - 5;
    sim.reset(at(0, 0, top, 0.3), 0);
    long painted = 0;
    for (const Pose& p : {at(0, 0, down, 0.3), at(0, 12, down, 0.3), at(0, 12, top, 0.3)}) {
      const Pose from = sim.state().handle;
      for (int i = 1; i <= 30; ++i) {
        sim.step(interpolatePose(from, p, i / 30.0), sim.state().t_s + 0.01);
        painted += coverage(r, geo, sim.state());
      }
    }
    // Summed over the 90 steps. The fan touches with hair tips 0.06 mm wide, under
    // a pixel at 8 px/mm, and leaves least: a few hundred pixel-steps.
    CHECK(painted > 200);
    CHECK(sim.stats().failed_steps == 0);
    CHECK_FALSE(sim.state().anyContact());
  }
}

TEST_CASE("the footprint of a fixed pose is the same in two runs", "[library][determinism]") {
  ::unsetenv("GALLIUM_DRIVER");
  auto run = [] {
    const Brush brush = library("calligraphy");
    BrushGeometry geo(brush);
    render::StrokeRenderer r;
    Simulation sim(brush, SimOptions{}, makeIpoptSolver());
    sim.reset(at(0, 0, brush.reachMm() + 1, 0.3), 0);
    moveTo(sim, at(0, 0, hairLength(brush) * std::cos(0.3) - 6, 0.3));
    render::FootprintImage fp;
    REQUIRE(r.footprint(geo, sim.state(), window(), 0.1, &fp));
    return std::hash<std::string_view>{}(std::string_view(
        reinterpret_cast<const char*>(fp.texels.data()), fp.texels.size() * sizeof(float)));
  };
  CHECK(run() == run());
}

TEST_CASE("the hair left out above the contact band is exactly what the footprint drops",
          "[library][footprint]") {
  // BrushGeometry::build and buildHair, given the contact band, leave out
  // the hair's triangles that stay above it (engine/geometry/brush_vertex.h,
  // reachesDown). The footprint renderer drops such triangles anyway, so the
  // hair must be the full build's with them filtered out: the same
  // triangles, bit for bit, in the same order. The surface's triangles are
  // all kept, and the renderer filters them, so a whole build must filter to
  // what the full one filters to. And the cut must be real: a pressed brush
  // has most of its hair above the band.
  constexpr double kBandMm = 0.1;  // the renderer's default --contact-band-mm
  auto filtered = [&](const std::vector<BrushVertex>& all) {
    std::vector<BrushVertex> kept;
    for (size_t t = 0; t + 2 < all.size(); t += 3)
      if (reachesDown(all[t], all[t + 1], all[t + 2], kBandMm))
        kept.insert(kept.end(), all.begin() + t, all.begin() + t + 3);
    return kept;
  };
  auto same = [](const std::vector<BrushVertex>& a, const std::vector<BrushVertex>& b) {
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(), [](const BrushVertex& p, const BrushVertex& q) {
             return p.x_mm == q.x_mm && p.y_mm == q.y_mm && p.z_mm == q.z_mm && p.u == q.u &&
                    p.v == q.v;
           });
  };
  for (const char* name : {"round", "flat", "bright", "filbert", "badger", "fan", "calligraphy"}) {
    INFO(name);
    const Brush brush = library(name);
    BrushGeometry geo(brush);
    Simulation sim(brush, SimOptions{}, makeSlsqpSolver(), makeIpoptSolver());
    const double top = brush.reachMm() + 1, down = hairLength(brush) * std::cos(0.3) - 5;
    sim.reset(at(0, 0, top, 0.3), 0);
    moveTo(sim, at(0, 0, down, 0.3));
    moveTo(sim, at(0, 6, down, 0.3));
    REQUIRE(sim.state().anyContact());
    std::vector<BrushVertex> all, cut, hair_all, hair_cut;
    geo.build(sim.state(), &all);
    geo.build(sim.state(), &cut, kBandMm);
    geo.buildHair(sim.state(), &hair_all);
    geo.buildHair(sim.state(), &hair_cut, kBandMm);
    CHECK(same(filtered(all), filtered(cut)));
    CHECK(same(filtered(hair_all), hair_cut));
    CHECK_FALSE(hair_cut.empty());  // pressed: some hair reaches the band
    // At least a third of the hair's triangles are above it, for every
    // library brush pressed 5 mm (measured: each leaves out more than half).
    CHECK(3 * (hair_all.size() - hair_cut.size()) >= hair_all.size());
  }
}

TEST_CASE("a joint's half solid is stamped only as often as its notches allow, and the paint "
          "sees the same sweep", "[library][footprint]") {
  // The round brush pressed 7 mm, then the whole state moved 2 mm across the
  // canvas (16 px at 8 px/mm, whole pixels: a shifted stamp rasterises the
  // same). At one stamp per pixel every half solid is drawn at each of 16
  // stamps; with the notches between copies held to kNotchPx, those pressed
  // on the paper (a disc some 7-9 px in radius) every 4 px or so. (A render's
  // steps move the hair 4 px at most; this long one shows the gaps a plan
  // too sparse would leave: with notches of 4 px allowed, 9 pixels change, 3
  // of them inside the sweep.) The paint sees the union of the steps'
  // footprints, so with the step before's (the state `from`): coverage may
  // change only in pixels whose centres lie within the notches, on the
  // outline of the sweep. Each such pixel touches an uncovered one
  // (8-neighbours), and there are at most kNotchPx of a pixel's worth along
  // the outline: under kOutlineShare of it.
  constexpr double kNotchPx = 0.25, kOutlineShare = 0.25;
  constexpr double kMinTriangleSaving = 0.15;  // measured: 0.27 of them are left out
  TiltedRound f;
  auto& [llvmpipe, brush, geo, r, sim] = f;
  moveTo(sim, at(0, 0, hairLength(brush) * std::cos(f.kTiltRad) - 7, f.kTiltRad));
  const BrushState from = sim.state();
  render::FootprintImage before;
  REQUIRE(r.footprint(geo, from, window(), 0.1, &before));
  const CanvasGrid g = window();
  auto origin = [&](const render::FootprintImage& fp) {
    const render::FootprintWindow& fw = fp.window;
    return std::pair{static_cast<int>(std::lround(g.colOf(fw.x0_mm))),
                     static_cast<int>(std::lround(g.rowOf(fw.y0_mm + fw.height_px / g.px_per_mm)))};
  };
  // Whether a footprint covers canvas pixel (col, row).
  auto covers = [&](const render::FootprintImage& fp, int col, int row) {
    const auto [c0, r0] = origin(fp);
    const int c = col - c0, rr = row - r0;
    return c >= 0 && rr >= 0 && c < fp.window.width_px && rr < fp.window.height_px &&
           fp.at(c, rr)[3] > 0;
  };
  for (const Eigen::Vector3d& shift : {Eigen::Vector3d(2, 0, 0), Eigen::Vector3d(0, 2, 0)}) {
    INFO("moved by (" << shift.transpose() << ") mm");
    BrushState to = from;
    to.handle.position_mm += shift;
    for (SpineState& s : to.spines)
      for (Eigen::Vector3d& p : s.joints_mm) p += shift;
    render::FootprintImage every, planned;
    REQUIRE(r.sweptFootprint(geo, from, to, window(), 0.1, 1.0 / 8, &every, 0));
    const size_t every_triangles = r.lastFootprintTriangles();
    REQUIRE(r.sweptFootprint(geo, from, to, window(), 0.1, 1.0 / 8, &planned, kNotchPx));
    const size_t planned_triangles = r.lastFootprintTriangles();
    auto full = [&](int c, int row) { return covers(before, c, row) || covers(every, c, row); };
    const auto [c0, r0] = origin(every);
    long area = 0, outline = 0, changed = 0, changed_inside = 0;
    for (int row = r0 - 40; row <= r0 + every.window.height_px + 40; ++row)
      for (int c = c0 - 40; c <= c0 + every.window.width_px + 40; ++c) {
        bool edge = false;
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) edge = edge || !full(c + dc, row + dr);
        const bool in_full = full(c, row);
        area += in_full;
        outline += in_full && edge;
        if (in_full != (covers(before, c, row) || covers(planned, c, row))) {
          ++changed;
          changed_inside += !edge;
        }
      }
    INFO(area << " px covered, " << outline << " on the outline, " << changed
              << " changed; triangles " << every_triangles << " -> " << planned_triangles);
    CHECK(area > 400);
    CHECK(changed_inside == 0);
    CHECK(changed <= kOutlineShare * outline);
    CHECK(planned_triangles <= (1 - kMinTriangleSaving) * every_triangles);
  }
}

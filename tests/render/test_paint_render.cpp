// The paint model driven by real strokes: brush simulation -> footprint (OSMesa)
// -> transfer -> compose (render/stroke_renderer.h, render/image/compose.h).

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "engine/base/fnv1a64.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/paint/paint.h"
#include "engine/paint/pigments.h"
#include "engine/solvers/solver_pair.h"
#include "engine/solvers/spine_solver.h"
#include "engine/dynamics/stepper.h"
#include "render/image/compose.h"
#include "render/image/image_compare.h"
#include "render/step_pipeline.h"
#include "render/stroke_renderer.h"
#include "tests/support/build_paths.h"

using namespace bristle;
using namespace bristle::render;

namespace {

const std::string kDir = BRISTLE_SOURCE_DIR;
const std::string kFlat = kDir + "/scenes/brushes/flat.json";
const std::string kRound = kDir + "/scenes/brushes/round.json";
const std::string kBroadside = kDir + "/scenes/trajectories/broadside-pull.csv";
const std::string kStraight = kDir + "/scenes/trajectories/straight-pull.csv";

Trajectory shifted(const std::string& path, double dx, double dy, double dz) {
  Trajectory t = loadTrajectory(path);
  for (TrajectorySample& s : t.samples) s.pose.position_mm += Eigen::Vector3d(dx, dy, dz);
  return t;
}

PaintLoad loadOf(PaintLoad::Mode mode, std::vector<std::string> paints, double amount = 1.0) {
  PaintLoad l;
  l.mode = mode;
  l.paints = std::move(paints);
  l.amount = amount;
  return l;
}

// Paints one stroke onto `canvas` with a freshly loaded (or, with no paints, clean) brush.
StrokeResult paintStroke(StrokeRenderer& renderer, const Brush& brush, const Trajectory& traj,
                         PaintCanvas& canvas, const PaintLoad& load) {
  BrushPaint paint(brush);
  if (load.paints.empty())
    paint.clean();
  else
    paint.load(load, canvas.model(), "test");
  return renderer.render(brush, traj, makeIpoptSolver(), StrokeOptions{}, &canvas, &paint);
}

// Pixel (col, row) of a world point.
int colAt(const CanvasGrid& g, double x) { return static_cast<int>(std::floor(g.colOf(x))); }
int rowAt(const CanvasGrid& g, double y) { return static_cast<int>(std::floor(g.rowOf(y))); }

bool wetAt(const PaintCanvas& c, int col, int row, double min_film_mm = 0.002) {
  return c.wet(c.index(col, row)).volume_mm3 / c.pixelAreaMm2() > min_film_mm;
}

// Painted pixels with world y in [y0, y1).
int coverageBetween(const PaintCanvas& c, double y0, double y1, double min_film_mm = 0.002) {
  const CanvasGrid& g = c.grid();
  int n = 0;
  for (int r = std::max(0, rowAt(g, y1)); r < std::min(g.height_px, rowAt(g, y0)); ++r)
    for (int col = 0; col < g.width_px; ++col) n += wetAt(c, col, r, min_film_mm);
  return n;
}

CanvasGrid unionGrid(const CanvasGrid& a, const CanvasGrid& b) {
  CanvasGrid g = a;
  g.x0_mm = std::min(a.x0_mm, b.x0_mm);
  g.y0_mm = std::min(a.y0_mm, b.y0_mm);
  g.width_px = static_cast<int>(
      std::ceil((std::max(a.x0_mm + a.widthMm(), b.x0_mm + b.widthMm()) - g.x0_mm) * g.px_per_mm));
  g.height_px = static_cast<int>(std::ceil(
      (std::max(a.y0_mm + a.heightMm(), b.y0_mm + b.heightMm()) - g.y0_mm) * g.px_per_mm));
  return g;
}

// Mean linear reflectance of the painted pixels of rows [r0, r1) whose column is
// in the fraction [f0, f1) of each row's painted extent.
std::array<double, 3> meanAcross(const PaintCanvas& c, int r0, int r1, double f0, double f1) {
  const CanvasGrid& g = c.grid();
  std::array<double, 3> sum{0, 0, 0};
  int n = 0;
  for (int r = r0; r < r1; ++r) {
    int lo = g.width_px, hi = -1;
    for (int col = 0; col < g.width_px; ++col)
      if (wetAt(c, col, r)) lo = std::min(lo, col), hi = std::max(hi, col);
    if (hi < lo) continue;
    const int a = lo + static_cast<int>(f0 * (hi - lo + 1));
    const int b = lo + static_cast<int>(f1 * (hi - lo + 1));
    for (int col = a; col < b; ++col) {
      if (!wetAt(c, col, r)) continue;
      const std::array<double, 3> refl = c.reflectance(c.index(col, r));
      for (int k = 0; k < 3; ++k) sum[k] += refl[k];
      ++n;
    }
  }
  for (double& v : sum) v /= std::max(n, 1);
  return sum;
}

// Share of blue in a colour: 0 for pure red, 1 for pure blue.
double blueShare(const std::array<double, 3>& c) { return c[2] / (c[0] + c[2]); }

}  // namespace

TEST_CASE("A double-loaded flat lays its two colours side by side, blended between",
          "[paint-render]") {
  const Brush flat = loadBrush(kFlat);
  const Trajectory pull = loadTrajectory(kBroadside);
  StrokeRenderer renderer;
  PaintCanvas canvas(canvasForStroke(flat, pull, StrokeOptions{}), PaperSpec{},
                     MixModel::kKubelkaMunk);
  // Red on the brush's -x side, blue on its +x side; pulled broadside along -y.
  paintStroke(renderer, flat, pull, canvas,
              loadOf(PaintLoad::Mode::kAcross, {"cadmium-red", "ultramarine"}));
  // The middle of the pull (y 25 .. 50 mm), away from where it starts and lifts.
  const CanvasGrid& g = canvas.grid();
  const int r0 = rowAt(g, 50), r1 = rowAt(g, 25);
  const double left = blueShare(meanAcross(canvas, r0, r1, 0.0, 0.25));
  const double right = blueShare(meanAcross(canvas, r0, r1, 0.75, 1.0));
  // The blended zone: of twenty bands across the middle half, the one whose
  // share is furthest from both sides. It need not be the middle band of the
  // canvas: on this pull that band's share is 0.13, 12 % of the way from the
  // red side's to the blue side's.
  double mid = left;
  for (int k = 0; k < 20; ++k) {
    const double a = 0.25 + 0.5 * k / 20, b = a + 0.5 / 20;
    const double share = blueShare(meanAcross(canvas, r0, r1, a, b));
    if (std::min(share - left, right - share) > std::min(mid - left, right - mid)) mid = share;
  }
  INFO("blue share: left " << left << ", most mixed " << mid << ", right " << right);
  // Cadmium red reflects ~10x more red than blue, ultramarine the reverse. The
  // bare paper's share is 0.47. Ultramarine is a transparent glaze, and the
  // flat's bundles, flattened on the paper, spread it thin enough for the paper
  // to show: the right quarter (measured 0.60) must be bluer than the paper by
  // 0.1 at least, as the left (0.23) is redder than it by far more.
  constexpr double kPaperShare = 0.47;
  CHECK(left < 0.25);
  CHECK(right > kPaperShare + 0.1);
  // Between them is a mixture: clearly apart from both sides (0.15 of the range).
  CHECK(mid > left + 0.15 * (right - left));
  CHECK(mid < right - 0.15 * (right - left));
}

TEST_CASE("A brush with little paint runs dry along the stroke, and a full one does not",
          "[paint-render]") {
  const Brush flat = loadBrush(kFlat);
  const Trajectory pull = loadTrajectory(kBroadside);
  StrokeRenderer renderer;
  // Coverage of the pull's last 12 mm over its first 12 mm (it runs from y = 60
  // down to y = 15), with this much paint on the brush.
  auto lastOverFirst = [&](double amount) {
    PaperSpec paper;
    paper.tooth_depth_mm = 0.05;
    PaintCanvas canvas(canvasForStroke(flat, pull, StrokeOptions{}), paper,
                       MixModel::kKubelkaMunk);
    paintStroke(renderer, flat, pull, canvas,
                loadOf(PaintLoad::Mode::kSolid, {"ivory-black"}, amount));
    // Pixels with a film that shows (0.01 mm: half an optical unit of ivory black
    // darkens the paper by over half).
    const int first = coverageBetween(canvas, 45, 57, 0.01),
              last = coverageBetween(canvas, 18, 30, 0.01);
    REQUIRE(first > 0);
    return double(last) / first;
  };
  // The footprint itself changes along the pull (the hairs bend over as it
  // drags), so a full brush is the control: its coverage ratio is the shape's.
  const double little = lastOverFirst(0.15), full = lastOverFirst(1.0);
  INFO("last / first coverage: little paint " << little << ", full " << full);
  // Running dry: the little-paint stroke keeps under 80% of the coverage the
  // shape alone leaves (measured: ~73%; the engine test isolates the effect).
  CHECK(little < 0.8 * full);
  CHECK(little > 0);           // ... broken, scratchy, not gone
}

TEST_CASE("A clean brush dragged through wet paint carries its colour on",
          "[paint-render]") {
  const Brush flat = loadBrush(kFlat), round = loadBrush(kRound);
  // A band of yellow across x = 24 .. 36 mm (the flat pulled down y at x = 30),
  // then the clean round along y = 40 from x = 12 to 67, through the band.
  const Trajectory band = loadTrajectory(kBroadside);
  const Trajectory drag = shifted(kStraight, 0, 20, 0);
  const CanvasGrid grid = unionGrid(canvasForStroke(flat, band, StrokeOptions{}),
                                    canvasForStroke(round, drag, StrokeOptions{}));
  PaintCanvas canvas(grid, PaperSpec{}, MixModel::kKubelkaMunk);
  StrokeRenderer renderer;
  paintStroke(renderer, flat, band, canvas, loadOf(PaintLoad::Mode::kSolid, {"cadmium-yellow"}));
  const double before = canvas.wetVolumeMm3();
  const StrokeResult r = paintStroke(renderer, round, drag, canvas, PaintLoad{});
  CHECK(r.picked_up_mm3 > 0);
  CHECK(r.deposited_mm3 > 0);
  // Nothing appears or vanishes: the clean brush only moves paint about (what it
  // still holds is the difference), to float rounding (1e-5, test_paint.cpp).
  CHECK(canvas.wetVolumeMm3() + (r.picked_up_mm3 - r.deposited_mm3) ==
        Approx(before).epsilon(1e-5));

  // Past the band (x 42 .. 60 mm) along the drag: yellow paint the brush brought.
  double volume = 0;
  std::array<double, 3> drop{0, 0, 0};
  int n = 0;
  for (int row = rowAt(grid, 44); row < rowAt(grid, 36); ++row)
    for (int col = colAt(grid, 42); col < colAt(grid, 60); ++col) {
      const size_t i = canvas.index(col, row);
      if (canvas.wet(i).volume_mm3 <= 0) continue;
      volume += canvas.wet(i).volume_mm3;
      const std::array<double, 3> refl = canvas.reflectance(i);
      for (int k = 0; k < 3; ++k) drop[k] += canvas.dryReflectance(i)[k] - refl[k];
      ++n;
    }
  INFO("carried " << volume << " mm^3 onto " << n << " px; mean drop R G B " << drop[0] / n
                  << " " << drop[1] / n << " " << drop[2] / n);
  CHECK(n > 200);  // over 3 mm^2 of the canvas
  CHECK(volume > 0.001 * before);
  // Yellow: it takes away blue (K_b = 3.45), not red.
  CHECK(drop[2] > 3 * drop[0]);
  CHECK(drop[2] / n > 0.05);
  // Before the band the clean brush had nothing to give. The flat's bundles,
  // flattened on the paper, take the band's own edge to x = 19.7 mm; the
  // round, pulled, lays its belly and tip along the paper behind the ferrule,
  // and a strip's load is shared along its length, so what its front picks up
  // in the band its tail lays down up to a contact length further back.
  double first_wet_x = 1e9;
  for (int row = rowAt(grid, 44); row < rowAt(grid, 36); ++row)
    for (int col = colAt(grid, 12); col < colAt(grid, 24); ++col)
      if (canvas.wet(canvas.index(col, row)).volume_mm3 > 0)
        first_wet_x = std::min(first_wet_x, grid.x0_mm + (col + 0.5) / grid.px_per_mm);
  // The drag touches down at x = 12 mm. Its paint may start no further back
  // than a quarter of the round's 20 mm of hair behind the band (the part of
  // the hair lying on the paper at this press); measured 16.6 mm.
  INFO("paint along the drag starts at x = " << first_wet_x << " mm");
  CHECK(first_wet_x > 19.7 - 0.25 * 20.0);
}

TEST_CASE("Light pressure on toothy paper covers markedly less than firm pressure",
          "[paint-render]") {
  const Brush round = loadBrush(kRound);
  StrokeRenderer renderer;
  // Painted pixels of the straight pull, held `lift_mm` higher, on paper of this grain.
  auto coverage = [&](double lift_mm, double tooth_mm) {
    const Trajectory t = shifted(kStraight, 0, 0, lift_mm);
    PaperSpec paper;
    paper.tooth_depth_mm = tooth_mm;
    PaintCanvas canvas(canvasForStroke(round, t, StrokeOptions{}), paper,
                       MixModel::kKubelkaMunk);
    paintStroke(renderer, round, t, canvas, loadOf(PaintLoad::Mode::kSolid, {"ivory-black"}));
    return double(coverageBetween(canvas, 0, 100, 1e-4));
  };
  // Held 6.5 mm higher the round barely reaches the paper (7 mm: not at all).
  const double light = coverage(6.5, 0.05) / coverage(6.5, 0.0);
  const double firm = coverage(0.0, 0.05) / coverage(0.0, 0.0);
  INFO("toothy / smooth coverage: light " << light << ", firm " << firm);
  CHECK(light < 0.5);         // a light touch catches the grain's peaks
  CHECK(firm > 0.75);         // firm pressure fills most of it (the rim stays broken)
  CHECK(light < 0.5 * firm);  // markedly less
}

TEST_CASE("Paint strokes are deterministic: same inputs, same pixels", "[paint-render]") {
  const Brush flat = loadBrush(kFlat);
  const Trajectory pull = loadTrajectory(kBroadside);
  auto render = [&](StrokeRenderer& renderer) {
    PaperSpec paper;
    paper.tooth_depth_mm = 0.05;
    PaintCanvas canvas(canvasForStroke(flat, pull, StrokeOptions{}), paper,
                       MixModel::kKubelkaMunk);
    paintStroke(renderer, flat, pull, canvas,
                loadOf(PaintLoad::Mode::kAcross, {"viridian", "titanium-white"}, 0.4));
    ComposeOptions opt;
    opt.impasto = true;
    const Image16 img = composeRgb16(canvas, opt);
    return fnv1a64(std::string_view(reinterpret_cast<const char*>(img.pixels.data()),
                                    img.pixels.size() * 2));
  };
  StrokeRenderer a, b;
  const std::uint64_t first = render(a);
  CHECK(render(a) == first);  // the same renderer again
  CHECK(render(b) == first);  // a fresh one
}

TEST_CASE("Compose: paper shows through where there is no paint, and impasto lights relief",
          "[paint-render]") {
  CanvasGrid g;
  g.width_px = 40;
  g.height_px = 20;
  PaperSpec paper;
  paper.colour = "#808080";
  PaintCanvas canvas(g, paper, MixModel::kKubelkaMunk);
  // A ridge of white paint 0.03 mm thick over columns 10 .. 29 (its edges slope
  // 17 degrees at the default 4x relief: lit, not turned away).
  Optics white;
  std::string why;
  REQUIRE(resolvePaint("titanium-white", MixModel::kKubelkaMunk, &white, &why));
  for (int r = 0; r < 20; ++r)
    for (int c = 10; c < 30; ++c) {
      PaintCell& cell = canvas.wet(canvas.index(c, r));
      cell.volume_mm3 = static_cast<float>(0.03 * canvas.pixelAreaMm2());
      cell.optics = white;
    }
  const Image8 flat = composeRgb8(canvas, ComposeOptions{});
  CHECK(flat.pixels[(5 * 40 + 2) * 3] == 0x80);  // bare paper, exactly its colour
  CHECK(flat.pixels[(5 * 40 + 20) * 3] > 0xe0);  // white paint
  ComposeOptions lit;
  lit.impasto = true;
  const Image8 shaded = composeRgb8(canvas, lit);
  // The light comes from the upper left (-x): the ridge's left edge faces it and
  // is brighter than the flat top, its right edge faces away and is darker.
  const int left_edge = shaded.pixels[(5 * 40 + 10) * 3];
  const int top = shaded.pixels[(5 * 40 + 20) * 3];
  const int right_edge = shaded.pixels[(5 * 40 + 29) * 3];
  INFO(left_edge << " " << top << " " << right_edge);
  CHECK(left_edge > top);
  CHECK(right_edge < top - 20);
  CHECK(top == flat.pixels[(5 * 40 + 20) * 3]);  // flat paint keeps its colour
}

// composeRgb8/16 memoise the sRGB encoding by the float's bits in a
// direct-mapped table; each code must still be exactly the formula's. The
// values mix repeats (a canvas's paper), spread values and values chosen to
// land in one slot, so a memo that answered by slot alone would fail.
TEST_CASE("Compose: the memoised sRGB codes are exactly the formula's, value by value",
          "[paint-render]") {
  std::vector<float> v;
  std::uint64_t state = 12345;
  auto next = [&state] {  // xorshift64*: a fixed sequence on every platform
    state ^= state >> 12, state ^= state << 25, state ^= state >> 27;
    return (state * 2685821657736338717ull) >> 40;  // 24 bits
  };
  for (int i = 0; i < 200000; ++i) {
    const float x = static_cast<float>(next()) / float(1 << 24);
    v.push_back(i % 3 == 0 ? 0.2140411f : x);  // a third of them one paper value
  }
  // Pairs of floats that share a slot, found by walking consecutive bit
  // patterns until one lands where an earlier one did.
  const auto slot = [](float f) { return (std::bit_cast<std::uint32_t>(f) * 2654435769u) >> 20; };
  std::vector<std::uint32_t> first_in(4096, 0);
  int colliding = 0;
  for (std::uint32_t b = 0x3e000000u; b < 0x3e000000u + 40000 && colliding < 200; ++b) {
    std::uint32_t& seen = first_in[slot(std::bit_cast<float>(b))];
    if (seen == 0) {
      seen = b;
      continue;
    }
    const float a = std::bit_cast<float>(seen), c = std::bit_cast<float>(b);
    v.insert(v.end(), {a, c, a, c});
    ++colliding;
  }
  REQUIRE(colliding > 20);
  v.insert(v.end(), {0.0f, 1.0f, -0.5f, 2.0f, 0.0031308f, 1e-30f});
  const std::vector<std::uint8_t> e8 = encodeSrgb8(v);
  const std::vector<std::uint16_t> e16 = encodeSrgb16(v);
  REQUIRE(e8.size() == v.size());
  REQUIRE(e16.size() == v.size());
  int wrong = 0;
  for (size_t i = 0; i < v.size(); ++i) {
    wrong += e8[i] != std::lround(255.0 * linearToSrgb(v[i]));
    wrong += e16[i] != std::lround(65535.0 * linearToSrgb(v[i]));
  }
  CHECK(wrong == 0);
}

// `bristle preview --at t` steps as the render does (Stepper::walk): the
// state it stops at is the very state the render painted at t. Before, the
// preview stepped the planned times without the render's halving of a step
// whose touching hairs jump too far, so where the render split a step (a
// pressed brush springing back at lift-off) it showed a state the render never
// reached.
TEST_CASE("preview's stepping stops at the state the render painted at that time",
          "[render][preview]") {
  const Brush brush = loadBrush(kRound);
  const Trajectory traj = loadTrajectory(kDir + "/scenes/trajectories/press-lift.csv");
  const StrokeOptions options;
  // The render, keeping every state its step callback sees.
  std::vector<BrushState> seen;
  std::vector<int> planned;
  {
    PaintCanvas canvas(canvasForStroke(brush, traj, options), PaperSpec{},
                       MixModel::kKubelkaMunk);
    BrushPaint paint(brush);
    paint.load(loadOf(PaintLoad::Mode::kSolid, {"sumi-ink"}), canvas.model(), "test");
    SolverPair solvers = makeSolverPair();
    StrokeRenderer renderer;
    renderer.render(brush, traj, std::move(solvers.primary), options, &canvas, &paint,
                    [&](const BrushState& st, int step, int) {
                      seen.push_back(st);
                      planned.push_back(step);
                    },
                    std::move(solvers.fallback));
  }
  // A split step reports its planned index twice: the last piece ends at the
  // planned time, reached by pieces rather than by one step.
  size_t split_end = 0;
  for (size_t i = 1; i < planned.size() && split_end == 0; ++i)
    if (planned[i] == planned[i - 1]) {
      split_end = i;
      while (split_end + 1 < planned.size() && planned[split_end + 1] == planned[i])
        ++split_end;
    }
  REQUIRE(split_end > 0);
  REQUIRE(split_end + 1 < seen.size());

  auto previewAt = [&](double t_s) {
    SolverPair solvers = makeSolverPair();
    Simulation sim(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
    Stepper(sim, walkOptions(options, options.px_per_mm)).walk(traj, {}, t_s);
    return sim.state();
  };
  auto sameJoints = [](const BrushState& a, const BrushState& b) {
    REQUIRE(a.spines.size() == b.spines.size());
    for (size_t s = 0; s < a.spines.size(); ++s)
      if (a.spines[s].joints_mm != b.spines[s].joints_mm) return false;
    return true;
  };
  // At the end of the split step, in the middle of it, and between two steps
  // (the last step at or before that time).
  for (size_t i : {split_end, split_end - 1}) {
    INFO("state " << i << " of the render, t = " << seen[i].t_s << " s");
    const BrushState at = previewAt(seen[i].t_s);
    CHECK(at.t_s == seen[i].t_s);
    CHECK(sameJoints(at, seen[i]));
  }
  const double between = 0.5 * (seen[split_end].t_s + seen[split_end + 1].t_s);
  const BrushState before = previewAt(between);
  CHECK(before.t_s == seen[split_end].t_s);
  CHECK(sameJoints(before, seen[split_end]));

  // The old preview's one unsplit step to the same time lands elsewhere.
  SolverPair solvers = makeSolverPair();
  Simulation old(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
  const std::vector<double> times = planStepTimes(traj, brush, options.sim);
  const double t_end = seen[split_end].t_s;
  old.reset(traj.poseAt(times.front()), times.front());
  for (size_t i = 1; i < times.size() && times[i - 1] < t_end; ++i)
    old.step(traj.poseAt(std::min(times[i], t_end)), std::min(times[i], t_end));
  CHECK_FALSE(sameJoints(old.state(), seen[split_end]));
}

// What ssim() takes: RGBA, the canvas's composed RGB with an opaque alpha.
Image16 opaqueRgba(const PaintCanvas& canvas) {
  const Image16 rgb = composeRgb16(canvas, ComposeOptions{});
  Image16 out{rgb.width, rgb.height, 4, {}};
  for (size_t i = 0; i + 2 < rgb.pixels.size(); i += 3)
    out.pixels.insert(out.pixels.end(), {rgb.pixels[i], rgb.pixels[i + 1], rgb.pixels[i + 2], 65535});
  return out;
}

// `brush` along `traj` in sumi ink, onto a canvas made for the stroke: the
// composed image, and the render's result in *result.
Image16 inkStroke(const Brush& brush, const Trajectory& traj, const StrokeOptions& options,
                  std::unique_ptr<SpineSolver> solver, StrokeResult* result,
                  const StepCallback& on_step = {},
                  std::unique_ptr<SpineSolver> fallback = nullptr) {
  PaintCanvas canvas(canvasForStroke(brush, traj, options), PaperSpec{}, MixModel::kKubelkaMunk);
  BrushPaint paint(brush);
  paint.load(loadOf(PaintLoad::Mode::kSolid, {"sumi-ink"}), canvas.model(), "test");
  StrokeRenderer renderer;
  *result = renderer.render(brush, traj, std::move(solver), options, &canvas, &paint, on_step,
                            std::move(fallback));
  return opaqueRgba(canvas);
}

// Steady steps (SimOptions::steady_step_mm, docs/dynamics.md "Steady steps"):
// planned steps are solved as one only where the brush does nothing the
// planned steps would resolve differently, and the stroke stays close to the
// one stepped as planned.
TEST_CASE("steady steps merge planned steps only while the contact set holds, and keep the "
          "stroke",
          "[render][steady]") {
  const Brush flat = loadBrush(kFlat);
  const Trajectory curve = shifted(kDir + "/scenes/trajectories/s-curve.csv", 0, 0, -1.8);
  struct Run {
    Image16 image;
    SimStats stats;
    int merged_kept = 0;  // steps that covered more than one planned step
    bool contact_held = true;
  };
  auto run = [&](double steady_mm) {
    StrokeOptions options;
    options.sim.steady_step_mm = steady_mm;
    Run r;
    BrushState last;
    int last_planned = -1;
    StrokeResult result;
    r.image = inkStroke(
        flat, curve, options, makeSlsqpSolver(), &result,
        [&](const BrushState& st, int planned, int) {
          if (last_planned >= 0 && planned > last_planned + 1) {
            ++r.merged_kept;
            for (size_t s = 0; s < st.spines.size(); ++s)
              if (st.spines[s].contact != last.spines[s].contact ||
                  st.spines[s].sliding != last.spines[s].sliding)
                r.contact_held = false;
          }
          last = st;
          last_planned = planned;
        });
    r.stats = result.stats;
    return r;
  };
  const Run planned = run(0);
  const Run steady = run(1.0);
  INFO("planned: " << planned.stats.steps << " steps; steady: " << steady.stats.steps
                   << " steps, " << steady.stats.steady_steps << " of them merging "
                   << steady.stats.steady_merged << " planned steps, "
                   << steady.stats.steady_rejected << " merges redone as planned");
  CHECK(planned.stats.steady_steps == 0);
  CHECK(planned.merged_kept == 0);
  REQUIRE(steady.stats.steady_steps > 0);
  CHECK(steady.merged_kept == steady.stats.steady_steps);
  CHECK(steady.stats.steady_merged >= 2 * steady.stats.steady_steps);
  CHECK(steady.contact_held);
  // Fewer solves: observed 437 steps against 919 for the library's flat.
  CHECK(steady.stats.steps < 0.7 * planned.stats.steps);
  // The same stroke to a painter: steady steps move a library brush's
  // S-curve to SSIM 0.95-1 of planned stepping, the fan's hair-thin marks
  // most (docs/PERFORMANCE.md, "Steady steps"); a stroke that lost its ends
  // or its bends falls far below 0.98.
  constexpr double kSameStrokeSsim = 0.98;
  const double same = ssim(planned.image, steady.image);
  INFO("SSIM " << same);
  CHECK(same > kSameStrokeSsim);
}

namespace {

// The flat along the S-curve in sumi ink, with `threads` (StrokeOptions::threads),
// onto `canvas` (made here for the stroke).
StrokeResult inkCurve(int threads, std::unique_ptr<SpineSolver> solver,
                      const StepCallback& on_step, std::optional<PaintCanvas>* canvas,
                      const std::string& brush = kFlat) {
  const Brush flat = loadBrush(brush);
  const Trajectory curve = shifted(kDir + "/scenes/trajectories/s-curve.csv", 0, 0, -1.8);
  StrokeOptions options;
  options.threads = threads;
  canvas->emplace(canvasForStroke(flat, curve, options), PaperSpec{}, MixModel::kKubelkaMunk);
  BrushPaint paint(flat);
  paint.load(loadOf(PaintLoad::Mode::kSolid, {"sumi-ink"}), (*canvas)->model(), "test");
  StrokeRenderer renderer;
  return renderer.render(flat, curve, std::move(solver), options, &**canvas, &paint, on_step);
}

// A solver that throws on its n-th solve: an error on the stepping thread.
class BreakingSolver : public SpineSolver {
 public:
  BreakingSolver(std::unique_ptr<SpineSolver> inner, int breaks_at)
      : inner_(std::move(inner)), breaks_at_(breaks_at) {}
  using SpineSolver::solve;
  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions,
                     std::span<const VolumeLink> links) override {
    if (++solves_ == breaks_at_) throw std::runtime_error("the solver broke");
    return inner_->solve(problems, solutions, links);
  }
  bool couplesSpines(int spines) const override { return inner_->couplesSpines(spines); }
  bool wantsPredictedStart() const override { return inner_->wantsPredictedStart(); }
  void setWatch(SolveWatch* watch) override { inner_->setWatch(watch); }
  const char* name() const override { return inner_->name(); }

 private:
  std::unique_ptr<SpineSolver> inner_;
  int breaks_at_ = 0, solves_ = 0;
};

// A solver that adds up the iterations it reports.
class CountingSolver : public SpineSolver {
 public:
  explicit CountingSolver(std::unique_ptr<SpineSolver> inner, long* iterations)
      : inner_(std::move(inner)), iterations_(iterations) {}
  using SpineSolver::solve;
  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions,
                     std::span<const VolumeLink> links) override {
    const SolveSummary s = inner_->solve(problems, solutions, links);
    *iterations_ += s.iterations;
    return s;
  }
  bool couplesSpines(int spines) const override { return inner_->couplesSpines(spines); }
  bool wantsPredictedStart() const override { return inner_->wantsPredictedStart(); }
  void setWatch(SolveWatch* watch) override { inner_->setWatch(watch); }
  const char* name() const override { return inner_->name(); }

 private:
  std::unique_ptr<SpineSolver> inner_;
  long* iterations_;
};

}  // namespace

// Simulation and drawing on two threads (StrokeOptions::threads,
// render/step_pipeline.h): the states reach the drawing side in the order they
// were solved, so a render that simulates ahead is the one that takes turns,
// pixel for pixel and step for step.
TEST_CASE("a render that simulates ahead on a second thread paints the same pixels, step for "
          "step",
          "[render][threads]") {
  struct Run {
    std::uint64_t pixels = 0;
    StrokeResult result;
    std::vector<std::pair<int, double>> steps;  // (planned step, t_s) as on_step saw them
  };
  auto run = [](int threads) {
    Run r;
    std::optional<PaintCanvas> canvas;
    r.result = inkCurve(threads, makeIpoptSolver(),
                        [&](const BrushState& st, int planned, int) {
                          r.steps.emplace_back(planned, st.t_s);
                        },
                        &canvas);
    const Image16 img = composeRgb16(*canvas, ComposeOptions{});
    r.pixels = fnv1a64(std::string_view(reinterpret_cast<const char*>(img.pixels.data()),
                                        img.pixels.size() * 2));
    return r;
  };
  const Run turns = run(1);
  const Run ahead = run(2);
  REQUIRE(turns.result.touched);
  CHECK(ahead.pixels == turns.pixels);
  CHECK(ahead.steps == turns.steps);
  CHECK(ahead.result.stats.steps == turns.result.stats.steps);
  CHECK(ahead.result.stats.iterations == turns.result.stats.iterations);
  // Bit for bit: the same transfers in the same order.
  CHECK(ahead.result.deposited_mm3 == turns.result.deposited_mm3);
  CHECK(ahead.result.picked_up_mm3 == turns.result.picked_up_mm3);
  const int machine = defaultRenderThreads();
  CHECK((machine == 1 || machine == 2));
}

// Either side of a render that simulates ahead may fail: the drawing side (here
// its step callback) or the stepping side (here its solver). Both threads stop,
// the error reaches the caller, and every step solved before a stepping error
// is drawn, as when the two take turns. A hang here is a deadlock (the test's
// timeout catches it).
TEST_CASE("an error on either thread of a render that simulates ahead stops both and reaches "
          "the caller",
          "[render][threads]") {
  // Drawn steps before the error, and the error's message.
  auto run = [](int threads, int solver_breaks_at, int drawing_breaks_at) {
    int drawn = 0;
    std::string message;
    std::optional<PaintCanvas> canvas;
    try {
      inkCurve(threads, std::make_unique<BreakingSolver>(makeSlsqpSolver(), solver_breaks_at),
               [&](const BrushState&, int, int) {
                 if (++drawn == drawing_breaks_at) throw std::runtime_error("the drawing broke");
               },
               &canvas);
    } catch (const std::runtime_error& e) {
      message = e.what();
    }
    return std::make_pair(drawn, message);
  };
  constexpr int kNever = -1;
  for (int threads : {1, 2}) {
    INFO("threads " << threads);
    // The drawing side fails while the stepping side waits on a full ring.
    CHECK(run(threads, kNever, 40) == std::make_pair(40, std::string("the drawing broke")));
    CHECK(run(threads, kNever, 1) == std::make_pair(1, std::string("the drawing broke")));
  }
  const auto turns = run(1, 60, kNever);
  const auto ahead = run(2, 60, kNever);
  CHECK(turns.second == "the solver broke");
  CHECK(turns.first > 1);
  CHECK(ahead == turns);
}

// --stats' solver_iterations is the work done: a step whose touching part
// jumped too far is redone in halves (render/stroke_renderer.cpp), and its
// first try's iterations stay counted, as a failed solve's and a redone
// steady step's do. (They were dropped: the round brush's first 0.6 s of a
// tablet recording reported 5,197 of its 8,611 Ipopt iterations.)
TEST_CASE("the solver's iterations stay counted when a step is redone in halves",
          "[render][stats]") {
  long reported = 0;
  std::optional<PaintCanvas> canvas;
  const StrokeResult r =
      inkCurve(1, std::make_unique<CountingSolver>(makeSlsqpSolver(), &reported),
               StepCallback{}, &canvas, kDir + "/scenes/brushes/fan.json");
  // The fan's tips along this S-curve outrun the handle: steps are redone in
  // halves (68 times observed on the library's depth S-curve).
  REQUIRE(r.stats.jump_split_steps > 0);
  CHECK(r.stats.iterations == reported);
}

// StrokeOptions::stop_on_jump: a step whose hair on the paper jumps too far is
// redone in halves, and its first try is given up at the first Ipopt iterate
// that shows the jump instead of after its solves converge. The solver's work
// stays counted, the renderer spends less of it, and the stroke stays the one
// judged by results alone.
TEST_CASE("a step that jumps is given up at its first iterate past the limit, and the stroke "
          "stays",
          "[render][jump]") {
  const Brush fan = loadBrush(kDir + "/scenes/brushes/fan.json");
  const Trajectory curve = shifted(kDir + "/scenes/trajectories/s-curve.csv", 0, 0, -1.8);
  struct Run {
    Image16 image;
    SimStats stats;
    long counted = 0;  // the iterations the solver reported
  };
  auto run = [&](double stop_on_jump) {
    StrokeOptions options;
    options.stop_on_jump = stop_on_jump;
    options.threads = 1;
    PaintCanvas canvas(canvasForStroke(fan, curve, options), PaperSpec{}, MixModel::kKubelkaMunk);
    BrushPaint paint(fan);
    paint.load(loadOf(PaintLoad::Mode::kSolid, {"sumi-ink"}), canvas.model(), "test");
    Run r;
    StrokeRenderer renderer;
    r.stats = renderer
                  .render(fan, curve, std::make_unique<CountingSolver>(makeIpoptSolver(), &r.counted),
                          options, &canvas, &paint)
                  .stats;
    r.image = opaqueRgba(canvas);
    return r;
  };
  const Run judged = run(0);
  const Run watched = run(StrokeOptions{}.stop_on_jump);
  INFO("judged by results: " << judged.stats.iterations << " iterations, "
                             << judged.stats.jump_split_steps << " steps redone in halves; watched: "
                             << watched.stats.iterations << " iterations, "
                             << watched.stats.jump_split_steps << " redone, "
                             << watched.stats.jump_stopped_steps << " of them stopped early");
  CHECK(judged.stats.jump_stopped_steps == 0);
  REQUIRE(judged.stats.jump_split_steps > 0);  // the fan's tips outrun the handle here
  CHECK(watched.stats.jump_stopped_steps > 0);
  CHECK(watched.stats.jump_stopped_steps <= watched.stats.jump_split_steps);
  CHECK(watched.stats.iterations == watched.counted);  // the stopped tries' work is counted
  // Observed: 10,276 iterations against 10,856 (0.95), with 160 steps
  // redone in halves against 75, every one of them stopped early.
  CHECK(watched.stats.iterations < judged.stats.iterations);
  // The same stroke to a painter: the halves start where the step began
  // either way, and a try stopped that would have passed is only split finer.
  // Observed SSIM 0.994; as for steady steps above, a stroke that lost its
  // ends or its bends falls far below 0.98.
  constexpr double kSameStrokeSsim = 0.98;
  const double same = ssim(judged.image, watched.image);
  INFO("SSIM " << same);
  CHECK(same > kSameStrokeSsim);
}

// A blot: the round pressed, held still for 0.7 s, lifted. Held at rest it
// solves nothing (SimOptions::settled_mm, docs/dynamics.md "A brush held
// still"), and its paint keeps flowing into the paper as if it were solved.
TEST_CASE("a blot held still paints what solving every held step paints", "[render][settled]") {
  const Brush round = loadBrush(kRound);
  double top = 0;
  for (const SpineSpec& s : round.spines) top = std::max(top, s.lengthMm());
  Trajectory blot;
  blot.path = "blot";
  for (const auto& [t, z] : std::vector<std::pair<double, double>>{
           {0.0, top + 1}, {0.3, top - 4}, {1.0, top - 4}, {1.3, top + 1}}) {
    TrajectorySample s;
    s.t_s = t;
    s.pose.position_mm = Eigen::Vector3d(30, 30, z);
    blot.samples.push_back(s);
  }
  struct Run {
    Image16 image;
    StrokeResult result;
  };
  auto run = [&](double settled_mm) {
    StrokeOptions options;
    options.sim.settled_mm = settled_mm;
    SolverPair solvers = makeSolverPair();
    Run r;
    r.image = inkStroke(round, blot, options, std::move(solvers.primary), &r.result, {},
                        std::move(solvers.fallback));
    return r;
  };
  const Run every = run(0);
  const Run settled = run(kSettledMm);
  INFO("solved steps " << every.result.stats.solved_steps << " -> "
                       << settled.result.stats.solved_steps << ", settled "
                       << settled.result.stats.settled_steps << ", iterations "
                       << every.result.stats.iterations << " -> "
                       << settled.result.stats.iterations);
  CHECK(every.result.stats.settled_steps == 0);
  // At rest the brush sends the same triangles each step, and its footprint
  // is kept rather than drawn again: at least once per settled step but the
  // first. Solved every step it rarely is (observed: 3 times, where two
  // solves happened to end on the same bits).
  INFO("footprints kept " << every.result.footprints_kept << " -> "
                          << settled.result.footprints_kept);
  CHECK(settled.result.footprints_kept >= settled.result.stats.settled_steps - 1);
  CHECK(every.result.footprints_kept < settled.result.stats.settled_steps / 4);
  // Observed: 50 of the 0.7 s hold's 84 planned steps (120 a second) at
  // rest, from 0.28 s into the hold.
  CHECK(settled.result.stats.settled_steps > 25);
  CHECK(settled.result.stats.solved_steps + settled.result.stats.settled_steps ==
        every.result.stats.solved_steps);
  CHECK(settled.result.stats.iterations < every.result.stats.iterations);
  // The paint laid down: held steps keep soaking the paper. The brush stands
  // within 3e-5 mm of where the solves keep it, so the amounts agree to far
  // better than a part in a thousand (observed: to the last printed digit).
  constexpr double kSamePaintShare = 1e-3;
  CHECK(std::fabs(settled.result.deposited_mm3 - every.result.deposited_mm3) <=
        kSamePaintShare * every.result.deposited_mm3);
  // The same blot: observed identical pixels; SSIM 0.9999 allows a pixel's
  // rounding and fails for a blot that lost its soak or its edge.
  constexpr double kSameBlotSsim = 0.9999;
  const double same = ssim(every.image, settled.image);
  INFO("SSIM " << same);
  CHECK(same > kSameBlotSsim);
}

// Render benchmarks (docs/PERFORMANCE.md): one footprint render + readback
// (OSMesa llvmpipe) at 256^2 and 512^2 windows with 5000 triangles, and a whole
// StrokeRenderer::render of the round brush along s-curve.csv. Times are wall
// clock (llvmpipe rasterises on its own threads), taken with a steady clock as
// manual time; the median and p95 over all timed calls are counters.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <span>
#include <string>
#include <vector>

#include "bench/bench_stats.h"
#include "bench/bench_main.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/dynamics/simulation.h"
#include "engine/model/trajectory.h"
#include "render/gl/footprint_renderer.h"
#include "render/stroke_renderer.h"
#include "tests/support/build_paths.h"

namespace {

using namespace bristle;
using namespace bristle::render;
using bench::Clock;
using bench::percentile;
using bench::seconds;

constexpr double kPxPerMm = 8;       // the CLI's default canvas resolution
constexpr double kClipMm = 0.1;      // StrokeOptions' default contact band
constexpr int kGridQuads = 50;       // 50 x 50 quads = 5000 triangles
constexpr double kWaveMm = 8;        // wavelength of the test surface
constexpr double kAmplitudeMm = 0.5; // about half the surface lies below the clip plane


void reportPercentiles(benchmark::State& state, std::vector<double>& us,
                       const std::string& prefix) {
  state.counters[prefix + "median_us"] = percentile(us, 50);
  state.counters[prefix + "p95_us"] = percentile(us, 95);
}

// A wavy height field filling the window: kGridQuads^2 quads, two triangles each,
// with brush-like texture coordinates (u across, v along).
std::vector<FootprintVertex> wavySurface(const FootprintWindow& w) {
  const double width_mm = w.width_px / w.px_per_mm, height_mm = w.height_px / w.px_per_mm;
  auto vertex = [&](int i, int j) {
    const double u = double(i) / kGridQuads, v = double(j) / kGridQuads;
    const double x = w.x0_mm + u * width_mm, y = w.y0_mm + v * height_mm;
    const double z = kAmplitudeMm * std::sin(2 * std::numbers::pi * x / kWaveMm) *
                     std::cos(2 * std::numbers::pi * y / kWaveMm);
    return FootprintVertex{float(x), float(y), float(z), float(u), float(v)};
  };
  std::vector<FootprintVertex> tris;
  tris.reserve(6 * kGridQuads * kGridQuads);
  for (int j = 0; j < kGridQuads; ++j)
    for (int i = 0; i < kGridQuads; ++i)
      tris.insert(tris.end(), {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1),
                               vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
  return tris;
}

// Times FootprintRenderer::render of `tris` in `window`, with its readback;
// the first call, which allocates the FBO, is left out.
void timeWindowRender(benchmark::State& state, std::span<const FootprintVertex> tris,
                      const FootprintWindow& window, FootprintImage* image) {
  FootprintRenderer renderer(std::max(window.width_px, window.height_px));
  renderer.render(tris, window, kClipMm, image);
  std::vector<double> us;
  for (auto _ : state) {
    const Clock::time_point t0 = Clock::now();
    renderer.render(tris, window, kClipMm, image);
    const double dt = seconds(t0, Clock::now());
    benchmark::DoNotOptimize(image->texels.data());
    state.SetIterationTime(dt);
    us.push_back(1e6 * dt);
  }
  reportPercentiles(state, us, "");
}

// A window range(0) pixels square at the CLI's resolution.
FootprintWindow squareWindow(const benchmark::State& state) {
  FootprintWindow window;
  window.width_px = window.height_px = static_cast<int>(state.range(0));
  window.px_per_mm = kPxPerMm;
  return window;
}

// One footprint render + readback; range(0) is the window side in pixels.
void BM_FootprintRender(benchmark::State& state) {
  const FootprintWindow window = squareWindow(state);
  const std::vector<FootprintVertex> tris = wavySurface(window);
  FootprintImage image;
  timeWindowRender(state, tris, window, &image);
  double covered = 0;
  for (size_t i = 3; i < image.texels.size(); i += 4) covered += image.texels[i];
  state.counters["triangles"] = double(tris.size() / 3);
  state.counters["covered_frac"] = covered / (double(window.width_px) * window.height_px);
}
BENCHMARK(BM_FootprintRender)
    ->ArgName("px")
    ->Arg(256)->Arg(512)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// The floor under any footprint of a window range(0) pixels square: clearing
// the float colour and depth targets and reading them back, with nothing
// drawn. Any footprint at that size costs at least this (docs/PERFORMANCE.md,
// "Footprints").
void BM_FootprintFloor(benchmark::State& state) {
  FootprintImage image;
  timeWindowRender(state, {}, squareWindow(state), &image);
}
BENCHMARK(BM_FootprintFloor)
    ->ArgName("px")
    ->Arg(256)->Arg(512)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// A whole stroke: simulation + footprint + paint per step, the round brush along
// s-curve.csv, with range(0) threads (StrokeOptions::threads: 1 takes turns, 2
// simulates ahead while drawing). Time: the stroke; counters: per step (between
// step callbacks, so a step the renderer redoes in smaller pieces counts in the
// next one; with 2 threads, the time between states drawn).
void BM_StrokeRender(benchmark::State& state) {
  const std::string dir = BRISTLE_SOURCE_DIR;
  const Brush brush = loadBrush(dir + "/scenes/brushes/round.json");
  const Trajectory traj = loadTrajectory(dir + "/scenes/trajectories/s-curve.csv");
  StrokeOptions options;
  options.threads = static_cast<int>(state.range(0));
  const CanvasGrid grid = canvasForStroke(brush, traj, options);
  StrokeRenderer renderer;
  std::vector<double> step_us;
  double total_s = 0;
  long steps = 0, sim_steps = 0, solved_steps = 0;
  for (auto _ : state) {
    PaintCanvas canvas(grid, PaperSpec{}, MixModel::kKubelkaMunk);
    BrushPaint paint(brush);
    paint.load(PaintLoad{PaintLoad::Mode::kSolid, {"ultramarine"}}, MixModel::kKubelkaMunk,
               "bench");
    Clock::time_point last = Clock::now();
    const Clock::time_point t0 = last;
    const StrokeResult r = renderer.render(
        brush, traj, makeIpoptSolver(), options, &canvas, &paint,
        [&](const BrushState&, int, int) {
          const Clock::time_point now = Clock::now();
          step_us.push_back(1e6 * seconds(last, now));
          last = now;
          ++steps;
        });
    const double dt = seconds(t0, Clock::now());
    if (!r.touched) {
      state.SkipWithError("the stroke left no paint");
      break;
    }
    state.SetIterationTime(dt);
    total_s += dt;
    sim_steps += r.stats.steps;
    solved_steps += r.stats.solved_steps;
  }
  const double strokes = std::max<double>(1, double(state.iterations()));
  state.counters["canvas_px"] = double(grid.width_px) * grid.height_px;
  state.counters["steps"] = double(steps) / strokes;  // step callbacks (painted states)
  state.counters["sim_steps"] = double(sim_steps) / strokes;  // kept simulation steps
  state.counters["solved_steps"] = double(solved_steps) / strokes;
  state.counters["steps_per_s"] = total_s > 0 ? double(steps) / total_s : 0;
  reportPercentiles(state, step_us, "step_");
}
BENCHMARK(BM_StrokeRender)
    ->ArgName("threads")
    ->Arg(1)
    ->Arg(2)
    ->Iterations(3)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

// A pressed state of a library brush, tilted 0.3 rad and pressed 6 mm; the
// calligraphy brush is given 200 strips (the paper's "as many as 200").
BrushState pressedState(const Brush& brush) {
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver(), makeIpoptSolver());
  double length = 0;
  for (const SpineSpec& s : brush.spines) length = std::max(length, s.lengthMm());
  Pose p;
  p.rotation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
  p.position_mm = Eigen::Vector3d(0, 0, brush.reachMm() + 1);
  sim.reset(p, 0);
  const double top = p.position_mm.z(), bottom = length * std::cos(0.3) - 6;
  for (int i = 1; i <= 60; ++i) {
    p.position_mm.z() = top + (bottom - top) * i / 60;
    sim.step(p, 0.01 * i);
  }
  return sim.state();
}

Brush benchBrush(int which) {
  const std::string dir = BRISTLE_SOURCE_DIR;
  Brush b = loadBrush(dir + (which == 0 ? "/scenes/brushes/round.json"
                                        : "/scenes/brushes/calligraphy.json"));
  if (which == 1) b.strips.count = 200;
  return b;
}

// Geometry update per step (paper §4): skinning + subdivision (+ 200 strips).
// range(0): 0 = round (surface), 1 = calligraphy (surface + 200 strips).
void BM_BrushGeometry(benchmark::State& state) {
  const Brush brush = benchBrush(static_cast<int>(state.range(0)));
  BrushGeometry geometry(brush);
  const BrushState st = pressedState(brush);
  std::vector<BrushVertex> tris;
  std::vector<double> us;
  for (auto _ : state) {
    tris.clear();
    const Clock::time_point t0 = Clock::now();
    geometry.build(st, &tris);
    const double dt = seconds(t0, Clock::now());
    state.SetIterationTime(dt);
    us.push_back(1e6 * dt);
  }
  state.counters["triangles"] = double(tris.size() / 3);
  reportPercentiles(state, us, "");
}
BENCHMARK(BM_BrushGeometry)->ArgName("strips200")->Arg(0)->Arg(1)->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// Times `render` (one footprint into its argument, false when nothing touched)
// once per benchmark iteration; reports the window size and the percentiles,
// and returns the last footprint.
template <typename Render>
FootprintImage timeFootprints(benchmark::State& state, Render&& render) {
  FootprintImage fp;
  std::vector<double> us;
  for (auto _ : state) {
    const Clock::time_point t0 = Clock::now();
    const bool touched = render(&fp);
    const double dt = seconds(t0, Clock::now());
    if (!touched) {
      state.SkipWithError("no footprint");
      break;
    }
    state.SetIterationTime(dt);
    us.push_back(1e6 * dt);
  }
  state.counters["window_px"] = double(fp.window.width_px) * fp.window.height_px;
  reportPercentiles(state, us, "");
  return fp;
}

// Geometry + footprint render + readback of `brush` pressed, at px_per_mm,
// which sets the footprint window's size.
void timePressedFootprint(benchmark::State& state, const Brush& brush, double px_per_mm) {
  BrushGeometry geometry(brush);
  const BrushState st = pressedState(brush);
  CanvasGrid grid;
  grid.px_per_mm = px_per_mm;
  grid.x0_mm = grid.y0_mm = -40;
  grid.width_px = grid.height_px = static_cast<int>(80 * grid.px_per_mm);
  StrokeRenderer renderer;
  const FootprintImage fp = timeFootprints(state, [&](FootprintImage* out) {
    return renderer.footprint(geometry, st, grid, kClipMm, out);
  });
  state.counters["window_w"] = fp.window.width_px;
  state.counters["window_h"] = fp.window.height_px;
}
// The calligraphy brush with 200 strips; range(0) = px per mm.
void BM_GeometryAndFootprint(benchmark::State& state) {
  timePressedFootprint(state, benchBrush(1), double(state.range(0)));
}
BENCHMARK(BM_GeometryAndFootprint)->ArgName("px_per_mm")->Arg(8)->Arg(16)->Arg(32)->Arg(56)
    ->UseManualTime()->Unit(benchmark::kMicrosecond);

// Thousands of hairs: geometry + footprint + readback of
// the pressed calligraphy brush with range(0) strips at 56 px/mm (a window of
// about 512^2, as above), so that 200 and 1,000 strips compare in one run.
void BM_StripCountFootprint(benchmark::State& state) {
  Brush brush = benchBrush(1);
  brush.strips.count = static_cast<int>(state.range(0));
  timePressedFootprint(state, brush, 56);
}
BENCHMARK(BM_StripCountFootprint)->ArgName("strips")->Arg(200)->Arg(1000)
    ->UseManualTime()->Unit(benchmark::kMicrosecond);

// The same pressed state swept over a step: the state moved range(0) pixels
// along x from the one before (8 px/mm). 0 px is one stamp, as above; 2 px is
// a default step's largest contact motion (0.25 mm), stamped twice. range(1)
// = 1 leaves out the triangles that can mark no pixel (the default), 0 draws
// them all: the same bytes, so the two compare llvmpipe's work alone.
void BM_SweptFootprint(benchmark::State& state) {
  const Brush brush = benchBrush(1);
  BrushGeometry geometry(brush);
  const BrushState to = pressedState(brush);
  CanvasGrid grid;
  grid.px_per_mm = 8;
  grid.x0_mm = grid.y0_mm = -40;
  grid.width_px = grid.height_px = 640;
  BrushState from = to;
  const Eigen::Vector3d back(-double(state.range(0)) / grid.px_per_mm, 0, 0);
  from.handle.position_mm += back;
  for (SpineState& s : from.spines)
    for (Eigen::Vector3d& p : s.joints_mm) p += back;
  StrokeRenderer renderer;
  renderer.footprintRenderer().setSkipUnmarking(state.range(1) != 0);
  timeFootprints(state, [&](FootprintImage* out) {
    return renderer.sweptFootprint(geometry, from, to, grid, kClipMm, 1 / grid.px_per_mm, out);
  });
  state.counters["triangles_drawn"] = double(renderer.footprintRenderer().lastDrawnTriangles());
}
BENCHMARK(BM_SweptFootprint)->ArgNames({"moved_px", "skip"})
    ->ArgsProduct({{0, 2, 4}, {0, 1}})->UseManualTime()->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  // An unknown GALLIUM_DRIVER makes OSMesa fail (or crash); llvmpipe is the default.
  unsetenv("GALLIUM_DRIVER");
  return bristle::bench::runBenchmarks(argc, argv);
}

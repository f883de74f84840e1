// Whole-scene render time of the three paintings in scenes/paintings/: load the
// scene, simulate and paint every stroke onto one PaintCanvas, compose to 8-bit
// sRGB (what `bristle render SCENE.json` does minus the PNG encoding). Manual
// time around that; counters: strokes, simulation steps, ms per step, and the
// paint laid down. Figures in docs/PERFORMANCE.md ("Scenes, sheets and the golden
// suite").

#include <benchmark/benchmark.h>

#include <string>

#include "bench_stats.h"
#include "bench/bench_main.h"
#include "engine/formats/scene.h"
#include "render/image/compose.h"
#include "render/scene_renderer.h"
#include "tests/support/build_paths.h"

namespace {

using bristle::bench::Clock;
using bristle::bench::seconds;

const char* const kPaintings[] = {"petals", "calligraphy", "landscape"};

void BM_SceneRender(benchmark::State& state) {
  const std::string name = kPaintings[state.range(0)];
  const std::string path = std::string(BRISTLE_SOURCE_DIR) + "/scenes/paintings/" + name + ".json";
  state.SetLabel(name);
  bristle::SimStats stats;
  double deposited = 0, total_s = 0;
  int runs = 0;
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const bristle::Scene scene = bristle::loadScene(path);
    bristle::PaintCanvas canvas = bristle::render::makeSceneCanvas(scene);
    const bristle::render::SceneResult r = bristle::render::renderScene(scene, {}, &canvas);
    const bristle::render::Image8 img = bristle::render::composeRgb8(canvas, {});
    benchmark::DoNotOptimize(img.pixels.data());
    const double s = seconds(t0, Clock::now());
    state.SetIterationTime(s);
    total_s += s;
    stats = r.stats;
    deposited = r.deposited_mm3;
    state.counters["strokes"] = double(scene.strokes.size());
    state.counters["canvas_px"] = double(canvas.pixels());
    ++runs;
  }
  state.counters["sim_steps"] = double(stats.steps);
  state.counters["fallback_solves"] = double(stats.fallback_solves);
  state.counters["ms_per_step"] = runs > 0 ? 1e3 * total_s / runs / stats.steps : 0;
  state.counters["deposited_mm3"] = deposited;
}

BENCHMARK(BM_SceneRender)
    ->ArgName("painting")
    ->DenseRange(0, 2)
    ->Iterations(2)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

}  // namespace

int main(int argc, char** argv) { return bristle::bench::runBenchmarks(argc, argv); }

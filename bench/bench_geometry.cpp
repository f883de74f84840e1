// The brush's geometry per simulation step (engine/geometry/brush_geometry.h): skinning
// and refining the surface (§4.1), the spines' bundles, the strips (§4.2), on
// library brushes pressed 3 mm into the paper. Side by side in one run:
//   - round, flat: what a step costs for a brush with a surface, strips and
//     spines;
//   - flat against the same flat with round bundles (its spines' thickness_mm
//     cleared): what the slabs' superellipse sections cost.
// Run: build/bench/bench_geometry --benchmark_repetitions=5
//      --benchmark_report_aggregates_only=true (docs/PERFORMANCE.md).

#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/dynamics/simulation.h"
#include "engine/solvers/spine_solver.h"
#include "engine/geometry/spine_bundles.h"
#include "tests/support/build_paths.h"

namespace {

using namespace bristle;

Brush libraryBrush(const std::string& name) {
  return loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json");
}

// The brush held upright and lowered until its tips are 3 mm into the paper:
// contact, loads on the spines, bundles spread and surface clamped.
BrushState pressedState(const Brush& brush) {
  Simulation sim(brush, SimOptions{}, makeSlsqpSolver());
  Pose pose;
  const double reach = brush.reachMm();
  pose.position_mm = Eigen::Vector3d(0, 0, reach + 1);
  double t = 0;
  sim.reset(pose, t);
  for (int i = 1; i <= 40; ++i) {
    pose.position_mm.z() = reach + 1 - 4.0 * i / 40;
    sim.step(pose, t += 0.005);
  }
  return sim.state();
}

void runBuild(benchmark::State& state, const Brush& brush, bool spines_only) {
  const BrushState pressed = pressedState(brush);
  BrushGeometry geometry(brush);
  std::vector<BrushVertex> tris;
  for (auto _ : state) {
    tris.clear();
    if (spines_only)
      buildSpineGeometry(brush, pressed, &tris);
    else
      geometry.build(pressed, &tris);
    benchmark::DoNotOptimize(tris.data());
  }
  state.counters["triangles"] = static_cast<double>(tris.size() / 3);
}

void BM_Geometry_Round(benchmark::State& state) {
  static const Brush b = libraryBrush("round");
  runBuild(state, b, state.range(0) != 0);
}

void BM_Geometry_Flat(benchmark::State& state) {
  static const Brush b = libraryBrush("flat");
  runBuild(state, b, state.range(0) != 0);
}

void BM_Geometry_FlatRoundBundles(benchmark::State& state) {
  static const Brush b = [] {
    Brush r = libraryBrush("flat");
    for (SpineSpec& s : r.spines) s.thickness_mm.clear();
    return r;
  }();
  runBuild(state, b, state.range(0) != 0);
}

// range(0): 0 = the whole geometry (BrushGeometry::build), 1 = the spines'
// bundles alone (buildSpineGeometry).
BENCHMARK(BM_Geometry_Round)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Geometry_Flat)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Geometry_FlatRoundBundles)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

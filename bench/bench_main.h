#pragma once
// The main of the benchmark programs that run bristle's solver in process:
// the heap policy the CLI sets (engine/base/heap_policy.h), so that their figures
// are the command line's, then Google Benchmark's own main.

#include <benchmark/benchmark.h>

#include "engine/base/heap_policy.h"

namespace bristle::bench {

inline int runBenchmarks(int argc, char** argv) {
  keepFreedHeap();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace bristle::bench

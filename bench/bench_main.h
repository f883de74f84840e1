#pragma once
// The main of the benchmark programs that run bristle's solver in process:
// the heap policy and process-wide set-up the CLI has (engine/base/heap_policy.h,
// process/process_hooks.h; the program links bristle::process), so that their
// figures are the command line's, then Google Benchmark's own main.

#include <benchmark/benchmark.h>

#include "engine/base/heap_policy.h"
#include "process/process_hooks.h"

namespace bristle::bench {

inline int runBenchmarks(int argc, char** argv) {
  keepFreedHeap();
  installProcessHooks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace bristle::bench

// Batch throughput: `bristle batch` on the standard stroke set
// (scenes/batch/standard.json: 7 library brushes x 4 strokes = 28 jobs) with 1
// and 2 workers, every job rendered (--overwrite) into a fresh folder. The time
// is the wall time of the whole batch process, as a user waits for it; the
// counter jobs_per_min is what a farm plans with. Arguments: workers, solver
// (0 = the manifest's default, Ipopt; 1 = SLSQP through the manifest's
// defaults), and whether the jobs start in the manifest's order (--in-order)
// rather than longest first. Figures in docs/PERFORMANCE.md ("Batch throughput").

#include <benchmark/benchmark.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "bench_stats.h"
#include "tests/support/build_paths.h"

namespace {

namespace fs = std::filesystem;
using bristle::bench::Clock;
using bristle::bench::seconds;

// The standard manifest, optionally with SLSQP as every job's solver: a copy in
// the temp folder with its paths made absolute.
std::string manifest(bool slsqp) {
  const fs::path dir = fs::path(BRISTLE_SOURCE_DIR) / "scenes" / "batch";
  const std::string original = (dir / "standard.json").string();
  if (!slsqp) return original;
  std::ifstream in(original);
  nlohmann::json m = nlohmann::json::parse(in);
  m["defaults"]["options"]["solver"] = "slsqp";
  for (nlohmann::json& job : m["jobs"])
    for (const char* key : {"brush", "trajectory", "scene", "sheet"})
      if (job.contains(key))
        job[key] = (dir / job[key].get<std::string>()).lexically_normal().string();
  const std::string path = (fs::temp_directory_path() /
                            ("bristle-bench-standard-slsqp-" + std::to_string(::getpid()) + ".json"))
                               .string();
  std::ofstream(path) << m.dump(2);
  return path;
}

void BM_BatchStandardSet(benchmark::State& state) {
  const int workers = static_cast<int>(state.range(0));
  const bool slsqp = state.range(1) == 1;
  const bool in_order = state.range(2) == 1;  // the manifest's order, not longest first
  const std::string m = manifest(slsqp);
  const fs::path out = fs::temp_directory_path() / ("bristle-bench-batch-" + std::to_string(::getpid()));
  state.SetLabel(std::string(slsqp ? "slsqp" : "ipopt") + ", " + std::to_string(workers) +
                 " worker(s)" + (in_order ? ", in order" : ""));
  int jobs = 0;
  double total_s = 0;
  for (auto _ : state) {
    fs::remove_all(out);
    const std::string cmd = std::string("env -u GALLIUM_DRIVER '") + BRISTLE_BIN + "' batch '" + m +
                            "' --out '" + out.string() + "' --jobs " + std::to_string(workers) +
                            " --overwrite --quiet --json" + (in_order ? " --in-order" : "") + " > '" + out.string() + ".jsonl'";
    const auto t0 = Clock::now();
    const int status = std::system(cmd.c_str());
    const double s = seconds(t0, Clock::now());
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      state.SkipWithError("bristle batch failed; see the .jsonl beside the output folder");
      break;
    }
    state.SetIterationTime(s);
    total_s += s;
    std::ifstream log(out.string() + ".jsonl");
    std::string line;
    while (std::getline(log, line))
      if (line.find("\"status\":\"rendered\"") != std::string::npos) ++jobs;
  }
  if (total_s > 0) {
    state.counters["jobs"] = static_cast<double>(jobs) / static_cast<double>(state.iterations());
    state.counters["jobs_per_min"] = 60.0 * jobs / total_s;
  }
  fs::remove_all(out);
  fs::remove(out.string() + ".jsonl");
  if (slsqp) fs::remove(m);
}

}  // namespace

// One iteration each: a run is minutes long and its spread is the machine's.
BENCHMARK(BM_BatchStandardSet)
    // {workers, SLSQP, in order}: one worker; two, longest first; two in the
    // manifest's order (what batch did before it ordered by cost).
    ->Args({1, 1, 0})
    ->Args({2, 1, 0})
    ->Args({2, 1, 1})
    ->Args({1, 0, 0})
    ->Args({2, 0, 0})
    ->Args({2, 0, 1})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kSecond);

BENCHMARK_MAIN();

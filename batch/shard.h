#pragma once
// Which jobs of a manifest one `bristle batch` process renders: a shard given
// on the command line, or the one a scheduler (Slurm, Kubernetes) assigned
// through the environment (docs/scale-out.md).

#include <functional>
#include <string>
#include <vector>

namespace bristle {

// A deterministic slice of the manifest: job k belongs to shard k mod count.
// Round-robin rather than contiguous blocks, so that shards get a similar mix
// when a manifest lists its heavy jobs together.
struct Shard {
  int index = 0, count = 1;
};
// "I/N" with 0 <= I < N; throws Error(kUsage) otherwise (e.g. "5/4", "0/0").
Shard parseShard(const std::string& text);
// The shard a scheduler assigned through the environment, when the command line
// gave none: Slurm job arrays (SLURM_ARRAY_TASK_ID minus SLURM_ARRAY_TASK_MIN,
// divided by SLURM_ARRAY_TASK_STEP, out of SLURM_ARRAY_TASK_COUNT), or a
// Kubernetes Indexed Job (JOB_COMPLETION_INDEX, out of `explicit_count`, which
// the Job's spec knows and the pod does not). `env` looks a variable up (nullptr
// when unset). Returns {0, 1} when neither is present; throws Error(kUsage) for
// inconsistent values, naming the variables.
Shard shardFromEnvironment(const std::function<const char*(const char*)>& env,
                           int explicit_count);
// Indices (ascending) of the jobs of `shard` among n jobs.
std::vector<int> jobsOfShard(int n, const Shard& shard);

}  // namespace bristle

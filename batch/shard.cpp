#include "batch/shard.h"

#include <algorithm>
#include <cstdlib>
#include <regex>
#include <string>

#include "engine/base/error.h"

namespace bristle {

Shard parseShard(const std::string& text) {
  static const std::regex kShard("([0-9]{1,6})/([0-9]{1,6})");
  std::smatch m;
  if (std::regex_match(text, m, kShard)) {
    const Shard s{std::stoi(m[1]), std::stoi(m[2])};
    if (s.count >= 1 && s.index < s.count) return s;
  }
  throw Error(ExitCode::kUsage, "--shard " + text +
                                    ": must be I/N with N >= 1 and 0 <= I < N (e.g. 0/4)");
}

namespace {

// A variable's value as an integer in [0, 999999999] (beyond any Slurm
// array's task ids), or -1 when unset; throws naming it for junk, a sign or
// a number beyond that, which strtol would clamp to another value.
long envInteger(const std::function<const char*(const char*)>& env, const char* name) {
  const char* v = env(name);
  if (v == nullptr || *v == '\0') return -1;
  static const std::regex kDigits("[0-9]{1,9}");
  if (!std::regex_match(v, kDigits))
    throw Error(ExitCode::kUsage,
                std::string(name) + "=" + v +
                    ": not a non-negative integer up to 999999999");
  return std::strtol(v, nullptr, 10);
}

}  // namespace

Shard shardFromEnvironment(const std::function<const char*(const char*)>& env,
                           int explicit_count) {
  const long slurm_id = envInteger(env, "SLURM_ARRAY_TASK_ID");
  if (slurm_id >= 0) {
    const long count = envInteger(env, "SLURM_ARRAY_TASK_COUNT");
    const long min = std::max(0L, envInteger(env, "SLURM_ARRAY_TASK_MIN"));
    // Slurm sets _STEP to 1 or more; 0 would make every task shard 0.
    long step = envInteger(env, "SLURM_ARRAY_TASK_STEP");
    if (step == 0)
      throw Error(ExitCode::kUsage, "SLURM_ARRAY_TASK_STEP=0: must be at least 1 (the array's "
                                    "step between task ids)");
    step = std::max(1L, step);
    const long index = (slurm_id - min) / step;
    if (count < 1 || slurm_id < min || (slurm_id - min) % step != 0 || index >= count) {
      throw Error(ExitCode::kUsage,
                  "SLURM_ARRAY_TASK_ID=" + std::to_string(slurm_id) + " with _MIN=" +
                      std::to_string(min) + " _STEP=" + std::to_string(step) + " _COUNT=" +
                      std::to_string(count) + ": not a task of the array");
    }
    return Shard{int(index), int(count)};
  }
  const long k8s = envInteger(env, "JOB_COMPLETION_INDEX");
  if (k8s >= 0) {
    if (explicit_count < 1 || k8s >= explicit_count)
      throw Error(ExitCode::kUsage,
                  "JOB_COMPLETION_INDEX=" + std::to_string(k8s) +
                      ": give the Job's completions as --shard-count N (N > index)");
    return Shard{int(k8s), explicit_count};
  }
  if (explicit_count > 1)
    throw Error(ExitCode::kUsage,
                "--shard-count without JOB_COMPLETION_INDEX: give --shard I/N instead");
  return Shard{};
}

std::vector<int> jobsOfShard(int n, const Shard& shard) {
  std::vector<int> mine;
  for (int k = shard.index; k < n; k += shard.count) mine.push_back(k);
  return mine;
}

}  // namespace bristle

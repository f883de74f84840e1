#pragma once
// Batch manifests (`bristle-batch/1`): many renders described in one file, and
// the pure parts of running them: which jobs a shard owns, the command line each
// job runs, and the key that says whether an output is up to date. The process
// handling (workers, signals, logs) lives in cli/batch_command.cpp; nothing here
// starts a process or touches the output folder. docs/batch.md is the user's
// reference.

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace bristle {

enum class BatchJobKind { kScene, kSheet, kStroke, kPreview };
const char* batchJobKindName(BatchJobKind kind);

struct BatchJob {
  int index = 0;        // position in the manifest (0-based): the sharding order
  std::string pointer;  // "/jobs/3", for messages
  std::string id;       // unique; defaults to the output's stem
  BatchJobKind kind = BatchJobKind::kScene;
  std::string input;    // scene or sheet file (resolved against the manifest's folder)
  std::string brush, trajectory;  // a stroke's or a preview's files (resolved; a
                                  // preview's trajectory may be empty: at rest)
  std::string output;   // relative to the batch's output folder; defaults to id + ".png"
  // Options passed to the render command, already merged with the manifest's
  // defaults: key (the long option without "--") -> value.
  nlohmann::json options = nlohmann::json::object();
};

struct BatchManifest {
  std::string path;
  std::vector<BatchJob> jobs;
};

// Reads and checks a manifest; throws bristle::Error: 66 when it is missing,
// 65 for bad data naming the JSON pointer and the rule (unknown keys, a job with
// no or two inputs, duplicate ids or outputs, an output that leaves the output
// folder, options a batch job may not set). Referenced files are NOT opened
// here: a missing scene fails its own job (66), not the whole batch.
BatchManifest loadBatchManifest(const std::string& path);
BatchManifest parseBatchManifest(const std::string& text, const std::string& path_for_messages,
                                 const std::string& base_dir);

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

// The command line of a job, without the program name and without the output
// option: e.g. {"render", "scene.json", "--impasto"} or {"preview", "b.json",
// "--trajectory", "t.csv", "--at", "1.2"}. The caller adds {"-o", path, "--quiet"}.
std::vector<std::string> batchJobArguments(const BatchJob& job);

// Every file the job reads (the scene or sheet first, then what it references),
// by loading the job's input with the render's own readers; throws their
// bristle::Error (66 missing, 65 bad data) so a broken job fails before a
// process is started for it. A file the manifest itself names is reported as
// `manifest: /jobs/N/field: ...`.
std::vector<std::string> batchJobInputs(const BatchJob& job, const std::string& manifest);

// The up-to-date key of a job: FNV-1a 64 over the bristle version, the program
// that renders, the job's command line (batchJobArguments) and the bytes of
// every input file. `program` identifies the renderer's code: the command line
// passes the FNV-1a 64 of its own executable, so a rebuilt bristle (same
// version, changed code) renders every job again instead of keeping pixels an
// older build made. Paths do not enter the key, so a checkout moved elsewhere
// keeps its outputs.
std::uint64_t batchJobKey(const BatchJob& job, const std::vector<std::string>& inputs,
                          std::uint64_t program = 0);

}  // namespace bristle

#pragma once
// Batch manifests (`bristle-batch/1`): many renders described in one file, and
// the command line each job runs. Nothing here starts a process or touches the
// output folder (batch/batch_run.h does). docs/batch.md is the user's reference.

#include <map>
#include <string>
#include <vector>

namespace bristle {

inline constexpr const char* kBatchFormat = "bristle-batch/1";

enum class BatchJobKind { kScene, kSheet, kStroke, kPreview };
const char* batchJobKindName(BatchJobKind kind);

// A job's options for its command, already merged with the manifest's
// defaults: the long option's name without "--" -> the words that follow it
// ({} for a flag that is set; a flag set to false is left out). std::map keeps
// the names sorted, so the same options give the same command line.
using BatchJobOptions = std::map<std::string, std::vector<std::string>>;

struct BatchJob {
  int index = 0;        // position in the manifest (0-based): the sharding order
  std::string pointer;  // "/jobs/3", for messages
  std::string id;       // unique; defaults to the output's stem
  BatchJobKind kind = BatchJobKind::kScene;
  std::string input;    // scene or sheet file (resolved against the manifest's folder)
  std::string brush, trajectory;  // a stroke's or a preview's files (resolved; a
                                  // preview's trajectory may be empty: at rest)
  std::string output;   // relative to the batch's output folder; defaults to id + ".png"
  BatchJobOptions options;
  // Where each option of `options` was set: "/jobs/3/options/px-per-mm", or
  // "/defaults/options/px-per-mm" for a default the job kept.
  std::map<std::string, std::string> option_pointers;
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

// The command line of a job, without the program name and without the output
// option: e.g. {"render", "scene.json", "--impasto"} or {"preview", "b.json",
// "--trajectory", "t.csv", "--at", "1.2"}. The caller adds {"-o", path, "--quiet"}.
std::vector<std::string> batchJobArguments(const BatchJob& job);

}  // namespace bristle

#pragma once
// One `bristle batch` run over the jobs of a shard: each job is checked
// (inputs readable, output beneath --out), skipped when its output is up to
// date, else rendered by its own bristle process (batch/process_pool.h) in a
// private folder beneath --out and renamed into place when it succeeded. What
// a farm needs from it:
// - a job that fails (bad input, a crash) fails alone and is logged;
// - an output appears only complete, already carrying its key: the job's own
//   process writes the key and its warnings into the PNG (--batch-key);
// - outputs whose key matches are skipped, so a rerun does only what changed;
// - SIGTERM/SIGINT stop the run between jobs: running jobs are abandoned, their
//   files removed, and the log says so;
// - the same manifest gives the same pixels whatever --jobs or --shard is,
//   because every job is a separate, deterministic render;
// - no problem is hidden: each job's warnings and figures (painted pixels,
//   paint laid down) are in its log entry, its warnings kept in its PNG for the
//   runs that skip it.

#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <vector>

#include "batch/manifest.h"
#include "batch/process_pool.h"
#include "batch/shard.h"

namespace bristle {

enum class BatchJobStatus { kRendered, kWouldRender, kSkipped, kFailed, kAbandoned };
// As the log writes it: "rendered", "would render", "skipped", ...
const char* batchJobStatusName(BatchJobStatus status);

struct BatchJobOutcome {
  BatchJobStatus status = BatchJobStatus::kFailed;
  int code = 0;  // the job's exit code (0 when it succeeded)
  std::string error;
  double seconds = 0;
  std::vector<std::string> warnings;  // of a rendered (or skipped) job
  nlohmann::json figures;             // of a rendered stroke or scene (render --stats)
};

struct BatchRunOptions {
  std::string out_dir;
  int workers = 1;
  bool overwrite = false;  // render even what is up to date
  bool dry_run = false;    // decide, render nothing
  // With several workers, start the longest jobs first (batch/job_cost.h);
  // else, and always with one worker, in the manifest's order.
  bool longest_first = true;
};

// Told of each job as it ends: its outcome and its log record (one JSON object).
using BatchJobReport =
    std::function<void(const BatchJob&, const BatchJobOutcome&, const nlohmann::json& record)>;
// Told how far the run is: jobs ended, failed, running.
using BatchProgress = std::function<void(int done, int failed, int running)>;

class BatchRun {
 public:
  // `log`, when given, receives each job's record as a line. `program` is the
  // bristle executable each job runs.
  BatchRun(const BatchManifest& manifest, BatchRunOptions options, std::ostream* log,
           std::string program);

  // Runs the jobs of `mine` (manifest indices); returns every one's outcome by index.
  std::map<int, BatchJobOutcome> run(const std::vector<int>& mine, const BatchJobReport& report,
                                     const BatchProgress& progress);

  // SIGTERM or SIGINT when one stopped the run, else 0.
  int stopSignal() const { return signals_.received(); }

 private:
  struct Pending;
  std::vector<Pending> decide(const std::vector<int>& mine);
  void render(const std::vector<Pending>& queue, const BatchProgress& progress);
  BatchJobOutcome complete(const Pending& p, int status) const;
  std::string outputPath(const BatchJob& job) const;
  nlohmann::json record(const BatchJob& job, const std::string& key,
                        const BatchJobOutcome& o) const;
  void finish(const BatchJob& job, const std::string& key, const BatchJobOutcome& o);

  const BatchManifest& manifest_;
  BatchRunOptions options_;
  std::ostream* log_;
  std::string program_, private_dir_;
  std::uint64_t program_hash_ = 0;  // FNV-1a 64 of program_'s bytes
  StopSignals signals_;             // caught from construction on
  BatchJobReport report_;
  std::map<int, BatchJobOutcome> outcomes_;
  int failed_ = 0;
};

// The counts of a run's outcomes, for its summary line.
struct BatchSummary {
  int rendered = 0, skipped = 0, failed = 0, abandoned = 0, warned = 0;
  int first_failure = 0;  // the exit code of the first failed job (by index), 0 if none
};
BatchSummary summarizeBatch(const std::map<int, BatchJobOutcome>& outcomes);

// The output folder, created when missing; throws kCantCreate otherwise.
void createBatchOutputFolder(const std::string& out_dir);
// A run's own job log: OUT/logs/batch-<UTC time>-<host>-<pid>-shard-I-of-N.jsonl
// (its folder created, never through a symbolic link).
std::string defaultBatchLogPath(const std::string& out_dir, const Shard& shard);
// The bristle executable of this process (/proc/self/exe).
std::string selfExecutable();

}  // namespace bristle

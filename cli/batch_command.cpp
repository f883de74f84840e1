// `bristle batch MANIFEST --out DIR`: the command line of a batch run
// (batch/batch_run.h does the work): the shard, the job log, each job's line
// and the summary.

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "batch/batch_run.h"
#include "batch/manifest.h"
#include "batch/shard.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/progress.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"

namespace bristle::cli {
namespace {

using Clock = std::chrono::steady_clock;

// Progress of a batch on stderr (not with --quiet or --json). On a terminal, a
// bar rewritten in place with the time left at the pace so far; elsewhere (a
// log, a pipe, a Slurm job's output) one whole line per job as it ends, so a
// long batch shows it is alive without a terminal's carriage returns.
class Progress {
 public:
  Progress(bool enabled, bool dry_run, int total)
      : enabled_(enabled && !dry_run), tty_(::isatty(2) == 1), total_(total) {}
  void update(int done, int failed, int running) {
    if (!enabled_ || !tty_) return;
    constexpr int kWidth = 30;
    const int filled = total_ > 0 ? kWidth * done / total_ : kWidth;
    const double secs = std::chrono::duration<double>(Clock::now() - start_).count();
    const std::string left =
        total_ > 0 && done < total_ ? remainingText(secs, double(done) / total_) : "";
    std::fprintf(stderr, "\rbatch [%s%s] %d/%d  %d failed  %d running%s\033[K",
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, '-').c_str(), done,
                 total_, failed, running, left.c_str());
    std::fflush(stderr);
  }
  // "batch: 3/16 painting-petals rendered in 41.2 s" (not on a terminal).
  void ended(const BatchJob& job, const BatchJobOutcome& o) {
    ++ended_;
    if (!enabled_ || tty_) return;
    std::string what = batchJobStatusName(o.status);
    if (o.status == BatchJobStatus::kSkipped) what = "up to date";
    if (o.status == BatchJobStatus::kRendered) {
      char secs[32];
      std::snprintf(secs, sizeof secs, " in %.1f s", o.seconds);
      what += secs;
    }
    if (o.status == BatchJobStatus::kFailed) what += " (exit " + std::to_string(o.code) + ")";
    std::fprintf(stderr, "batch: %d/%d %s %s\n", ended_, total_, oneLine(job.id).c_str(),
                 what.c_str());
    std::fflush(stderr);
  }
  void finish() {
    if (enabled_ && tty_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  bool enabled_, tty_;
  int total_, ended_ = 0;
  Clock::time_point start_ = Clock::now();
};

// The job log is appended to: never to the manifest or a file a job reads.
void checkLogIsNoInput(const BatchArgs& args, const BatchManifest& manifest) {
  std::vector<NamedFile> inputs{{"manifest", args.manifest}};
  for (const BatchJob& job : manifest.jobs) {
    const std::string at = args.manifest + ": " + job.pointer;
    inputs.push_back({at + (job.kind == BatchJobKind::kSheet ? "/sheet" : "/scene"), job.input});
    inputs.push_back(
        {at + (job.kind == BatchJobKind::kPreview ? "/preview" : "/brush"), job.brush});
    inputs.push_back({at + "/trajectory", job.trajectory});
  }
  checkOutputs({{"--log", args.log}}, inputs);
}

// Each job as it ends: its JSON line (--json), or its failure and warnings.
void reportJob(const BatchArgs& args, const std::string& out_path, const BatchJob& job,
               const BatchJobOutcome& o, const nlohmann::json& record) {
  if (args.json) {
    std::cout << record.dump() << '\n' << std::flush;
  } else if (o.status == BatchJobStatus::kWouldRender) {
    std::cout << job.id << "  ->  " << out_path << "  (would render)\n";
  } else if (o.status == BatchJobStatus::kFailed) {
    printError("job '" + job.id + "' failed (" + std::to_string(o.code) + "): " + o.error);
  } else {
    for (const std::string& w : o.warnings) printError("job '" + job.id + "': warning: " + w);
  }
}

// The summary: a JSON line (log, --json) and the line people read.
void reportSummary(const BatchArgs& args, const Shard& shard, size_t jobs, const BatchSummary& s,
                   double secs, const std::string& log_path, std::ofstream* log) {
  const nlohmann::json summary = {
      {"summary", true},       {"manifest", args.manifest},
      {"shard", std::to_string(shard.index) + "/" + std::to_string(shard.count)},
      {"jobs", jobs},          {"rendered", s.rendered},
      {"skipped", s.skipped},  {"failed", s.failed},
      {"abandoned", s.abandoned}, {"warned", s.warned},
      {"seconds", std::round(secs * 1000) / 1000}, {"log", log_path}};
  if (!args.dry_run) *log << summary.dump() << '\n' << std::flush;
  const std::string with_warnings =
      s.warned ? ", " + std::to_string(s.warned) + " with warnings" : std::string();
  if (args.json) {
    std::cout << summary.dump() << '\n' << std::flush;
  } else if (!args.quiet && args.dry_run) {
    // Also when every job is up to date: the user sees that the run looked.
    std::printf("batch: %zu jobs (shard %d/%d): %d would render, %d up to date, %d failed%s "
                "(dry run)\n",
                jobs, shard.index, shard.count, s.rendered, s.skipped, s.failed,
                with_warnings.c_str());
  } else if (!args.quiet) {
    const std::string abandoned =
        s.abandoned ? ", " + std::to_string(s.abandoned) + " abandoned" : std::string();
    std::fprintf(stderr,
                 "batch: %zu jobs (shard %d/%d): %d rendered, %d up to date, %d failed%s%s in "
                 "%.1f s; log %s\n",
                 jobs, shard.index, shard.count, s.rendered, s.skipped, s.failed,
                 abandoned.c_str(), with_warnings.c_str(), secs, log_path.c_str());
  }
}

}  // namespace

int runBatch(const BatchArgs& args) {
  try {
    if (args.jobs < 1) throw Error(ExitCode::kUsage, "--jobs must be at least 1");
    const Shard shard = !args.shard.empty()
                            ? parseShard(args.shard)
                            : shardFromEnvironment([](const char* n) { return std::getenv(n); },
                                                   args.shard_count);
    const BatchManifest manifest = loadBatchManifest(args.manifest);
    checkLogIsNoInput(args, manifest);
    const std::vector<int> mine = jobsOfShard(static_cast<int>(manifest.jobs.size()), shard);
    createBatchOutputFolder(args.out_dir);
    std::string log_path = args.log;
    std::ofstream log;
    if (!args.dry_run) {
      if (log_path.empty()) log_path = defaultBatchLogPath(args.out_dir, shard);
      log.open(log_path, std::ios::app);
      if (!log) throw Error(ExitCode::kCantCreate, log_path + ": cannot create the job log");
    }

    const auto t0 = Clock::now();
    BatchRun run(manifest,
                 {args.out_dir, args.jobs, args.overwrite, args.dry_run, !args.in_order},
                 args.dry_run ? nullptr : &log, selfExecutable());
    Progress progress(!args.quiet && !args.json, args.dry_run, static_cast<int>(mine.size()));
    const BatchSummary summary = summarizeBatch(run.run(
        mine,
        [&](const BatchJob& job, const BatchJobOutcome& o, const nlohmann::json& record) {
          reportJob(args, record["output"].get<std::string>(), job, o, record);
          progress.ended(job, o);
        },
        [&](int done, int failed, int running) { progress.update(done, failed, running); }));
    progress.finish();
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    reportSummary(args, shard, mine.size(), summary, secs, log_path, &log);
    if (run.stopSignal() != 0) return 128 + run.stopSignal();
    if (summary.first_failure == 0 && summary.warned > 0 && args.fail_on_warning) {
      if (!args.json)
        printError("batch: " + std::to_string(summary.warned) +
                   (summary.warned == 1 ? " job has" : " jobs have") +
                   " warnings (--fail-on-warning)");
      return static_cast<int>(ExitCode::kCheckFailed);
    }
    return summary.first_failure;
  } catch (const Error& e) {
    printError(e.what());
    return static_cast<int>(e.code());
  }
}

Subcommand registerBatch(CLI::App& app) {
  auto ba = std::make_shared<BatchArgs>();
  CLI::App* batch =
      app.add_subcommand("batch", "Render the jobs of a manifest, a few at a time");
  batch->footer(
      "Examples:\n"
      "  bristle batch scenes/batch/standard.json --out renders/ --jobs 2\n"
      "  bristle batch jobs.json --out renders/ --shard 1/4 --json\n"
      "  sbatch --array=0-3 scripts/slurm/bristle-batch.sbatch jobs.json renders/\n"
      "Each job runs in its own bristle process; outputs appear only complete, and are\n"
      "skipped when already up to date (the job's key is stored in the PNG). A failed job\n"
      "does not stop the others. Without --shard, the shard comes from Slurm's\n"
      "SLURM_ARRAY_TASK_ID/_COUNT/_MIN or Kubernetes' JOB_COMPLETION_INDEX (+ --shard-count).\n"
      "SIGTERM or Ctrl-C abandons running jobs and leaves no partial file.\n"
      "Each job's log entry lists its warnings and figures (painted pixels, failed solves,\n"
      "paint laid down); the warnings are also printed on stderr.\n"
      "Exit: 0 when every job of the shard succeeded, else the first failed job's code;\n"
      "1 with --fail-on-warning when a job has warnings and none failed;\n"
      "143/130 when stopped by SIGTERM/SIGINT. See docs/batch.md.");
  batch->add_option("manifest", ba->manifest, "Batch manifest (bristle-batch/1 JSON)")
      ->required();
  batch->add_option("--out", ba->out_dir, "Output folder (created if missing)")->required();
  batch->add_option("-j,--jobs", ba->jobs, "Jobs rendered at once (processes)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  batch->add_option("--shard", ba->shard,
                    "Render only shard I of N (I/N, 0-based): jobs k with k mod N = I");
  batch->add_option("--shard-count", ba->shard_count,
                    "Shard count for a Kubernetes Indexed Job (JOB_COMPLETION_INDEX is the index)")
      ->check(CLI::Range(1, 100000));
  batch->add_flag("--overwrite", ba->overwrite,
                  "Render every job, even when its output is up to date");
  batch->add_flag("--json", ba->json, "One JSON object per job on stdout, then a summary");
  batch->add_option("--log", ba->log,
                    "Job log (JSON lines; default "
                    "OUT/logs/batch-<time>-<host>-<pid>-shard-I-of-N.jsonl)");
  batch->add_flag("--dry-run", ba->dry_run,
                  "List the shard's jobs and whether they would render, then a summary line; "
                  "render nothing");
  batch->add_flag("--fail-on-warning", ba->fail_on_warning,
                  "Exit 1 when a job has warnings (and none failed): a brush that never touched "
                  "the paper, no visible paint, failed solves");
  batch->add_flag("--in-order", ba->in_order,
                  "Start the jobs in the manifest's order (by default, with --jobs above 1, "
                  "the longest start first so that none runs alone at the end)");
  batch->add_flag("-q,--quiet", ba->quiet, "No progress, no summary");
  return {batch, [ba] { return runBatch(*ba); }};
}

}  // namespace bristle::cli

#include "batch/batch_run.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include "batch/job_cost.h"
#include "batch/job_key.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"

namespace bristle {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The batch's own folders beneath --out (the job log's, the children's private
// one) are never reached through a symbolic link: like the outputs
// (engine/base/atomic_output.h), nothing the batch writes may land outside --out.
void refuseSymlinkFolder(const std::string& dir) {
  std::error_code ec;
  if (fs::is_symlink(dir, ec))
    throw Error(ExitCode::kCantCreate,
                dir + ": cannot create: is a symbolic link; a batch writes only beneath --out");
}

std::string hostName() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) return "host";
  return buf;
}

std::string utcStamp() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%SZ", &tm);
  return buf;
}

std::string lastLine(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ExitCode::kIoError, path + ": cannot read the job's output");
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The warnings a job's stderr holds ("bristle: warning: W" lines), without the prefix.
std::vector<std::string> warningLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  const std::string prefix = "bristle: warning: ";
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) out.push_back(line.substr(prefix.size()));
  return out;
}

// A job's end by a signal or a non-zero exit: its code and one-line error.
BatchJobOutcome failure(int status, const std::string& stderr_path) {
  BatchJobOutcome o;
  if (WIFEXITED(status)) {
    o.code = WEXITSTATUS(status);
    o.error = lastLine(stderr_path);
    // The child's one-line error, without its "bristle: " prefix.
    if (o.error.rfind("bristle: ", 0) == 0) o.error.erase(0, 9);
    if (o.error.empty()) o.error = "exited with " + std::to_string(o.code);
  } else {
    o.code = static_cast<int>(ExitCode::kSoftware);
    o.error = "killed by signal " + std::to_string(WTERMSIG(status));
  }
  return o;
}

}  // namespace

const char* batchJobStatusName(BatchJobStatus s) {
  switch (s) {
    case BatchJobStatus::kRendered: return "rendered";
    case BatchJobStatus::kWouldRender: return "would render";
    case BatchJobStatus::kSkipped: return "skipped";
    case BatchJobStatus::kFailed: return "failed";
    case BatchJobStatus::kAbandoned: return "abandoned";
  }
  return "?";
}

// A job to render, and the files of its process in the private folder.
struct BatchRun::Pending {
  const BatchJob* job = nullptr;
  std::string key;              // hex
  std::string png, err, stats;  // the child's output, stderr and --stats
  Clock::time_point start;
};

BatchRun::BatchRun(const BatchManifest& manifest, BatchRunOptions options, std::ostream* log,
                   std::string program)
    : manifest_(manifest),
      options_(std::move(options)),
      log_(log),
      program_(std::move(program)),
      // The renderer's own code enters every key (batchJobKey): ~2 MB read once per run.
      program_hash_(fnv1a64Files({program_})) {}

std::string BatchRun::outputPath(const BatchJob& job) const {
  return (fs::path(options_.out_dir) / job.output).string();
}

std::map<int, BatchJobOutcome> BatchRun::run(const std::vector<int>& mine,
                                             const BatchJobReport& report,
                                             const BatchProgress& progress) {
  report_ = report;
  const std::vector<Pending> queue = decide(mine);
  if (!queue.empty()) render(queue, progress);
  return std::move(outcomes_);
}

// Each job checked and keyed: failed, skipped (up to date), listed (dry run),
// or queued to render.
std::vector<BatchRun::Pending> BatchRun::decide(const std::vector<int>& mine) {
  std::vector<Pending> queue;
  for (const int k : mine) {
    const BatchJob& job = manifest_.jobs[k];
    const auto t0 = Clock::now();
    try {
      checkBeneath(options_.out_dir, job.output);  // a link out of --out fails the job
      const std::vector<std::string> inputs = batchJobInputs(job, manifest_.path);
      const std::string key = hex64(batchJobKey(job, inputs, program_hash_));
      BatchJobOutcome skipped{BatchJobStatus::kSkipped, 0, "", 0, {}, {}};
      if (!options_.overwrite && batchOutputUpToDate(outputPath(job), key, &skipped.warnings)) {
        skipped.seconds = secondsSince(t0);
        finish(job, key, skipped);
      } else if (options_.dry_run) {
        finish(job, key, BatchJobOutcome{BatchJobStatus::kWouldRender, 0, "", 0, {}, {}});
      } else {
        queue.push_back({&job, key, "", "", "", {}});
      }
    } catch (const Error& e) {
      finish(job, "",
             BatchJobOutcome{BatchJobStatus::kFailed, static_cast<int>(e.code()), e.what(),
                             secondsSince(t0), {}, {}});
    }
  }
  return queue;
}

// The queued jobs through the process pool, each in its own bristle process
// writing into one private folder per batch process, so that an abandoned
// job's leftovers go with it, and shards on several hosts sharing the output
// folder never collide.
void BatchRun::render(const std::vector<Pending>& queued, const BatchProgress& progress) {
  private_dir_ = (fs::path(options_.out_dir) /
                  (".bristle-batch-" + hostName() + "-" + std::to_string(::getpid())))
                     .string();
  refuseSymlinkFolder(private_dir_);
  std::error_code ec;
  fs::create_directories(private_dir_, ec);
  if (ec) throw Error(ExitCode::kCantCreate, private_dir_ + ": cannot create: " + ec.message());

  std::vector<Pending> queue = queued;
  // With several workers, the longest jobs start first, so that none of them
  // is left to run alone at the end (batch/job_cost.h). One worker keeps the
  // manifest's order, and its log with it.
  if (options_.workers > 1 && options_.longest_first) {
    std::vector<std::pair<double, size_t>> order;
    for (size_t i = 0; i < queue.size(); ++i)
      order.emplace_back(-estimateJobCost(*queue[i].job), i);
    std::stable_sort(order.begin(), order.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Pending> sorted;
    for (const auto& [cost, i] : order) sorted.push_back(std::move(queue[i]));
    queue = std::move(sorted);
  }
  std::vector<ChildCommand> commands;
  for (Pending& p : queue) {
    const std::string tag = (fs::path(private_dir_) / std::to_string(p.job->index)).string();
    p.png = tag + ".png";
    p.err = tag + ".stderr";
    ChildCommand c{{program_}, p.err};
    for (std::string& a : batchJobArguments(*p.job)) c.argv.push_back(std::move(a));
    // The child stamps the key (and its warnings) into the PNG it writes.
    c.argv.insert(c.argv.end(), {"-o", p.png, "--quiet", "--batch-key", p.key});
    if (p.job->kind == BatchJobKind::kStroke || p.job->kind == BatchJobKind::kScene) {
      // `render` reports its figures; `sheet` and `preview` have none.
      p.stats = tag + ".stats.json";
      c.argv.insert(c.argv.end(), {"--stats", p.stats});
    }
    commands.push_back(std::move(c));
  }

  PoolCallbacks callbacks;
  callbacks.started = [&](size_t i) { queue[i].start = Clock::now(); };
  callbacks.ended = [&](size_t i, int status) {
    finish(*queue[i].job, queue[i].key, complete(queue[i], status));
  };
  callbacks.progress = [&](int running) {
    if (progress) progress(static_cast<int>(outcomes_.size()), failed_, running);
  };
  const PoolResult pool = runProcessPool(commands, options_.workers, signals_, callbacks);
  for (const size_t i : pool.abandoned)
    finish(*queue[i].job, queue[i].key,
           BatchJobOutcome{BatchJobStatus::kAbandoned, 0,
                           "stopped by signal " + std::to_string(signals_.received()),
                           secondsSince(queue[i].start), {}, {}});
  for (size_t i = pool.next; i < queue.size(); ++i)
    finish(*queue[i].job, queue[i].key,
           BatchJobOutcome{BatchJobStatus::kAbandoned, 0, "not started: stopped by signal", 0,
                           {}, {}});
  fs::remove_all(private_dir_, ec);
}

// A finished child: its PNG (already carrying the key) moved into place, its
// warnings and figures read; or its failure.
BatchJobOutcome BatchRun::complete(const Pending& p, int status) const {
  BatchJobOutcome o;
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    try {
      o.warnings = warningLines(p.err);
      if (!p.stats.empty()) {
        nlohmann::json stats = nlohmann::json::parse(readBytes(p.stats), nullptr, false);
        if (stats.is_object()) {
          o.warnings = stats.value("warnings", std::vector<std::string>{});
          stats.erase("warnings");
          o.figures = std::move(stats);
        }
      }
      // Beneath --out, never through a symbolic link out of it.
      moveFileBeneath(p.png, options_.out_dir, p.job->output);
      o.status = BatchJobStatus::kRendered;
    } catch (const Error& e) {
      o.code = static_cast<int>(e.code());
      o.error = e.what();
    }
  } else {
    o = failure(status, p.err);
  }
  std::error_code ec;
  fs::remove(p.png, ec);
  fs::remove(p.err, ec);
  if (!p.stats.empty()) fs::remove(p.stats, ec);
  o.seconds = secondsSince(p.start);
  return o;
}

nlohmann::json BatchRun::record(const BatchJob& job, const std::string& key,
                                const BatchJobOutcome& o) const {
  nlohmann::json j = {{"job", job.id},
                      {"index", job.index},
                      {"kind", batchJobKindName(job.kind)},
                      {"input_hash", key},
                      {"output", outputPath(job)},
                      {"status", batchJobStatusName(o.status)},
                      {"seconds", std::round(o.seconds * 1000) / 1000}};
  if (o.status == BatchJobStatus::kFailed) {
    j["exit_code"] = o.code;
    j["error"] = o.error;
  } else if (o.status == BatchJobStatus::kAbandoned) {
    j["error"] = o.error;
  }
  if (o.status == BatchJobStatus::kRendered || o.status == BatchJobStatus::kWouldRender ||
      o.status == BatchJobStatus::kSkipped)
    j["warnings"] = o.warnings;
  if (!o.figures.is_null()) j["figures"] = o.figures;
  return j;
}

void BatchRun::finish(const BatchJob& job, const std::string& key, const BatchJobOutcome& o) {
  outcomes_[job.index] = o;
  if (o.status == BatchJobStatus::kFailed) ++failed_;
  const nlohmann::json j = record(job, key, o);
  if (log_ != nullptr && o.status != BatchJobStatus::kWouldRender)
    *log_ << j.dump() << '\n' << std::flush;
  if (report_) report_(job, o, j);
}

BatchSummary summarizeBatch(const std::map<int, BatchJobOutcome>& outcomes) {
  BatchSummary s;
  for (const auto& [index, o] : outcomes) {
    s.warned += !o.warnings.empty();
    switch (o.status) {
      case BatchJobStatus::kRendered:
      case BatchJobStatus::kWouldRender: ++s.rendered; break;
      case BatchJobStatus::kSkipped: ++s.skipped; break;
      case BatchJobStatus::kAbandoned: ++s.abandoned; break;
      case BatchJobStatus::kFailed:
        ++s.failed;
        if (s.first_failure == 0) s.first_failure = o.code != 0 ? o.code : 70;
        break;
    }
  }
  return s;
}

void createBatchOutputFolder(const std::string& out_dir) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir))
    throw Error(ExitCode::kCantCreate, out_dir + ": cannot create the output folder" +
                                           (ec ? ": " + ec.message() : ""));
}

std::string defaultBatchLogPath(const std::string& out_dir, const Shard& shard) {
  const fs::path dir = fs::path(out_dir) / "logs";
  refuseSymlinkFolder(dir.string());
  std::error_code ec;
  fs::create_directories(dir, ec);
  return (dir / ("batch-" + utcStamp() + "-" + hostName() + "-" + std::to_string(::getpid()) +
                 "-shard-" + std::to_string(shard.index) + "-of-" +
                 std::to_string(shard.count) + ".jsonl"))
      .string();
}

std::string selfExecutable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error(ExitCode::kSoftware, "cannot find the bristle executable: " + ec.message());
  return p.string();
}

}  // namespace bristle

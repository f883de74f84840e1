// `bristle batch`: renders the jobs of a manifest (batch/manifest.h), each in its
// own bristle process, a few at a time. What a farm needs from it:
// - a job that fails (bad input, a crash) fails alone and is logged;
// - an output appears only complete: the child writes into a private folder,
//   and the batch stamps the job's key into the PNG and renames it into place;
// - outputs whose key matches are skipped, so a rerun does only what changed;
// - SIGTERM/SIGINT stop the run between jobs: running jobs are abandoned, their
//   files removed, and the log says so;
// - the same manifest gives the same pixels whatever --jobs or --shard is,
//   because every job is a separate, deterministic render;
// - no problem is hidden: each job's warnings (a brush that never touched the
//   paper, failed solves) and figures (painted pixels, paint laid down) are in
//   its log entry, kept in its PNG for the runs that skip it, and
//   --fail-on-warning makes them fail the batch.

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "batch/job_key.h"
#include "batch/manifest.h"
#include "batch/shard.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "engine/atomic_output.h"
#include "engine/error.h"
#include "engine/fnv1a64.h"
#include "render/png_io.h"

extern char** environ;

namespace bristle::cli {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The batch's own folders beneath --out (the job log's, the children's private
// one) are never reached through a symbolic link: like the outputs
// (engine/atomic_output.h), nothing the batch writes may land outside --out.
void refuseSymlinkFolder(const std::string& dir) {
  std::error_code ec;
  if (fs::is_symlink(dir, ec))
    throw Error(ExitCode::kCantCreate,
                dir + ": cannot create: is a symbolic link; a batch writes only beneath --out");
}

// The PNG text key that carries a job's up-to-date key, and the one that
// carries its warnings (a JSON list), so that a run skipping it still logs them.
constexpr const char* kKeyText = "bristle:batch-key";
constexpr const char* kWarningsText = "bristle:batch-warnings";
// How often the run loop looks at its children and at the stop flag. Short
// enough that a stop or a finished job is seen without delay a person notices,
// long enough to cost nothing beside a render (~0.01% of a core).
constexpr auto kPollInterval = std::chrono::milliseconds(20);

volatile sig_atomic_t g_stop_signal = 0;
extern "C" void onStopSignal(int sig) { g_stop_signal = sig; }

// SIGTERM and SIGINT only set a flag: the run loop stops between jobs. SIGPIPE
// is ignored so that a closed stdout (| head) shows as a write error instead.
void installSignalHandlers() {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);
}

std::string selfExecutable() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw Error(ExitCode::kSoftware, "cannot find the bristle executable: " + ec.message());
  return p.string();
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

// Whether `path` is a complete PNG stamped with `key` (a corrupt or truncated
// file is not: it is rendered again); *warnings gets the warnings stamped with it.
bool upToDate(const std::string& path, const std::string& key,
              std::vector<std::string>* warnings) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  bool same = false;
  try {
    for (const auto& [k, v] : render::readPngText(path)) {
      if (k == kKeyText) same = v == key;
      if (k == kWarningsText) {
        const nlohmann::json list = nlohmann::json::parse(v, nullptr, false);
        if (list.is_array())
          for (const nlohmann::json& w : list)
            if (w.is_string()) warnings->push_back(w.get<std::string>());
      }
    }
  } catch (const std::exception&) {
    return false;
  }
  return same;
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

enum class Status { kRendered, kSkipped, kFailed, kAbandoned };
const char* statusName(Status s) {
  switch (s) {
    case Status::kRendered: return "rendered";
    case Status::kSkipped: return "skipped";
    case Status::kFailed: return "failed";
    case Status::kAbandoned: return "abandoned";
  }
  return "?";
}

struct Outcome {
  Status status = Status::kFailed;
  int code = 0;  // the job's exit code (0 when it succeeded)
  std::string error;
  double seconds = 0;
  std::vector<std::string> warnings;  // of a rendered (or skipped) job
  nlohmann::json figures;             // of a rendered stroke or scene (render --stats)
};

struct PendingJob {
  const BatchJob* job = nullptr;
  std::string key;  // hex
};

struct Running {
  PendingJob pending;
  pid_t pid = -1;
  std::string png, err, stats;  // the child's output, stderr and --stats, in the private folder
  Clock::time_point start;
};

class Progress {
 public:
  Progress(bool enabled, int total) : enabled_(enabled && ::isatty(2)), total_(total) {}
  void update(int done, int failed, int running) {
    if (!enabled_) return;
    constexpr int kWidth = 30;
    const int filled = total_ > 0 ? kWidth * done / total_ : kWidth;
    std::fprintf(stderr, "\rbatch [%s%s] %d/%d  %d failed  %d running ",
                 std::string(filled, '#').c_str(), std::string(kWidth - filled, '-').c_str(), done,
                 total_, failed, running);
    std::fflush(stderr);
  }
  void finish() {
    if (enabled_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  bool enabled_;
  int total_;
};

// The run: a queue of pending jobs, up to `workers` children, the log.
class BatchRun {
 public:
  BatchRun(const BatchArgs& args, const BatchManifest& manifest, std::ofstream* log)
      : args_(args),
        manifest_(manifest),
        log_(log),
        exe_(selfExecutable()),
        // The renderer's own code enters every key (batchJobKey): ~2 MB read
        // once per run.
        program_(fnv1a64Files({exe_})) {}

  // Returns the outcome of every job of the shard, by manifest index.
  std::map<int, Outcome> run(const std::vector<int>& mine) {
    Progress progress(!args_.quiet && !args_.json, static_cast<int>(mine.size()));
    std::vector<PendingJob> queue;
    for (const int k : mine) {
      const BatchJob& job = manifest_.jobs[k];
      const auto t0 = Clock::now();
      try {
        checkBeneath(args_.out_dir, job.output);  // a link out of --out fails the job
        const std::vector<std::string> inputs = batchJobInputs(job, manifest_.path);
        const std::string key = hex64(batchJobKey(job, inputs, program_));
        Outcome skipped{Status::kSkipped, 0, "", 0, {}, {}};
        if (!args_.overwrite && upToDate(outputPath(job), key, &skipped.warnings)) {
          skipped.seconds = seconds(t0);
          finish(job, key, skipped);
        } else if (args_.dry_run) {
          finishDry(job, key);
        } else {
          queue.push_back({&job, key});
        }
      } catch (const Error& e) {
        finish(job, "", Outcome{Status::kFailed, static_cast<int>(e.code()), e.what(), seconds(t0), {}, {}});
      }
    }
    if (args_.dry_run) return std::move(outcomes_);

    std::error_code ec;
    if (!queue.empty()) {
      refuseSymlinkFolder(private_dir_ = privateDir());
      fs::create_directories(private_dir_, ec);
      if (ec) throw Error(ExitCode::kCantCreate, private_dir_ + ": cannot create: " + ec.message());
    }
    size_t next = 0;
    std::vector<Running> running;
    const int workers = std::max(1, args_.jobs);
    while (next < queue.size() || !running.empty()) {
      if (g_stop_signal != 0) break;
      while (next < queue.size() && static_cast<int>(running.size()) < workers &&
             g_stop_signal == 0) {
        running.push_back(start(queue[next++]));
      }
      progress.update(static_cast<int>(outcomes_.size()), failed_, static_cast<int>(running.size()));
      std::this_thread::sleep_for(kPollInterval);
      for (auto it = running.begin(); it != running.end();) {
        int status = 0;
        const pid_t r = ::waitpid(it->pid, &status, WNOHANG);
        if (r == it->pid) {
          complete(*it, status);
          it = running.erase(it);
        } else {
          ++it;
        }
      }
    }
    if (g_stop_signal != 0) abandon(&running, queue, next);
    progress.finish();
    if (!private_dir_.empty()) fs::remove_all(private_dir_, ec);
    return std::move(outcomes_);
  }

 private:
  std::string outputPath(const BatchJob& job) const {
    return (fs::path(args_.out_dir) / job.output).string();
  }

  // One folder per batch process for the children's files, so that an
  // abandoned job's leftovers go with it, and shards on several hosts sharing
  // the output folder never collide.
  std::string privateDir() const {
    return (fs::path(args_.out_dir) /
            (".bristle-batch-" + hostName() + "-" + std::to_string(::getpid())))
        .string();
  }

  static double seconds(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
  }

  Running start(const PendingJob& p) {
    Running r;
    r.pending = p;
    r.start = Clock::now();
    const std::string tag = std::to_string(p.job->index);
    r.png = (fs::path(private_dir_) / (tag + ".png")).string();
    r.err = (fs::path(private_dir_) / (tag + ".stderr")).string();

    std::vector<std::string> argv_s = {exe_};
    for (std::string& a : batchJobArguments(*p.job)) argv_s.push_back(std::move(a));
    argv_s.insert(argv_s.end(), {"-o", r.png, "--quiet"});
    if (p.job->kind == BatchJobKind::kStroke || p.job->kind == BatchJobKind::kScene) {
      // `render` reports its figures; `sheet` and `preview` have none.
      r.stats = (fs::path(private_dir_) / (tag + ".stats.json")).string();
      argv_s.insert(argv_s.end(), {"--stats", r.stats});
    }
    std::vector<char*> argv;
    for (std::string& a : argv_s) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_addopen(&actions, 2, r.err.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    // The child starts with default signal handling (our handler only sets a
    // flag in this process).
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    sigset_t defaults;
    sigemptyset(&defaults);
    sigaddset(&defaults, SIGTERM);
    sigaddset(&defaults, SIGINT);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
    const int rc = ::posix_spawn(&r.pid, exe_.c_str(), &actions, &attr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    if (rc != 0) {
      throw Error(ExitCode::kSoftware, "cannot start " + exe_ + ": " + std::strerror(rc));
    }
    return r;
  }

  void complete(const Running& r, int status) {
    const BatchJob& job = *r.pending.job;
    Outcome o;
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
      try {
        o.warnings = warningLines(r.err);
        if (!r.stats.empty()) {
          nlohmann::json stats = nlohmann::json::parse(readBytes(r.stats), nullptr, false);
          if (stats.is_object()) {
            o.warnings = stats.value("warnings", std::vector<std::string>{});
            stats.erase("warnings");
            o.figures = std::move(stats);
          }
        }
        std::string png = render::withPngText(readBytes(r.png), kKeyText, r.pending.key);
        if (!o.warnings.empty())
          png = render::withPngText(png, kWarningsText,
                                    nlohmann::json(o.warnings).dump(-1, ' ', true));
        // Beneath --out, never through a symbolic link out of it.
        writeFileBeneath(args_.out_dir, job.output, png);
        o.status = Status::kRendered;
      } catch (const Error& e) {
        o.code = static_cast<int>(e.code());
        o.error = e.what();
      }
    } else if (WIFEXITED(status)) {
      o.code = WEXITSTATUS(status);
      o.error = lastLine(r.err);
      // The child's one-line error, without its "bristle: " prefix.
      if (o.error.rfind("bristle: ", 0) == 0) o.error.erase(0, 9);
      if (o.error.empty()) o.error = "exited with " + std::to_string(o.code);
    } else {
      o.code = static_cast<int>(ExitCode::kSoftware);
      o.error = "killed by signal " + std::to_string(WTERMSIG(status));
    }
    std::error_code ec;
    fs::remove(r.png, ec);
    fs::remove(r.err, ec);
    if (!r.stats.empty()) fs::remove(r.stats, ec);
    o.seconds = seconds(r.start);
    finish(job, r.pending.key, o);
  }

  // A stop signal: the running children get SIGTERM (they hold no output yet:
  // theirs is in the private folder), are reaped, and are logged abandoned, as
  // are the jobs that never started.
  void abandon(std::vector<Running>* running, const std::vector<PendingJob>& queue, size_t next) {
    for (const Running& r : *running) ::kill(r.pid, SIGTERM);
    for (const Running& r : *running) {
      int status = 0;
      while (::waitpid(r.pid, &status, 0) < 0 && errno == EINTR) {
      }
      finish(*r.pending.job, r.pending.key,
             Outcome{Status::kAbandoned, 0, "stopped by signal " + std::to_string(g_stop_signal),
                     seconds(r.start), {}, {}});
    }
    running->clear();
    for (size_t i = next; i < queue.size(); ++i)
      finish(*queue[i].job, queue[i].key,
             Outcome{Status::kAbandoned, 0, "not started: stopped by signal", 0, {}, {}});
  }

  nlohmann::json record(const BatchJob& job, const std::string& key, const Outcome& o) const {
    nlohmann::json j = {{"job", job.id},
                        {"index", job.index},
                        {"kind", batchJobKindName(job.kind)},
                        {"input_hash", key},
                        {"output", outputPath(job)},
                        {"status", statusName(o.status)},
                        {"seconds", std::round(o.seconds * 1000) / 1000}};
    if (o.status == Status::kFailed) {
      j["exit_code"] = o.code;
      j["error"] = o.error;
    } else if (o.status == Status::kAbandoned) {
      j["error"] = o.error;
    }
    if (o.status == Status::kRendered || o.status == Status::kSkipped)
      j["warnings"] = o.warnings;
    if (!o.figures.is_null()) j["figures"] = o.figures;
    return j;
  }

  void finish(const BatchJob& job, const std::string& key, const Outcome& o) {
    outcomes_[job.index] = o;
    if (o.status == Status::kFailed) ++failed_;
    const nlohmann::json j = record(job, key, o);
    if (log_ != nullptr) *log_ << j.dump() << '\n' << std::flush;
    if (args_.json) {
      std::cout << j.dump() << '\n' << std::flush;
    } else if (o.status == Status::kFailed) {
      printError("job '" + job.id + "' failed (" + std::to_string(o.code) + "): " + o.error);
    } else {
      for (const std::string& w : o.warnings) printError("job '" + job.id + "': warning: " + w);
    }
  }

  void finishDry(const BatchJob& job, const std::string& key) {
    outcomes_[job.index] = Outcome{Status::kRendered, 0, "", 0, {}, {}};
    nlohmann::json j = record(job, key, outcomes_[job.index]);
    j["status"] = "would render";
    if (args_.json) {
      std::cout << j.dump() << '\n';
    } else {
      std::cout << job.id << "  ->  " << outputPath(job) << "  (would render)\n";
    }
  }

  const BatchArgs& args_;
  const BatchManifest& manifest_;
  std::ofstream* log_;
  std::string exe_, private_dir_;
  std::uint64_t program_ = 0;  // FNV-1a 64 of exe_'s bytes
  std::map<int, Outcome> outcomes_;
  int failed_ = 0;
};

}  // namespace

int runBatch(const BatchArgs& args) {
  try {
    if (args.jobs < 1) throw Error(ExitCode::kUsage, "--jobs must be at least 1");
    const Shard shard = !args.shard.empty()
                            ? parseShard(args.shard)
                            : shardFromEnvironment([](const char* n) { return std::getenv(n); },
                                                   args.shard_count);
    const BatchManifest manifest = loadBatchManifest(args.manifest);
    // The job log is appended to: never to the manifest or a file a job reads.
    std::vector<NamedFile> inputs{{"manifest", args.manifest}};
    for (const BatchJob& job : manifest.jobs) {
      const std::string at = args.manifest + ": " + job.pointer;
      inputs.push_back({at + (job.kind == BatchJobKind::kSheet ? "/sheet" : "/scene"), job.input});
      inputs.push_back({at + (job.kind == BatchJobKind::kPreview ? "/preview" : "/brush"), job.brush});
      inputs.push_back({at + "/trajectory", job.trajectory});
    }
    checkOutputs({{"--log", args.log}}, inputs);
    const std::vector<int> mine = jobsOfShard(static_cast<int>(manifest.jobs.size()), shard);

    std::error_code ec;
    fs::create_directories(args.out_dir, ec);
    if (ec || !fs::is_directory(args.out_dir)) {
      throw Error(ExitCode::kCantCreate, args.out_dir + ": cannot create the output folder" +
                                             (ec ? ": " + ec.message() : ""));
    }
    std::string log_path = args.log;
    std::ofstream log;
    if (!args.dry_run) {
      if (log_path.empty()) {
        const fs::path dir = fs::path(args.out_dir) / "logs";
        refuseSymlinkFolder(dir.string());
        fs::create_directories(dir, ec);
        log_path = (dir / ("batch-" + utcStamp() + "-" + hostName() + "-" +
                           std::to_string(::getpid()) + "-shard-" + std::to_string(shard.index) +
                           "-of-" + std::to_string(shard.count) + ".jsonl"))
                       .string();
      }
      log.open(log_path, std::ios::app);
      if (!log) throw Error(ExitCode::kCantCreate, log_path + ": cannot create the job log");
    }

    installSignalHandlers();
    const auto t0 = Clock::now();
    BatchRun run(args, manifest, args.dry_run ? nullptr : &log);
    const std::map<int, Outcome> outcomes = run.run(mine);

    int rendered = 0, skipped = 0, failed = 0, abandoned = 0, warned = 0, first_failure = 0;
    for (const auto& [index, o] : outcomes) {
      warned += !o.warnings.empty();
      switch (o.status) {
        case Status::kRendered: ++rendered; break;
        case Status::kSkipped: ++skipped; break;
        case Status::kAbandoned: ++abandoned; break;
        case Status::kFailed:
          ++failed;
          if (first_failure == 0) first_failure = o.code != 0 ? o.code : 70;
          break;
      }
    }
    const double secs = std::chrono::duration<double>(Clock::now() - t0).count();
    const nlohmann::json summary = {
        {"summary", true},       {"manifest", args.manifest},
        {"shard", std::to_string(shard.index) + "/" + std::to_string(shard.count)},
        {"jobs", mine.size()},   {"rendered", rendered},
        {"skipped", skipped},    {"failed", failed},
        {"abandoned", abandoned}, {"warned", warned},
        {"seconds", std::round(secs * 1000) / 1000}, {"log", log_path}};
    if (!args.dry_run) log << summary.dump() << '\n' << std::flush;
    const std::string with_warnings =
        warned ? ", " + std::to_string(warned) + " with warnings" : std::string();
    if (args.json) {
      std::cout << summary.dump() << '\n' << std::flush;
    } else if (!args.quiet && args.dry_run) {
      // Also when every job is up to date: the user sees that the run looked.
      std::printf("batch: %zu jobs (shard %d/%d): %d would render, %d up to date, %d failed%s "
                  "(dry run)\n",
                  mine.size(), shard.index, shard.count, rendered, skipped, failed,
                  with_warnings.c_str());
    } else if (!args.quiet) {
      std::fprintf(stderr,
                   "batch: %zu jobs (shard %d/%d): %d rendered, %d up to date, %d failed%s%s in "
                   "%.1f s; log %s\n",
                   mine.size(), shard.index, shard.count, rendered, skipped, failed,
                   abandoned ? (", " + std::to_string(abandoned) + " abandoned").c_str() : "",
                   with_warnings.c_str(), secs, log_path.c_str());
    }
    if (g_stop_signal != 0) return 128 + g_stop_signal;
    if (first_failure == 0 && warned > 0 && args.fail_on_warning) {
      if (!args.json)
        printError("batch: " + std::to_string(warned) +
                   (warned == 1 ? " job has" : " jobs have") + " warnings (--fail-on-warning)");
      return static_cast<int>(ExitCode::kCheckFailed);
    }
    return first_failure;
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
  batch->add_flag("-q,--quiet", ba->quiet, "No progress, no summary");
  return {batch, [ba] { return runBatch(*ba); }};
}

}  // namespace bristle::cli

// The process pool of `bristle batch` (batch/process_pool.h): it never runs
// more children than its workers, reports every end with its status (an exit
// code, a signal), wakes as soon as a child ends rather than on a timer, and a
// stop signal ends the run between jobs with the running children reaped.

#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "batch/process_pool.h"
#include "engine/base/error.h"
#include "temp_dir.h"

using namespace bristle;
using bristle::testing::TempDir;

namespace {

ChildCommand shell(const std::string& script, const TempDir& dir) {
  return {{"/bin/sh", "-c", script}, dir.file("stderr")};
}

std::vector<std::string> lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

}  // namespace

TEST_CASE("process pool: at most `workers` children at once, all of them run", "[batch][pool]") {
  TempDir dir;
  const std::string log = dir.file("log");
  // Each child notes its start and end (small O_APPEND writes do not interleave).
  std::vector<ChildCommand> commands;
  for (int i = 0; i < 6; ++i)
    commands.push_back(shell("echo s >> '" + log + "'; sleep 0.2; echo e >> '" + log + "'", dir));
  const StopSignals signals;
  int most_reported = 0, ended = 0;
  PoolCallbacks callbacks;
  callbacks.ended = [&](size_t, int status) {
    ++ended;
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
  };
  callbacks.progress = [&](int running) { most_reported = std::max(most_reported, running); };
  const PoolResult r = runProcessPool(commands, 2, signals, callbacks);
  CHECK(r.next == commands.size());
  CHECK(r.abandoned.empty());
  CHECK(ended == 6);
  CHECK(most_reported == 2);
  // What the children saw: never more than two between a start and its end,
  // and two at some point (the workers are used).
  int running = 0, most = 0;
  for (const std::string& l : lines(log)) {
    running += l == "s" ? 1 : -1;
    most = std::max(most, running);
  }
  CHECK(running == 0);
  CHECK(most == 2);
}

TEST_CASE("process pool: exit codes and signals are reported per child", "[batch][pool][errors]") {
  TempDir dir;
  const std::vector<ChildCommand> commands = {shell("exit 0", dir), shell("exit 66", dir),
                                              shell("kill -KILL $$", dir)};
  const StopSignals signals;
  std::map<size_t, int> status;
  PoolCallbacks callbacks;
  callbacks.ended = [&](size_t i, int s) { status[i] = s; };
  runProcessPool(commands, 3, signals, callbacks);
  REQUIRE(status.size() == 3);
  CHECK((WIFEXITED(status[0]) && WEXITSTATUS(status[0]) == 0));
  CHECK((WIFEXITED(status[1]) && WEXITSTATUS(status[1]) == 66));
  CHECK((WIFSIGNALED(status[2]) && WTERMSIG(status[2]) == SIGKILL));
}

TEST_CASE("process pool: a child's end is seen at once, not at the next tick of a timer",
          "[batch][pool]") {
  TempDir dir;
  // 50 quick children one after another: with a 20 ms poll this took >= 1 s.
  const std::vector<ChildCommand> commands(50, shell("exit 0", dir));
  const StopSignals signals;
  const auto t0 = std::chrono::steady_clock::now();
  int ended = 0;
  PoolCallbacks callbacks;
  callbacks.ended = [&](size_t, int) { ++ended; };
  runProcessPool(commands, 1, signals, callbacks);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(ended == 50);
  // A start of /bin/sh takes ~1-5 ms; 0.9 s leaves room for a loaded machine
  // while staying under what 50 ticks of 20 ms would take.
  CHECK(seconds < 0.9);
}

TEST_CASE("process pool: a stop signal abandons the running children and starts no more",
          "[batch][pool]") {
  TempDir dir;
  const std::vector<ChildCommand> commands = {shell("sleep 30", dir), shell("sleep 30", dir),
                                              shell("exit 0", dir)};
  const StopSignals signals;
  PoolCallbacks callbacks;
  int ended = 0;
  // Once both workers are busy, this process gets SIGTERM, as from `kill`.
  callbacks.started = [&](size_t i) {
    if (i == 1) ::raise(SIGTERM);
  };
  callbacks.ended = [&](size_t, int) { ++ended; };
  const auto t0 = std::chrono::steady_clock::now();
  const PoolResult r = runProcessPool(commands, 2, signals, callbacks);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  CHECK(signals.received() == SIGTERM);
  CHECK(r.abandoned == std::vector<size_t>{0, 1});
  CHECK(r.next == 2);  // the third never started
  CHECK(ended == 0);
  CHECK(seconds < 10);  // the sleeps were stopped, not waited for
}

TEST_CASE("process pool: a program that cannot start is a software error (70)",
          "[batch][pool][errors]") {
  TempDir dir;
  const StopSignals signals;
  const std::vector<ChildCommand> commands = {{{dir.file("no-such-program")}, dir.file("err")}};
  try {
    runProcessPool(commands, 1, signals, {});
    FAIL("started a missing program");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::kSoftware);
  }
}

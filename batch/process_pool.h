#pragma once
// A pool of child processes for `bristle batch`: commands run in order, at most
// `workers` at once, and the pool sleeps until something happens instead of
// polling. A child's end (SIGCHLD) and a stop (SIGTERM, SIGINT) each write a
// byte to a pipe the pool waits on with poll(2), so neither is missed however
// it falls between two checks (the self-pipe trick).
//
// SIGTERM and SIGINT only set a flag while a StopSignals lives: the run stops
// between jobs, and the running children get SIGTERM and are reaped.

#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

namespace bristle {

// Catches SIGTERM, SIGINT and SIGCHLD for its lifetime (one at a time per
// process) and restores the previous handlers when it goes.
class StopSignals {
 public:
  StopSignals();
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  // The stop signal received (SIGTERM or SIGINT), 0 when none.
  int received() const;
  // Blocks until a signal arrives (a child ended, or a stop): returns at once
  // when one arrived since the last call.
  void wait() const;
};

struct ChildCommand {
  std::vector<std::string> argv;  // argv[0] is the program's path
  std::string stderr_path;        // the child's stderr (stdin and stdout are /dev/null)
};

struct PoolCallbacks {
  // Command i was started (before it can end).
  std::function<void(size_t i)> started;
  // Command i ended with this wait status (waitpid's), in the order they end.
  std::function<void(size_t i, int status)> ended;
  // After each start or end: how many are running.
  std::function<void(int running)> progress;
};

struct PoolResult {
  // Commands stopped by a stop signal while running (given SIGTERM and
  // reaped), and the first command never started (commands.size() when all
  // were started).
  std::vector<size_t> abandoned;
  size_t next = 0;
};

// Runs the commands, at most `workers` at once, until all have ended or
// `signals` received a stop. Throws Error(kSoftware) when a child cannot be
// started (the running ones are stopped first).
PoolResult runProcessPool(const std::vector<ChildCommand>& commands, int workers,
                          const StopSignals& signals, const PoolCallbacks& callbacks);

}  // namespace bristle

#include "batch/process_pool.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "engine/base/error.h"

extern char** environ;

namespace bristle {
namespace {

volatile sig_atomic_t g_stop_signal = 0;
// The self-pipe of the live StopSignals (-1 when there is none).
int g_wake_read = -1, g_wake_write = -1;
struct sigaction g_previous[3];
constexpr int kSignals[3] = {SIGTERM, SIGINT, SIGCHLD};

extern "C" void onBatchSignal(int sig) {
  const int saved_errno = errno;
  if (sig != SIGCHLD) g_stop_signal = sig;
  const char byte = 0;
  // Non-blocking: a full pipe already holds a wake-up.
  [[maybe_unused]] const ssize_t n = ::write(g_wake_write, &byte, 1);
  errno = saved_errno;
}

struct Child {
  size_t index = 0;
  pid_t pid = -1;
};

pid_t spawn(const ChildCommand& command) {
  std::vector<std::string> words = command.argv;
  std::vector<char*> argv;
  for (std::string& a : words) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, 2, command.stderr_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  // The child starts with default signal handling (ours only wake this process).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t defaults;
  sigemptyset(&defaults);
  for (const int sig : kSignals) sigaddset(&defaults, sig);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int rc = ::posix_spawn(&pid, argv[0], &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  if (rc != 0)
    throw Error(ExitCode::kSoftware, "cannot start " + words[0] + ": " + std::strerror(rc));
  return pid;
}

int waitFor(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

// SIGTERM to every running child, then each reaped: they hold no output yet.
std::vector<size_t> stopAll(std::vector<Child>* running) {
  for (const Child& c : *running) ::kill(c.pid, SIGTERM);
  std::vector<size_t> stopped;
  for (const Child& c : *running) {
    waitFor(c.pid);
    stopped.push_back(c.index);
  }
  running->clear();
  return stopped;
}

// Reaps the children that have ended (without blocking), reporting each.
void reapEnded(std::vector<Child>* running, const PoolCallbacks& callbacks) {
  for (auto it = running->begin(); it != running->end();) {
    int status = 0;
    if (::waitpid(it->pid, &status, WNOHANG) == it->pid) {
      const size_t index = it->index;
      it = running->erase(it);
      if (callbacks.ended) callbacks.ended(index, status);
    } else {
      ++it;
    }
  }
}

}  // namespace

StopSignals::StopSignals() {
  if (g_wake_write >= 0) throw std::logic_error("StopSignals: one at a time");
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC | O_NONBLOCK) != 0)
    throw Error(ExitCode::kSoftware, std::string("cannot create a pipe: ") + std::strerror(errno));
  g_wake_read = fds[0];
  g_wake_write = fds[1];
  g_stop_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = onBatchSignal;
  sigemptyset(&sa.sa_mask);
  for (int i = 0; i < 3; ++i) {
    sa.sa_flags = SA_RESTART | (kSignals[i] == SIGCHLD ? SA_NOCLDSTOP : 0);
    sigaction(kSignals[i], &sa, &g_previous[i]);
  }
}

StopSignals::~StopSignals() {
  for (int i = 0; i < 3; ++i) sigaction(kSignals[i], &g_previous[i], nullptr);
  ::close(g_wake_read);
  ::close(g_wake_write);
  g_wake_read = g_wake_write = -1;
}

int StopSignals::received() const { return g_stop_signal; }

void StopSignals::wait() const {
  pollfd p{g_wake_read, POLLIN, 0};
  if (::poll(&p, 1, -1) < 0) return;  // EINTR: a signal, which is what we wait for
  char buf[64];
  while (::read(g_wake_read, buf, sizeof buf) > 0) {
  }
}

PoolResult runProcessPool(const std::vector<ChildCommand>& commands, int workers,
                          const StopSignals& signals, const PoolCallbacks& callbacks) {
  PoolResult result;
  std::vector<Child> running;
  const size_t limit = static_cast<size_t>(std::max(1, workers));
  const auto progress = [&] {
    if (callbacks.progress) callbacks.progress(static_cast<int>(running.size()));
  };
  while ((result.next < commands.size() || !running.empty()) && signals.received() == 0) {
    while (result.next < commands.size() && running.size() < limit && signals.received() == 0) {
      const size_t i = result.next;
      try {
        running.push_back({i, spawn(commands[i])});
      } catch (const Error&) {
        stopAll(&running);
        throw;
      }
      ++result.next;
      if (callbacks.started) callbacks.started(i);
    }
    progress();
    // Sleeps until a child ends or a stop arrives: no polling interval.
    signals.wait();
    reapEnded(&running, callbacks);
    progress();
  }
  if (signals.received() != 0) result.abandoned = stopAll(&running);
  return result;
}

}  // namespace bristle

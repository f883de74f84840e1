#include "engine/base/temp_files.h"

#include <limits.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <vector>

namespace bristle {
namespace {

// A command holds a few temporary files at once (-o, --trace, --forces,
// --stats and a probe), `import` to a scene one per stroke until all are
// written: the table grows by chunks of 64 slots, each allocated outside the
// handler and linked in with an atomic pointer the handler follows.
constexpr int kSlots = 64;

enum SlotState : int { kFree = 0, kFilling = 1, kActive = 2 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};

struct Chunk {
  Slot slots[kSlots];
  std::atomic<Chunk*> next{nullptr};  // never unlinked nor freed
};

Chunk g_first;
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads slots");
static_assert(std::atomic<Chunk*>::is_always_lock_free, "the signal handler follows chunks");

extern "C" void removeTempFilesAndDie(int sig) {
  const int saved_errno = errno;
  for (Chunk* c = &g_first; c != nullptr; c = c->next.load(std::memory_order_acquire))
    for (Slot& s : c->slots)
      if (s.state.load(std::memory_order_acquire) == kActive) ::unlink(s.path);
  errno = saved_errno;
  // SA_RESETHAND restored the default action on entry; the signal is blocked
  // while the handler runs, so it ends the process as soon as this returns.
  ::raise(sig);
}

// Every catchable signal whose default action ends the process (signal(7)):
// any of them may come while a temporary file exists (SIGHUP when the terminal
// closes, SIGXCPU/SIGXFSZ from a limit, SIGPIPE from a closed -o - reader,
// SIGABRT from std::terminate), and each must leave none. The faults a bad
// instruction raises (SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGTRAP, SIGSYS) stay
// with their default action and the sanitizers' handlers: a temporary file may
// then be left, which docs/errors.md ("Outputs") says.
std::vector<int> cleanupSignals() {
  std::vector<int> sigs = {SIGHUP,  SIGINT,  SIGQUIT,   SIGABRT, SIGUSR1, SIGUSR2,
                           SIGPIPE, SIGALRM, SIGTERM,   SIGSTKFLT, SIGXCPU, SIGXFSZ,
                           SIGVTALRM, SIGPROF, SIGIO, SIGPWR};
  for (int sig = SIGRTMIN; sig <= SIGRTMAX; ++sig) sigs.push_back(sig);
  return sigs;
}

}  // namespace

void installTempFileCleanup() {
  struct sigaction sa {};
  sa.sa_handler = removeTempFilesAndDie;
  sigfillset(&sa.sa_mask);  // one cleanup at a time, whichever signals come
  sa.sa_flags = SA_RESETHAND;
  for (const int sig : cleanupSignals()) {
    // A signal ignored by whoever started us (nohup for SIGHUP, a shell's
    // background job for SIGINT, a parent that ignores SIGPIPE) stays ignored.
    // Besides SIGINT and SIGTERM, which a command's own handler hands back
    // here (record), a handler someone else installed (a profiler's SIGPROF)
    // is kept too: only the default action, which would end the process, is
    // replaced.
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) != 0) continue;
    const bool plain = (old.sa_flags & SA_SIGINFO) == 0;
    if (plain && old.sa_handler == SIG_IGN) continue;
    const bool default_or_ours =
        plain && (old.sa_handler == SIG_DFL || old.sa_handler == removeTempFilesAndDie);
    if (!default_or_ours && sig != SIGINT && sig != SIGTERM) continue;
    ::sigaction(sig, &sa, nullptr);
  }
}

TempFileRegistration::TempFileRegistration(const std::string& path) {
  if (path.size() >= PATH_MAX) return;
  for (Chunk* c = &g_first; c != nullptr;) {
    for (Slot& s : c->slots) {
      int expected = kFree;
      if (s.state.compare_exchange_strong(expected, kFilling, std::memory_order_acq_rel)) {
        std::memcpy(s.path, path.c_str(), path.size() + 1);
        s.state.store(kActive, std::memory_order_release);
        slot_ = &s.state;
        return;
      }
    }
    Chunk* next = c->next.load(std::memory_order_acquire);
    if (next == nullptr) {
      // Another thread may link one first; then ours is dropped and theirs used.
      auto* fresh = new Chunk;
      if (c->next.compare_exchange_strong(next, fresh, std::memory_order_acq_rel))
        next = fresh;
      else
        delete fresh;
    }
    c = next;
  }
}

TempFileRegistration::~TempFileRegistration() {
  if (slot_ != nullptr) slot_->store(kFree, std::memory_order_release);
}

}  // namespace bristle

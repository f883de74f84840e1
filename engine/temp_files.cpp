#include "engine/temp_files.h"

#include <limits.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

namespace bristle {
namespace {

// A command writes at most a few outputs at once (-o, --trace, --forces and a
// probe): 64 slots never fill.
constexpr int kSlots = 64;

enum SlotState : int { kFree = 0, kFilling = 1, kActive = 2 };

struct Slot {
  std::atomic<int> state{kFree};
  char path[PATH_MAX];
};

Slot g_slots[kSlots];
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads slots");

extern "C" void removeTempFilesAndDie(int sig) {
  const int saved_errno = errno;
  for (Slot& s : g_slots)
    if (s.state.load(std::memory_order_acquire) == kActive) ::unlink(s.path);
  errno = saved_errno;
  // SA_RESETHAND restored the default action on entry; the signal is blocked
  // while the handler runs, so it ends the process as soon as this returns.
  ::raise(sig);
}

}  // namespace

void installTempFileCleanup() {
  struct sigaction sa {};
  sa.sa_handler = removeTempFilesAndDie;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGINT);
  sigaddset(&sa.sa_mask, SIGTERM);
  sa.sa_flags = SA_RESETHAND;
  for (const int sig : {SIGINT, SIGTERM}) {
    // A signal ignored by whoever started us (nohup, a shell's background job
    // for SIGINT) stays ignored.
    struct sigaction old {};
    if (::sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &sa, nullptr);
  }
}

TempFileRegistration::TempFileRegistration(const std::string& path) {
  if (path.size() >= PATH_MAX) return;
  for (int i = 0; i < kSlots; ++i) {
    int expected = kFree;
    if (g_slots[i].state.compare_exchange_strong(expected, kFilling, std::memory_order_acq_rel)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(kActive, std::memory_order_release);
      slot_ = i;
      return;
    }
  }
}

TempFileRegistration::~TempFileRegistration() {
  if (slot_ >= 0) g_slots[slot_].state.store(kFree, std::memory_order_release);
}

}  // namespace bristle

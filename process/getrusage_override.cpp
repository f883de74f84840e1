// getrusage(2) for a bristle program: the executable's definition comes first
// when the dynamic linker binds libipopt's reference to getrusage, so this
// takes the C library's place for the whole process. Inside an engaged
// IpoptTimersOff scope (engine/solvers/ipopt/ipopt_timers.h) it answers zero
// usage without a system call; everywhere else it is the plain system call,
// as glibc's wrapper is. Linked only into programs (process/process_hooks.h).

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cstring>

#include "engine/solvers/ipopt/ipopt_timers.h"

extern "C" int getrusage(int who, struct rusage* usage) noexcept {
  if (usage != nullptr && bristle::skipIpoptTimerRead()) {
    std::memset(usage, 0, sizeof *usage);
    return 0;
  }
  return static_cast<int>(syscall(SYS_getrusage, who, usage));
}

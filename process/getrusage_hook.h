#pragma once
// bristle's one rule for getrusage(2) (engine/solvers/ipopt/ipopt_timers.h):
// inside an engaged IpoptTimersOff scope, zero usage without a system call;
// everywhere else the real system call. Two ways to put it in Ipopt's path:
//
//  - a program links process/getrusage_override.cpp (bristle::process): the
//    executable's getrusage comes first when the dynamic linker binds
//    libipopt's reference, so it takes the C library's place;
//  - a module loaded with RTLD_LOCAL (the Python module) cannot do that, the C
//    library comes first in the global scope, so routeIpoptGetrusage() writes
//    timerAwareGetrusage into libipopt's own relocation slot for getrusage.

#include <sys/resource.h>

namespace bristle {

// The rule above, with getrusage's signature.
int timerAwareGetrusage(int who, struct rusage* usage) noexcept;

// Writes timerAwareGetrusage into the getrusage slot (PLT/GOT) of every loaded
// libipopt. True when at least one slot was found and written; false leaves
// the process as it was: Ipopt's timers make their system calls, the solves
// are the same, only slower. Call once at start, before any solve (the write
// is not synchronised with a thread inside libipopt). Idempotent.
// `through_rule` false writes the C library's getrusage back instead, so that
// a benchmark can compare the two in one process.
bool routeIpoptGetrusage(bool through_rule = true);

}  // namespace bristle

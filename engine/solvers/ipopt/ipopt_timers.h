#pragma once

// Ipopt 3.11's own timers, switched off while bristle solves.
//
// Ipopt 3.11 (Debian bookworm's) times every task of every iteration through
// getrusage(2), 100-300 system calls per iteration, up to about a quarter of a
// brush solve (docs/PERFORMANCE.md, "Ipopt's warm starts and its timers").
// Ipopt 3.14 can switch them off (option timing_statistics, off by default);
// 3.11 cannot. So bristle defines getrusage itself: on a thread inside an
// IpoptTimersOff scope it returns zero usage without a system call, and everywhere else it makes the
// real system call. Nothing of Ipopt's algorithm reads the timers except the
// max_cpu_time limit, so the solver keeps them on when that limit is set.
//
// That getrusage replaces the C library's for the whole process, so it is no
// part of the engine library: a program opts in by linking the object
// process/getrusage_override.cpp (bristle::process; docs/api.md, "Process-wide
// set-up"). Without it IpoptTimersOff changes nothing: Ipopt's timers run, the
// solves are the same, only slower.

#include <cstdint>

namespace bristle {

// While alive, getrusage on this thread reports zero usage (no system call).
// Scopes nest; `engage` false makes the scope a no-op.
class IpoptTimersOff {
 public:
  explicit IpoptTimersOff(bool engage);
  ~IpoptTimersOff();
  IpoptTimersOff(const IpoptTimersOff&) = delete;
  IpoptTimersOff& operator=(const IpoptTimersOff&) = delete;

 private:
  bool was_off_;
};

// getrusage calls this thread answered with zeros since it started (tests).
std::uint64_t ipoptTimerReadsSkipped();

// Reads Ipopt's own CPU clock (Ipopt::CpuTime, through libipopt's binding of
// getrusage) inside an engaged IpoptTimersOff scope: true when bristle's rule
// answered it without a system call (tests of process/getrusage_hook.h).
bool ipoptClockReadSkipped();

// For the getrusage override: true (and counted) when this thread is inside an
// engaged IpoptTimersOff scope, so the call is answered with zeros.
bool skipIpoptTimerRead();

}  // namespace bristle

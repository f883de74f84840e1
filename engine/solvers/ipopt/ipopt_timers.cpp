#include "engine/solvers/ipopt/ipopt_timers.h"

#include <IpUtils.hpp>

namespace bristle {
namespace {

thread_local bool t_timers_off = false;
thread_local std::uint64_t t_reads_skipped = 0;

}  // namespace

IpoptTimersOff::IpoptTimersOff(bool engage) : was_off_(t_timers_off) {
  if (engage) t_timers_off = true;
}

IpoptTimersOff::~IpoptTimersOff() { t_timers_off = was_off_; }

std::uint64_t ipoptTimerReadsSkipped() { return t_reads_skipped; }

bool skipIpoptTimerRead() {
  if (!t_timers_off) return false;
  ++t_reads_skipped;
  return true;
}

bool ipoptClockReadSkipped() {
  const std::uint64_t before = t_reads_skipped;
  const IpoptTimersOff off(true);
  static_cast<void>(Ipopt::CpuTime());
  return t_reads_skipped != before;
}

}  // namespace bristle

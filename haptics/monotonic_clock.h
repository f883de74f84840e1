#pragma once
// The servo loop's and the session file's clock: monotonic (never stepped by
// NTP or the user), so intervals between samples and flushes are true.

#include <chrono>
#include <cstdint>

namespace bristle::haptics {

inline std::int64_t monotonicNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace bristle::haptics

#pragma once
// Progress on stderr for commands that render many strokes (a scene's strokes, a
// sheet's cells): "bristle: stroke 3/12, step 140/800 (18%)", only when stderr is
// a terminal, at most every 0.2 s, and a newline after the last step.

#include <unistd.h>

#include <chrono>
#include <cstdio>

namespace bristle::cli {

class PartProgress {
 public:
  // `part` names what is counted ("stroke", "cell").
  PartProgress(bool enabled, const char* part) : enabled_(enabled && ::isatty(2)), part_(part) {}
  void update(int index, int count, long step, long steps) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    const bool last = step + 1 >= steps;
    if (!last && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    std::fprintf(stderr, "\rbristle: %s %d/%d, step %ld/%ld (%3.0f%%)", part_, index + 1, count,
                 step + 1, steps, 100.0 * double(step + 1) / double(steps));
    if (last) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_;
  const char* part_;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace bristle::cli

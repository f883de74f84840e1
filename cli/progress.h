#pragma once
// Progress on stderr for a render's steps (a stroke's, a scene's strokes, a
// sheet's cells), unless --quiet:
// - on a terminal, one line rewritten in place at most every 0.2 s:
//   "bristle: stroke 3/12, step 140/800 (18%)", and a newline after the last step;
// - elsewhere (a log file, a pipe, a batch job's stderr), a whole line at most
//   once a minute, the first after a minute, so a run shorter than a minute
//   prints nothing and a long one shows it is alive:
//   "bristle: progress: step 140/800 (18%) after 60 s". BRISTLE_PROGRESS_SECONDS
//   sets the minute to other seconds (docs/errors.md, "Long runs").

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace bristle::cli {

class PartProgress {
 public:
  // `part` names what is counted ("stroke", "cell"); nullptr for one stroke.
  PartProgress(bool enabled, const char* part)
      : enabled_(enabled), tty_(::isatty(2) == 1), part_(part), interval_(logInterval()) {}

  void update(int index, int count, long step, long steps) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    const bool last = step + 1 >= steps;
    std::string what = part_ == nullptr ? std::string()
                                        : std::string(part_) + " " + std::to_string(index + 1) +
                                              "/" + std::to_string(count) + ", ";
    char counts[96];
    std::snprintf(counts, sizeof counts, "step %ld/%ld (%3.0f%%)", step + 1, steps,
                  100.0 * double(step + 1) / double(steps));
    if (tty_) {
      if (!last && now - last_ < std::chrono::milliseconds(200)) return;
      last_ = now;
      std::fprintf(stderr, "\rbristle: %s%s", what.c_str(), counts);
      if (last) std::fprintf(stderr, "\n");
      return;
    }
    if (now - last_line_ < interval_) return;
    last_line_ = now;
    const double secs = std::chrono::duration<double>(now - start_).count();
    std::fprintf(stderr, "bristle: progress: %s%s after %.0f s\n", what.c_str(), counts, secs);
    std::fflush(stderr);
  }

 private:
  static std::chrono::steady_clock::duration logInterval() {
    const char* env = std::getenv("BRISTLE_PROGRESS_SECONDS");
    char* end = nullptr;
    const double s = env != nullptr ? std::strtod(env, &end) : 60.0;
    const bool ok = env == nullptr || (end != env && *end == '\0' && s > 0 && s <= 86400);
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(ok ? s : 60.0));
  }

  bool enabled_, tty_;
  const char* part_;
  std::chrono::steady_clock::duration interval_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_{};
  std::chrono::steady_clock::time_point last_line_ = start_;
};

}  // namespace bristle::cli

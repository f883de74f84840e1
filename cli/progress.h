#pragma once
// Progress on stderr for a render's steps (a stroke's, a scene's strokes, a
// sheet's cells), unless --quiet:
// - on a terminal, one line rewritten in place at most every 0.2 s:
//   "bristle: stroke 3/12, step 140/800 (18%), about 40 s left", and a newline
//   after the last step;
// - elsewhere (a log file, a pipe, a batch job's stderr), a whole line at most
//   once a minute, the first after a minute, so a run shorter than a minute
//   prints nothing and a long one shows it is alive:
//   "bristle: progress: step 140/800 (18%) after 60 s, about 4 min left".
//   BRISTLE_PROGRESS_SECONDS
//   sets the minute to other seconds (docs/errors.md, "Long runs").

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace bristle::cli {

// "about 40 s left", "about 3 min left": the time still to go, if the rest goes
// at the pace so far. Nothing until 2% is done and 1 s has passed, since the
// first steps' pace says little of the rest's.
inline std::string remainingText(double elapsed_s, double fraction) {
  if (fraction < 0.02 || fraction >= 1 || elapsed_s < 1) return "";
  const double left = elapsed_s * (1 - fraction) / fraction;
  char buf[48];
  if (left < 90)
    std::snprintf(buf, sizeof buf, ", about %.0f s left", std::max(1.0, left));
  else if (left < 5400)
    std::snprintf(buf, sizeof buf, ", about %.0f min left", left / 60);
  else
    std::snprintf(buf, sizeof buf, ", about %.1f h left", left / 3600);
  return buf;
}

class PartProgress {
 public:
  // `part` names what is counted ("stroke", "cell"); nullptr for one stroke.
  PartProgress(bool enabled, const char* part)
      : enabled_(enabled), tty_(::isatty(2) == 1), part_(part), interval_(logInterval()) {}

  // `step` of `steps` planned (0-based): the total is the plan's, fixed before
  // the run, and a step redone in halves does not count twice.
  void update(int index, int count, long step, long steps) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    const bool last = step + 1 >= steps;
    std::string what = part_ == nullptr ? std::string()
                                        : std::string(part_) + " " + std::to_string(index + 1) +
                                              "/" + std::to_string(count) + ", ";
    const double fraction = double(step + 1) / double(steps);
    const double secs = std::chrono::duration<double>(now - start_).count();
    char counts[96];
    std::snprintf(counts, sizeof counts, "step %ld/%ld (%3.0f%%)", step + 1, steps,
                  100.0 * fraction);
    const std::string left = last ? std::string() : remainingText(secs, fraction);
    if (tty_) {
      if (!last && now - last_ < std::chrono::milliseconds(200)) return;
      last_ = now;
      // \033[K clears what a longer line before left behind.
      std::fprintf(stderr, "\rbristle: %s%s%s\033[K", what.c_str(), counts, left.c_str());
      if (last) std::fprintf(stderr, "\n");
      return;
    }
    if (now - last_line_ < interval_) return;
    last_line_ = now;
    std::fprintf(stderr, "bristle: progress: %s%s after %.0f s%s\n", what.c_str(), counts, secs,
                 left.c_str());
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

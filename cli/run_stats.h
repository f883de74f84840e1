#pragma once
// What a render found worth knowing besides its image, for `render --stats
// FILE` and through it `batch`'s job log: its warnings and its figures.

#include <string>
#include <vector>

#include "engine/simulation.h"

namespace bristle::cli {

struct RunStats {
  long painted_pixels = 0;       // visible paint (render/compose.h, kInkLevels)
  long pixels = 0;               // of the image
  long planned_steps = 0;        // the plan's steps, as progress counts them
  SimStats sim;                  // steps taken (split halves too), failed steps, ...
  double paint_laid_mm3 = 0;     // paint deposited on the canvas
  double paint_picked_up_mm3 = 0;
  std::vector<std::string> warnings;  // one line each, without "warning: "

  // Prints "bristle: warning: W" on stderr and keeps W.
  void warn(const std::string& w);
};

// The warning about steps whose solve failed ("" when none did).
std::string failedSolvesWarning(const SimStats& stats);

// Writes the stats as one JSON object to path (atomically; nothing for "").
void writeRunStats(const std::string& path, const RunStats& stats);

}  // namespace bristle::cli

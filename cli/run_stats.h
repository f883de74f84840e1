#pragma once
// What a render found worth knowing besides its image, for `render --stats
// FILE` and through it `batch`'s job log: its warnings and its figures.

#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/model/trajectory.h"

namespace bristle::cli {

struct RunStats {
  long painted_pixels = 0;       // visible paint (render/image/compose.h, kInkLevels)
  long pixels = 0;               // of the image
  long planned_steps = 0;        // the plan's steps, as progress counts them
  SimStats sim;                  // steps taken (split halves too), failed steps, ...
  double paint_laid_mm3 = 0;     // paint deposited on the canvas
  double paint_picked_up_mm3 = 0;
  std::vector<std::string> warnings;  // one line each, without "warning: "

  // Prints "bristle: warning: W" on stderr and keeps W.
  void warn(const std::string& w);
};

// Prints each warning as "bristle: warning: W" and returns them, for the
// run's stats and its PNG text.
std::vector<std::string> printWarnings(std::vector<std::string> warnings);

// The warnings about a single stroke's inputs (engine/formats/input_warnings.h): the
// brush's scale, the trajectory's length and its steps planned with
// `options`, which throws as the render would at a step limit. Not printed:
// a command prints them once every check before its run has passed, so that
// a refusal stays its one line.
std::vector<std::string> strokeInputWarnings(const Brush& brush, const Trajectory& trajectory,
                                             const SimOptions& options);

// The warning about steps whose solve failed ("" when none did).
std::string failedSolvesWarning(const SimStats& stats);

// Writes the stats as one JSON object to path (atomically; nothing for "").
void writeRunStats(const std::string& path, const RunStats& stats);

}  // namespace bristle::cli

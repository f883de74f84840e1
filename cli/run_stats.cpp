#include "cli/run_stats.h"

#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/input_warnings.h"
#include "engine/dynamics/stepper.h"

namespace bristle::cli {

void RunStats::warn(const std::string& w) {
  printError("warning: " + w);
  warnings.push_back(w);
}

std::vector<std::string> printWarnings(std::vector<std::string> warnings) {
  for (const std::string& w : warnings) printError("warning: " + w);
  return warnings;
}

std::vector<std::string> strokeInputWarnings(const Brush& brush, const Trajectory& trajectory,
                                             const SimOptions& options) {
  const double steps = plannedStepCount(trajectory, brush, options);
  std::vector<std::string> out;
  for (std::string w : {brushScaleWarning(brush), trajectoryWarning(trajectory, steps, &brush,
                                                                    options)})
    if (!w.empty()) out.push_back(std::move(w));
  return out;
}

std::string failedSolvesWarning(const SimStats& stats) {
  if (stats.failed_steps <= 0) return "";
  return std::to_string(stats.failed_steps) + " of " + std::to_string(stats.steps) +
         " steps had a failed solve (" + std::to_string(stats.failed_spine_solves) +
         " spine solves); those spines were carried along frozen in their last good pose, "
         "for at most " + std::to_string(stats.longest_failed_run) + " steps in a row";
}

void writeRunStats(const std::string& path, const RunStats& s) {
  if (path.empty()) return;
  const nlohmann::json j = {
      {"painted_pixels", s.painted_pixels},
      {"pixels", s.pixels},
      {"planned_steps", s.planned_steps},
      {"steps", s.sim.steps},
      {"solved_steps", s.sim.solved_steps},
      {"settled_steps", s.sim.settled_steps},
      {"stiction_resolves", s.sim.resolves},
      {"solver_iterations", s.sim.iterations},
      {"steady_steps", s.sim.steady_steps},
      {"steady_merged_steps", s.sim.steady_merged},
      {"steady_rejected", s.sim.steady_rejected},
      {"jump_split_steps", s.sim.jump_split_steps},
      {"jump_stopped_steps", s.sim.jump_stopped_steps},
      {"recentred_solves", s.sim.recentred_solves},
      {"isolated_solves", s.sim.isolated_solves},
      {"rescue_iterations", s.sim.rescue_iterations},
      {"failed_steps", s.sim.failed_steps},
      {"failed_spine_solves", s.sim.failed_spine_solves},
      {"fallback_solves", s.sim.fallback_solves},
      {"paint_laid_mm3", s.paint_laid_mm3},
      {"paint_picked_up_mm3", s.paint_picked_up_mm3},
      {"warnings", s.warnings}};
  AtomicOutput out(path);
  out.stream() << j.dump() << '\n';
  out.commit();
}

}  // namespace bristle::cli

#include "batch/job_cost.h"

#include <exception>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/first_contact.h"
#include "engine/formats/scene.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/model/trajectory.h"

namespace bristle {

namespace {

double strokeCost(const Trajectory& trajectory, const Brush& brush) {
  const std::vector<double> steps =
      planStepTimes(resolveDepths(trajectory, brush), brush, SimOptions{});
  return static_cast<double>(steps.size()) * static_cast<double>(brush.spines.size());
}

}  // namespace

double estimateJobCost(const BatchJob& job) {
  try {
    switch (job.kind) {
      case BatchJobKind::kPreview: return 1;
      case BatchJobKind::kSheet: return kUnknownJobCost;
      case BatchJobKind::kStroke:
        // A recording (docs/input.md) is not read here: unknown, started first.
        return strokeCost(loadTrajectory(job.trajectory), loadBrush(job.brush));
      case BatchJobKind::kScene: {
        const Scene scene = loadScene(job.input);
        double cost = 0;
        for (const SceneStroke& s : scene.strokes)
          cost += strokeCost(s.trajectory, scene.brushes[s.brush]);
        return cost;
      }
    }
  } catch (const std::exception&) {
    // Unreadable here: the job itself will say why, and soon.
  }
  return kUnknownJobCost;
}

}  // namespace bristle

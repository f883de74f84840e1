// Fuzz target: the trajectory reader (bristle-trajectory/1 CSV), then what
// render does with a trajectory before it allocates the simulation: its depths
// (if it gives depth_mm) made the brush's ferrule heights, the check against
// the brush and the plan of its steps (limited per trajectory and per second
// of gesture).

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/first_contact.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/model/trajectory.h"
#include "engine/base/text_file.h"
#include "fuzz/fuzz_input.h"
#include "tests/support/build_paths.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bristle::Brush round =
      bristle::loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  try {
    const bristle::Trajectory t = bristle::resolveDepths(
        bristle::parseTrajectory(bristle::fuzz::text(data, size), "t.csv"), round);
    bristle::validateTrajectoryForBrush(t, round);
    const std::vector<double> steps = bristle::planStepTimes(t, round, bristle::SimOptions{});
    if (steps.size() > static_cast<std::size_t>(bristle::kMaxPlannedSteps) + 1) std::abort();
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}

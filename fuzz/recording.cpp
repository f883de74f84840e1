// Fuzz target: the recording readers (MyPaint events, Pointer Events CSV, SVG
// paths through pugixml and lib2geom; the format detected from the content,
// as for a file name with no known extension), then what `render --trajectory`
// does with a recording before it allocates the simulation: the default
// mapping for the round brush, its depths made ferrule heights, the check
// against the brush and the plan of its steps. Also each pen-down stroke as a
// scene's trajectory, as `import -o OUT.json` writes them.

#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/first_contact.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/model/trajectory.h"
#include "fuzz/fuzz_input.h"
#include "input/import.h"
#include "input/pen_mapping.h"
#include "tests/support/build_paths.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const bristle::Brush round =
      bristle::loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  const std::string text = bristle::fuzz::text(data, size);
  try {
    std::vector<std::string> warnings;
    const bristle::Trajectory t = bristle::resolveDepths(
        bristle::input::loadTrajectoryOrRecording(text, "recording", round, "round", &warnings),
        round);
    bristle::validateTrajectoryForBrush(t, round);
    const std::vector<double> steps = bristle::planStepTimes(t, round, bristle::SimOptions{});
    if (steps.size() > static_cast<std::size_t>(bristle::kMaxPlannedSteps) + 1) std::abort();
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  try {
    bristle::input::ImportOptions options;
    bristle::input::resolveMaxDepth(&options, round, "round");
    const bristle::input::Recording rec = bristle::input::readInput(text, "recording", options);
    for (const bristle::Trajectory& stroke :
         bristle::input::toStrokeTrajectories(rec, options.mapping))
      bristle::validateTrajectoryForBrush(bristle::resolveDepths(stroke, round), round);
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}

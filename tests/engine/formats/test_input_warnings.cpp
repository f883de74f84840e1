// Inputs every rule accepts but that are almost surely a mistake
// (engine/formats/input_warnings.h): a trajectory in milliseconds, one that plans
// hours of solving, a brush whose spines and surface are in different units.
// Each warning is checked as the whole line a user reads.

#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/formats/input_warnings.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/base/text_file.h"
#include "engine/model/trajectory.h"
#include "tests/support/build_paths.h"

using namespace bristle;

namespace {

const std::string kSource = BRISTLE_SOURCE_DIR;

// A trajectory of the handle held upright 25 mm up, at (x, 40) at each time t.
Trajectory upright(const std::vector<std::pair<double, double>>& t_x) {
  std::string text = "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  for (const auto& [t, x] : t_x)
    text += std::to_string(t) + "," + std::to_string(x) + ",40,25,1,0,0,0\n";
  return parseTrajectory(text, "t.csv");
}

std::string warningFor(const Trajectory& t, const Brush& brush, const SimOptions& options = {}) {
  return trajectoryWarning(t, plannedStepCount(t, brush, options), &brush, options);
}

// The round brush with every cage vertex (or every spine length and root) scaled.
Brush scaledRound(double cage_scale, double spine_scale) {
  nlohmann::json doc =
      nlohmann::json::parse(readTextFile(kSource + "/scenes/brushes/round.json"));
  for (auto& v : doc["surface"]["cage_vertices_mm"])
    for (auto& c : v) c = c.get<double>() * cage_scale;
  for (auto& s : doc["spines"]) {
    for (auto& c : s["root_mm"]) c = c.get<double>() * spine_scale;
    for (auto& l : s["segment_lengths_mm"]) l = l.get<double>() * spine_scale;
  }
  return parseBrush(doc.dump(), "b.json");
}

}  // namespace

TEST_CASE("a trajectory over 10 minutes asks whether its times were in milliseconds",
          "[warnings]") {
  const Brush round = loadBrush(kSource + "/scenes/brushes/round.json");
  // A 5.35 s stroke written in milliseconds: 642,001 steps at the default 120 Hz.
  const Trajectory ms = upright({{0, 15}, {5350, 40}});
  CHECK(warningFor(ms, round) ==
        "t.csv: t_s spans 5350 s (89 min, 642001 simulation steps); were the times in "
        "milliseconds?");
  // Without a brush (validate T.csv) the steps are not known.
  CHECK(trajectoryWarning(ms, 0, nullptr, {}) ==
        "t.csv: t_s spans 5350 s (89 min); were the times in milliseconds?");
  CHECK(trajectoryWarning(upright({{0, 15}, {3e6, 40}}), 0, nullptr, {}) ==
        "t.csv: t_s spans 3000000 s (833 h); were the times in microseconds?");
  // Ten minutes is the limit, not a mistake.
  CHECK(warningFor(upright({{0, 15}, {600, 40}}), round).empty());
  CHECK(warningFor(upright({{0, 15}, {601, 40}}), round) ==
        "t.csv: t_s spans 601 s (10 min, 72121 simulation steps); were the times in "
        "milliseconds?");
}

TEST_CASE("a trajectory planning over a million steps names what makes them", "[warnings]") {
  const Brush round = loadBrush(kSource + "/scenes/brushes/round.json");
  // 300 m of handle travel in 10 s: the positions read as micrometres.
  const Trajectory far = upright({{0, 0}, {5, 100000}, {10, 0}, {15, 100000}});
  const double steps = plannedStepCount(far, round, {});
  REQUIRE(steps == 1200001);
  CHECK(warningFor(far, round) ==
        "t.csv: the trajectory plans 1200001 simulation steps, over 1000000 (an hour or more of "
        "solving): the spine roots travel 300000 mm at most 0.25 mm a step; were x_mm, y_mm and "
        "z_mm in micrometres?");
  // Eight minutes at the highest rate.
  SimOptions fast;
  fast.min_rate_hz = 10000;
  CHECK(warningFor(upright({{0, 15}, {480, 40}}), round, fast) ==
        "t.csv: the trajectory plans 4800001 simulation steps, over 1000000 (an hour or more of "
        "solving): 480 s of t_s at 10000 steps a second");
  CHECK(warningFor(upright({{0, 15}, {480, 40}}), round).empty());  // 57,601 at 120 Hz
}

TEST_CASE("a brush whose spines and surface differ in size tenfold is named", "[warnings]") {
  // Every library brush: spines and surface agree (within a factor of 1.2).
  for (const auto& entry : std::filesystem::directory_iterator(kSource + "/scenes/brushes")) {
    if (entry.path().extension() != ".json") continue;
    INFO(entry.path());
    CHECK(brushScaleWarning(loadBrush(entry.path().string())).empty());
  }
  CHECK(brushScaleWarning(scaledRound(1, 1)).empty());
  // Spines in metres, the surface in millimetres.
  CHECK(brushScaleWarning(scaledRound(1, 0.001)) ==
        "b.json: /spines span 0.02 mm but /surface/cage_vertices_mm spans 19.9 mm (996 times "
        "larger); both are in mm: were they written in different units?");
  CHECK(brushScaleWarning(scaledRound(0.001, 1)) ==
        "b.json: /spines span 20 mm but /surface/cage_vertices_mm spans 0.0199 mm (1004 times "
        "smaller); both are in mm: were they written in different units?");
}

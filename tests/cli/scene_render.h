#pragma once
// Renders a scene (bristle-scene/1 JSON) end to end through the bristle
// executable and returns its coverage, checking that it exits 0 and that no
// step failed to solve (its --stats file's failed_steps).

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <fstream>
#include <string>

#include "cli_runner.h"
#include "tests/support/mark_png.h"

namespace bristle::testing {

// Writes `scene` as STEM.json in `dir`, renders it to STEM.png and reads it.
inline testsupport::Coverage renderSceneChecked(const nlohmann::json& scene, const TempDir& dir,
                                                const std::string& stem) {
  const std::string scene_path = dir.file(stem + ".json");
  std::ofstream(scene_path) << scene.dump();
  const std::string png = dir.file(stem + ".png");
  const std::string stats = dir.file(stem + "-stats.json");
  const RunResult r =
      runBristle("render -q '" + scene_path + "' -o '" + png + "' --stats '" + stats + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  std::ifstream in(stats);
  CHECK(nlohmann::json::parse(in).at("failed_steps").get<int>() == 0);
  return testsupport::loadCoveragePng(png);
}

}  // namespace bristle::testing

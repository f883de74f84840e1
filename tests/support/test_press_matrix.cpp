// The reduced press matrix (the whole one: bench/bench_matrix): every library brush, pressed
// to 80 % of its hair length upright and pulled, pulled fast at a 60-degree
// tilt, and pressed straight down and lifted, with the reference solver. Not
// one step may fail. bench/bench_matrix runs the whole matrix (108 cases per
// brush) and reports time per step.

#include <catch2/catch.hpp>
#include <string>

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "tests/support/press_matrix.h"
#include "tests/support/build_paths.h"

using namespace bristle;
using namespace bristle::testsupport;

TEST_CASE("press matrix: no library brush fails a step, however hard it is pressed",
          "[matrix]") {
  const char* name =
      GENERATE("round", "flat", "bright", "filbert", "badger", "fan", "calligraphy");
  const std::string path = std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json";
  const Brush brush = loadBrush(path);
  struct Row {
    CaseKind kind;
    double fraction, tilt_deg, speed_mm_s;
  };
  for (const Row& row : {Row{CaseKind::kPull, 0.8, 0, 50}, Row{CaseKind::kPull, 0.4, 60, 200},
                         Row{CaseKind::kPressLift, 0.8, 0, 0}}) {
    Case c;
    c.brush_path = path;
    c.kind = row.kind;
    c.press_fraction = row.fraction;
    c.tilt_deg = row.tilt_deg;
    c.speed_mm_s = row.speed_mm_s;
    INFO(name << ": " << describe(c));
    const CaseResult r = runCase(brush, c, "ipopt", /*fallback=*/false);
    CHECK(r.steps > 100);
    CHECK(r.failed_steps == 0);
  }
}

// `bristle measure` end to end (render/brush_measure.h, docs/fidelity.md
// "Measuring a brush"): the protocol's measures behave as a pressed, pulled
// brush must, the table is the same every run, and bad input gets one line.

#include <algorithm>
#include <catch2/catch.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "cli_runner.h"

using namespace bristle::testing;

namespace {

struct Row {
  double depth_mm = 0, width_mm = 0, drag_mm = 0, offset_mm = 0;
  int failed_steps = 0;
};

std::vector<Row> parseTable(const std::string& csv) {
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  REQUIRE(line == "depth_mm,width_mm,drag_mm,offset_mm,failed_steps");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    Row r;
    char comma;
    std::istringstream fields(line);
    fields >> r.depth_mm >> comma >> r.width_mm >> comma >> r.drag_mm >> comma >> r.offset_mm >>
        comma >> r.failed_steps;
    REQUIRE_FALSE(fields.fail());
    rows.push_back(r);
  }
  return rows;
}

// The protocol's resolution, 10 px/mm: a measure's pixel.
constexpr double kFootprintPixelMm = 0.1;

}  // namespace

TEST_CASE("measure: a deeper press is wider and its footprint trails behind the handle",
          "[cli][measure]") {
  TempDir dir;
  const std::string csv = dir.file("round.csv");
  const RunResult r = runBristle("measure round --depths 2,6 -q -o '" + csv + "'");
  INFO(r.err);
  REQUIRE(r.code == 0);
  CHECK(r.out.empty());  // -q: no table, no path
  const std::vector<Row> rows = parseTable(readAll(csv));
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].depth_mm == 2);
  CHECK(rows[1].depth_mm == 6);
  for (const Row& row : rows) {
    INFO("depth " << row.depth_mm << ": width " << row.width_mm << ", drag " << row.drag_mm
                  << ", offset " << row.offset_mm);
    CHECK(row.failed_steps == 0);
    // Pulled along +x, friction holds the hair back: the footprint is widest
    // behind the handle's axis and its tip trails further behind.
    CHECK(row.offset_mm > 2 * kFootprintPixelMm);
    CHECK(row.drag_mm > 2 * kFootprintPixelMm);
    // No wider than the round's hair can spread (20 mm long, pressed 6 mm).
    CHECK(row.width_mm < 20);
  }
  // Pressed three times as deep, more hair lies on the paper: wider by more
  // than the two pixels an edge may flip by.
  CHECK(rows[1].width_mm > rows[0].width_mm + 2 * kFootprintPixelMm);
}

TEST_CASE("measure: the same brush and protocol give the same table", "[cli][measure]") {
  const RunResult a = runBristle("measure flat --depths 3 -q -o -");
  const RunResult b = runBristle("measure flat --depths 3 -q -o -");
  REQUIRE(a.code == 0);
  REQUIRE(b.code == 0);
  CHECK(parseTable(a.out).size() == 1);
  CHECK(a.out == b.out);
}

TEST_CASE("measure: bad depths and speeds get one line and exit 64", "[cli][measure]") {
  for (const std::string& args : {std::string("--depths 0"), std::string("--depths 2,200"),
                                  std::string("--depths 2,nan"), std::string("--speed-mm-s 0")}) {
    INFO(args);
    const RunResult r = runBristle("measure round " + args);
    CHECK(r.code == 64);
    CHECK(r.out.empty());
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  }
  const RunResult missing = runBristle("measure no-such-brush");
  CHECK(missing.code == 66);
  CHECK_THAT(missing.err, Catch::Matchers::Contains("no-such-brush"));
}

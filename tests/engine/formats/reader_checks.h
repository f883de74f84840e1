#pragma once
// What the reader tests of tests/engine/formats/ share: a check that a reader
// refused its input as docs/design.md ("Exit codes") says (the sysexits code,
// and a one-line message naming the file, the field -- JSON pointer, or CSV
// line and column -- and the broken rule), and a small valid brush and
// trajectory to break.

#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "test_helpers.h"

// Runs expr, which must throw bristle::Error with the given code and a single-line
// message that starts with "file: " and contains every further argument.
#define CHECK_READER_ERROR(expr, expected_code, file, ...)                              \
  do {                                                                                  \
    const bristle::testing::Caught caught_ =                                            \
        bristle::testing::catchError([&] { (void)(expr); });                            \
    INFO("message: " << caught_.message);                                               \
    REQUIRE(caught_.thrown);                                                            \
    CHECK(caught_.code == static_cast<int>(expected_code));                             \
    CHECK_THAT(caught_.message, Catch::Matchers::StartsWith(std::string(file) + ": ")); \
    CHECK(caught_.message.find('\n') == std::string::npos);                             \
    for (const std::string& part_ : std::vector<std::string>{__VA_ARGS__})              \
      CHECK_THAT(caught_.message, Catch::Matchers::Contains(part_));                    \
  } while (false)

#define CHECK_BRUSH_ERROR(text, ...)                                                  \
  CHECK_READER_ERROR(parseBrush(text, "brush.json"), ExitCode::kDataError, "brush.json", \
                     __VA_ARGS__)
#define CHECK_TRAJ_ERROR(text, ...) \
  CHECK_READER_ERROR(parseTrajectory(text, "t.csv"), ExitCode::kDataError, "t.csv", __VA_ARGS__)

namespace bristle::testing {

// A small valid brush that uses every optional block.
inline const char* const kBrush = R"({
  "format": "bristle-brush/1",
  "name": "test",
  "description": "two spines",
  "spines": [
    {"root_mm": [0, 0, 0], "segment_lengths_mm": [5, 4], "stiffness_nmm_per_rad": [8, 6],
     "damping_nmm": [0.01, 0.02], "rest_angles_rad": [[0, 0], [0.1, -0.1]],
     "width_mm": [2, 1.5, 0.5]},
    {"root_mm": [1, 0, -0.5], "segment_lengths_mm": [5, 4], "stiffness_nmm_per_rad": [8, 6],
     "width_mm": [2, 1.5, 0]}
  ],
  "friction": {"mu_static": 0.5, "mu_kinetic": 0.4,
               "anisotropy": {"strength": 0.3, "exponent": 3}},
  "paint": {"capacity": 1.5}
})";

// A valid trajectory: line 1 format, line 2 header, lines 3-5 samples.
inline const char* const kTraj =
    "# bristle-trajectory/1\n"
    "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n"
    "0,0,0,10,1,0,0,0\n"
    "0.5,10,0,10,1,0,0,0\n"
    "1,20,0,10,1,0,0,0\n";

}  // namespace bristle::testing

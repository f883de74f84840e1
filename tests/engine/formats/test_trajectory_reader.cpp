// The trajectory reader (`bristle-trajectory/1` CSV,
// engine/formats/trajectory_reader.h): good files read with their poses, and
// every bad input refused with the sysexits code of docs/design.md ("Exit
// codes") and a one-line message that names the file, the line and column and
// the broken rule.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/base/json_reader.h"
#include "engine/base/spelling.h"
#include "engine/base/text_file.h"
#include "engine/model/trajectory.h"
#include "temp_dir.h"
#include "tests/engine/formats/reader_checks.h"

using namespace bristle;
using bristle::testing::Caught;
using bristle::testing::catchError;
using bristle::testing::kBrush;
using bristle::testing::kSourceDir;
using bristle::testing::kTraj;
using bristle::testing::TempDir;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

namespace fs = std::filesystem;

// "# bristle-trajectory/1", the header on line 2, then the rows from line 3.
std::string traj(const std::string& header, const std::vector<std::string>& rows) {
  std::string text = "# bristle-trajectory/1\n" + header + "\n";
  for (const std::string& r : rows) text += r + "\n";
  return text;
}
const std::string kHeader = "t_s,x_mm,y_mm,z_mm,qw,qx,qy,qz";

// Quaternions in the CSVs below carry 8 decimals; the angles they give are
// exact to ~1e-8 rad.
constexpr double kAngleTolRad = 1e-7;
constexpr double kTolMm = 1e-12;  // lerp of small integers is exact to rounding

}  // namespace

// ---------------------------------------------------------------- trajectory: good input

TEST_CASE("every trajectory in scenes/trajectories parses", "[readers]") {
  int count = 0;
  // With scenes/trajectories/depth/, the same strokes in press depths.
  for (const auto& entry : fs::recursive_directory_iterator(kSourceDir / "scenes/trajectories")) {
    if (entry.path().extension() != ".csv") continue;
    ++count;
    INFO(entry.path().string());
    const Trajectory t = loadTrajectory(entry.path().string());
    REQUIRE(t.samples.size() >= 2);
    CHECK(t.samples.front().line > 1);
    for (size_t i = 0; i < t.samples.size(); ++i) {
      CHECK(t.samples[i].pose.rotation.norm() == Approx(1.0).epsilon(1e-12));
      if (i > 0) CHECK(t.samples[i].t_s > t.samples[i - 1].t_s);
    }
  }
  CHECK(count >= 3);
}

TEST_CASE("comments, blank lines, CRLF and spaces around cells are allowed", "[readers]") {
  const std::string text =
      "# bristle-trajectory/1\r\n"   // 1
      "\r\n"                         // 2
      "# made by hand\r\n"           // 3
      "t_s, x_mm ,y_mm,z_mm,qw,qx,qy,qz\r\n"  // 4
      "   # an indented comment\r\n"          // 5
      "0,0,0,10,1,0,0,0\r\n"                  // 6
      "\r\n"                                  // 7
      "\t\r\n"                                // 8
      "# between samples\r\n"                 // 9
      " 0.5 , 10 ,0,10, 1 ,0,0,0\r\n"         // 10
      "# trailing comment";                   // 11, no final newline
  const Trajectory t = parseTrajectory(text, "t.csv");
  REQUIRE(t.samples.size() == 2);
  CHECK(t.samples[0].line == 6);
  CHECK(t.samples[1].line == 10);
  CHECK(t.samples[1].t_s == 0.5);
  CHECK(t.samples[1].pose.position_mm == Eigen::Vector3d(10, 0, 10));
  CHECK(t.startTime() == 0.0);
  CHECK(t.endTime() == 0.5);
}

TEST_CASE("quaternions are normalised on read", "[readers]") {
  const Trajectory t = parseTrajectory(traj(kHeader, {"0,0,0,0,2,0,0,0", "1,0,0,0,1,1,0,0",
                                                      "2,0,0,0,0.001,0,0,0",
                                                      "3,0,0,0,0,0,-3,4"}),
                                       "t.csv");
  REQUIRE(t.samples.size() == 4);
  for (const TrajectorySample& s : t.samples) CHECK(s.pose.rotation.norm() == Approx(1.0));
  CHECK(t.samples[0].pose.rotation.w() == Approx(1.0));
  CHECK(t.samples[1].pose.rotation.w() == Approx(std::sqrt(0.5)));
  CHECK(t.samples[1].pose.rotation.x() == Approx(std::sqrt(0.5)));
  CHECK(t.samples[2].pose.rotation.w() == Approx(1.0));  // tiny but not near zero
  CHECK(t.samples[3].pose.rotation.y() == Approx(-0.6));
  CHECK(t.samples[3].pose.rotation.z() == Approx(0.8));
}

TEST_CASE("optional columns buttons and fx_n,fy_n,fz_n parse, in any column order",
          "[readers]") {
  const Trajectory plain = parseTrajectory(kTraj, "t.csv");
  CHECK(plain.samples[1].buttons == 0);
  CHECK_FALSE(plain.samples[1].force_n.has_value());

  const Trajectory rec = parseTrajectory(
      traj(kHeader + ",buttons,fx_n,fy_n,fz_n",
           {"0,0,0,10,1,0,0,0,0,0,0,0", "0.001,0.5,0,9.5,1,0,0,0,3,0.1,-0.2,1.5"}),
      "t.csv");
  REQUIRE(rec.samples.size() == 2);
  CHECK(rec.samples[1].buttons == 3);
  REQUIRE(rec.samples[1].force_n.has_value());
  CHECK(*rec.samples[1].force_n == Eigen::Vector3d(0.1, -0.2, 1.5));

  const Trajectory shuffled = parseTrajectory(
      traj("fz_n,qz,buttons,qy,z_mm,fx_n,qx,y_mm,t_s,qw,fy_n,x_mm",
           {"1,0,1,0,3,4,0,2,0,1,5,1", "1,0,65535,0,6,4,0,5,2,1,5,4"}),
      "t.csv");
  REQUIRE(shuffled.samples.size() == 2);
  CHECK(shuffled.samples[1].t_s == 2.0);
  CHECK(shuffled.samples[1].pose.position_mm == Eigen::Vector3d(4, 5, 6));
  CHECK(shuffled.samples[1].buttons == 65535);
  CHECK(*shuffled.samples[0].force_n == Eigen::Vector3d(4, 5, 1));
}

TEST_CASE("poseAt lerps position, slerps rotation and clamps outside the span", "[readers]") {
  // Start upright at (0,0,10); end 1 s later at (20,0,10) turned 90 deg about z.
  const Trajectory t = parseTrajectory(
      traj(kHeader, {"0,0,0,10,1,0,0,0", "1,20,0,10,0.70710678,0,0,0.70710678",
                     "3,20,40,0,0.70710678,0,0,0.70710678"}),
      "t.csv");
  const Eigen::Quaterniond start = t.samples[0].pose.rotation;
  const Eigen::Quaterniond end = t.samples[1].pose.rotation;
  const double quarter_turn = std::numbers::pi / 2;

  const Pose mid = t.poseAt(0.5);
  CHECK((mid.position_mm - Eigen::Vector3d(10, 0, 10)).norm() < kTolMm);
  CHECK(rotationAngleRad(start, mid.rotation) == Approx(quarter_turn / 2).margin(kAngleTolRad));
  CHECK(rotationAngleRad(mid.rotation, end) == Approx(quarter_turn / 2).margin(kAngleTolRad));
  // The midpoint turns about z: it maps x to (cos 45, sin 45, 0).
  const Eigen::Vector3d x_mid = mid.rotation * Eigen::Vector3d::UnitX();
  CHECK((x_mid - Eigen::Vector3d(std::sqrt(0.5), std::sqrt(0.5), 0)).norm() < kAngleTolRad);

  const Pose q1 = t.poseAt(0.25);
  CHECK((q1.position_mm - Eigen::Vector3d(5, 0, 10)).norm() < kTolMm);
  CHECK(rotationAngleRad(start, q1.rotation) == Approx(quarter_turn / 4).margin(kAngleTolRad));

  // Second segment: pure translation over 2 s.
  const Pose p2 = t.poseAt(2.0);
  CHECK((p2.position_mm - Eigen::Vector3d(20, 20, 5)).norm() < kTolMm);
  CHECK(rotationAngleRad(p2.rotation, end) < kAngleTolRad);
  CHECK(t.segmentAt(0.5) == 0);
  CHECK(t.segmentAt(1.0) == 1);
  CHECK(t.segmentAt(2.0) == 1);

  // Clamped outside [0, 3] s, exact at the samples.
  CHECK(t.poseAt(-5).position_mm == t.samples[0].pose.position_mm);
  CHECK(rotationAngleRad(t.poseAt(-5).rotation, start) == 0);
  CHECK(t.poseAt(99).position_mm == t.samples[2].pose.position_mm);
  CHECK(t.poseAt(3).position_mm == Eigen::Vector3d(20, 40, 0));
  CHECK((t.poseAt(1).position_mm - Eigen::Vector3d(20, 0, 10)).norm() < kTolMm);
  CHECK(t.segmentAt(-5) == 0);
  CHECK(t.segmentAt(99) == 1);
}

TEST_CASE("poseAt slerps along the shortest path when the quaternion sign flips",
          "[readers]") {
  // q and -q are the same rotation; the midpoint must still be 45 deg, not 135.
  const Trajectory t = parseTrajectory(
      traj(kHeader, {"0,0,0,0,1,0,0,0", "1,0,0,0,-0.70710678,0,0,-0.70710678"}), "t.csv");
  const Pose mid = t.poseAt(0.5);
  CHECK(rotationAngleRad(t.samples[0].pose.rotation, mid.rotation) ==
        Approx(std::numbers::pi / 4).margin(kAngleTolRad));
}

// ---------------------------------------------------------------- trajectory: bad input

TEST_CASE("trajectory format line: missing or unknown version is 65 naming it", "[readers]") {
  const std::string rows = "0,0,0,10,1,0,0,0\n1,0,0,10,1,0,0,0\n";
  CHECK_TRAJ_ERROR(kHeader + "\n" + rows, "t.csv: line 1",
                   "first line must be '# bristle-trajectory/1'");
  CHECK_TRAJ_ERROR("# bristle-trajectory/2\n" + kHeader + "\n" + rows, "t.csv: line 1",
                   "unknown format version 'bristle-trajectory/2'");
  CHECK_TRAJ_ERROR("# bristle-trajectory/10\n" + kHeader + "\n" + rows, "line 1",
                   "'bristle-trajectory/10'");
  CHECK_TRAJ_ERROR("# a comment first\n# bristle-trajectory/1\n" + kHeader + "\n" + rows,
                   "line 1", "bristle-trajectory/1");
  CHECK_TRAJ_ERROR("#bristle-trajectory/1\n" + kHeader + "\n" + rows, "line 1");
  CHECK_TRAJ_ERROR("", "t.csv: line 1", "bristle-trajectory/1");
  CHECK_TRAJ_ERROR("# bristle-trajectory/1\n", "missing header");
  CHECK_TRAJ_ERROR("# bristle-trajectory/1\n# only comments\n\n", "missing header");
}

TEST_CASE("trajectory columns separated by semicolons or tabs are 65 naming the separator",
          "[readers]") {
  const std::vector<std::string> rows = {"0,10,0,10,1,0,0,0", "1,10,0,10,1,0,0,0"};
  CHECK_TRAJ_ERROR(traj("t_s;x_mm;y_mm;z_mm;qw;qx;qy;qz", rows),
                   "t.csv: line 2: columns are separated by ';'; bristle trajectories use ','");
  CHECK_TRAJ_ERROR(traj("t_s\tx_mm\ty_mm\tz_mm\tqw\tqx\tqy\tqz", rows),
                   "t.csv: line 2: columns are separated by tabs; bristle trajectories use ','");
  CHECK_TRAJ_ERROR(traj("t_s x_mm y_mm z_mm qw qx qy qz", rows),
                   "t.csv: line 2: columns are separated by spaces; bristle trajectories use ','");
  // A data line in another separator, under a header in ','.
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,10,0,10,1,0,0,0", "1;10;0;10;1;0;0;0"}),
                   "t.csv: line 4: columns are separated by ';'; bristle trajectories use ','");
  // Spaces after the commas are padding, and a header of unknown words keeps
  // its own message.
  CHECK(parseTrajectory(traj("t_s, x_mm, y_mm, z_mm, qw, qx, qy, qz", rows), "t.csv")
            .samples.size() == 2);
  CHECK_TRAJ_ERROR(traj("time;x;y", rows), "t.csv: line 2, column 1 (time;x;y): unknown column");
}

TEST_CASE("trajectory header: unknown, missing, duplicate columns are 65", "[readers]") {
  const std::vector<std::string> rows = {"0,0,0,10,1,0,0,0", "1,0,0,10,1,0,0,0"};
  CHECK_TRAJ_ERROR(traj("t_s,x_mm,y_mm,z_mm,w_mm,qw,qx,qy,qz", rows),
                   "t.csv: line 2, column 5 (w_mm)", "unknown column 'w_mm'");
  CHECK_TRAJ_ERROR(traj("T_s,x_mm,y_mm,z_mm,qw,qx,qy,qz", rows), "line 2, column 1",
                   "unknown column 'T_s'");
  CHECK_TRAJ_ERROR(traj(kHeader + ",", rows), "line 2, column 9", "unknown column ''");
  CHECK_TRAJ_ERROR(traj("t_s,x_mm,y_mm,z_mm,qw,qx,qy", rows), "t.csv: line 2",
                   "required column 'qz'");
  CHECK_TRAJ_ERROR(traj("x_mm,y_mm,z_mm,qw,qx,qy,qz", rows), "line 2", "'t_s'");
  CHECK_TRAJ_ERROR(traj(kHeader + ",x_mm", rows), "line 2, column 9 (x_mm)",
                   "duplicate column");
  CHECK_TRAJ_ERROR(traj(kHeader + ",buttons,buttons", rows), "line 2, column 10 (buttons)",
                   "duplicate column");
}

TEST_CASE("trajectory force columns come all three or none", "[readers]") {
  const std::vector<std::string> rows = {"0,0,0,10,1,0,0,0,0", "1,0,0,10,1,0,0,0,0"};
  CHECK_TRAJ_ERROR(traj(kHeader + ",fx_n", rows), "line 2", "fx_n,fy_n,fz_n");
  CHECK_TRAJ_ERROR(traj(kHeader + ",fx_n,fz_n", {"0,0,0,10,1,0,0,0,0,0", "1,0,0,10,1,0,0,0,0,0"}),
                   "line 2", "all three or none");
}

TEST_CASE("malformed CSV cells are 65 naming line and column", "[readers]") {
  auto bad = [](const std::string& row4) {
    return traj(kHeader, {"0,0,0,10,1,0,0,0", row4, "1,20,0,10,1,0,0,0"});
  };
  CHECK_TRAJ_ERROR(bad("0.5,10,abc,10,1,0,0,0"), "t.csv: line 4, column 3 (y_mm)",
                   "'abc' is not a number");
  CHECK_TRAJ_ERROR(bad("0.5,10,,10,1,0,0,0"), "line 4, column 3 (y_mm)", "is not a number");
  CHECK_TRAJ_ERROR(bad("0.5,10,0,1 0,1,0,0,0"), "line 4, column 4 (z_mm)", "'1 0'");
  CHECK_TRAJ_ERROR(bad("0.5,10,0,10,1,0,0,0x1"), "line 4, column 8 (qz)", "is not a number");
  CHECK_TRAJ_ERROR(bad("0.5s,10,0,10,1,0,0,0"), "line 4, column 1 (t_s)", "'0.5s'");
  // A ',' inside quotes is the cell's (engine/base/csv.h): one cell, not a number.
  CHECK_TRAJ_ERROR(bad("\"0,5\",10,0,10,1,0,0,0"), "t.csv: line 4, column 1 (t_s)",
                   "'0,5' is not a number");
  CHECK_TRAJ_ERROR(bad("0.5,+-10,0,10,1,0,0,0"), "line 4, column 2 (x_mm)",
                   "'+-10' is not a number");
}

TEST_CASE("trajectory cells are read as every bristle CSV reads them", "[readers]") {
  // The trajectory goes through the one CSV reading of engine/base/csv.h, as
  // the pen recordings do: quoted cells and header names (as a spreadsheet
  // quotes them), a leading '+', and a value below the smallest double (0).
  const Trajectory t = parseTrajectory(
      traj("\"t_s\",x_mm,\"y_mm\",z_mm,qw,qx,qy,qz",
           {"0,0,0,10,1,0,0,0", "\"0.5\",+10,1e-400,\"10\",1,0,0,0", "1,20,0,10,1,0,0,0"}),
      "t.csv");
  REQUIRE(t.samples.size() == 3);
  CHECK(t.samples[1].t_s == 0.5);
  CHECK(t.samples[1].pose.position_mm.x() == 10);
  CHECK(t.samples[1].pose.position_mm.y() == 0);
  CHECK(t.samples[1].pose.position_mm.z() == 10);
  // Messages name the cell without its quotes, as the header names it.
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "\"later\",0,0,10,1,0,0,0"}),
                   "t.csv: line 4, column 1 (t_s)", "'later' is not a number");
  CHECK_TRAJ_ERROR(traj(kHeader + ",\"speed\"", {"0,0,0,10,1,0,0,0,1", "1,0,0,10,1,0,0,0,1"}),
                   "t.csv: line 2, column 9 (speed)", "unknown column 'speed'");
}

TEST_CASE("nan, inf and out-of-range CSV cells are 65 naming line and column", "[readers]") {
  auto bad = [](const std::string& row4) {
    return traj(kHeader, {"0,0,0,10,1,0,0,0", row4, "1,20,0,10,1,0,0,0"});
  };
  for (const char* cell : {"nan", "NaN", "-nan", "inf", "-inf", "Infinity", "nan(0x1)"}) {
    INFO(cell);
    CHECK_TRAJ_ERROR(bad(std::string("0.5,10,0,10,1,") + cell + ",0,0"),
                     "line 4, column 6 (qx)", "'" + std::string(cell) + "': must be finite");
  }
  CHECK_TRAJ_ERROR(bad("0.5,1e999,0,10,1,0,0,0"), "line 4, column 2 (x_mm)", "'1e999'");
  CHECK_TRAJ_ERROR(bad("0.5,10,-1e999,10,1,0,0,0"), "line 4, column 3 (y_mm)", "'-1e999'");
  CHECK_TRAJ_ERROR(bad("inf,10,0,10,1,0,0,0"), "line 4, column 1 (t_s)", "must be finite");
  CHECK_TRAJ_ERROR(traj(kHeader + ",fx_n,fy_n,fz_n",
                        {"0,0,0,10,1,0,0,0,0,0,0", "1,0,0,10,1,0,0,0,0,nan,0"}),
                   "line 4, column 10 (fy_n)", "must be finite");
}

TEST_CASE("a row with the wrong number of fields is 65 naming line and column", "[readers]") {
  auto bad = [](const std::string& row4) {
    return traj(kHeader, {"0,0,0,10,1,0,0,0", row4, "1,20,0,10,1,0,0,0"});
  };
  CHECK_TRAJ_ERROR(bad("0.5,10,0,10,1,0,0"), "t.csv: line 4, column 8 (qz)",
                   "has 7 fields, the header has 8");
  CHECK_TRAJ_ERROR(bad("0.5"), "line 4, column 2 (x_mm)", "has 1 fields");
  CHECK_TRAJ_ERROR(bad("0.5,10,0,10,1,0,0,0,0"), "line 4, column 9", "has 9 fields");
  CHECK_TRAJ_ERROR(bad("0.5,10,0,10,1,0,0,0,"), "line 4, column 9", "has 9 fields");
}

TEST_CASE("time must increase strictly", "[readers]") {
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "0,1,0,10,1,0,0,0"}),
                   "t.csv: line 4, column 1 (t_s)", "increase strictly");
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "0.5,1,0,10,1,0,0,0",
                                  "0.25,2,0,10,1,0,0,0"}),
                   "line 5, column 1 (t_s)", "t_s = 0.25", "increase strictly");
  // Line numbers count comments and blank lines.
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "# note", "", "-1,1,0,10,1,0,0,0"}),
                   "line 6, column 1 (t_s)", "t_s = -1");
  // With t_s in another column the message names that column and its value.
  CHECK_TRAJ_ERROR(traj("x_mm,y_mm,z_mm,qw,qx,qy,qz,t_s",
                        {"9,0,10,1,0,0,0,0", "8,0,10,1,0,0,0,0.5", "7,0,10,1,0,0,0,0.5"}),
                   "line 5, column 8 (t_s)", "t_s = 0.5 is not after");
}

TEST_CASE("a near-zero quaternion is 65 naming the line", "[readers]") {
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "1,0,0,10,0,0,0,0"}), "t.csv: line 4",
                   "near-zero norm");
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1e-9,0,0,0", "1,0,0,10,1,0,0,0"}), "line 3",
                   "near-zero norm");
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "1,0,0,10,0,-1e-7,1e-7,0"}), "line 4",
                   "near-zero norm");
}

TEST_CASE("a trajectory needs at least 2 samples", "[readers]") {
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0"}), "t.csv: line 3",
                   "at least 2 samples");
  CHECK_TRAJ_ERROR(traj(kHeader, {}), "line 2", "at least 2 samples");
  CHECK_TRAJ_ERROR(traj(kHeader, {"0,0,0,10,1,0,0,0", "# a comment"}), "at least 2 samples");
}

TEST_CASE("buttons must be a non-negative integer bitmask", "[readers]") {
  auto withButtons = [](const std::string& b) {
    return traj(kHeader + ",buttons", {"0,0,0,10,1,0,0,0,0", "1,0,0,10,1,0,0,0," + b});
  };
  for (const char* b : {"1.5", "-1", "65536", "1e9", "0.001"}) {
    INFO(b);
    CHECK_TRAJ_ERROR(withButtons(b), "t.csv: line 4, column 9 (buttons)", "integer bitmask");
  }
  CHECK_TRAJ_ERROR(withButtons("x"), "line 4, column 9 (buttons)", "is not a number");
  CHECK_TRAJ_ERROR(withButtons(""), "line 4, column 9 (buttons)", "is not a number");
  CHECK(parseTrajectory(withButtons("5"), "t.csv").samples[1].buttons == 5);
  CHECK(parseTrajectory(withButtons("0"), "t.csv").samples[1].buttons == 0);
}

// ------------------------------------------- trajectory: heights relative to the paper

TEST_CASE("depth_mm in place of z_mm parses as press depth past first contact", "[readers]") {
  const std::string header = "t_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz";
  const Trajectory t =
      parseTrajectory(traj(header, {"0,1,2,-3,1,0,0,0", "1,1,2,4.5,1,0,0,0"}), "t.csv");
  CHECK(t.depth_column == 4);
  CHECK(t.needsBrush());
  REQUIRE(t.samples.size() == 2);
  CHECK(t.samples[0].depth_mm == -3);  // negative: hovering above first contact
  CHECK(t.samples[1].depth_mm == 4.5);
  // No height until a brush gives one (resolveDepths).
  CHECK(t.samples[1].pose.position_mm == Eigen::Vector3d(1, 2, 0));
  // In any column, with the optional columns.
  const Trajectory moved = parseTrajectory(
      traj("depth_mm,t_s,x_mm,y_mm,qw,qx,qy,qz,buttons", {"2,0,0,0,1,0,0,0,1", "3,1,0,0,1,0,0,0,0"}),
      "t.csv");
  CHECK(moved.depth_column == 1);
  CHECK(moved.samples[1].depth_mm == 3);
  // A file with z_mm needs no brush.
  CHECK(parseTrajectory(kTraj, "t.csv").depth_column == 0);
  CHECK_FALSE(parseTrajectory(kTraj, "t.csv").needsBrush());
}

TEST_CASE("the depth_mm example of docs/formats.md parses", "[readers]") {
  const std::string doc = readTextFile((kSourceDir / "docs/formats.md").string());
  const size_t section = doc.find("### Heights relative to the paper");
  REQUIRE(section != std::string::npos);
  const size_t start = doc.find('\n', doc.find("```", section)) + 1;
  const size_t end = doc.find("```", start);
  const Trajectory t = parseTrajectory(doc.substr(start, end - start), "formats.md");
  CHECK(t.depth_column == 4);
  CHECK(t.samples.size() == 4);
  CHECK(t.samples[1].depth_mm == 4);
}

TEST_CASE("depth_mm with z_mm, twice, non-finite or over the limit is 65 naming line and column",
          "[readers]") {
  const std::vector<std::string> rows = {"0,0,0,10,1,0,0,0,1", "1,0,0,10,1,0,0,0,1"};
  CHECK_TRAJ_ERROR(traj(kHeader + ",depth_mm", rows), "t.csv: line 2, column 9 (depth_mm)",
                   "z_mm and depth_mm", "give one");
  CHECK_TRAJ_ERROR(traj("t_s,x_mm,y_mm,depth_mm,z_mm,qw,qx,qy,qz", rows),
                   "t.csv: line 2, column 5 (z_mm)", "z_mm and depth_mm");
  CHECK_TRAJ_ERROR(traj("t_s,x_mm,y_mm,depth_mm,depth_mm,qx,qy,qz", rows),
                   "line 2, column 5 (depth_mm)", "duplicate column");
  // Neither: the missing height names both ways to give it.
  CHECK_TRAJ_ERROR(traj("t_s,x_mm,y_mm,qw,qx,qy,qz", {"0,0,0,1,0,0,0", "1,0,0,1,0,0,0"}),
                   "t.csv: line 2", "required column 'z_mm'", "depth_mm");
  const std::string header = "t_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz";
  auto bad = [&](const std::string& depth) {
    return traj(header, {"0,0,0,1,1,0,0,0", "0.5,0,0," + depth + ",1,0,0,0", "1,0,0,1,1,0,0,0"});
  };
  for (const char* cell : {"nan", "inf", "-inf"}) {
    INFO(cell);
    CHECK_TRAJ_ERROR(bad(cell), "t.csv: line 4, column 4 (depth_mm)", "must be finite");
  }
  CHECK_TRAJ_ERROR(bad("1e999"), "line 4, column 4 (depth_mm)", "outside the range of a double");
  CHECK_TRAJ_ERROR(bad("-200000"), "line 4, column 4 (depth_mm)", "limit of +-100000 mm");
  CHECK_TRAJ_ERROR(bad("deep"), "line 4, column 4 (depth_mm)", "is not a number");
}

#include "bristle/trajectory.h"

#include <cmath>
#include <memory>
#include <string>

#include "api/model.h"
#include "engine/base/text_file.h"
#include "engine/formats/trajectory_reader.h"
#include "input/import.h"

namespace bristle::api {

namespace {

// The name in messages of a trajectory built from arrays; its samples are
// numbered from 1 where a file's messages give the line.
constexpr const char* kArraysName = "Trajectory::fromArrays";

[[noreturn]] void badArgument(const std::string& argument, size_t i, const std::string& rule) {
  throw api::Error(ErrorCategory::kDataError, std::string(kArraysName) + ": " + argument + "[" +
                                                  std::to_string(i) + "]: " + rule);
}

// The rules a bristle-trajectory/1 file's cells meet (engine/model/trajectory.cpp),
// for one value of an array.
void checkValue(const std::string& argument, size_t i, double v, double limit,
                const char* limit_text) {
  if (!std::isfinite(v)) badArgument(argument, i, "must be finite");
  if (std::fabs(v) > limit) badArgument(argument, i, std::string("is outside the limit of ") + limit_text);
}

void checkSizes(size_t n, const char* argument, size_t size) {
  if (size != n)
    throw api::Error(ErrorCategory::kDataError,
                     std::string(kArraysName) + ": " + argument + " has " + std::to_string(size) +
                         " samples, t_s has " + std::to_string(n) + " (they must be equal)");
}

// One sample's time and rotation; the position is the caller's.
TrajectorySample sampleAt(const std::vector<double>& t_s,
                          const std::vector<std::array<double, 4>>& q_wxyz, size_t i) {
  checkValue("t_s", i, t_s[i], kMaxTimeS, "+-1e9 s");
  if (i > 0 && !(t_s[i] > t_s[i - 1]))
    badArgument("t_s", i, "is not after t_s[" + std::to_string(i - 1) +
                              "] (time must increase strictly)");
  const std::array<double, 4>& q = q_wxyz[i];
  for (double c : q)
    checkValue("quaternion_wxyz", i, c, kMaxQuaternionComponent,
               "+-1e6 (quaternions are normalised)");
  const Eigen::Quaterniond rotation(q[0], q[1], q[2], q[3]);
  // The file reader's rule (engine/model/trajectory.cpp): a norm this small
  // names no rotation.
  if (rotation.norm() < 1e-6) badArgument("quaternion_wxyz", i, "has near-zero norm");
  TrajectorySample s;
  s.t_s = t_s[i];
  s.line = static_cast<int>(i) + 1;
  s.pose.rotation = rotation.normalized();
  return s;
}

Trajectory::Model arraysModel(size_t n) {
  if (n < 2)
    throw api::Error(ErrorCategory::kDataError,
                     std::string(kArraysName) + ": t_s has " + std::to_string(n) +
                         " samples: a trajectory needs at least 2");
  Trajectory::Model m;
  m.trajectory.path = kArraysName;
  m.trajectory.samples.reserve(n);
  return m;
}

}  // namespace

Trajectory Trajectory::load(const std::string& path) {
  return translateErrors([&] {
    return Trajectory(std::make_shared<Model>(Model{loadTrajectory(path)}));
  });
}

Trajectory Trajectory::load(const std::string& path, const Brush& brush,
                            std::vector<std::string>* warnings) {
  return translateErrors([&] {
    const bristle::Brush& b = brush.model().brush;
    std::vector<std::string> notes;
    bristle::Trajectory t =
        input::loadTrajectoryOrRecording(readTextFile(path), path, b, b.name, &notes);
    if (warnings != nullptr) warnings->insert(warnings->end(), notes.begin(), notes.end());
    return Trajectory(std::make_shared<Model>(Model{std::move(t)}));
  });
}

Trajectory Trajectory::fromArrays(const std::vector<double>& t_s,
                                  const std::vector<std::array<double, 3>>& xyz_mm,
                                  const std::vector<std::array<double, 4>>& quaternion_wxyz) {
  checkSizes(t_s.size(), "xyz_mm", xyz_mm.size());
  checkSizes(t_s.size(), "quaternion_wxyz", quaternion_wxyz.size());
  Model m = arraysModel(t_s.size());
  for (size_t i = 0; i < t_s.size(); ++i) {
    for (double v : xyz_mm[i]) checkValue("xyz_mm", i, v, kMaxPositionMm, "+-100000 mm");
    TrajectorySample s = sampleAt(t_s, quaternion_wxyz, i);
    s.pose.position_mm = Eigen::Vector3d(xyz_mm[i][0], xyz_mm[i][1], xyz_mm[i][2]);
    m.trajectory.samples.push_back(std::move(s));
  }
  return Trajectory(std::make_shared<Model>(std::move(m)));
}

Trajectory Trajectory::fromArraysWithDepth(
    const std::vector<double>& t_s, const std::vector<std::array<double, 2>>& xy_mm,
    const std::vector<double>& depth_mm,
    const std::vector<std::array<double, 4>>& quaternion_wxyz) {
  checkSizes(t_s.size(), "xy_mm", xy_mm.size());
  checkSizes(t_s.size(), "depth_mm", depth_mm.size());
  checkSizes(t_s.size(), "quaternion_wxyz", quaternion_wxyz.size());
  Model m = arraysModel(t_s.size());
  m.trajectory.depth_column = 1;  // heights wait for a brush (resolveDepths)
  for (size_t i = 0; i < t_s.size(); ++i) {
    for (double v : xy_mm[i]) checkValue("xy_mm", i, v, kMaxPositionMm, "+-100000 mm");
    checkValue("depth_mm", i, depth_mm[i], kMaxPositionMm, "+-100000 mm");
    TrajectorySample s = sampleAt(t_s, quaternion_wxyz, i);
    s.pose.position_mm = Eigen::Vector3d(xy_mm[i][0], xy_mm[i][1], 0);
    s.depth_mm = depth_mm[i];
    m.trajectory.samples.push_back(std::move(s));
  }
  return Trajectory(std::make_shared<Model>(std::move(m)));
}

std::size_t Trajectory::sampleCount() const { return model_->trajectory.samples.size(); }
double Trajectory::startS() const { return model_->trajectory.startTime(); }
double Trajectory::endS() const { return model_->trajectory.endTime(); }
bool Trajectory::hasDepths() const { return model_->trajectory.needsBrush(); }

}  // namespace bristle::api

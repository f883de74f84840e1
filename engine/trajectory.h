#pragma once
// Recorded 6-DOF stylus trajectory, CSV format `bristle-trajectory/1`
// (ARCHITECTURE.md, "Formats"), and pose interpolation at any time.

#include <optional>
#include <string>
#include <vector>

#include "engine/pose.h"

namespace bristle {

struct TrajectorySample {
  double t_s = 0;
  Pose pose;
  int buttons = 0;                                    // bitmask, 0 when absent
  std::optional<Eigen::Vector3d> force_n;             // recorded sessions only
  int line = 0;                                       // 1-based line in the file
};

struct Trajectory {
  std::string path;  // for messages
  std::vector<TrajectorySample> samples;

  double startTime() const { return samples.front().t_s; }
  double endTime() const { return samples.back().t_s; }
  // Pose at time t (clamped to the recorded span): lerp + slerp between samples.
  Pose poseAt(double t_s) const;
  // Index k of the segment [samples[k], samples[k+1]] that contains t.
  size_t segmentAt(double t_s) const;
};

// Parses and validates a trajectory; throws bristle::Error (66 missing, 65 bad
// data naming the line and column).
Trajectory loadTrajectory(const std::string& path);
Trajectory parseTrajectory(const std::string& text, const std::string& path_for_messages);

}  // namespace bristle

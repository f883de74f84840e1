#pragma once
// The reader of a trajectory file, CSV format `bristle-trajectory/1`
// (docs/formats.md, "Trajectory"): each cell checked against its column's
// rule and the limits of engine/model/trajectory.h, each problem a one-line
// error naming the line and column (docs/errors.md).

#include <string>

#include "engine/model/trajectory.h"

namespace bristle {

// Parses and validates a trajectory; throws bristle::Error (66 missing, 65 bad
// data naming the line and column).
Trajectory loadTrajectory(const std::string& path);
Trajectory parseTrajectory(const std::string& text, const std::string& path_for_messages);

}  // namespace bristle

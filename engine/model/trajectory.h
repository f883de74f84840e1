#pragma once
// Recorded 6-DOF stylus trajectory, the model of the CSV format
// `bristle-trajectory/1` (docs/formats.md, "Trajectory"; its reader is
// engine/formats/trajectory_reader.h), and pose interpolation at any time.

#include <optional>
#include <limits>
#include <string>
#include <vector>

#include "engine/model/pose.h"

namespace bristle {

// Limits on what a trajectory may say (docs/errors.md, "Limits"), checked as it
// is read. Positions: a canvas is at most 16384 px a side, 32.8 m at the
// coarsest 0.5 px/mm, so a handle 100 m from the origin can never be drawn,
// while squared distances (1e10 mm^2) keep full double precision.
inline constexpr double kMaxPositionMm = 1e5;
// Times: 31 years; a millisecond still has 7 significant digits to spare.
inline constexpr double kMaxTimeS = 1e9;
// Quaternion components: normalised on read, so any scale is the same rotation,
// but the norm must not overflow (1e200) or vanish.
inline constexpr double kMaxQuaternionComponent = 1e6;

struct TrajectorySample {
  double t_s = 0;
  Pose pose;
  int buttons = 0;                                    // bitmask, 0 when absent
  std::optional<Eigen::Vector3d> force_n;             // recorded sessions only
  int line = 0;                                       // 1-based line in the file
  // A file with a depth_mm column: the press depth past the brush's first
  // contact (mm; positive into the paper, negative above it). Its
  // pose.position_mm.z() is 0 until resolveDepths (engine/geometry/first_contact.h)
  // gives the ferrule's height for a brush.
  double depth_mm = 0;
};

struct Trajectory {
  std::string path;  // for messages
  int t_column = 1;  // 1-based column of t_s in the file, for messages
  std::vector<TrajectorySample> samples;
  // 1-based column of depth_mm when the file gives heights as press depth past
  // first contact (docs/formats.md, "Heights relative to the paper"), 0 when it
  // gives the ferrule's z_mm.
  int depth_column = 0;
  // Whether resolveDepths has turned the depths into a brush's ferrule heights.
  bool depths_resolved = false;

  // Whether the poses still wait for a brush: depths not yet resolved.
  bool needsBrush() const { return depth_column != 0 && !depths_resolved; }

  double startTime() const { return samples.front().t_s; }
  double endTime() const { return samples.back().t_s; }
  // Pose at time t (clamped to the recorded span): lerp + slerp between samples.
  Pose poseAt(double t_s) const;
  // Index k of the segment [samples[k], samples[k+1]] that contains t.
  size_t segmentAt(double t_s) const;
  // Whether some sample holds the handle within reach_mm of the canvas, the
  // rectangle [0, width_mm] x [0, height_mm] at z = 0 (unbounded by default):
  // no hair reaches further from the ferrule than its brush's reach, so a
  // trajectory that never does cannot touch the paper.
  bool comesWithinReach(double reach_mm,
                        double width_mm = std::numeric_limits<double>::infinity(),
                        double height_mm = std::numeric_limits<double>::infinity()) const;
};

}  // namespace bristle

#pragma once
// From pen samples to a handle trajectory (docs/input.md, "The mapping"):
// positions to canvas millimetres, pressure to a press depth past the brush's
// first contact (a trajectory's depth_mm column, so that it suits every brush),
// tilt and twist to the handle's rotation.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "engine/model/trajectory.h"
#include "input/recording.h"

namespace bristle::input {

struct MappingOptions {
  // Press depth at pressure 1 (mm past first contact); the caller resolves it
  // from --max-depth-mm, or --max-depth-frac times the brush's hair length.
  double max_depth_mm = 8;
  double pressure_gamma = 1;  // depth = max_depth_mm * pressure^gamma
  double hover_mm = 2;        // pen up: this far above first contact
  double mm_per_unit = 0;     // 0: the recording's own (Recording::mm_per_unit)
  bool flip_y = true;         // the sources' y points down; the canvas's up
  double margin_mm = 10;      // around the recording's bounding box
  double smooth_ms = 0;       // moving-average window (0: none)
  double lead_s = 0.1;        // hover before a first / after a last pen-down sample
  // For samples without tilt or twist (MyPaint events, SVG, a CSV without
  // those columns): a constant pen tilt (tiltX, tiltY in degrees, in the
  // source's axes) and twist (degrees clockwise seen from above).
  double tilt_x_deg = 0, tilt_y_deg = 0, twist_deg = 0;
};

// The depth past first contact of a sample: max_depth * pressure^gamma when
// the pen is down (0 at the lightest touch), -hover when it is up.
double pressureToDepthMm(double pressure, bool down, const MappingOptions& options);

// The handle's rotation (brush frame to canvas frame) for a pen whose axis,
// tip to top, is `axis_canvas` in the canvas frame, twisted clockwise (seen
// from above) by twist_deg about it: the shortest arc taking the brush's +z
// (its handle) to the axis, then the twist. Upright and untwisted is the
// identity: the brush's width axis (x) along the canvas's x.
Eigen::Quaterniond handleRotation(const Eigen::Vector3d& axis_canvas, double twist_deg);

// Where the recording lands on the canvas: its bounding box (all samples, pen
// up or down) scaled to mm with its lower-left corner at (margin, margin).
struct Placement {
  double x_min = 0, y_min = 0, y_max = 0;
  double mm_per_unit = 1;
  bool flip_y = true;
  double margin_mm = 0;
  double width_mm = 0, height_mm = 0;  // the box plus a margin on each side
  Eigen::Vector2d toMm(double x, double y) const;
};
Placement placementOf(const Recording& rec, const MappingOptions& options);

// The samples smoothed by a centred moving average of window smooth_ms over
// x, y, pressure, the pen's axis and twist, within each run of pen-down or
// pen-up samples (never across a touch or a lift); as they are when 0.
std::vector<PenSample> smoothed(const std::vector<PenSample>& samples, double smooth_ms);

// The whole recording as one trajectory with a depth_mm column (pen-up
// samples hover), starting at t = 0, with a hover sample lead_s before a
// first sample that is down and after a last one. Each sample's `line` is the
// source's. Throws Error(kDataError) naming the source line when a position
// lands beyond the trajectory limit (kMaxPositionMm).
Trajectory toTrajectory(const Recording& rec, const MappingOptions& options);

// Each pen-down run as its own trajectory (a scene's strokes), on the same
// placement and clock as toTrajectory's: the pen-up sample before and after
// the run when there is one (hovering), else a hover sample lead_s away.
std::vector<Trajectory> toStrokeTrajectories(const Recording& rec, const MappingOptions& options);

// The comment lines (without '# ') that say how the trajectory was made: the
// source, units, placement, depth and tilt rules (`depth_rule` from the
// caller: how max_depth_mm was chosen).
std::vector<std::string> mappingNotes(const Recording& rec, const MappingOptions& options,
                                      const std::string& depth_rule);

// A trajectory with depth_mm as bristle-trajectory/1 text: the format line,
// the notes as comments, then t_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz,buttons
// (buttons bit 0: the pen is down).
std::string trajectoryCsv(const Trajectory& trajectory, const std::vector<std::string>& notes);

}  // namespace bristle::input

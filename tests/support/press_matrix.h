#pragma once
// The press matrix (tests and bench/bench_matrix.cpp): a library brush pressed
// straight down to a fraction of its hair length, then pulled along +x or lifted
// again, at a handle tilt -- and what the simulation made of it (failed steps,
// time per step). Only the public simulation API is used, so the matrix measures
// any implementation of engine/dynamics/simulation.h.
//
// Tilt convention: the handle is rotated by `tilt_deg` about the world +y axis
// (Eigen::AngleAxisd(tilt, UnitY)). The brush's +z (towards the handle) then
// leans towards +x and its hairs (-z) towards -x: a positive tilt leans the
// handle forwards into a pull along +x, so the hairs trail behind it.

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/model/trajectory.h"

namespace bristle::testsupport {

// Rotation of the handle for a tilt in degrees (convention above).
Eigen::Quaterniond tiltRotation(double tilt_deg);

// Lowest z (world, mm) of the brush at rest with its handle at `handle`: every
// spine's joints, roots included, from Simulation::reset (no solve).
double restLowestZMm(const Brush& brush, const Pose& handle);

// The handle height (z of the pose, mm) at which the brush at rest, with this
// orientation, first touches z = 0 with a spine joint: where the solver's
// contact (eq. 5) begins. The hair bundles around the spines reach lower and
// touch first (bristle::firstContactHeightMm, engine/geometry/first_contact.h, what a
// trajectory's depth_mm counts from); the press matrix counts from the spines.
double spineContactHeightMm(const Brush& brush, const Eigen::Quaterniond& tilt);

// The longest spine of the brush (mm): what a press fraction is a fraction of.
double hairLengthMm(const Brush& brush);

enum class CaseKind { kPull, kPressLift };
const char* toString(CaseKind kind);

struct Case {
  std::string brush_path;
  double press_fraction = 0;  // of the hair length, past first contact (0..0.8)
  double tilt_deg = 0;        // 0, 30, 60 (convention above)
  double speed_mm_s = 50;     // pull speed (10..200); unused by press_lift
  CaseKind kind = CaseKind::kPull;
};

// "pull f0.40 t30 v50" / "press_lift f0.40 t30".
std::string describe(const Case& c);

// Timing of the trajectory (seconds) and its geometry (mm).
inline constexpr double kHoverMm = 2;        // start this far above first contact
inline constexpr double kDescendS = 0.3;     // hover -> pressed
inline constexpr double kPullMm = 30;        // along +x
inline constexpr double kHoldS = 0.2;        // press_lift: pressed and still
inline constexpr double kLiftS = 0.3;        // pressed -> clear
inline constexpr double kLiftClearMm = 6;    // clear = this far above first contact
inline constexpr double kAirHoldS = 0.1;     // still, in the air, at the end
inline constexpr double kMinRootZMm = 0.5;   // the ferrule stays at least this high

struct CaseTrajectory {
  Trajectory trajectory;
  double contact_height_mm = 0;  // handle z of first contact (spineContactHeightMm)
  double depth_mm = 0;           // handle z below first contact at the deepest
  double asked_depth_mm = 0;     // press_fraction * hair length
  bool clamped = false;          // depth < asked: the ferrule would have hit the canvas
  double contact_start_s = 0, contact_end_s = 0;  // pressed at .. lift starts
  double end_x_mm = 0;           // handle x at the end of the contact
};

// Hover 2 mm above first contact at x = 0, descend in 0.3 s to the press depth,
// pull 30 mm along +x at the case's speed (pull) or hold 0.2 s (press_lift),
// lift in 0.3 s to 6 mm above first contact, hold 0.1 s. The depth is clamped so
// the lowest spine root stays >= 0.5 mm above the canvas.
CaseTrajectory makeCaseTrajectoryDetailed(const Brush& brush, const Case& c);
Trajectory makeCaseTrajectory(const Brush& brush, const Case& c);

struct CaseResult {
  int steps = 0;
  int failed_steps = 0;
  int failed_spine_solves = 0;
  int longest_failed_run = 0;  // consecutive steps with a failed spine solve
  int fallback_solves = 0;     // spine solves the fallback solver rescued
  double wall_s = 0;           // all steps (not the set-up)
  double s_per_step = 0;
  bool clamped = false;
  double depth_mm = 0;
  std::vector<double> step_s;  // wall time of every step, in order
  // What the steps cost: solver iterations (SimStats::iterations), solves redone
  // after a stick -> slip, pieces of steps redone in halves, and spine-steps
  // with some joint on the canvas (the solves a step could not skip).
  long iterations = 0;
  int resolves = 0, split_steps = 0;
  long contact_spine_steps = 0;
};

// Runs the simulation over planStepTimes with default SimOptions and `solver`
// "ipopt" or "slsqp". With `fallback`, the other one rescues a spine whose solve
// failed, as bristle render does; without, a failure stays a failure. Throws
// bristle::Error(kUsage) for another solver name.
CaseResult runCase(const Brush& brush, const Case& c, const std::string& solver,
                   bool fallback = true);

}  // namespace bristle::testsupport

#pragma once
// Small builders shared by the engine tests.

#include <filesystem>
#include <string>
#include <vector>

#include <algorithm>
#include <cmath>

#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/dynamics/simulation.h"
#include "engine/mechanics/spine_kinematics.h"
#include "engine/model/trajectory.h"
#include "tests/support/build_paths.h"

namespace bristle::testing {

// The source tree: shipped brushes, scenes and trajectories the tests read.
inline const std::filesystem::path kSourceDir = BRISTLE_SOURCE_DIR;

// What a call threw, if it threw a bristle::Error: for checking exit codes and
// messages of bad input.
struct Caught {
  bool thrown = false;
  int code = 0;
  std::string message;
};

template <class F>
inline Caught catchError(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return {true, static_cast<int>(e.code()), e.what()};
  }
  return {};
}


// A spine hanging from the ferrule centre, with the given per-joint data.
inline SpineSpec makeSpine(std::vector<double> lengths_mm, std::vector<double> k_nmm,
                           double damping_nmm = 0, Eigen::Vector3d root = Eigen::Vector3d::Zero()) {
  SpineSpec s;
  s.root_mm = root;
  s.segment_lengths_mm = lengths_mm;
  s.stiffness_nmm_per_rad = k_nmm;
  s.damping_nmm.assign(lengths_mm.size(), damping_nmm);
  s.rest_angles_rad.assign(lengths_mm.size(), Eigen::Vector2d::Zero());
  s.width_mm.assign(lengths_mm.size() + 1, 1.0);
  return s;
}

inline Brush makeBrush(std::vector<SpineSpec> spines, double mu_s, double mu_k) {
  Brush b;
  b.name = "test";
  b.path = "test-brush";
  b.spines = std::move(spines);
  b.friction.mu_static = mu_s;
  b.friction.mu_kinetic = mu_k;
  return b;
}

// The farthest any joint of a brush is from its place in another state (mm).
inline double maxJointDistanceMm(const BrushState& a, const BrushState& b) {
  double d = 0;
  for (size_t s = 0; s < a.spines.size(); ++s)
    for (size_t j = 0; j < a.spines[s].joints_mm.size(); ++j)
      d = std::max(d, (a.spines[s].joints_mm[j] - b.spines[s].joints_mm[j]).norm());
  return d;
}

inline Pose poseAt(double x, double y, double z) {
  Pose p;
  p.position_mm = Eigen::Vector3d(x, y, z);
  return p;
}

// Moves the handle in a straight line from a to b in steps of at most step_mm,
// 0.01 s apart.
inline void moveHandle(Simulation& sim, const Pose& a, const Pose& b, double* t,
                       double step_mm = 0.1) {
  const double dist = (b.position_mm - a.position_mm).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(dist / step_mm)));
  for (int i = 1; i <= n; ++i) sim.step(interpolatePose(a, b, double(i) / n), *t += 0.01);
}

// eq. 10's (theta, phi) of joint k's axis relative to its parent: the
// simulation's own angles are increments from a re-based rotation.
inline Eigen::Vector2d jointAngles(const SpineState& s, int k) {
  return eulerAnglesOfAxis(s.rot[k]);
}

// The bend of joint k from its rest axis (rad).
inline double bendFromRest(const SpineSpec& spec, const SpineState& s, int k) {
  const Eigen::Vector3d a = s.rot[k].col(2);
  const Eigen::Vector3d a0 = restRotations(spec)[k].col(2);
  return std::atan2(a0.cross(a).norm(), a0.dot(a));
}

}  // namespace bristle::testing

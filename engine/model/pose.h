#pragma once
// A handle pose maps the brush frame to the world (canvas) frame
// (docs/design.md, "Frames and units"): identity rotation holds the brush
// vertically above the canvas with its hairs hanging along -z.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace bristle {

struct Pose {
  Eigen::Vector3d position_mm = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();

  Eigen::Vector3d apply(const Eigen::Vector3d& p_brush_mm) const {
    return position_mm + rotation * p_brush_mm;
  }
};

// Position lerp and shortest-path quaternion slerp, u in [0, 1].
inline Pose interpolatePose(const Pose& a, const Pose& b, double u) {
  Pose p;
  p.position_mm = (1.0 - u) * a.position_mm + u * b.position_mm;
  p.rotation = a.rotation.slerp(u, b.rotation).normalized();
  return p;
}

// Angle in radians of the rotation that takes a to b (0..pi).
inline double rotationAngleRad(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

}  // namespace bristle

#include "engine/geometry/first_contact.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/geometry/brush_surface.h"
#include "engine/base/error.h"
#include "engine/geometry/spine_bundles.h"
#include "engine/mechanics/spine_kinematics.h"

namespace bristle {

FirstContact::FirstContact(const Brush& brush) : brush_(&brush) {
  for (const SpineSpec& spec : brush.spines) {
    std::vector<double> q(2 * spec.jointCount());
    for (int k = 0; k < spec.jointCount(); ++k) {
      q[2 * k] = spec.rest_angles_rad[k][0];
      q[2 * k + 1] = spec.rest_angles_rad[k][1];
    }
    rest_q_.push_back(std::move(q));
  }
  // The surface at rest is rigid in the brush frame: its refined vertices
  // once, each orientation only rotates them.
  if (brush.surface.present()) {
    const BrushSurface surface(brush);
    surface_rest_mm_.reserve(surface.refinedVertexCount());
    for (int i = 0; i < surface.refinedVertexCount(); ++i)
      surface_rest_mm_.push_back(surface.refinedRestPosition(i));
  }
}

double FirstContact::heightMm(const Eigen::Quaterniond& rotation) const {
  // The ferrule at the origin: the lowest point of the rest geometry is
  // -(first contact height).
  Pose held;
  held.rotation = rotation.normalized();
  double lowest = 0;  // the ferrule itself
  SpineFk fk;
  for (size_t s = 0; s < brush_->spines.size(); ++s) {
    const SpineSpec& spec = brush_->spines[s];
    spineForwardKinematics(spec, held, rest_q_[s].data(), 0, &fk);
    const std::vector<double> reach = bundleReachBelowPoints(spec, fk.x, held);
    for (size_t j = 0; j < fk.x.size(); ++j) lowest = std::min(lowest, fk.x[j].z() - reach[j]);
  }
  // z of R p is the third row of R dotted with p.
  const Eigen::Vector3d world_z = held.rotation.toRotationMatrix().row(2).transpose();
  for (const Eigen::Vector3d& p : surface_rest_mm_) lowest = std::min(lowest, world_z.dot(p));
  return -lowest;
}

double firstContactHeightMm(const Brush& brush, const Eigen::Quaterniond& rotation) {
  return FirstContact(brush).heightMm(rotation);
}

Trajectory resolveDepths(const Trajectory& trajectory, const Brush& brush) {
  Trajectory out = trajectory;
  if (!trajectory.needsBrush()) return out;
  const FirstContact contact(brush);
  // Consecutive samples mostly share an orientation: compute it once.
  Eigen::Quaterniond last_rotation(0, 0, 0, 0);
  double height = 0;
  for (TrajectorySample& s : out.samples) {
    if (s.pose.rotation.coeffs() != last_rotation.coeffs()) {
      height = contact.heightMm(s.pose.rotation);
      last_rotation = s.pose.rotation;
    }
    const double z = height - s.depth_mm;
    if (std::fabs(z) > kMaxPositionMm) {
      std::ostringstream msg;
      msg << "depth_mm = " << s.depth_mm << " puts the ferrule of brush '" << brush.name
          << "' at z = " << z << " mm, outside the limit of +-100000 mm";
      throw dataError(trajectory.path,
                      "line " + std::to_string(s.line) + ", column " +
                          std::to_string(trajectory.depth_column) + " (depth_mm)",
                      msg.str());
    }
    s.pose.position_mm.z() = z;
  }
  out.depths_resolved = true;
  return out;
}

}  // namespace bristle

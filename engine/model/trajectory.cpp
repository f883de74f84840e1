#include "engine/model/trajectory.h"

#include <algorithm>

namespace bristle {

size_t Trajectory::segmentAt(double t_s) const {
  if (samples.size() < 2 || t_s <= samples.front().t_s) return 0;
  if (t_s >= samples.back().t_s) return samples.size() - 2;
  auto it = std::upper_bound(samples.begin(), samples.end(), t_s,
                             [](double t, const TrajectorySample& s) { return t < s.t_s; });
  return static_cast<size_t>(it - samples.begin()) - 1;
}

Pose Trajectory::poseAt(double t_s) const {
  if (samples.size() == 1 || t_s <= samples.front().t_s) return samples.front().pose;
  if (t_s >= samples.back().t_s) return samples.back().pose;
  const size_t k = segmentAt(t_s);
  const TrajectorySample& a = samples[k];
  const TrajectorySample& b = samples[k + 1];
  return interpolatePose(a.pose, b.pose, (t_s - a.t_s) / (b.t_s - a.t_s));
}

bool Trajectory::comesWithinReach(double r, double w, double h) const {
  for (const TrajectorySample& s : samples) {
    const Eigen::Vector3d& p = s.pose.position_mm;
    if (p.z() <= r && p.x() >= -r && p.x() <= w + r && p.y() >= -r && p.y() <= h + r) return true;
  }
  return false;
}

}  // namespace bristle

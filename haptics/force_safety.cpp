#include "haptics/force_safety.h"

#include <algorithm>
#include <cmath>

namespace bristle::haptics {

Eigen::Vector3d ForceSafety::filter(double t_s, const Eigen::Vector3d& raw_n, double model_age_s,
                                    bool motor_hot, bool device_error) {
  const double dt = started_ ? std::max(0.0, t_s - last_t_s_) : 0.0;
  started_ = true;
  last_t_s_ = t_s;
  flags_ = 0;
  if (device_error || !raw_n.allFinite() || model_age_s < 0) {
    // Zero now; forces come back only through the ramp.
    gain_ = 0;
    flags_ |= device_error ? std::uint32_t{kSafetyDeviceError} : 0u;
    flags_ |= !raw_n.allFinite() ? std::uint32_t{kSafetyNotFinite} : 0u;
    flags_ |= model_age_s < 0 ? std::uint32_t{kSafetyNoModel} : 0u;
    return Eigen::Vector3d::Zero();
  }
  if (model_age_s > limits_.stale_after_s) {
    flags_ |= kSafetyStale;
    gain_ = std::max(0.0, gain_ - dt / limits_.fade_s);
  } else {
    gain_ = std::min(1.0, gain_ + dt / limits_.ramp_s);
  }
  if (gain_ < 1) flags_ |= kSafetyRamping;
  Eigen::Vector3d f = gain_ * raw_n;
  const double limit = motor_hot ? limits_.continuous_max_n : limits_.nominal_max_n;
  if (motor_hot) flags_ |= kSafetyHot;
  const double mag = f.norm();
  if (mag > limit) {
    // A hair inside the limit, so rounding never lands a clamped force above
    // it (the device would flag HD_EXCEEDED_MAX_FORCE).
    constexpr double kClampMargin = 1e-9;
    f *= limit * (1 - kClampMargin) / mag;
    flags_ |= kSafetyClamped;
  }
  return f;
}

}  // namespace bristle::haptics

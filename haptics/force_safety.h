#pragma once
// What stands between the force model and the motors (docs/design.md,
// "The haptic device API"). Pure logic on the servo tick's time, so tests
// drive it with simulated time, no threads:
//   - zero force on NaN/inf and on any device error; afterwards forces ramp in
//     again from zero;
//   - ramp forces in at the start (gain 0 -> 1 over ramp_s);
//   - watchdog: when the force model is older than stale_after_s (three sim
//     frames), the gain fades linearly to zero over fade_s (~50 ms), and ramps
//     back in once fresh models arrive;
//   - clamp the magnitude to the nominal maximum force, or to the continuous
//     maximum while the motors are hot.
// filter() never allocates and never blocks.

#include <Eigen/Core>
#include <cstdint>

namespace bristle::haptics {

struct SafetyLimits {
  double nominal_max_n = 3.3;     // Touch / Omni (docs/design.md, "The haptic device API")
  double continuous_max_n = 0.88;
  double ramp_s = 0.25;           // gain 0 -> 1 at start and after an error
  double fade_s = 0.05;           // gain 1 -> 0 when the model goes stale
  double stale_after_s = 0.1;     // three frames of a 30 Hz simulation
};

enum SafetyFlag : std::uint32_t {
  kSafetyClamped = 1u << 0,   // magnitude limited
  kSafetyRamping = 1u << 1,   // gain < 1 while ramping in
  kSafetyStale = 1u << 2,     // model older than stale_after_s: fading
  kSafetyNotFinite = 1u << 3, // the model gave NaN/inf: zeroed
  kSafetyDeviceError = 1u << 4,  // device error this tick: zeroed
  kSafetyHot = 1u << 5,       // continuous limit in force
  kSafetyNoModel = 1u << 6,   // no force model yet: zero
};

class ForceSafety {
 public:
  explicit ForceSafety(const SafetyLimits& limits) : limits_(limits) {}

  // One servo tick at time t_s (monotonic). model_age_s < 0 means no model.
  Eigen::Vector3d filter(double t_s, const Eigen::Vector3d& raw_n, double model_age_s,
                         bool motor_hot, bool device_error);

  std::uint32_t flags() const { return flags_; }  // of the last tick
  double gain() const { return gain_; }
  const SafetyLimits& limits() const { return limits_; }

 private:
  SafetyLimits limits_;
  double gain_ = 0;
  double last_t_s_ = 0;
  bool started_ = false;
  std::uint32_t flags_ = 0;
};

}  // namespace bristle::haptics

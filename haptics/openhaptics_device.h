#pragma once
// A Phantom (Touch, Omni, Desktop, Premium) through OpenHaptics' HDAPI,
// loaded at run time (haptics/hdapi.h). The call sequence is the one mature
// drivers share (docs/design.md, "The haptic device API"): hdInitDevice ->
// calibration check -> hdEnable(FORCE_OUTPUT, MAX_FORCE_CLAMPING, FORCE_RAMPING) ->
// hdScheduleAsynchronous(servo, max priority) -> hdSetSchedulerRate(1000) ->
// hdStartScheduler; each tick hdBeginFrame, read pose and buttons, set the
// force, hdEndFrame, hdGetError; shutdown hdStopScheduler -> hdUnschedule ->
// hdDisableDevice.

#include <atomic>
#include <string>

#include "haptics/device.h"
#include "haptics/device_frame.h"
#include "haptics/hdapi.h"

namespace bristle::haptics {

class OpenHapticsDevice : public Device {
 public:
  // Throws bristle::Error(kUnavailable): library or symbol missing (named),
  // or hdInitDevice failing (with the HD error string).
  explicit OpenHapticsDevice(const std::string& library_path, double rate_hz = 1000,
                             const DeviceMapping& mapping = {});
  ~OpenHapticsDevice() override;

  std::string model() const override { return model_; }
  double nominalMaxForceN() const override { return nominal_max_n_; }
  double continuousMaxForceN() const override { return continuous_max_n_; }
  double servoRateHz() const override { return rate_hz_; }
  void start(TickFn tick, void* ctx) override;
  void stop() override;
  DeviceStatus beginFrame(DeviceFrame* out) override;
  DeviceStatus endFrame(const Eigen::Vector3d& force_n) override;

  // Said once to the user at start (e.g. "calibration needed"); may be empty.
  const std::string& notice() const { return notice_; }

 private:
  static hd::HDCallbackCode servoCallback(void* self);
  DeviceStatus pendingError();
  // Throws kUnavailable with `what` and the HD error string if an error is pending.
  void checkSetup(const char* what);

  hd::HdApi api_;
  hd::HHD hhd_ = hd::kInvalidHandle;
  DeviceMapping mapping_;
  double rate_hz_;
  std::string model_, notice_;
  double nominal_max_n_ = 0, continuous_max_n_ = 0;
  hd::HDSchedulerHandle handle_ = 0;
  bool scheduled_ = false, running_ = false;
  TickFn tick_fn_ = nullptr;
  void* tick_ctx_ = nullptr;
  std::atomic<bool> stop_{false};
  long tick_ = 0;  // servo thread only
};

}  // namespace bristle::haptics

#pragma once
// The device for runs without a Phantom (`--device none`): it plays a
// trajectory as the stylus, one servo tick per period on its own thread
// (clock_nanosleep to absolute deadlines), and logs the forces it is sent.
// Device time is ticks / rate, so the poses it reports are the trajectory's,
// tick for tick, however late the thread wakes.

#include <atomic>
#include <thread>

#include "engine/model/trajectory.h"
#include "haptics/device.h"

namespace bristle::haptics {

struct NoneDeviceOptions {
  double rate_hz = 1000;
  double nominal_max_n = 3.3;  // as a Touch / Omni (docs/design.md, "The haptic device API")
  double continuous_max_n = 0.88;
};

class NoneDevice : public Device {
 public:
  NoneDevice(Trajectory trajectory, const NoneDeviceOptions& options = {});
  ~NoneDevice() override;

  std::string model() const override { return "none (trajectory " + trajectory_.path + ")"; }
  double nominalMaxForceN() const override { return options_.nominal_max_n; }
  double continuousMaxForceN() const override { return options_.continuous_max_n; }
  double servoRateHz() const override { return options_.rate_hz; }
  void start(TickFn tick, void* ctx) override;
  void stop() override;
  DeviceStatus beginFrame(DeviceFrame* out) override;
  DeviceStatus endFrame(const Eigen::Vector3d& force_n) override;

  // Whether the servo thread got real-time (SCHED_FIFO) priority.
  bool realtime() const { return realtime_.load(); }
  static constexpr int kRealtimePriority = 80;  // below the kernel's own (99)

 private:
  void run(TickFn tick, void* ctx);

  Trajectory trajectory_;
  NoneDeviceOptions options_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  long tick_ = 0;  // servo thread only
  std::atomic<bool> realtime_{false};
};

}  // namespace bristle::haptics

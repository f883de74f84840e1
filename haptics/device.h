#pragma once
// A haptic device as the servo loop sees it: it runs the loop's tick at the
// servo rate on its own thread, reports the stylus (canvas frame) and buttons
// at the start of each tick, and takes the force (canvas frame, N) at its end.
// beginFrame/endFrame are called only from inside the tick, and neither
// allocates nor blocks. Errors inside the tick are reported by value, with a
// static message string, so the servo thread never allocates for them.

#include <Eigen/Core>
#include <memory>
#include <string>

#include "engine/model/pose.h"

namespace bristle::haptics {

struct DeviceFrame {
  double t_s = 0;       // device time: servo ticks / servo rate
  Pose pose;            // stylus as a brush handle, canvas frame
  int buttons = 0;      // bitmask: button 1 = 1, button 2 = 2
  bool motor_hot = false;
  bool end_of_input = false;  // a played trajectory has ended
};

struct DeviceStatus {
  unsigned code = 0;              // 0 = fine; otherwise the device's error code
  bool fatal = false;             // the device cannot go on: stop the loop
  const char* message = nullptr;  // static text naming the error
  bool ok() const { return code == 0; }
};

class Device {
 public:
  virtual ~Device() = default;
  virtual std::string model() const = 0;
  virtual double nominalMaxForceN() const = 0;
  virtual double continuousMaxForceN() const = 0;
  virtual double servoRateHz() const = 0;

  // Runs tick(ctx) every servo period on the device's servo thread until it
  // returns false or stop() is called.
  using TickFn = bool (*)(void* ctx);
  virtual void start(TickFn tick, void* ctx) = 0;
  // Ends the servo thread; on return tick is no longer called. Idempotent.
  virtual void stop() = 0;

  virtual DeviceStatus beginFrame(DeviceFrame* out) = 0;
  virtual DeviceStatus endFrame(const Eigen::Vector3d& force_n) = 0;
};

}  // namespace bristle::haptics

#pragma once
// The 1 kHz servo loop (paper §5): each tick it reads the stylus, evaluates the
// latest force model (eqs. 21-22) at the stylus position, passes the force
// through the safety filter and sends it to the device. It runs on the
// device's servo thread, never allocates, never blocks, and takes no locks:
//   sim thread  -> servo: force models through a seqlock (models());
//   servo -> sim thread: the latest stylus pose through a seqlock (poses());
//   servo -> recorder:   one ServoSample per tick through an SPSC ring.

#include <atomic>
#include <cstdint>

#include "haptics/device.h"
#include "haptics/force_model.h"
#include "haptics/force_safety.h"
#include "haptics/seqlock.h"
#include "haptics/spsc_ring.h"

namespace bristle::haptics {

struct StylusState {
  double t_s = 0;
  double position_mm[3] = {0, 0, 0};
  double rotation_wxyz[4] = {1, 0, 0, 0};
  int buttons = 0;
  std::uint64_t tick = 0;
  bool valid = false;
  Pose pose() const;
};

struct ServoSample {
  std::uint64_t tick = 0;
  double t_s = 0;                // device time
  std::int64_t wall_ns = 0;      // CLOCK_MONOTONIC at the start of the tick
  double position_mm[3] = {0, 0, 0};
  double rotation_wxyz[4] = {1, 0, 0, 0};
  int buttons = 0;
  double force_n[3] = {0, 0, 0};  // sent to the device (canvas frame)
  double model_force_n[3] = {0, 0, 0};  // the force model's, before safety
  std::uint32_t safety_flags = 0;
  std::uint64_t model_frame = 0;
};

struct ServoOptions {
  SafetyLimits safety;  // nominal/continuous max are taken from the device
  double duration_s = 0;  // stop after this much device time (0 = no limit)
  size_t ring_capacity = 1 << 16;  // 65 s at 1 kHz before samples drop
};

class ServoLoop {
 public:
  ServoLoop(Device* device, const ServoOptions& options);
  ~ServoLoop();

  void start();
  // Asks the loop to end: its last tick sends zero force. Returns at once.
  void requestStop() { stop_requested_.store(true); }
  // Waits for the servo thread to end, then stops the device.
  void join();
  bool finished() const { return finished_.load(); }

  Seqlock<ForceModel>& models() { return models_; }
  Seqlock<StylusState>& stylus() { return stylus_; }
  SpscRing<ServoSample>& samples() { return samples_; }

  // Why the loop ended by itself.
  enum class End { kRunning, kStopRequested, kEndOfInput, kDuration, kDeviceError };
  End end() const { return end_.load(); }
  // The device error that ended it (code, static message).
  DeviceStatus fatalError() const;
  std::uint64_t ticks() const { return ticks_.load(); }
  std::uint64_t deviceErrors() const { return device_errors_.load(); }

 private:
  static bool tickThunk(void* self) { return static_cast<ServoLoop*>(self)->tick(); }
  bool tick();
  void finish(End why);

  Device* device_;
  ServoOptions options_;
  ForceSafety safety_;
  Seqlock<ForceModel> models_;
  Seqlock<StylusState> stylus_;
  SpscRing<ServoSample> samples_;
  std::atomic<bool> stop_requested_{false}, finished_{false};
  std::atomic<End> end_{End::kRunning};
  std::atomic<unsigned> fatal_code_{0};
  std::atomic<const char*> fatal_message_{nullptr};
  std::atomic<std::uint64_t> ticks_{0}, device_errors_{0};
  bool started_ = false;
  // Servo thread only:
  std::uint64_t last_model_frame_ = 0;
  double last_model_t_s_ = -1;  // device time when the current model arrived
};

}  // namespace bristle::haptics

#include "haptics/servo_loop.h"

#include <chrono>
#include <thread>

#include "haptics/monotonic_clock.h"

namespace bristle::haptics {

Pose StylusState::pose() const {
  Pose p;
  p.position_mm = Eigen::Vector3d(position_mm[0], position_mm[1], position_mm[2]);
  p.rotation = Eigen::Quaterniond(rotation_wxyz[0], rotation_wxyz[1], rotation_wxyz[2],
                                  rotation_wxyz[3]);
  return p;
}


ServoLoop::ServoLoop(Device* device, const ServoOptions& options)
    : device_(device), options_(options), safety_([&] {
        SafetyLimits l = options.safety;
        l.nominal_max_n = device->nominalMaxForceN();
        l.continuous_max_n = device->continuousMaxForceN();
        return l;
      }()),
      samples_(options.ring_capacity) {}

ServoLoop::~ServoLoop() {
  requestStop();
  join();
}

void ServoLoop::start() {
  started_ = true;
  device_->start(&ServoLoop::tickThunk, this);
}

void ServoLoop::join() {
  if (!started_) return;
  // The servo thread sends a last zero force and ends within a tick or two;
  // a device whose scheduler stopped calling back is stopped all the same.
  constexpr int kJoinWaitMs = 500;
  for (int i = 0; i < kJoinWaitMs && !finished_.load(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  device_->stop();
  started_ = false;
}

void ServoLoop::finish(End why) {
  End expected = End::kRunning;
  end_.compare_exchange_strong(expected, why);
  finished_.store(true);
}

DeviceStatus ServoLoop::fatalError() const {
  DeviceStatus st;
  st.code = fatal_code_.load();
  st.fatal = st.code != 0;
  st.message = fatal_message_.load();
  return st;
}

bool ServoLoop::tick() {
  if (finished_.load(std::memory_order_relaxed)) return false;
  ServoSample smp;
  smp.wall_ns = monotonicNs();
  DeviceFrame frame;
  DeviceStatus status = device_->beginFrame(&frame);

  // The stylus, for the sim thread.
  StylusState st;
  st.t_s = frame.t_s;
  for (int i = 0; i < 3; ++i) st.position_mm[i] = frame.pose.position_mm[i];
  st.rotation_wxyz[0] = frame.pose.rotation.w();
  st.rotation_wxyz[1] = frame.pose.rotation.x();
  st.rotation_wxyz[2] = frame.pose.rotation.y();
  st.rotation_wxyz[3] = frame.pose.rotation.z();
  st.buttons = frame.buttons;
  st.tick = ticks_.load(std::memory_order_relaxed);
  st.valid = true;
  stylus_.store(st);

  // eqs. 21-22 at the stylus, then the safety filter.
  ForceModel model;
  models_.load(&model);
  if (model.valid && model.frame != last_model_frame_) {
    last_model_frame_ = model.frame;
    last_model_t_s_ = frame.t_s;
  }
  const Eigen::Vector3d raw = model.valid ? model.evaluate(frame.pose.position_mm)
                                          : Eigen::Vector3d::Zero();
  const double age = model.valid ? frame.t_s - last_model_t_s_ : -1.0;
  const bool stopping = stop_requested_.load(std::memory_order_relaxed);
  Eigen::Vector3d f = safety_.filter(frame.t_s, raw, age, frame.motor_hot, !status.ok());
  if (stopping) f.setZero();  // the last tick: forces to zero first
  DeviceStatus end_status = device_->endFrame(f);
  if (status.ok()) status = end_status;
  if (!status.ok()) {
    device_errors_.fetch_add(1, std::memory_order_relaxed);
    // The force of this tick already went out; the filter zeroes the next one
    // and ramps in again from zero.
    safety_.filter(frame.t_s, Eigen::Vector3d::Zero(), -1.0, frame.motor_hot, true);
    f.setZero();
  }

  smp.tick = st.tick;
  smp.t_s = frame.t_s;
  for (int i = 0; i < 3; ++i) {
    smp.position_mm[i] = st.position_mm[i];
    smp.force_n[i] = f[i];
    smp.model_force_n[i] = raw[i];
  }
  for (int i = 0; i < 4; ++i) smp.rotation_wxyz[i] = st.rotation_wxyz[i];
  smp.buttons = frame.buttons;
  smp.safety_flags = safety_.flags() | (status.ok() ? 0u : std::uint32_t{kSafetyDeviceError});
  smp.model_frame = model.frame;
  samples_.push(smp);
  ticks_.fetch_add(1, std::memory_order_relaxed);

  if (status.fatal) {
    fatal_message_.store(status.message);
    fatal_code_.store(status.code);
    finish(End::kDeviceError);
    return false;  // fatal scheduler error: stop scheduling
  }
  if (stopping) {
    finish(End::kStopRequested);
    return false;
  }
  if (frame.end_of_input) {
    requestStop();  // one more tick sends zero force, then ends
    end_.store(End::kEndOfInput);
    return true;
  }
  if (options_.duration_s > 0 && frame.t_s >= options_.duration_s) {
    requestStop();
    end_.store(End::kDuration);
    return true;
  }
  return true;
}

}  // namespace bristle::haptics

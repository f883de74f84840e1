#include "haptics/none_device.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <cmath>
#include <stdexcept>

namespace bristle::haptics {

NoneDevice::NoneDevice(Trajectory trajectory, const NoneDeviceOptions& options)
    : trajectory_(std::move(trajectory)), options_(options) {
  // It plays poses: depths past first contact must have become a brush's
  // ferrule heights (resolveDepths) before it gets them.
  if (trajectory_.needsBrush())
    throw std::logic_error(trajectory_.path + ": depth_mm not resolved for the brush");
}

NoneDevice::~NoneDevice() { stop(); }

void NoneDevice::start(TickFn tick, void* ctx) {
  stop_ = false;
  tick_ = 0;
  thread_ = std::thread([this, tick, ctx] { run(tick, ctx); });
}

void NoneDevice::stop() {
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

void NoneDevice::run(TickFn tick, void* ctx) {
  // A servo thread wants the CPU the moment its deadline comes: real-time
  // FIFO priority when the system grants it (root, or CAP_SYS_NICE / an
  // rtprio limit), else it runs at normal priority, which jitters under load
  // (docs/PERFORMANCE.md, "Haptic servo loop"). The OpenHaptics scheduler does the same for itself.
  sched_param sp{};
  sp.sched_priority = kRealtimePriority;
  realtime_ = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
  const long period_ns = std::lround(1e9 / options_.rate_hz);
  timespec next{};
  clock_gettime(CLOCK_MONOTONIC, &next);
  while (!stop_.load(std::memory_order_relaxed)) {
    if (!tick(ctx)) break;
    ++tick_;
    next.tv_nsec += period_ns;
    while (next.tv_nsec >= 1000000000L) {
      next.tv_nsec -= 1000000000L;
      ++next.tv_sec;
    }
    // Absolute deadlines: a late wake-up does not push every later tick back.
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr) != 0) {
    }
  }
}

DeviceStatus NoneDevice::beginFrame(DeviceFrame* out) {
  out->t_s = static_cast<double>(tick_) / options_.rate_hz;
  const double t = trajectory_.startTime() + out->t_s;
  out->pose = trajectory_.poseAt(t);
  const TrajectorySample& s = trajectory_.samples[trajectory_.segmentAt(t)];
  out->buttons = s.buttons;
  out->motor_hot = false;
  out->end_of_input = t > trajectory_.endTime();
  return {};
}

DeviceStatus NoneDevice::endFrame(const Eigen::Vector3d& /*force_n*/) {
  return {};  // no motors: the force is logged by the session, not sent anywhere
}

}  // namespace bristle::haptics

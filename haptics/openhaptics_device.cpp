#include "haptics/openhaptics_device.h"

#include <algorithm>
#include <cstdio>

#include "engine/base/error.h"

namespace bristle::haptics {

namespace {
// HD_MOTOR_TEMPERATURE is normalised per motor: 0 room temperature, 1 the
// driver's overheat limit. Above this the continuous force limit applies.
constexpr double kHotFraction = 0.8;
}  // namespace

OpenHapticsDevice::OpenHapticsDevice(const std::string& library_path, double rate_hz,
                                     const DeviceMapping& mapping)
    : api_(hd::HdApi::load(library_path)), mapping_(mapping), rate_hz_(rate_hz) {
  while (api_.hdGetError().errorCode != hd::kSuccess) {
  }  // start from a clean error stack
  hhd_ = api_.hdInitDevice(nullptr);  // HD_DEFAULT_DEVICE
  const hd::HDErrorInfo e = api_.hdGetError();
  if (e.errorCode != hd::kSuccess || hhd_ == hd::kInvalidHandle) {
    const char* s = e.errorCode != hd::kSuccess ? api_.hdGetErrorString(e.errorCode) : nullptr;
    throw Error(ExitCode::kUnavailable,
                library_path + ": hdInitDevice failed: " +
                    (s != nullptr ? s : "invalid device handle") + " (HD error 0x" +
                    [&] {
                      char b[16];
                      std::snprintf(b, sizeof b, "%04x", e.errorCode);
                      return std::string(b);
                    }() +
                    ")");
  }
  api_.hdMakeCurrentDevice(hhd_);
  if (api_.hdCheckCalibration() != hd::kCalibrationOk)
    notice_ = "the device needs calibration: put the stylus in its inkwell (forces stay off "
              "until the driver reports it calibrated)";
  const char* m = api_.hdGetString(hd::kDeviceModelType);
  model_ = std::string("OpenHaptics ") + (m != nullptr ? m : "device");
  api_.hdGetDoublev(hd::kNominalMaxForce, &nominal_max_n_);
  api_.hdGetDoublev(hd::kNominalMaxContinuousForce, &continuous_max_n_);
  checkSetup("reading the force limits");
  if (!(nominal_max_n_ > 0)) nominal_max_n_ = 0;  // no limit reported: no force
  if (!(continuous_max_n_ > 0) || continuous_max_n_ > nominal_max_n_)
    continuous_max_n_ = nominal_max_n_;
  api_.hdEnable(hd::kForceOutput);
  api_.hdEnable(hd::kMaxForceClamping);
  api_.hdEnable(hd::kForceRamping);
  checkSetup("enabling force output");
}

OpenHapticsDevice::~OpenHapticsDevice() {
  stop();
  if (hhd_ != hd::kInvalidHandle) api_.hdDisableDevice(hhd_);
  // libHD itself stays loaded: it is never dlclose'd.
}

void OpenHapticsDevice::checkSetup(const char* what) {
  const hd::HDErrorInfo e = api_.hdGetError();
  if (e.errorCode == hd::kSuccess) return;
  const char* s = api_.hdGetErrorString(e.errorCode);
  throw Error(ExitCode::kUnavailable,
              std::string("OpenHaptics: ") + what + " failed: " + (s != nullptr ? s : "?"));
}

void OpenHapticsDevice::start(TickFn tick, void* ctx) {
  tick_fn_ = tick;
  tick_ctx_ = ctx;
  tick_ = 0;
  stop_ = false;
  handle_ = api_.hdScheduleAsynchronous(&OpenHapticsDevice::servoCallback, this,
                                        hd::kMaxSchedulerPriority);
  scheduled_ = true;
  api_.hdSetSchedulerRate(static_cast<hd::HDulong>(rate_hz_));
  api_.hdStartScheduler();
  running_ = true;
  checkSetup("starting the servo scheduler");
}

void OpenHapticsDevice::stop() {
  stop_ = true;
  if (running_) api_.hdStopScheduler();
  running_ = false;
  if (scheduled_) api_.hdUnschedule(handle_);
  scheduled_ = false;
}

hd::HDCallbackCode OpenHapticsDevice::servoCallback(void* p) {
  auto* self = static_cast<OpenHapticsDevice*>(p);
  if (self->stop_.load(std::memory_order_relaxed)) return hd::kCallbackDone;
  const bool go_on = self->tick_fn_(self->tick_ctx_);
  ++self->tick_;
  return go_on ? hd::kCallbackContinue : hd::kCallbackDone;
}

DeviceStatus OpenHapticsDevice::pendingError() {
  DeviceStatus st;
  // Newest first; report the first, drain the rest (a fatal one wins).
  for (hd::HDErrorInfo e = api_.hdGetError(); e.errorCode != hd::kSuccess;
       e = api_.hdGetError()) {
    const bool fatal = hd::isFatalSchedulerError(e.errorCode);
    if (st.code == 0 || (fatal && !st.fatal)) {
      st.code = e.errorCode;
      st.fatal = fatal;
      st.message = api_.hdGetErrorString(e.errorCode);
    }
  }
  return st;
}

DeviceStatus OpenHapticsDevice::beginFrame(DeviceFrame* out) {
  api_.hdBeginFrame(hhd_);
  double transform[16];
  api_.hdGetDoublev(hd::kCurrentTransform, transform);
  int buttons = 0;
  api_.hdGetIntegerv(hd::kCurrentButtons, &buttons);
  double temperature[6] = {0, 0, 0, 0, 0, 0};
  api_.hdGetDoublev(hd::kMotorTemperature, temperature);
  out->t_s = static_cast<double>(tick_) / rate_hz_;
  out->pose = mapping_.toCanvas(transform);
  out->buttons = buttons;
  out->motor_hot = *std::max_element(temperature, temperature + 6) > kHotFraction;
  out->end_of_input = false;
  return pendingError();
}

DeviceStatus OpenHapticsDevice::endFrame(const Eigen::Vector3d& force_n) {
  const Eigen::Vector3d f = mapping_.forceToDevice(force_n);
  const double d[3] = {f.x(), f.y(), f.z()};
  api_.hdSetDoublev(hd::kCurrentForce, d);
  api_.hdEndFrame(hhd_);
  return pendingError();
}

}  // namespace bristle::haptics

#pragma once
// The part of the OpenHaptics HDAPI C ABI that bristle uses (types, constants,
// signatures; docs/haptics.md, "The HDAPI subset").
// Nothing here links against libHD: HdApi::load() opens it with dlopen and
// resolves each function with dlsym. The library is never dlclose'd (vendor
// drivers break when reloaded).

#include <string>

namespace bristle::haptics::hd {

using HHD = unsigned int;
using HDenum = unsigned int;
using HDerror = unsigned int;
using HDCallbackCode = unsigned int;
using HDint = int;
using HDdouble = double;
using HDulong = unsigned long;
using HDushort = unsigned short;
using HDboolean = unsigned char;
using HDstring = const char*;
using HDSchedulerHandle = unsigned long;
using HDSchedulerCallback = HDCallbackCode (*)(void*);

struct HDErrorInfo {
  HDerror errorCode;
  int internalErrorCode;
  HHD hHD;
};

// Errors.
inline constexpr HDerror kSuccess = 0x0000;
inline constexpr HDerror kWarmMotors = 0x0200;
inline constexpr HDerror kExceededMaxForce = 0x0201;
inline constexpr HDerror kExceededMaxForceImpulse = 0x0202;
inline constexpr HDerror kExceededMaxVelocity = 0x0203;
inline constexpr HDerror kForceError = 0x0204;
inline constexpr HDerror kDeviceFault = 0x0300;
inline constexpr HDerror kCommError = 0x0302;
inline constexpr HDerror kCommConfigError = 0x0303;
inline constexpr HDerror kTimerError = 0x0304;
inline constexpr HDerror kInvalidPriority = 0x0500;
inline constexpr HDerror kSchedulerFull = 0x0501;
inline constexpr HDerror kInvalidLicense = 0x0600;
// Scheduler errors end the servo callback (HD_CALLBACK_DONE).
inline bool isFatalSchedulerError(HDerror e) {
  return e == kCommError || e == kCommConfigError || e == kTimerError || e == kInvalidPriority ||
         e == kSchedulerFull;
}

// State and limits (hdGetDoublev / hdGetIntegerv / hdGetString).
inline constexpr HDenum kCurrentButtons = 0x2000;
inline constexpr HDenum kCurrentPosition = 0x2050;
inline constexpr HDenum kCurrentVelocity = 0x2051;
inline constexpr HDenum kCurrentTransform = 0x2052;
inline constexpr HDenum kUsableWorkspaceDimensions = 0x2551;
inline constexpr HDenum kNominalMaxStiffness = 0x2602;
inline constexpr HDenum kNominalMaxForce = 0x2603;
inline constexpr HDenum kNominalMaxContinuousForce = 0x2604;
inline constexpr HDenum kMotorTemperature = 0x2605;
inline constexpr HDenum kCurrentForce = 0x2700;
// hdGetString: the device's model name (HD_DEVICE_MODEL_TYPE in the headers).
inline constexpr HDenum kDeviceModelType = 0x2501;
// hdEnable flags.
inline constexpr HDenum kForceOutput = 0x4000;
inline constexpr HDenum kMaxForceClamping = 0x4001;
inline constexpr HDenum kForceRamping = 0x4002;
// Scheduler.
inline constexpr HDCallbackCode kCallbackDone = 0;
inline constexpr HDCallbackCode kCallbackContinue = 1;
inline constexpr HDushort kMaxSchedulerPriority = 65535;
inline constexpr HDenum kCalibrationOk = 0x5000;
inline constexpr HHD kInvalidHandle = 0xFFFFFFFF;

// The resolved entry points.
struct HdApi {
  HHD (*hdInitDevice)(HDstring) = nullptr;
  void (*hdDisableDevice)(HHD) = nullptr;
  void (*hdMakeCurrentDevice)(HHD) = nullptr;
  void (*hdBeginFrame)(HHD) = nullptr;
  void (*hdEndFrame)(HHD) = nullptr;
  HDErrorInfo (*hdGetError)() = nullptr;
  HDstring (*hdGetErrorString)(HDerror) = nullptr;
  void (*hdEnable)(HDenum) = nullptr;
  void (*hdDisable)(HDenum) = nullptr;
  void (*hdGetDoublev)(HDenum, HDdouble*) = nullptr;
  void (*hdGetIntegerv)(HDenum, HDint*) = nullptr;
  void (*hdSetDoublev)(HDenum, const HDdouble*) = nullptr;
  HDstring (*hdGetString)(HDenum) = nullptr;
  void (*hdStartScheduler)() = nullptr;
  void (*hdStopScheduler)() = nullptr;
  void (*hdSetSchedulerRate)(HDulong) = nullptr;
  HDSchedulerHandle (*hdScheduleAsynchronous)(HDSchedulerCallback, void*, HDushort) = nullptr;
  void (*hdUnschedule)(HDSchedulerHandle) = nullptr;
  HDenum (*hdCheckCalibration)() = nullptr;

  // Opens `path` (dlopen) and resolves every function above. Throws
  // bristle::Error(kUnavailable) naming the library and dlerror() when it
  // cannot be opened, or the first missing symbol.
  static HdApi load(const std::string& path);
};

// BRISTLE_HD_LIBRARY if set, else "libHD.so" (found by the dynamic loader).
std::string hdLibraryPath();

}  // namespace bristle::haptics::hd

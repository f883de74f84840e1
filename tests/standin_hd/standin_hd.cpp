// A stand-in for OpenHaptics' libHD.so, built by the tests: the same C ABI
// (haptics/hdapi.h; docs/design.md, "The haptic device API"), no hardware. It
//   - plays a scripted stylus path at the scheduler rate (1 kHz): a
//     bristle-trajectory/1 CSV in the canvas frame (STANDIN_HD_PATH), turned
//     into device-frame transforms with bristle's own DeviceMapping, so the
//     path bristle reads back is the CSV's; after its end the stylus rests;
//   - reports pose, buttons, limits (STANDIN_HD_MAX_FORCE, default 3.3 N as a
//     Touch; STANDIN_HD_CONTINUOUS_FORCE, default 0.88 N) and motor
//     temperature (1.0 from tick STANDIN_HD_HOT_AT on);
//   - records every force it is sent (STANDIN_HD_FORCES: "tick,fx,fy,fz" in
//     the device frame) and counts those above its nominal maximum;
//   - injects errors: STANDIN_HD_INIT_ERROR=0x0300 makes hdInitDevice fail;
//     STANDIN_HD_ERROR_AT=<tick>:<code> raises <code> at that tick's
//     hdBeginFrame (e.g. 300:0x0302 a comm error, 300:0x0201 exceeded force).
// Built once as libHD.so and once without hdScheduleAsynchronous
// (STANDIN_HD_OMIT_SCHEDULE) to test a library that lacks a symbol.

#include <time.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "haptics/device_frame.h"

namespace {

using HDCallbackCode = unsigned int;
using HDSchedulerCallback = HDCallbackCode (*)(void*);
struct HDErrorInfo {
  unsigned int errorCode;
  int internalErrorCode;
  unsigned int hHD;
};

struct PathPoint {
  double t_s;
  double transform[16];
  int buttons;
};

struct State {
  std::vector<PathPoint> path;
  double rate_hz = 1000;
  double max_force = 3.3, continuous_force = 0.88;
  long hot_at = -1;
  long error_at = -1;
  unsigned error_code = 0;
  std::atomic<unsigned> pending{0};
  std::atomic<long> tick{0};
  long frame_tick = 0;
  double force[3] = {0, 0, 0};
  std::FILE* forces = nullptr;
  long over_max = 0;
  HDSchedulerCallback cb = nullptr;
  void* cb_data = nullptr;
  std::thread scheduler;
  std::atomic<bool> running{false};
  bool enabled_output = false;
};

State& st() {
  static State s;
  return s;
}

double envDouble(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::strtod(v, nullptr) : fallback;
}

void loadPath() {
  State& s = st();
  const char* p = std::getenv("STANDIN_HD_PATH");
  if (p == nullptr) return;
  std::ifstream in(p);
  std::string line;
  bool header = false;
  int buttons_col = -1;
  bristle::haptics::DeviceMapping mapping;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    if (!header) {
      header = true;
      for (size_t i = 0; i < cells.size(); ++i)
        if (cells[i] == "buttons") buttons_col = static_cast<int>(i);
      continue;
    }
    PathPoint pt{};
    pt.t_s = std::stod(cells[0]);
    bristle::Pose pose;
    pose.position_mm = Eigen::Vector3d(std::stod(cells[1]), std::stod(cells[2]), std::stod(cells[3]));
    pose.rotation = Eigen::Quaterniond(std::stod(cells[4]), std::stod(cells[5]),
                                       std::stod(cells[6]), std::stod(cells[7]))
                        .normalized();
    mapping.toDevice(pose, pt.transform);
    pt.buttons = buttons_col >= 0 ? std::stoi(cells[buttons_col]) : 0;
    s.path.push_back(pt);
  }
}

const PathPoint* pointAt(long tick) {
  State& s = st();
  if (s.path.empty()) return nullptr;
  const double t = s.path.front().t_s + static_cast<double>(tick) / s.rate_hz;
  // The path is sampled at 1 kHz or coarser: the latest sample at or before t.
  size_t k = 0;
  while (k + 1 < s.path.size() && s.path[k + 1].t_s <= t) ++k;
  return &s.path[k];
}

void runScheduler() {
  State& s = st();
  const long period_ns = std::lround(1e9 / s.rate_hz);
  timespec next{};
  clock_gettime(CLOCK_MONOTONIC, &next);
  while (s.running.load()) {
    if (s.cb != nullptr && s.cb(s.cb_data) == 0) s.cb = nullptr;  // HD_CALLBACK_DONE
    s.tick.fetch_add(1);
    next.tv_nsec += period_ns;
    while (next.tv_nsec >= 1000000000L) {
      next.tv_nsec -= 1000000000L;
      ++next.tv_sec;
    }
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr);
  }
}

}  // namespace

extern "C" {

unsigned int hdInitDevice(const char*) {
  State& s = st();
  if (const char* e = std::getenv("STANDIN_HD_INIT_ERROR")) {
    s.pending = static_cast<unsigned>(std::strtoul(e, nullptr, 0));
    return 0xFFFFFFFFu;
  }
  s.max_force = envDouble("STANDIN_HD_MAX_FORCE", 3.3);
  s.continuous_force = envDouble("STANDIN_HD_CONTINUOUS_FORCE", 0.88);
  s.hot_at = static_cast<long>(envDouble("STANDIN_HD_HOT_AT", -1));
  if (const char* e = std::getenv("STANDIN_HD_ERROR_AT")) {
    char* rest = nullptr;
    s.error_at = std::strtol(e, &rest, 10);
    if (rest != nullptr && *rest == ':') s.error_code = static_cast<unsigned>(std::strtoul(rest + 1, nullptr, 0));
  }
  if (const char* f = std::getenv("STANDIN_HD_FORCES")) s.forces = std::fopen(f, "w");
  loadPath();
  return 1;
}

void hdDisableDevice(unsigned int) {
  State& s = st();
  if (s.forces != nullptr) {
    std::fprintf(s.forces, "# over_max %ld\n", s.over_max);
    std::fclose(s.forces);
    s.forces = nullptr;
  }
}
void hdMakeCurrentDevice(unsigned int) {}

void hdBeginFrame(unsigned int) {
  State& s = st();
  s.frame_tick = s.tick.load();
  if (s.frame_tick == s.error_at) s.pending = s.error_code;
}

void hdEndFrame(unsigned int) {
  State& s = st();
  const double m = std::sqrt(s.force[0] * s.force[0] + s.force[1] * s.force[1] + s.force[2] * s.force[2]);
  if (m > s.max_force) ++s.over_max;
  if (s.forces != nullptr)
    std::fprintf(s.forces, "%ld,%.9g,%.9g,%.9g\n", s.frame_tick, s.force[0], s.force[1], s.force[2]);
}

HDErrorInfo hdGetError() {
  HDErrorInfo e{st().pending.exchange(0), 0, 1};
  return e;
}

const char* hdGetErrorString(unsigned int code) {
  switch (code) {
    case 0x0000: return "HD_SUCCESS";
    case 0x0201: return "HD_EXCEEDED_MAX_FORCE";
    case 0x0300: return "HD_DEVICE_FAULT";
    case 0x0302: return "HD_COMM_ERROR";
    case 0x0303: return "HD_COMM_CONFIG_ERROR";
    case 0x0304: return "HD_TIMER_ERROR";
    default: return "HD_UNKNOWN_ERROR";
  }
}

void hdEnable(unsigned int cap) {
  if (cap == 0x4000) st().enabled_output = true;
}
void hdDisable(unsigned int) {}

void hdGetDoublev(unsigned int what, double* out) {
  State& s = st();
  switch (what) {
    case 0x2052: {  // HD_CURRENT_TRANSFORM
      const PathPoint* p = pointAt(s.frame_tick);
      if (p != nullptr) std::memcpy(out, p->transform, sizeof p->transform);
      break;
    }
    case 0x2603: *out = s.max_force; break;
    case 0x2604: *out = s.continuous_force; break;
    case 0x2605:  // HD_MOTOR_TEMPERATURE, 3 motors
      for (int i = 0; i < 3; ++i) out[i] = s.hot_at >= 0 && s.frame_tick >= s.hot_at ? 1.0 : 0.1;
      break;
    default: break;
  }
}

void hdGetIntegerv(unsigned int what, int* out) {
  if (what == 0x2000) {  // HD_CURRENT_BUTTONS
    const PathPoint* p = pointAt(st().frame_tick);
    *out = p != nullptr ? p->buttons : 0;
  }
}

void hdSetDoublev(unsigned int what, const double* v) {
  if (what == 0x2700) std::memcpy(st().force, v, sizeof st().force);  // HD_CURRENT_FORCE
}

const char* hdGetString(unsigned int) { return "Stand-in Touch"; }

void hdStartScheduler() {
  State& s = st();
  s.running = true;
  s.scheduler = std::thread(runScheduler);
}

void hdStopScheduler() {
  State& s = st();
  s.running = false;
  if (s.scheduler.joinable()) s.scheduler.join();
}

void hdSetSchedulerRate(unsigned long hz) { st().rate_hz = static_cast<double>(hz); }

#ifndef STANDIN_HD_OMIT_SCHEDULE
unsigned long hdScheduleAsynchronous(HDSchedulerCallback cb, void* data, unsigned short) {
  st().cb = cb;
  st().cb_data = data;
  return 1;
}
#endif

void hdUnschedule(unsigned long) { st().cb = nullptr; }

unsigned int hdCheckCalibration() { return 0x5000; }

}  // extern "C"

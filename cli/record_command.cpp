// `bristle record --brush B.json -o session.csv [--device auto|openhaptics|none]
//  [--trajectory T.csv] [--forces forces.csv] [--png out.png] [--duration S]`
// and `bristle replay session.csv --brush B.json -o out.png`.

#include <csignal>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/stroke_png.h"
#include "engine/atomic_output.h"
#include "engine/brush.h"
#include "engine/error.h"
#include "engine/temp_files.h"
#include "engine/trajectory.h"
#include "haptics/hdapi.h"
#include "haptics/live_session.h"
#include "haptics/none_device.h"
#include "haptics/openhaptics_device.h"
#include "haptics/session_file.h"

namespace bristle::cli {
namespace {

std::atomic<bool> g_interrupt{false};
extern "C" void onSignal(int) { g_interrupt.store(true); }

// Renders a session file: the same function for record --png and replay, so
// both give the same pixels.
void renderSession(const Brush& brush, const std::string& session_path,
                   const std::string& brush_hash, const StrokePngOptions& png,
                   const std::string& output) {
  haptics::Session session = haptics::loadSession(session_path, brush_hash);
  for (const std::string& w : session.warnings) printError("warning: " + w);
  // A live session may start with the brush held into the paper; the stroke
  // starts where the brush was first clear of it (as the live sim did).
  std::vector<TrajectorySample>& smp = session.trajectory.samples;
  size_t first = 0;
  while (first + 1 < smp.size() && !haptics::brushClearOfCanvas(brush, smp[first].pose)) ++first;
  if (first > 0) {
    printError("warning: " + session_path + ": the brush starts in the paper; the stroke starts "
               "at line " + std::to_string(smp[first].line));
    smp.erase(smp.begin(), smp.begin() + static_cast<long>(first));
  }
  validateTrajectoryForBrush(session.trajectory, brush);
  renderStrokePng(brush, session.trajectory, png, output);
}

std::unique_ptr<haptics::Device> openDevice(const RecordArgs& args, bool* is_none) {
  auto none = [&]() -> std::unique_ptr<haptics::Device> {
    *is_none = true;
    if (args.trajectory.empty())
      throw Error(ExitCode::kUsage,
                  "--device none: needs --trajectory T.csv to play as the stylus");
    return std::make_unique<haptics::NoneDevice>(loadTrajectory(args.trajectory));
  };
  if (args.device == "none") return none();
  const std::string lib = haptics::hd::hdLibraryPath();
  if (args.device == "openhaptics") {
    auto dev = std::make_unique<haptics::OpenHapticsDevice>(lib);
    if (!dev->notice().empty()) printError("notice: " + dev->notice());
    return dev;
  }
  // auto: OpenHaptics if it opens, else none.
  try {
    auto dev = std::make_unique<haptics::OpenHapticsDevice>(lib);
    if (!dev->notice().empty()) printError("notice: " + dev->notice());
    return dev;
  } catch (const Error& e) {
    if (e.code() != ExitCode::kUnavailable || args.trajectory.empty()) throw;
    printError(std::string("notice: no haptic device (") + e.what() +
               "); falling back to --device none");
    return none();
  }
}

const char* endText(haptics::ServoLoop::End e) {
  switch (e) {
    case haptics::ServoLoop::End::kStopRequested: return "stopped";
    case haptics::ServoLoop::End::kEndOfInput: return "end of the trajectory";
    case haptics::ServoLoop::End::kDuration: return "--duration reached";
    case haptics::ServoLoop::End::kDeviceError: return "device error";
    case haptics::ServoLoop::End::kRunning: break;
  }
  return "running";
}

// The render of a session (record --png, replay): the same options for both,
// checked before anything runs.
template <class Args>
StrokePngOptions sessionPngOptions(const Args& args, const std::string& session) {
  StrokePngOptions png;
  static_cast<PaintOptions&>(png) = args;
  png.solver = args.solver;
  png.px_per_mm = args.px_per_mm;
  png.inputs = {args.brush, session};
  checkStrokePngOptions(png);
  return png;
}

}  // namespace

int runRecord(const RecordArgs& args) {
  const StrokePngOptions png = sessionPngOptions(args, args.output);
  // Every output is checked before the session file is opened (which
  // truncates it): none is an input or another output, each can be created.
  checkOutputs({{"-o", args.output}, {"--forces", args.forces}, {"--png", args.png}},
               {{"--brush", args.brush}, {"--trajectory", args.trajectory}});
  const Brush brush = loadBrush(args.brush);
  const std::string hash = haptics::brushFileHash(args.brush);
  checkCanCreate(args.output);
  if (!args.forces.empty()) checkCanCreate(args.forces);
  if (!args.png.empty()) checkCanCreate(args.png);

  bool is_none = false;
  std::unique_ptr<haptics::Device> device = openDevice(args, &is_none);
  if (is_none) {
    // The played trajectory is planned as its replay will be, before the session
    // is opened: one over the step limits (docs/errors.md) would record for
    // days a session that no replay could render.
    const Trajectory played = loadTrajectory(args.trajectory);
    validateTrajectoryForBrush(played, brush);
    planStepTimes(played, brush, SimOptions{});
  }

  haptics::SessionHeader header;
  header.device_model = device->model();
  header.servo_rate_hz = device->servoRateHz();
  header.session_rate_hz = args.session_rate_hz;
  header.brush_path = args.brush;
  header.brush_hash = hash;
  haptics::SessionWriter writer(args.output, args.forces, header);

  haptics::LiveOptions live;
  live.sim_rate_hz = args.sim_rate_hz;
  live.solver = args.live_solver;
  live.servo.duration_s = args.duration_s;
  live.interrupt = &g_interrupt;
  live.notice = [](const std::string& m) { printError("notice: " + m); };
  g_interrupt = false;
  std::signal(SIGINT, onSignal);
  std::signal(SIGTERM, onSignal);
  const haptics::LiveResult r = haptics::runLiveSession(brush, device.get(), &writer, live);
  installTempFileCleanup();  // the --png render's temporary file

  if (!args.quiet)
    std::fprintf(stderr,
                 "bristle: %s: %llu servo ticks, %llu sim frames, %ld session rows, largest "
                 "force %.3f N (device max %.2f N)%s\n",
                 endText(r.end), static_cast<unsigned long long>(r.servo_ticks),
                 static_cast<unsigned long long>(r.sim_frames), r.session_rows, r.max_force_n,
                 device->nominalMaxForceN(),
                 r.dropped_samples > 0 ? ", some samples dropped" : "");
  if (r.device_errors > 0 && r.end != haptics::ServoLoop::End::kDeviceError)
    printError("warning: " + std::to_string(r.device_errors) +
               " device errors (force zeroed for those ticks)");
  if (r.end == haptics::ServoLoop::End::kDeviceError) {
    char code[16];
    std::snprintf(code, sizeof code, "0x%04x", r.error.code);
    throw Error(ExitCode::kUnavailable,
                device->model() + ": device error " + code + " (" +
                    (r.error.message != nullptr ? r.error.message : "unknown") +
                    "): force zeroed and the session ended; " + args.output +
                    " holds it up to the error");
  }
  if (!args.png.empty()) {
    renderSession(brush, args.output, hash, png, args.png);
    if (!args.quiet) std::cout << args.png << "\n";
  }
  if (!args.quiet) std::cout << args.output << "\n";
  return 0;
}

int runReplay(const ReplayArgs& args) {
  const StrokePngOptions png = sessionPngOptions(args, args.session);
  checkOutputs({{"-o", args.output}}, {{"session", args.session}, {"--brush", args.brush}});
  const Brush brush = loadBrush(args.brush);
  checkCanCreate(args.output);
  renderSession(brush, args.session, haptics::brushFileHash(args.brush), png, args.output);
  if (!args.quiet) std::cout << args.output << "\n";
  return 0;
}

}  // namespace bristle::cli

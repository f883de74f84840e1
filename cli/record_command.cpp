// `bristle record --brush B.json -o session.csv [--device auto|openhaptics|none]
//  [--trajectory T.csv] [--forces forces.csv] [--png out.png] [--duration S]`
// and `bristle replay session.csv --brush B.json -o out.png`.

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <cstdio>
#include <iostream>
#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/inputs.h"
#include "cli/run_stats.h"
#include "cli/session_render.h"
#include "cli/stroke_png.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/formats/input_warnings.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/base/temp_files.h"
#include "engine/model/trajectory.h"
#include "haptics/hdapi.h"
#include "haptics/live_session.h"
#include "haptics/none_device.h"
#include "haptics/openhaptics_device.h"
#include "haptics/session_file.h"

namespace bristle::cli {
namespace {

std::atomic<bool> g_interrupt{false};
extern "C" void onSignal(int) { g_interrupt.store(true); }

// Renders a session: the same function for record --png and replay, so both
// give the same pixels. `warn_inputs`: tell what looks like a mistake in the
// brush and the session (replay; record told it of the brush and the played
// trajectory before it began).
void renderSession(const Brush& brush, haptics::Session session, const std::string& session_path,
                   const StrokePngOptions& png, const std::string& output, bool warn_inputs) {
  for (const std::string& w : session.warnings) printError("warning: " + w);
  // A session written by hand may give depths past first contact, as any
  // trajectory may.
  session.trajectory = resolveDepths(session.trajectory, brush);
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
  if (warn_inputs)
    printWarnings(strokeInputWarnings(brush, session.trajectory, strokeOptions(png).sim));
  renderStrokePng(brush, session.trajectory, png, output);
}

std::unique_ptr<haptics::Device> openDevice(const RecordArgs& args, const Brush& brush) {
  auto none = [&]() -> std::unique_ptr<haptics::Device> {
    if (args.trajectory.empty())
      throw Error(ExitCode::kUsage,
                  "--device none: needs --trajectory T.csv to play as the stylus");
    // The stylus plays the trajectory as this brush is held along it. It is
    // planned as its replay will be, before the session is opened: one over
    // the step limits (docs/errors.md) would record for days a session that no
    // replay could render.
    Trajectory played = resolveDepths(loadTrajectoryArg(args.trajectory, brush), brush);
    validateTrajectoryForBrush(played, brush);
    const double steps = plannedStepCount(played, brush, SimOptions{});
    // Played in real time: a trajectory in milliseconds would record for hours.
    const std::string w = trajectoryWarning(played, steps, &brush, SimOptions{});
    auto device = std::make_unique<haptics::NoneDevice>(std::move(played));
    if (!w.empty()) printWarnings({w});
    return device;
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
    if (e.code() != ExitCode::kUnavailable) throw;
    if (args.trajectory.empty())
      throw Error(e.code(), std::string(e.what()) +
                                "; or, without a device, --device none --trajectory T.csv "
                                "plays a trajectory as the stylus");
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
StrokePngOptions sessionPngOptions(const SessionRender& r, const std::string& brush_file,
                                   const std::string& session) {
  StrokePngOptions png;
  static_cast<PaintOptions&>(png) = r;
  png.solver = r.solver;
  png.solver_max_iterations = r.solver_max_iterations;
  png.ipopt_options = r.ipopt_options;
  png.px_per_mm = r.px_per_mm;
  png.inputs = {brush_file, session};
  checkStrokePngOptions(png);
  return png;
}

// The render options a session's header records, read by the parser of the
// options themselves and checked as a render checks them: a value that breaks
// an option's rule is a data error (65) naming the session, also when replay
// is given that option (the file is broken either way). Options the header
// does not record keep their defaults.
SessionRender recordedRender(const haptics::Session& session, const std::string& session_path) {
  SessionRender r;
  CLI::App parser;
  addSessionRenderOptions(&parser, r, "", "");
  requireFiniteNumbers(parser);
  std::vector<std::string> words = sessionRenderWords(session, session_path);
  std::reverse(words.begin(), words.end());  // CLI11 takes the words last first
  try {
    parser.parse(words);
    sessionPngOptions(r, "", "");
  } catch (const CLI::ParseError& e) {
    throw Error(ExitCode::kDataError, session_path + ": header: " + e.what());
  } catch (const Error& e) {
    throw Error(ExitCode::kDataError, session_path + ": header: " + e.what());
  }
  return r;
}

// What a session's "# brush:" line records of --brush: a library name as
// given, a file as its absolute path, so that replay finds it from anywhere.
std::string recordedBrush(const std::string& ref, const std::string& file) {
  if (isBrushName(ref)) return ref;
  return std::filesystem::absolute(file).lexically_normal().string();
}

// The brush of a session's header ("# brush: round" or a path) as a file: a
// name is looked up in the library; a relative path is taken from the working
// folder, else from the session's folder. kUsage when the header names none.
std::string brushOfSession(const haptics::Session& session, const std::string& session_path) {
  const auto it = session.header.find("brush");
  if (it == session.header.end() || it->second.empty())
    throw Error(ExitCode::kUsage, session_path +
                                      ": the header records no brush (no '# brush:' line); "
                                      "give --brush");
  const std::string& ref = it->second;
  if (isBrushName(ref)) return findBrushFile(ref, session_path + ": # brush:");
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::path(ref).is_absolute() || fs::exists(fs::symlink_status(ref, ec))) return ref;
  const fs::path beside = fs::path(session_path).parent_path() / ref;
  return fs::exists(fs::symlink_status(beside, ec)) ? beside.string() : ref;
}

}  // namespace

int runRecord(const RecordArgs& args) {
  checkPngOutputName("record", "--png", args.png, true);
  const std::string brush_file = findBrushFile(args.brush, "--brush");
  const StrokePngOptions png = sessionPngOptions(args, brush_file, args.output);
  sessionRenderHeader(args);  // refused before the session starts, as the options above
  // Every output is checked before the session file is opened (which
  // truncates it): none is an input or another output, each can be created.
  checkCliFiles({{"-o", args.output}, {"--forces", args.forces}, {"--png", args.png}},
                {{"--brush", brush_file}, {"--trajectory", args.trajectory}}, {"--png"},
                {"--trajectory"});
  const Brush brush = loadBrush(brush_file);
  const std::string hash = haptics::brushFileHash(brush_file);
  checkCanCreate(args.output);
  if (!args.forces.empty()) checkCanCreate(args.forces);
  if (!args.png.empty()) checkCanCreateArg(args.png);

  std::unique_ptr<haptics::Device> device = openDevice(args, brush);
  // Once the device (and the trajectory it plays) passed every check.
  if (const std::string w = brushScaleWarning(brush); !w.empty()) printWarnings({w});

  haptics::SessionHeader header;
  header.device_model = device->model();
  header.servo_rate_hz = device->servoRateHz();
  header.session_rate_hz = args.session_rate_hz;
  header.brush_path = recordedBrush(args.brush, brush_file);
  header.brush_hash = hash;
  header.options = sessionRenderHeader(args);
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
    renderSession(brush, haptics::loadSession(args.output, hash), args.output, png, args.png,
                  false);
    if (!args.quiet && !isStdio(args.png)) std::cout << args.png << "\n";
  }
  // With --png -, stdout holds the PNG alone.
  if (!args.quiet && !isStdio(args.png)) std::cout << args.output << "\n";
  return 0;
}

int runReplay(const ReplayArgs& args) {
  checkPngOutputName("replay", "-o", args.output, true);
  checkCliFiles({{"-o", args.output}}, {{"session", args.session}}, {"-o"}, {});
  // The brush: --brush, whose hash differing from the recorded one is a
  // warning (the user chose it); else the session's own, which must be the
  // file it was recorded with.
  haptics::Session session;
  std::string brush_file;
  if (!args.brush.empty()) {
    brush_file = findBrushFile(args.brush, "--brush");
    session = haptics::loadSession(args.session, haptics::brushFileHash(brush_file));
  } else {
    session = haptics::loadSession(args.session);
    brush_file = brushOfSession(session, args.session);
    const std::string hash = haptics::brushFileHash(brush_file);
    const auto recorded = session.header.find("brush_fnv1a64");
    if (recorded == session.header.end())
      session.warnings.push_back(args.session +
                                 ": no brush_fnv1a64 header: cannot check the brush " +
                                 brush_file);
    else if (recorded->second != hash)
      throw Error(ExitCode::kDataError,
                  args.session + ": brush_fnv1a64 " + recorded->second + ": the brush " +
                      brush_file + " (from the header) is " + hash +
                      ": it changed since the recording; give --brush to replay with it anyway");
  }
  // The render: the header's options, less those given here.
  const SessionRender render = mergeSessionRender(recordedRender(session, args.session), session,
                                                  args, args.given, args.session,
                                                  &session.warnings);
  const StrokePngOptions png = sessionPngOptions(render, brush_file, args.session);
  checkCliFiles({{"-o", args.output}}, {{"session", args.session}, {"--brush", brush_file}},
                {"-o"}, {});
  const Brush brush = loadBrush(brush_file);
  checkCanCreateArg(args.output);
  renderSession(brush, std::move(session), args.session, png, args.output, true);
  if (!args.quiet && !isStdio(args.output)) std::cout << args.output << "\n";
  return 0;
}

Subcommand registerRecord(CLI::App& app) {
  auto rec = std::make_shared<RecordArgs>();
  CLI::App* record = app.add_subcommand(
      "record", "Paint live with a haptic device (or play a trajectory) and record the session");
  record->footer(
      "Examples:\n"
      "  bristle record --brush round -o session.csv --png live.png\n"
      "  bristle record --device none --trajectory scenes/trajectories/s-curve.csv \\\n"
      "      --brush round -o session.csv --forces forces.csv\n"
      "The session (bristle-trajectory/1 with buttons and forces) is written as it goes;\n"
      "its header records the brush and the options of the --png render, with which\n"
      "bristle replay renders it again.\n"
      "Ends on Ctrl-C, --duration, or the end of --trajectory. BRISTLE_HD_LIBRARY names\n"
      "the OpenHaptics library (default libHD.so). Exit 69: device unavailable or failed.");
  record->add_option("--brush", rec->brush,
                     "Brush: a library name (round) or a file (bristle-brush/1 JSON)")
      ->required();
  record->add_option("-o,--output", rec->output, "Session file to write (CSV)")->required();
  record->add_option("--device", rec->device, "Haptic device")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "openhaptics", "none"}));
  record->add_option("--trajectory", rec->trajectory,
                     "Trajectory the 'none' device plays as the stylus (bristle-trajectory/1; - "
                     "reads stdin)");
  record->add_option("--forces", rec->forces, "Write every servo tick's force (CSV, 1 kHz)");
  record->add_option("--png", rec->png,
                     "Render the recorded stroke to this PNG at the end (PNG only: .jpg ... are "
                     "refused; - writes it to stdout)");
  record->add_option("--duration", rec->duration_s, "Stop after this many seconds (0: no limit)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 86400.0));
  record->add_option("--sim-rate-hz", rec->sim_rate_hz, "Simulation frames per second")
      ->capture_default_str()
      ->check(CLI::Range(5.0, 500.0));
  record->add_option("--session-rate-hz", rec->session_rate_hz, "Session rows per second")
      ->capture_default_str()
      ->check(CLI::Range(10.0, 1000.0));
  addSolverOption(
      record, "--live-solver", [rec](SolverKind k) { rec->live_solver = k; },
      "Spine solver of the live simulation (SLSQP keeps 30 Hz on 2 cores)",
      solverKindName(rec->live_solver));
  addSessionRenderOptions(record, *rec, "Resolution of --png",
                          "Spine solver of the --png render (as replay's)");
  record->add_flag("-q,--quiet", rec->quiet, "No summary, no output paths on stdout");
  return {record, [rec] { return runRecord(*rec); }};
}

Subcommand registerReplay(CLI::App& app) {
  auto rep = std::make_shared<ReplayArgs>();
  CLI::App* replay =
      app.add_subcommand("replay", "Render a recorded session (same pixels as live)");
  replay->footer(
      "Examples:\n"
      "  bristle replay session.csv -o replay.png\n"
      "  bristle replay session.csv --brush flat -o as-flat.png\n"
      "  bristle replay session.csv --px-per-mm 16 -o large.png\n"
      "The render takes the options the session's header records (those of record's\n"
      "--png: --paint, --px-per-mm, --solver, ...), so that it is the live --png byte for\n"
      "byte. An option given here wins, with a warning when the header's differs. The\n"
      "defaults shown above apply only to an older session whose header has none.\n"
      "Without --brush, the brush is the one the session's header records (a library\n"
      "name, or a file's path), and it must be the same file: a hash that differs from\n"
      "the header's brush_fnv1a64 is an error (65). With --brush, it is a warning.");
  replay->add_option("session", rep->session, "Session file (from bristle record)")->required();
  replay->add_option("--brush", rep->brush,
                     "Brush, instead of the one the session's header records (a library name "
                     "or a file)");
  addPngOutput(replay, rep->output);
  addSessionRenderOptions(replay, *rep, "Canvas resolution (pixels per mm)", "Spine solver");
  replay->add_flag("-q,--quiet", rep->quiet, "No output path on stdout");
  return {replay, [replay, rep] {
            rep->given = givenOptions(replay);
            return runReplay(*rep);
          }};
}

}  // namespace bristle::cli

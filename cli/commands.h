#pragma once
// One function per subcommand, each returning its exit code (docs/design.md,
// "Style habits", item 12), and one per subcommand that registers it: its
// options, help and examples, in the subcommand's own file. cli/main.cpp
// calls the registrations and runs the subcommand that was parsed.

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/paint_options.h"
#include "engine/dynamics/simulation.h"
#include "engine/solvers/solver_pair.h"

namespace CLI {
class App;
}

namespace bristle {
struct CanvasGrid;
}

namespace bristle::cli {

// A registered subcommand: its CLI11 subcommand, and what runs it once its
// options are parsed (returning the exit code). `check`, when set, holds the
// checks the parsed options get before any file is read, those CLI11 cannot
// make (an option a scene sets itself, a paint's name); `run` makes them too.
struct Subcommand {
  Subcommand(CLI::App* a, std::function<int()> r, std::function<void()> c = {})
      : app(a), run(std::move(r)), check(std::move(c)) {}
  CLI::App* app = nullptr;
  std::function<int()> run;
  std::function<void()> check;
};
// Every subcommand but `help`, registered on `app` in the order of bristle
// --help (cli/commands.cpp); numbers given them must be finite.
std::vector<Subcommand> registerCommands(CLI::App& app);

// Parses `args` (the words after the program's name, e.g. {"render", "--brush",
// "b.json", ...}) as bristle's command line and makes the command's checks
// (Subcommand::check) without running it: a command line a batch job or a
// golden would run is checked before it runs. Throws kUsage with CLI11's or
// the check's message.
void checkCommandLine(const std::vector<std::string>& args);

// The long names ("--paint") of the options given on the command line of `app`.
std::vector<std::string> givenOptions(const CLI::App* app);

Subcommand registerRender(CLI::App& app);
Subcommand registerValidate(CLI::App& app);
Subcommand registerBrushes(CLI::App& app);
Subcommand registerPigments(CLI::App& app);
Subcommand registerPreview(CLI::App& app);
Subcommand registerRecord(CLI::App& app);
Subcommand registerReplay(CLI::App& app);
Subcommand registerSheet(CLI::App& app);
Subcommand registerBatch(CLI::App& app);
Subcommand registerCompare(CLI::App& app);
Subcommand registerImport(CLI::App& app);  // cli/import_command.cpp
Subcommand registerMeasure(CLI::App& app);  // cli/measure_command.cpp
Subcommand registerFit(CLI::App& app);      // cli/fit_command.cpp

struct RenderArgs : PaintOptions {  // paint and paper: cli/paint_options.h
  std::string scene;  // positional: a bristle-scene/1 file instead of --brush/--trajectory
  std::vector<std::string> given;  // the options given on the command line ("--trace", ...)
  std::string brush, trajectory, output;
  std::string trace, forces, stats;  // optional outputs
  SolverKind solver = SolverKind::kIpopt;
  double px_per_mm = 8;
  double max_step_mm = 0.25;
  double steady_step_mm = SimOptions{}.steady_step_mm;
  double min_rate_hz = 120;
  double contact_band_mm = 0.1;
  int solver_max_iterations = kDefaultSolverMaxIterations;  // also a scene's
  int threads = 0;  // --threads (0: render::defaultRenderThreads()); also a scene's
  std::vector<std::string> ipopt_options;  // NAME=VALUE
  std::string preset;  // --preset: bristle/render.h's presetOptions, under the step options given
  std::vector<double> offset_mm;           // x, y, z added to every handle position
  bool quiet = false;
  std::string batch_key;  // --batch-key (hidden): from `bristle batch` (batch/job_key.h)
};
int runRender(const RenderArgs& args);
// `bristle render`'s checks of its options alone (its Subcommand::check): with a
// scene, only the options a scene leaves open; with a stroke, the paint, paper
// and solver options as the stroke's render reads them.
void checkRenderOptions(const RenderArgs& args);
// A whole scene (called by runRender when args.scene is set).
int runRenderScene(const RenderArgs& args);
// kUsage for an option given with a scene that the scene sets itself.
void checkSceneOptions(const RenderArgs& args);

int runValidate(const std::vector<std::string>& files);

struct PreviewArgs {
  std::string brush, trajectory, output;
  double at_s = 0;
  std::vector<double> offset_mm;
  int width_px = 800, height_px = 600;
  double px_per_mm = 8;
  double contact_band_mm = 0.1;
  bool quiet = false;
  std::string batch_key;  // --batch-key (hidden): from `bristle batch`
};
int runPreview(const PreviewArgs& args);

// Lists the brushes (*.json) of the library's folders, in lookup order, each
// name once (from the first folder holding it).
int runBrushes(const std::vector<std::string>& library_dirs);

// Lists the pigment table; swatches: auto (on a terminal), always, never.
int runPigments(const std::string& swatches);

// `bristle record`: a live session with a haptic device (or a played
// trajectory), written as it goes; `bristle replay`: its render.
struct RecordArgs : SessionRender {  // of the --png render
  std::string brush, output, device = "auto", trajectory, forces, png;
  double duration_s = 0;       // 0: until Ctrl-C / end of the trajectory
  double sim_rate_hz = 30;
  double session_rate_hz = 100;
  SolverKind live_solver = SolverKind::kSlsqp;  // of the live simulation: it must keep up
  bool quiet = false;
};
int runRecord(const RecordArgs& args);

struct ReplayArgs : SessionRender {
  std::string session, brush, output;
  std::vector<std::string> given;  // the options given on the command line ("--paint", ...)
  bool quiet = false;
};
int runReplay(const ReplayArgs& args);

// `bristle sheet`: a grid of strokes, brushes x trajectories (engine/formats/sheet.h).
struct SheetArgs {
  std::string sheet, output;
  double px_per_mm = 0;  // 0: the sheet's
  std::optional<SolverKind> solver;  // nothing: the sheet's
  int solver_max_iterations = kDefaultSolverMaxIterations;
  int threads = 0;  // --threads (0: render::defaultRenderThreads())
  bool impasto = false;
  bool quiet = false;
  std::string batch_key;  // --batch-key (hidden): from `bristle batch`
};
int runSheet(const SheetArgs& args);
// `bristle batch`: the jobs of a manifest (batch/manifest.h), each in its own
// process, up to `jobs` at once (batch/batch_run.h).
struct BatchArgs {
  std::string manifest, out_dir, shard, log;
  int jobs = 1;
  int shard_count = 0;  // with JOB_COMPLETION_INDEX (Kubernetes)
  bool overwrite = false, json = false, dry_run = false, quiet = false;
  bool fail_on_warning = false;  // exit 1 when a job has warnings and none failed
  bool in_order = false;         // start jobs in the manifest's order, not longest first
};
int runBatch(const BatchArgs& args);

// `bristle compare A B`: image metrics against a tolerance; 0 within, 1 not.
// The limits are NaN unless given; they override the preset's.
struct CompareArgs {
  std::string a, b, diff;
  std::string tolerance;  // exact, strict, loose; empty: exact, or custom with limits
  double max_abs = kUnset, pixel_threshold = kUnset, max_percent_over = kUnset;
  double min_ssim = kUnset, min_psnr_db = kUnset;
  double diff_gain = 16;  // difference x gain of full scale saturates the red ramp
  std::string align;      // empty: pixel for pixel; "canvas": by the bristle:canvas text
  bool json = false;
  static constexpr double kUnset = std::numeric_limits<double>::quiet_NaN();
};
int runCompare(const CompareArgs& args);

// The PNG text "bristle:canvas": where the image lies on the canvas (mm).
std::string canvasText(const CanvasGrid& grid);

// Prints "bristle: <message>" on stderr.
void printError(const std::string& message);

// The end-of-run warning about steps whose solve failed (nothing if none did).
void warnFailedSolves(const SimStats& stats);

}  // namespace bristle::cli

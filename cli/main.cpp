// bristle: the command line. This file owns CLI11 (slow to compile: keep it in
// one translation unit) and maps errors to the exit codes of docs/design.md,
// "Exit codes".

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <functional>
#include <iostream>

#include "bristle/version.h"
#include "cli/commands.h"
#include "cli/inputs.h"
#include "engine/error.h"
#include "engine/temp_files.h"

namespace {

constexpr const char* kDescription =
    "bristle renders brush strokes from recorded 6-DOF stylus motion with the\n"
    "physically based 3D brush of Baxter & Lin (2004).\n";

constexpr const char* kFooter =
    "Examples:\n"
    "  bristle render --brush round \\\n"
    "                 --trajectory scenes/trajectories/s-curve.csv -o s.png --trace s.jsonl\n"
    "  bristle render --solver slsqp --brush flat \\\n"
    "                 --trajectory scenes/trajectories/straight-pull.csv -o flat.png\n"
    "  bristle render --brush round --trajectory - -o - < T.csv > out.png\n"
    "  bristle preview fan -o fan.png\n"
    "  bristle brushes\n"
    "  bristle pigments\n"
    "  bristle validate round scenes/trajectories/s-curve.csv\n"
    "  bristle record --brush round -o session.csv --png live.png\n"
    "  bristle replay session.csv -o replay.png\n"
    "  bristle compare golden/round-s-curve.png new.png --tolerance strict --diff d.png\n"
    "  bristle sheet scenes/sheets/library.json -o library-sheet.png\n"
    "  bristle batch scenes/batch/standard.json --out renders/ --jobs 2\n"
    "A brush is a library name (bristle brushes lists them) or a file; - is stdin for\n"
    "a trajectory and stdout for a PNG.\n"
    "\n"
    "Exit codes: 0 ok, 1 images differ (compare), 64 usage, 65 bad input\n"
    "data, 66 input missing, 69 haptic device unavailable (or failed), 70 internal\n"
    "error, 73 cannot create output, 74 I/O error.\n";

// Paint and paper options of a single-stroke render (render, record --png, replay).
void addPaintOptions(CLI::App* app, bristle::cli::PaintOptions& p) {
  app->add_option("--paint,--colour,--color", p.paint,
                  "Paint(s) on the brush: NAME[,NAME..], pigment names or #rrggbb")
      ->capture_default_str();
  app->add_option("--load", p.load,
                  "Loading: solid (one paint), across (2-3 paints side by side across the "
                  "brush's width), tip (body paint, tip paint)")
      ->capture_default_str()
      ->check(CLI::IsMember({"solid", "across", "tip"}));
  app->add_option("--amount", p.amount, "Paint on the brush, a fraction of its capacity (0, 1]")
      ->capture_default_str();
  app->add_option("--tip-length", p.tip_length,
                  "--load tip: share of the hair length the tip paint covers")
      ->capture_default_str();
  app->add_option("--mix", p.mix, "Pigment mixing: km (Kubelka-Munk) or rgb (linear RGB)")
      ->capture_default_str()
      ->check(CLI::IsMember({"km", "rgb"}));
  app->add_option("--paper-tooth", p.paper_tooth_mm,
                  "Depth of the paper's grain (mm); light strokes catch only its peaks")
      ->capture_default_str();
  app->add_option("--paper-scale", p.paper_scale_mm, "Feature size of the paper's grain (mm)")
      ->capture_default_str();
  app->add_option("--paper-seed", p.paper_seed, "Seed of the paper's grain")
      ->capture_default_str();
  app->add_flag("--impasto", p.impasto, "Light the paint's thickness from the upper left");
  app->add_option("--bits", p.bits, "Bits per PNG channel")
      ->capture_default_str()
      ->check(CLI::IsMember({8, 16}));
  app->add_option("--background", p.background, "Paper colour (#rrggbb)")
      ->capture_default_str();
}

// --solver and its like: a name on the command line, a SolverKind from there on.
// `set` receives the parsed kind; `shown` is the default --help shows (none if empty).
CLI::Option* addSolverOption(CLI::App* app, const std::string& name,
                             std::function<void(bristle::SolverKind)> set,
                             const std::string& help, const std::string& shown) {
  CLI::Option* o = app->add_option_function<std::string>(
      name, [set](const std::string& text) { set(*bristle::parseSolverKind(text)); }, help);
  if (!shown.empty()) o->default_str(shown);
  return o->check(CLI::IsMember({"ipopt", "slsqp"}));
}

// The iteration limit of the spine solvers, the same for every command that simulates.
void addSolverMaxIterations(CLI::App* app, int& max_iterations) {
  app->add_option("--solver-max-iterations", max_iterations,
                  "Iteration limit per solve (Ipopt iterations, SLSQP energy evaluations); a "
                  "spine that hits it with both solvers keeps its last state")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
}

}  // namespace

int main(int argc, char** argv) {
  using bristle::cli::printError;
  // Brush names, on the command line and in the scenes, sheets and manifests it reads.
  bristle::setBrushLibraryDirs(bristle::cli::cliBrushLibraryDirs());
  CLI::App app(kDescription, "bristle");
  app.footer(kFooter);
  app.set_version_flag("--version", std::string("bristle ") + bristle::kVersion);
  app.require_subcommand(0, 1);

  bristle::cli::RenderArgs r;
  CLI::App* render = app.add_subcommand("render", "Render a scene, or a stroke: a brush along a trajectory");
  render->footer(
      "Examples:\n"
      "  bristle render scenes/paintings/petals.json -o petals.png --impasto\n"
      "  bristle render --brush round \\\n"
      "      --trajectory scenes/trajectories/s-curve.csv -o s.png --trace s.jsonl\n"
      "  bristle render --brush flat --trajectory T.csv -o petal.png \\\n"
      "      --paint cadmium-red,titanium-white --load across --impasto\n"
      "  bristle render --brush round --trajectory T.csv -o dry.png \\\n"
      "      --paint burnt-umber --amount 0.15 --paper-tooth 0.06\n"
      "  bristle render --brush round --trajectory - -o - < T.csv | bristle compare ref.png -\n"
      "The canvas is sized to everything the brush can reach plus a 5 mm margin.\n"
      "Paints: a pigment name (bristle pigments lists them: ultramarine, cadmium-yellow,\n"
      "titanium-white, sumi-ink, ...) or #rrggbb.");
  render->add_option("scene", r.scene, "A scene (bristle-scene/1 JSON): a whole painting");
  render->add_option("--brush", r.brush, "Brush: a library name (round) or a file (bristle-brush/1 JSON)");
  render->add_option("--trajectory", r.trajectory, "Trajectory (bristle-trajectory/1 CSV); - reads stdin");
  render->add_option("-o,--output", r.output, "Output PNG; - writes it to stdout")->required();
  render->add_option("--trace", r.trace, "Write the per-step trace (JSON lines)");
  render->add_option("--forces", r.forces, "Write the force on the handle per step (CSV)");
  render->add_option("--stats", r.stats,
                     "Write the run's figures and warnings (JSON: painted pixels, failed "
                     "solves, paint laid down, ...)");
  addSolverOption(
      render, "--solver", [&r](bristle::SolverKind k) { r.solver = k; }, "Spine solver",
      bristle::solverKindName(r.solver));
  addSolverMaxIterations(render, r.solver_max_iterations);
  render->add_option("--offset-mm", r.offset_mm,
                     "Shift the trajectory by X Y Z mm (e.g. 0 0 10 to hold a longer brush "
                     "higher)")
      ->expected(3);
  render->add_option("--ipopt-option", r.ipopt_options,
                     "Extra Ipopt option NAME=VALUE (repeatable), e.g. mu_strategy=monotone");
  render->add_option("--px-per-mm", r.px_per_mm, "Canvas resolution (pixels per mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 100.0));
  render->add_option("--max-step-mm", r.max_step_mm,
                     "Largest motion of a spine root per simulation step (mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 5.0));
  render->add_option("--min-rate-hz", r.min_rate_hz, "Fewest simulation steps per second")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 10000.0));
  render->add_option("--contact-band-mm", r.clip_mm,
                     "Brush geometry below this height touches the paper (mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 2.0));
  addPaintOptions(render, r);
  render->add_flag("-q,--quiet", r.quiet, "No progress, no output path on stdout");

  std::vector<std::string> files;
  CLI::App* validate = app.add_subcommand("validate", "Check brush and scene (.json) and trajectory (.csv) files");
  validate->footer(
      "Examples:\n"
      "  bristle validate round\n"
      "  bristle validate scenes/brushes/flat.json scenes/trajectories/s-curve.csv\n"
      "  bristle validate scenes/paintings/calligraphy.json scenes/sheets/small.json\n"
      "Each file is checked on its own (a .csv is a trajectory; a .json a scene or a sheet\n"
      "when its format says so, else a brush), a scene or sheet with every file it names.\n"
      "Brushes and trajectories given together are then checked in pairs as render checks\n"
      "them before its run (the same messages): a brush that starts below the paper is\n"
      "exit 65, one that never comes within reach of it a warning. Exit: the first error's.");
  validate->add_option("files", files, "Files to check; a library brush by its name (round)")->required();

  // The library: the source tree's, else the install's; BRISTLE_BRUSHES points elsewhere.
  std::string library = std::getenv("BRISTLE_BRUSHES") ? std::getenv("BRISTLE_BRUSHES")
                                                        : bristle::cli::defaultBrushLibrary();
  CLI::App* brushes = app.add_subcommand("brushes", "List the brush library, one line each");
  brushes->footer(
      "Examples:\n"
      "  bristle brushes\n"
      "  bristle brushes --library scenes/brushes\n"
      "Each name listed works wherever a brush is taken (--brush round). A name is looked\n"
      "up as NAME.json in the source tree's scenes/brushes, then the install's\n"
      "share/bristle/brushes, then each folder of BRISTLE_BRUSH_PATH (colon-separated).\n"
      "A brush that contains '/' or ends in .json is a path, used as given.");
  brushes->add_option("--library", library, "Folder of brush files (default: $BRISTLE_BRUSHES, "
                                            "else the source tree's scenes/brushes, else the "
                                            "install's share/bristle/brushes)");

  std::string swatches = "auto";
  CLI::App* pigments = app.add_subcommand("pigments", "List the pigment table: names, colours, Kubelka-Munk K and S");
  pigments->footer(
      "Examples:\n"
      "  bristle pigments\n"
      "  bristle pigments --swatches never\n"
      "The colour is what a film of the paint (2 units thick) shows over white paper.\n"
      "Any name listed, or a colour #rrggbb, works as --paint. See docs/paint.md.");
  pigments->add_option("--swatches", swatches,
                       "Colour swatches (24-bit ANSI): auto (when stdout is a terminal), "
                       "always, never")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "always", "never"}));

  bristle::cli::PreviewArgs pv;
  CLI::App* preview = app.add_subcommand("preview", "Draw a brush in 3D, at rest or at a time of a trajectory");
  preview->footer(
      "Examples:\n"
      "  bristle preview fan -o fan.png\n"
      "  bristle preview round --trajectory scenes/trajectories/s-curve.csv \\\n"
      "      --at 1.2 -o round-1.2s.png\n"
      "The inset shows the footprint: what of the brush touches the paper.");
  preview->add_option("brush", pv.brush, "Brush: a library name (round) or a file (bristle-brush/1 JSON)")->required();
  preview->add_option("-o,--output", pv.output, "Output PNG; - writes it to stdout")->required();
  CLI::Option* pv_traj =
      preview->add_option("--trajectory", pv.trajectory, "Simulate along this trajectory (- reads stdin) ...");
  // Without a trajectory there is no time to go to and nothing to shift: refused
  // (exit 64), not silently ignored.
  preview->add_option("--at", pv.at_s,
                      "... up to this time (s): the last step at or before it of `bristle "
                      "render` (same --px-per-mm)")->capture_default_str()->needs(pv_traj);
  preview->add_option("--offset-mm", pv.offset_mm, "Shift the trajectory by X Y Z mm")->expected(3)->needs(pv_traj);
  preview->add_option("--width", pv.width_px, "Image width (px)")->capture_default_str()->check(CLI::Range(64, 4096));
  preview->add_option("--height", pv.height_px, "Image height (px)")->capture_default_str()->check(CLI::Range(64, 4096));
  preview->add_option("--px-per-mm", pv.px_per_mm,
                      "Footprint resolution; as render's, it also sets how finely a step is split")->capture_default_str()->check(CLI::Range(0.5, 100.0));
  preview->add_flag("-q,--quiet", pv.quiet, "No output path on stdout");

  bristle::cli::RecordArgs rec;
  CLI::App* record = app.add_subcommand(
      "record", "Paint live with a haptic device (or play a trajectory) and record the session");
  record->footer(
      "Examples:\n"
      "  bristle record --brush round -o session.csv --png live.png\n"
      "  bristle record --device none --trajectory scenes/trajectories/s-curve.csv \\\n"
      "      --brush round -o session.csv --forces forces.csv\n"
      "The session (bristle-trajectory/1 with buttons and forces) is written as it goes.\n"
      "Ends on Ctrl-C, --duration, or the end of --trajectory. BRISTLE_HD_LIBRARY names\n"
      "the OpenHaptics library (default libHD.so). Exit 69: device unavailable or failed.");
  record->add_option("--brush", rec.brush, "Brush: a library name (round) or a file (bristle-brush/1 JSON)")->required();
  record->add_option("-o,--output", rec.output, "Session file to write (CSV)")->required();
  record->add_option("--device", rec.device, "Haptic device")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "openhaptics", "none"}));
  record->add_option("--trajectory", rec.trajectory,
                     "Trajectory the 'none' device plays as the stylus (bristle-trajectory/1; - reads stdin)");
  record->add_option("--forces", rec.forces, "Write every servo tick's force (CSV, 1 kHz)");
  record->add_option("--png", rec.png, "Render the recorded stroke to this PNG at the end (- writes it to stdout)");
  record->add_option("--duration", rec.duration_s, "Stop after this many seconds (0: no limit)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 86400.0));
  record->add_option("--sim-rate-hz", rec.sim_rate_hz, "Simulation frames per second")
      ->capture_default_str()
      ->check(CLI::Range(5.0, 500.0));
  record->add_option("--session-rate-hz", rec.session_rate_hz, "Session rows per second")
      ->capture_default_str()
      ->check(CLI::Range(10.0, 1000.0));
  record->add_option("--px-per-mm", rec.px_per_mm, "Resolution of --png")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 100.0));
  addSolverOption(
      record, "--solver", [&rec](bristle::SolverKind k) { rec.solver = k; },
      "Spine solver of the --png render (as replay's)", bristle::solverKindName(rec.solver));
  addSolverOption(
      record, "--live-solver", [&rec](bristle::SolverKind k) { rec.live_solver = k; },
      "Spine solver of the live simulation (SLSQP keeps 30 Hz on 2 cores)",
      bristle::solverKindName(rec.live_solver));
  addPaintOptions(record, rec);
  record->add_flag("-q,--quiet", rec.quiet, "No summary, no output paths on stdout");

  bristle::cli::ReplayArgs rep;
  CLI::App* replay = app.add_subcommand("replay", "Render a recorded session (same pixels as live)");
  replay->footer(
      "Examples:\n"
      "  bristle replay session.csv -o replay.png\n"
      "  bristle replay session.csv --brush flat -o as-flat.png\n"
      "Without --brush, the brush is the one the session's header records (a library\n"
      "name, or a file's path), and it must be the same file: a hash that differs from\n"
      "the header's brush_fnv1a64 is an error (65). With --brush, it is a warning.\n"
      "Give the --png options of the recording (--paint, --px-per-mm, ...) to get its pixels.");
  replay->add_option("session", rep.session, "Session file (from bristle record)")->required();
  replay->add_option("--brush", rep.brush,
                     "Brush, instead of the one the session's header records (a library name or a file)");
  replay->add_option("-o,--output", rep.output, "Output PNG; - writes it to stdout")->required();
  replay->add_option("--px-per-mm", rep.px_per_mm, "Canvas resolution (pixels per mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 100.0));
  addSolverOption(
      replay, "--solver", [&rep](bristle::SolverKind k) { rep.solver = k; }, "Spine solver",
      bristle::solverKindName(rep.solver));
  addPaintOptions(replay, rep);
  replay->add_flag("-q,--quiet", rep.quiet, "No output path on stdout");

  bristle::cli::SheetArgs sh;
  CLI::App* sheet = app.add_subcommand(
      "sheet", "Render a stroke sheet: a labelled grid of brushes x trajectories");
  sheet->footer(
      "Examples:\n"
      "  bristle sheet scenes/sheets/library.json -o library-sheet.png\n"
      "  bristle sheet scenes/sheets/small.json -o small.png --px-per-mm 4 --solver slsqp\n"
      "Every cell is one brush along one trajectory on its own canvas, all at one scale,\n"
      "centred on its inked area; rows are brushes (their names), columns trajectories\n"
      "(their file stems). The sheet format is docs/sheet-format.md.");
  sheet->add_option("sheet", sh.sheet, "Sheet file (bristle-sheet/1 JSON)")->required();
  sheet->add_option("-o,--output", sh.output, "Output PNG; - writes it to stdout")->required();
  sheet->add_option("--px-per-mm", sh.px_per_mm, "Resolution, instead of the sheet's px_per_mm")
      ->check(CLI::Range(0.5, 100.0));
  addSolverOption(
      sheet, "--solver", [&sh](bristle::SolverKind k) { sh.solver = k; },
      "Spine solver, instead of the sheet's", "");
  addSolverMaxIterations(sheet, sh.solver_max_iterations);
  sheet->add_flag("--impasto", sh.impasto, "Light the paint's thickness from the upper left");
  sheet->add_flag("-q,--quiet", sh.quiet, "No progress, no summary, no output path on stdout");

  bristle::cli::BatchArgs ba;
  CLI::App* batch = app.add_subcommand("batch", "Render the jobs of a manifest, a few at a time");
  batch->footer(
      "Examples:\n"
      "  bristle batch scenes/batch/standard.json --out renders/ --jobs 2\n"
      "  bristle batch jobs.json --out renders/ --shard 1/4 --json\n"
      "  sbatch --array=0-3 scripts/slurm/bristle-batch.sbatch jobs.json renders/\n"
      "Each job runs in its own bristle process; outputs appear only complete, and are\n"
      "skipped when already up to date (the job's key is stored in the PNG). A failed job\n"
      "does not stop the others. Without --shard, the shard comes from Slurm's\n"
      "SLURM_ARRAY_TASK_ID/_COUNT/_MIN or Kubernetes' JOB_COMPLETION_INDEX (+ --shard-count).\n"
      "SIGTERM or Ctrl-C abandons running jobs and leaves no partial file.\n"
      "Each job's log entry lists its warnings and figures (painted pixels, failed solves,\n"
      "paint laid down); the warnings are also printed on stderr.\n"
      "Exit: 0 when every job of the shard succeeded, else the first failed job's code;\n"
      "1 with --fail-on-warning when a job has warnings and none failed;\n"
      "143/130 when stopped by SIGTERM/SIGINT. See docs/batch.md.");
  batch->add_option("manifest", ba.manifest, "Batch manifest (bristle-batch/1 JSON)")->required();
  batch->add_option("--out", ba.out_dir, "Output folder (created if missing)")->required();
  batch->add_option("-j,--jobs", ba.jobs, "Jobs rendered at once (processes)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  batch->add_option("--shard", ba.shard, "Render only shard I of N (I/N, 0-based): jobs k with k mod N = I");
  batch->add_option("--shard-count", ba.shard_count,
                    "Shard count for a Kubernetes Indexed Job (JOB_COMPLETION_INDEX is the index)")
      ->check(CLI::Range(1, 100000));
  batch->add_flag("--overwrite", ba.overwrite, "Render every job, even when its output is up to date");
  batch->add_flag("--json", ba.json, "One JSON object per job on stdout, then a summary");
  batch->add_option("--log", ba.log, "Job log (JSON lines; default OUT/logs/batch-<time>-<host>-<pid>-shard-I-of-N.jsonl)");
  batch->add_flag("--dry-run", ba.dry_run, "List the shard's jobs and whether they would render, then a summary line; render nothing");
  batch->add_flag("--fail-on-warning", ba.fail_on_warning,
                  "Exit 1 when a job has warnings (and none failed): a brush that never touched "
                  "the paper, no visible paint, failed solves");
  batch->add_flag("-q,--quiet", ba.quiet, "No progress, no summary");

  bristle::cli::CompareArgs cmp;
  CLI::App* compare = app.add_subcommand("compare", "Compare two PNGs: hash, differences, PSNR, SSIM against a tolerance");
  compare->footer(
      "Examples:\n"
      "  bristle compare golden/round-s-curve.png new.png --tolerance strict --diff d.png\n"
      "  bristle compare a.png b.png --json --max-abs 4 --min-ssim 0.995\n"
      "  bristle compare golden/round-s-curve.png new.png --align canvas --tolerance strict\n"
      "Differences are in 8-bit steps (1/255 of full scale) whatever the bit depth.\n"
      "Presets: exact (equal pixels; the default), strict (max abs <= 2, <= 0.1% of pixels\n"
      "over 1), loose (SSIM >= 0.99, <= 1% of pixels over 8). Exit 0 within tolerance, 1 not\n"
      "(also when the sizes differ).\n"
      "--align canvas compares two renders (strokes or scenes) where their canvases overlap,\n"
      "by the bristle:canvas text each PNG carries, so renders on canvases of different\n"
      "extent compare; ink outside the overlap counts as differing pixels. Both must have\n"
      "one px/mm; a PNG without the text is refused (65). See docs/golden-tests.md.");
  compare->add_option("a", cmp.a, "First PNG (the reference); - reads stdin")->required();
  compare->add_option("b", cmp.b, "Second PNG; - reads stdin")->required();
  compare->add_option("--diff", cmp.diff, "Write the amplified difference image (PNG)");
  compare->add_option("--align", cmp.align,
                      "canvas: compare two renders where their canvases overlap, by the "
                      "bristle:canvas text each PNG carries")
      ->check(CLI::IsMember({"canvas"}));
  compare->add_option("--diff-gain", cmp.diff_gain, "Amplification of --diff")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 65535.0));
  compare->add_flag("--json", cmp.json, "One JSON object on stdout: metrics, tolerance, verdict");
  compare->add_option("--tolerance", cmp.tolerance, "Preset: exact, strict or loose")
      ->check(CLI::IsMember({"exact", "strict", "loose"}));
  compare->add_option("--max-abs", cmp.max_abs, "Largest channel difference allowed (8-bit steps)")
      ->check(CLI::Range(0.0, 255.0));
  compare->add_option("--pixel-threshold", cmp.pixel_threshold,
                      "A pixel differs when a channel differs by more than this (8-bit steps)")
      ->check(CLI::Range(0.0, 255.0));
  compare->add_option("--max-percent-over", cmp.max_percent_over,
                      "Largest % of pixels over --pixel-threshold allowed")
      ->check(CLI::Range(0.0, 100.0));
  compare->add_option("--min-ssim", cmp.min_ssim, "Smallest SSIM allowed")
      ->check(CLI::Range(-1.0, 1.0));
  compare->add_option("--min-psnr", cmp.min_psnr_db, "Smallest PSNR allowed (dB)")
      ->check(CLI::Range(0.0, 1000.0));

  std::string help_topic;
  CLI::App* help = app.add_subcommand("help", "Show help for bristle or one command");
  help->footer(
      "Examples:\n"
      "  bristle help\n"
      "  bristle help validate\n"
      "Each command's help (also COMMAND --help) shows its options and its own examples.");
  help->add_option("command", help_topic, "Command to explain");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    printError(e.what() + std::string(" (see bristle --help)"));
    return static_cast<int>(bristle::ExitCode::kUsage);
  }

  // SIGINT and SIGTERM remove the temporary files of unfinished outputs, then
  // end the process as they would have (`batch` and `record` stop more gently).
  bristle::installTempFileCleanup();
  try {
    if (render->parsed()) {
      for (const CLI::Option* o : render->get_options())
        if (o->count() > 0 && !o->get_positional()) r.given.push_back(o->get_name());
      return bristle::cli::runRender(r);
    }
    if (validate->parsed()) return bristle::cli::runValidate(files);
    if (brushes->parsed()) return bristle::cli::runBrushes(library);
    if (pigments->parsed()) return bristle::cli::runPigments(swatches);
    if (preview->parsed()) return bristle::cli::runPreview(pv);
    if (record->parsed()) return bristle::cli::runRecord(rec);
    if (replay->parsed()) return bristle::cli::runReplay(rep);
    if (sheet->parsed()) return bristle::cli::runSheet(sh);
    if (compare->parsed()) return bristle::cli::runCompare(cmp);
    if (batch->parsed()) return bristle::cli::runBatch(ba);
    if (help->parsed() && !help_topic.empty()) {
      for (CLI::App* sub : {render, validate, brushes, pigments, preview, record, replay, sheet, batch, compare}) {
        if (sub->get_name() == help_topic) {
          std::cout << sub->help("bristle");
          return 0;
        }
      }
      printError("help: unknown command '" + help_topic + "' (commands: render, preview, validate, brushes, pigments, record, replay, sheet, batch, compare)");
      return static_cast<int>(bristle::ExitCode::kUsage);
    }
    std::cout << app.help();
    return help->parsed() ? 0 : static_cast<int>(bristle::ExitCode::kUsage);
  } catch (const bristle::Error& e) {
    printError(e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    printError(std::string("internal error: ") + e.what());
    return static_cast<int>(bristle::ExitCode::kSoftware);
  }
}

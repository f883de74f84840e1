// `bristle render --brush B.json --trajectory T.csv -o out.png`

#include <cstdio>
#include <iostream>
#include <memory>

#include <algorithm>

#include "batch/job_key.h"
#include "bristle/render.h"
#include "bristle/version.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/inputs.h"
#include "cli/progress.h"
#include "cli/run_stats.h"
#include "cli/stroke_png.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/model/canvas.h"
#include "engine/paint/paint.h"
#include "engine/paint/pigments.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/formats/trace.h"
#include "engine/model/trajectory.h"
#include "engine/dynamics/stepper.h"
#include "render/image/compose.h"
#include "render/image/png_io.h"
#include "render/stroke_renderer.h"

namespace bristle::cli {

// World placement of the image, so that pixels can be mapped back to canvas mm.
std::string canvasText(const CanvasGrid& g) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x0_mm=%.6f y0_mm=%.6f px_per_mm=%.6f width_px=%d height_px=%d",
                g.x0_mm, g.y0_mm, g.px_per_mm, g.width_px, g.height_px);
  return buf;
}

void printError(const std::string& message) {
  std::cerr << "bristle: " << oneLine(message) << "\n";
}

void warnFailedSolves(const SimStats& stats) {
  const std::string w = failedSolvesWarning(stats);
  if (!w.empty()) printError("warning: " + w);
}

namespace {

// The figures and warnings of a stroke: those found before the run (already
// printed), then the ones it brought (printed as they are found).
RunStats strokeStats(const StrokePngResult& png_result, const std::string& traj_name,
                     const std::vector<std::string>& before) {
  const render::StrokeResult& result = png_result.stroke;
  RunStats stats;
  stats.warnings = before;
  stats.painted_pixels = png_result.ink_pixels;
  stats.pixels = png_result.pixels;
  stats.sim = result.stats;
  stats.paint_laid_mm3 = result.deposited_mm3;
  stats.paint_picked_up_mm3 = result.picked_up_mm3;
  if (!result.touched)
    stats.warn("the brush never touched the canvas (" + traj_name + "): the image is blank");
  else if (png_result.ink_pixels == 0)
    stats.warn("the brush touched the canvas (" + traj_name + ") but left no visible paint");
  if (const std::string w = failedSolvesWarning(result.stats); !w.empty()) stats.warn(w);
  return stats;
}

// --preset NAME: the preset's step options (bristle/render.h, presetOptions),
// each unless given on the command line itself (--ipopt-option given replaces
// the preset's Ipopt options, as Python's ipopt_options= does).
void applyPreset(const RenderArgs& args, StrokePngOptions* png) {
  if (args.preset.empty()) return;
  const api::RenderOptions preset = api::presetOptions(args.preset);
  const auto given = [&args](const char* name) {
    return std::find(args.given.begin(), args.given.end(), name) != args.given.end();
  };
  if (!given("--max-step-mm")) png->max_step_mm = preset.max_step_mm;
  if (!given("--steady-step-mm")) png->steady_step_mm = preset.steady_step_mm;
  if (!given("--min-rate-hz")) png->min_rate_hz = preset.min_rate_hz;
  if (!given("--ipopt-option")) png->ipopt_options = preset.ipopt_options;
}

// The options of a stroke's render (render --brush --trajectory).
StrokePngOptions strokePngOptionsOf(const RenderArgs& args) {
  StrokePngOptions png;
  png.solver = args.solver;
  png.solver_max_iterations = args.solver_max_iterations;
  png.ipopt_options = args.ipopt_options;
  png.px_per_mm = args.px_per_mm;
  png.contact_band_mm = args.contact_band_mm;
  png.max_step_mm = args.max_step_mm;
  png.steady_step_mm = args.steady_step_mm;
  png.min_rate_hz = args.min_rate_hz;
  png.threads = args.threads;
  static_cast<PaintOptions&>(png) = args;
  applyPreset(args, &png);
  return png;
}

// --offset-mm X Y Z (none when not given) moves every handle position.
void applyOffset(const std::vector<double>& offset_mm, Trajectory* trajectory) {
  if (offset_mm.size() != 3) return;
  const Eigen::Vector3d offset(offset_mm[0], offset_mm[1], offset_mm[2]);
  if (!offset.allFinite()) throw Error(ExitCode::kUsage, "--offset-mm: must be finite");
  if (offset.cwiseAbs().maxCoeff() > kMaxPositionMm)
    throw Error(ExitCode::kUsage, "--offset-mm: must be within +-100000 mm (the limit)");
  for (TrajectorySample& s : trajectory->samples) s.pose.position_mm += offset;
}

}  // namespace

void checkRenderOptions(const RenderArgs& args) {
  if (!args.scene.empty()) return checkSceneOptions(args);
  checkStrokePngOptions(strokePngOptionsOf(args));
}

int runRender(const RenderArgs& args) {
  checkPngOutputName("render", "-o", args.output, true);
  if (!args.scene.empty()) return runRenderScene(args);
  if (args.brush.empty() || args.trajectory.empty())
    throw Error(ExitCode::kUsage,
                "render: give a SCENE.json, or --brush and --trajectory (see bristle render --help)");
  StrokePngOptions png = strokePngOptionsOf(args);
  const std::string brush_file = findBrushFile(args.brush, "--brush");
  png.inputs = {brush_file, args.trajectory};
  checkRenderOptions(args);
  checkCliFiles({{"-o", args.output},
                 {"--trace", args.trace},
                 {"--forces", args.forces},
                 {"--stats", args.stats}},
                {{"--brush", brush_file}, {"--trajectory", args.trajectory}}, {"-o"},
                {"--trajectory"});

  const Brush brush = loadBrush(brush_file);
  // Depths past first contact become this brush's ferrule heights before any
  // offset moves the handle.
  Trajectory trajectory = resolveDepths(loadTrajectoryArg(args.trajectory, brush), brush);
  applyOffset(args.offset_mm, &trajectory);
  validateTrajectoryForBrush(trajectory, brush);
  render::canvasForStroke(brush, trajectory, strokeOptions(png));  // fails early if too large
  std::vector<std::string> input_warnings =
      strokeInputWarnings(brush, trajectory, strokeOptions(png).sim);

  // Fail before the long run if an output cannot be created; each output is
  // written to a temporary file and all are renamed only when every one was
  // written (engine/base/atomic_output.h).
  checkCanCreateArg(args.output);
  CommitGroup outputs;
  if (!args.stats.empty()) checkCanCreate(args.stats);
  std::unique_ptr<AtomicOutput> trace, forces;
  if (!args.trace.empty()) trace = std::make_unique<AtomicOutput>(args.trace);
  if (!args.forces.empty()) {
    forces = std::make_unique<AtomicOutput>(args.forces);
    forces->stream() << "t_s,fx_n,fy_n,fz_n\n";
    forces->stream().precision(9);
  }
  // Every check passed: what looks like a mistake is told before the long run.
  input_warnings = printWarnings(std::move(input_warnings));

  PartProgress progress(!args.quiet, nullptr);
  long planned_steps = 0;
  int failed_reported = 0;
  constexpr int kMaxFailureLines = 5;  // then only the summary
  auto on_step = [&](const BrushState& st, int step, int steps) {
    if (trace) trace->stream() << traceLine(st) << '\n';
    if (forces)
      forces->stream() << st.t_s << ',' << st.force_n.x() << ',' << st.force_n.y() << ','
                       << st.force_n.z() << '\n';
    for (size_t s = 0; s < st.spines.size(); ++s)
      if (!st.spines[s].summary.usable() && failed_reported++ < kMaxFailureLines)
        printError("warning: step " + std::to_string(st.step) + " (t = " +
                   std::to_string(st.t_s) + " s): spine " + std::to_string(s) +
                   " solve failed (" + st.spines[s].summary.message +
                   "); continuing from its last good state");
    planned_steps = steps;
    progress.update(0, 1, step, steps);
  };
  const std::string traj_name = isStdio(args.trajectory) ? std::string(kStdinName) : args.trajectory;
  RunStats stats;
  // The warnings are known before the PNG is written, so that a batch job's
  // PNG carries them with its key.
  const StrokePngResult png_result =
      renderStrokePng(brush, trajectory, png, args.output, on_step, [&](const StrokePngResult& r) {
        stats = strokeStats(r, traj_name, input_warnings);
        return batchPngText(args.batch_key, stats.warnings);
      });
  const render::StrokeResult& result = png_result.stroke;
  if (trace) trace->commit();
  if (forces) forces->commit();
  stats.planned_steps = planned_steps;
  writeRunStats(args.stats, stats);
  outputs.commit();
  if (!args.quiet) {
    // The planned steps first, as progress counted them; then the steps taken,
    // which splitting a step in halves makes more.
    const SimStats& st = result.stats;
    std::fprintf(stderr,
                 "bristle: %ld planned steps; %d simulation steps (%d solved, %d at rest, %d "
                 "stiction re-solves, %d rescued by the fallback solver), %ld solver iterations\n",
                 planned_steps, st.steps, st.solved_steps, st.settled_steps, st.resolves,
                 st.fallback_solves, st.iterations);
    std::fprintf(stderr,
                 "bristle: paint: %.3g mm^3 laid down, %.3g mm^3 picked up; %.3g of %.3g mm^3 "
                 "left on the brush\n",
                 result.deposited_mm3, result.picked_up_mm3, png_result.left_on_brush_mm3,
                 png_result.loaded_mm3);
    if (!isStdio(args.output)) std::cout << args.output << "\n";
  }
  return 0;
}

Subcommand registerRender(CLI::App& app) {
  auto r = std::make_shared<RenderArgs>();
  CLI::App* render =
      app.add_subcommand("render", "Render a scene, or a stroke: a brush along a trajectory");
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
  render->add_option("scene", r->scene, "A scene (bristle-scene/1 JSON): a whole painting");
  render->add_option("--brush", r->brush,
                     "Brush: a library name (round) or a file (bristle-brush/1 JSON)");
  render->add_option("--trajectory", r->trajectory,
                     "Trajectory (bristle-trajectory/1 CSV); - reads stdin");
  addPngOutput(render, r->output);
  render->add_option("--trace", r->trace, "Write the per-step trace (JSON lines)");
  render->add_option("--forces", r->forces, "Write the force on the handle per step (CSV)");
  render->add_option("--stats", r->stats,
                     "Write the run's figures and warnings (JSON: painted pixels, failed "
                     "solves, paint laid down, ...)");
  addSolver(render, r->solver, "Spine solver");
  addSolverMaxIterations(render, r->solver_max_iterations);
  addRenderThreads(render, r->threads);
  render->add_option("--offset-mm", r->offset_mm,
                     "Shift the trajectory by X Y Z mm (e.g. 0 0 10 to hold a longer brush "
                     "higher)")
      ->expected(3);
  addIpoptOption(render, r->ipopt_options);
  addPxPerMm(render, r->px_per_mm, "Canvas resolution (pixels per mm)");
  render->add_option("--max-step-mm", r->max_step_mm,
                     "Largest motion of a spine root per simulation step (mm); a step in which "
                     "the hair on the paper moves more than twice this (or 2 px) is redone in "
                     "halves")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 5.0));
  render->add_option("--steady-step-mm", r->steady_step_mm,
                     "Where the brush is steady (no joint touches down, lifts, sticks or slips), "
                     "planned steps are solved as one while the handle moves at most this far "
                     "(mm); 0 solves every planned step")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 5.0));
  render->add_option("--min-rate-hz", r->min_rate_hz, "Fewest simulation steps per second")
      ->capture_default_str()
      ->check(CLI::Range(1.0, 10000.0));
  render->add_option("--preset", r->preset,
                     "Named step options: thumbnail takes coarser steps and Ipopt's tol=1e-4 "
                     "for small images (2 px/mm data sets; docs/PERFORMANCE.md); "
                     "--max-step-mm, --steady-step-mm, --min-rate-hz and --ipopt-option "
                     "given beside it win")
      ->check(CLI::IsMember({"default", "thumbnail"}));
  render->add_option("--contact-band-mm", r->contact_band_mm,
                     "Brush geometry below this height touches the paper (mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 2.0));
  addPaintOptions(render, *r);
  render->add_flag("-q,--quiet", r->quiet, "No progress, no output path on stdout");
  addBatchKey(render, r->batch_key);
  return {render,
          [render, r] {
            r->given = givenOptions(render);
            return runRender(*r);
          },
          [render, r] {
            r->given = givenOptions(render);
            checkRenderOptions(*r);
          }};
}

}  // namespace bristle::cli

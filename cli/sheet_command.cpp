// `bristle sheet SHEET.json -o sheet.png`: a grid of strokes, brushes x
// trajectories, every cell labelled (engine/formats/sheet.h, render/sheet_renderer.h,
// docs/sheet-format.md).

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "batch/job_key.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/inputs.h"
#include "cli/progress.h"
#include "cli/run_stats.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/sheet.h"
#include "render/image/compose.h"
#include "render/image/png_io.h"
#include "render/sheet_renderer.h"

namespace bristle::cli {
namespace {

// Millimetres and resolutions for people: 4 significant digits, no trailing zeros.
std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

// The sheet's warnings: those about its inputs, found and printed before the
// run, then (printed as they are found) cells without paint or larger than
// their cell, failed solves.
std::vector<std::string> sheetWarnings(const Sheet& sheet, const render::SheetImage& result,
                                       const std::vector<std::string>& before) {
  RunStats stats;
  stats.warnings = before;  // printed before the run
  for (const render::SheetCell& c : result.cells) {
    const std::string where = sheet.path + ": brush '" + sheet.brushLabel(c.brush) +
                              "' on trajectory '" + sheet.trajectoryLabel(c.trajectory) + "'";
    if (c.ink.width == 0)
      stats.warn(where + ": the brush left no visible paint");
    else if (c.clipped)
      stats.warn(where + ": the stroke (" + fmt(c.ink.width / sheet.px_per_mm) + " x " +
                 fmt(c.ink.height / sheet.px_per_mm) +
                 " mm) is larger than the cell; its middle is shown (/cell_mm)");
  }
  if (const std::string w = failedSolvesWarning(result.stats); !w.empty()) stats.warn(w);
  return stats.warnings;
}

}  // namespace

int runSheet(const SheetArgs& args) {
  checkPngOutputName("sheet", "-o", args.output, true);
  checkCliFiles({{"-o", args.output}}, {{"sheet", args.sheet}}, {"-o"}, {});
  Sheet sheet = loadSheet(args.sheet);
  std::vector<NamedFile> inputs;
  for (size_t i = 0; i < sheet.brush_paths.size(); ++i)
    inputs.push_back({args.sheet + ": /brushes/" + std::to_string(i), sheet.brush_paths[i]});
  for (size_t i = 0; i < sheet.trajectory_paths.size(); ++i)
    inputs.push_back(
        {args.sheet + ": /trajectories/" + std::to_string(i), sheet.trajectory_paths[i]});
  checkCliFiles({{"-o", args.output}}, inputs, {"-o"}, {});
  // Command-line overrides of the sheet's own settings (a quick, coarse proof).
  if (args.px_per_mm > 0) sheet.px_per_mm = args.px_per_mm;
  if (args.solver) sheet.solver = *args.solver;
  const std::vector<std::string> input_warnings = sheetInputWarnings(sheet);
  checkCanCreateArg(args.output);
  printWarnings(input_warnings);

  PartProgress progress(!args.quiet, "cell");
  render::SheetRenderOptions options;
  options.compose.impasto = args.impasto;
  options.solver_max_iterations = args.solver_max_iterations;
  options.threads = args.threads;
  const render::SheetImage result = render::renderSheet(
      sheet, options,
      [&](int cell, int cells, long step, long steps) { progress.update(cell, cells, step, steps); });

  // The hash covers the sheet and every brush and trajectory it lists, by the
  // one function `bristle batch` uses to decide whether this PNG is up to date.
  render::PngText text = render::provenanceText(sheetInputsHash(sheet));
  text.push_back({"bristle:sheet", sheet.name});
  text.push_back({"bristle:sheet-grid",
                  std::to_string(result.layout.rows) + " x " + std::to_string(result.layout.cols) +
                      (sheet.brushes_in_columns ? " (trajectories x brushes)"
                                                : " (brushes x trajectories)") +
                      ", cells " + fmt(result.cell_width_mm) + " x " +
                      fmt(result.cell_height_mm) + " mm at " + fmt(sheet.px_per_mm) + " px/mm"});
  // Before the write, so that a batch job's PNG carries them with its key.
  const std::vector<std::string> warnings = sheetWarnings(sheet, result, input_warnings);
  for (auto& entry : batchPngText(args.batch_key, warnings)) text.push_back(std::move(entry));
  render::writePng(args.output, result.image, text);
  if (!args.quiet) {
    const SimStats& st = result.stats;
    std::fprintf(stderr,
                 "bristle: %zu cells (%d x %d), %d steps (%d solved, %d rescued by the fallback "
                 "solver), %ld solver iterations; image %d x %d px\n",
                 result.cells.size(), result.layout.rows, result.layout.cols, st.steps,
                 st.solved_steps, st.fallback_solves, st.iterations, result.layout.width_px,
                 result.layout.height_px);
    if (!isStdio(args.output)) std::cout << args.output << "\n";
  }
  return 0;
}

Subcommand registerSheet(CLI::App& app) {
  auto sh = std::make_shared<SheetArgs>();
  CLI::App* sheet = app.add_subcommand(
      "sheet", "Render a stroke sheet: a labelled grid of brushes x trajectories");
  sheet->footer(
      "Examples:\n"
      "  bristle sheet scenes/sheets/library.json -o library-sheet.png\n"
      "  bristle sheet scenes/sheets/small.json -o small-slsqp.png --solver slsqp\n"
      "Every cell is one brush along one trajectory on its own canvas, all at one scale,\n"
      "centred on its inked area; rows are brushes (their names), columns trajectories\n"
      "(their file stems). The sheet format is docs/sheet-format.md.");
  sheet->add_option("sheet", sh->sheet, "Sheet file (bristle-sheet/1 JSON)")->required();
  addPngOutput(sheet, sh->output);
  addPxPerMm(sheet, sh->px_per_mm, "Resolution, instead of the sheet's px_per_mm",
             /*show_default=*/false);
  addSolverOption(
      sheet, "--solver", [sh](SolverKind k) { sh->solver = k; },
      "Spine solver, instead of the sheet's", "");
  addSolverMaxIterations(sheet, sh->solver_max_iterations);
  addRenderThreads(sheet, sh->threads);
  sheet->add_flag("--impasto", sh->impasto, "Light the paint's thickness from the upper left");
  sheet->add_flag("-q,--quiet", sh->quiet, "No progress, no summary, no output path on stdout");
  addBatchKey(sheet, sh->batch_key);
  return {sheet, [sh] { return runSheet(*sh); }};
}

}  // namespace bristle::cli

// `bristle measure BRUSH [-o table.csv]`: the brush measured as a robot measures
// a real one (render/brush_measure.h, docs/fidelity.md "Measuring a brush"):
// the width, offset and drag of its footprint in constant-depth pulls.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "cli/measure_plot.h"
#include "cli/options.h"
#include "cli/progress.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "render/brush_fit.h"
#include "render/brush_measure.h"

namespace bristle::cli {
namespace {

struct MeasureArgs {
  std::string brush, output, plot, compare;
  render::MeasureProtocol protocol;
  SolverKind solver = SolverKind::kIpopt;
  int solver_max_iterations = kDefaultSolverMaxIterations;
  bool quiet = false;
};

// The deepest press a protocol may ask (mm): deeper than any library brush's hair.
constexpr double kMaxDepthMm = 100;

void checkMeasureArgs(const MeasureArgs& a) {
  if (a.protocol.depths_mm.empty()) throw Error(ExitCode::kUsage, "--depths: give at least one depth");
  for (double d : a.protocol.depths_mm)
    if (!(d > 0 && d <= kMaxDepthMm))
      throw Error(ExitCode::kUsage, "--depths: each depth must be in (0, 100] mm (got " +
                                        std::to_string(d) + ")");
  if (!a.plot.empty()) checkPngOutputName("measure", "--plot", a.plot, false);
  if (!a.compare.empty() && a.plot.empty())
    throw Error(ExitCode::kUsage, "--compare: draws the table on the plot; give --plot too");
}

// The table, as CSV: one row per depth, "untouched" rows with empty measures.
std::string measureCsv(const std::vector<render::DepthMeasure>& rows) {
  std::ostringstream out;
  out << "depth_mm,width_mm,drag_mm,offset_mm,failed_steps\n";
  char line[160];
  for (const render::DepthMeasure& m : rows) {
    if (m.shape.touched)
      std::snprintf(line, sizeof line, "%g,%.2f,%.2f,%.2f,%d\n", m.depth_mm, m.shape.width_mm,
                    m.shape.drag_mm, m.shape.offset_mm, m.failed_steps);
    else
      std::snprintf(line, sizeof line, "%g,,,,%d\n", m.depth_mm, m.failed_steps);
    out << line;
  }
  return out.str();
}

// The measures as a table for people, then the CSV's path.
void printMeasureTable(const std::vector<render::DepthMeasure>& rows, const std::string& path) {
  std::printf("%-9s %9s %9s %10s\n", "depth mm", "width mm", "drag mm", "offset mm");
  for (const render::DepthMeasure& m : rows) {
    if (m.shape.touched)
      std::printf("%9g %9.2f %9.2f %10.2f\n", m.depth_mm, m.shape.width_mm, m.shape.drag_mm,
                  m.shape.offset_mm);
    else
      std::printf("%9g %9s %9s %10s\n", m.depth_mm, "-", "-", "-");
  }
  std::fflush(stdout);
  std::cout << path << "\n";
}

int runMeasure(const MeasureArgs& args) {
  checkMeasureArgs(args);
  const std::string brush_file = findBrushFile(args.brush, "");
  const bool to_file = !args.output.empty() && !isStdio(args.output);
  checkOutputs({{"-o", to_file ? args.output : ""}, {"--plot", args.plot}},
               {{"brush", brush_file}, {"--compare", args.compare}});
  if (!args.plot.empty()) checkGnuplot("--plot");
  // The table to compare with is read before the long run, so a bad one fails at once.
  render::MeasurementTable table;
  if (!args.compare.empty()) table = render::readMeasurementTable(args.compare, {});
  const Brush brush = loadBrush(brush_file);
  SolverSettings solvers;
  solvers.kind = args.solver;
  solvers.max_iterations = args.solver_max_iterations;
  PartProgress progress(!args.quiet, "depth");
  const std::vector<render::DepthMeasure> rows = render::measureBrush(
      brush, args.protocol, solvers,
      [&](int depth, int depths, int step, int steps) { progress.update(depth, depths, step, steps); });
  const std::string csv = measureCsv(rows);
  if (!args.plot.empty()) {
    MeasurePlot plot;
    plot.title = "bristle measure " + brush.name;
    plot.curves = {{brush.name, rows}};
    if (!args.compare.empty()) {
      plot.table = &table;
      plot.table_title = std::filesystem::path(args.compare).filename().string();
    }
    writeMeasurePlot(args.plot, "--plot", plot);
  }
  if (!to_file && CommitGroup::open() != nullptr) {
    // After the plot is in place: a run that fails writes nothing to stdout.
    CommitGroup::open()->atCommit([csv]() { std::cout << csv; });
  } else if (!to_file) {
    std::cout << csv;
  } else {
    AtomicOutput out(args.output);
    out.stream() << csv;
    out.commit();
    if (!args.quiet) printMeasureTable(rows, args.output);
  }
  for (const render::DepthMeasure& m : rows)
    if (m.failed_steps > 0)
      std::cerr << "bristle: warning: the pull at " << m.depth_mm << " mm had " << m.failed_steps
                << " steps with a failed solve; its measures may be off\n";
  return 0;
}

}  // namespace

Subcommand registerMeasure(CLI::App& app) {
  auto ma = std::make_shared<MeasureArgs>();
  CLI::App* measure = app.add_subcommand(
      "measure", "Measure a brush's footprint (width, drag, offset) against press depth");
  measure->footer(
      "Examples:\n"
      "  bristle measure calligraphy\n"
      "  bristle measure round --depths 1,2,3,4,5 -o round-measured.csv\n"
      "  bristle measure calligraphy --depths 2,6,10 --plot calligraphy.png \\\n"
      "      --compare data/real-brushes/wang2020-calligraphy.csv\n"
      "The protocol (docs/fidelity.md, \"Measuring a brush\"): the brush held upright,\n"
      "lowered at x = 0 from 2 mm above first contact to each depth in 0.5 s, then\n"
      "pulled along +x at --speed-mm-s for 40 mm. Its footprint is read at 5 steps of\n"
      "the pull's last quarter, and each measure is their median:\n"
      "  width   the footprint's extent across the pull (the line's width);\n"
      "  offset  how far behind the handle's axis the footprint is widest;\n"
      "  drag    how far it reaches behind that, to the trailing tip.\n"
      "These are the quantities a robot measured on a real calligraphy brush (Wang et\n"
      "al., IROS 2020). Without -o, or with -o -, the CSV goes to stdout.");
  measure->add_option("brush", ma->brush,
                      "Brush: a library name (round) or a file (bristle-brush/1 JSON)")
      ->required();
  measure->add_option("-o,--output", ma->output, "CSV table of the measures (- writes stdout)");
  measure->add_option("--plot", ma->plot,
                      "PNG: width, drag and offset against depth, drawn by gnuplot");
  measure->add_option("--compare", ma->compare,
                      "A measurement table (depth_mm,width_mm,drag_mm,offset_mm) drawn as "
                      "points on the plot");
  measure->add_option("--depths", ma->protocol.depths_mm,
                      "Press depths past first contact (mm), comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  measure->add_option("--speed-mm-s", ma->protocol.speed_mm_s, "Pull speed (mm/s)")
      ->check(CLI::Range(1.0, 500.0))
      ->capture_default_str();
  measure->add_option("--pull-mm", ma->protocol.pull_mm,
                      "Pull length (mm); the footprint is read over its last quarter")
      ->check(CLI::Range(4.0, 400.0))
      ->capture_default_str();
  addPxPerMm(measure, ma->protocol.px_per_mm,
             "Footprint resolution (pixels per mm); the window spans the brush's reach");
  addSolver(measure, ma->solver, "Spine solver");
  addSolverMaxIterations(measure, ma->solver_max_iterations);
  measure->add_flag("-q,--quiet", ma->quiet, "No progress, no table on stdout with -o");
  return {measure, [ma]() { return runMeasure(*ma); }, [ma]() { checkMeasureArgs(*ma); }};
}

}  // namespace bristle::cli

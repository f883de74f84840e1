// `bristle fit BRUSH MEASUREMENTS.csv -o FITTED.json`: the brush's free
// parameters chosen so that `bristle measure` reproduces a table of measured
// widths, drags and offsets (render/brush_fit.h; docs/fit.md).

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "cli/measure_plot.h"
#include "cli/options.h"
#include "cli/progress.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/spelling.h"
#include "engine/base/text_file.h"
#include "engine/formats/brush_reader.h"
#include "render/brush_fit.h"

namespace bristle::cli {
namespace {

// The exit of a fit stopped by its time or evaluation limit before it
// converged, the best brush found written (docs/errors.md): sysexits'
// EX_TEMPFAIL, "try again", which the cache makes cheap.
constexpr int kExitNotConverged = 75;

struct FitArgs {
  std::string brush, table, output, report, plot, params, cache, name, description;
  std::vector<std::string> columns = {"width_mm", "drag_mm"};
  render::FitOptions fit;
  bool no_cache = false, quiet = false;
};

// The fitted columns by name; kUsage for an unknown one.
std::vector<render::FitColumn> parseColumns(const std::vector<std::string>& names) {
  const std::vector<std::string> known = {"width_mm", "drag_mm", "offset_mm"};
  std::vector<render::FitColumn> out;
  for (const std::string& n : names) {
    const auto it = std::find(known.begin(), known.end(), n);
    if (it == known.end()) {
      const auto meant = closestSpelling(n, known);
      throw Error(ExitCode::kUsage, "--columns: unknown column '" + n + "'" +
                                        (meant ? "; did you mean " + *meant + "?"
                                               : " (known: width_mm, drag_mm, offset_mm)"));
    }
    const auto c = static_cast<render::FitColumn>(it - known.begin());
    if (std::find(out.begin(), out.end(), c) != out.end())
      throw Error(ExitCode::kUsage, "--columns: " + n + " given twice");
    out.push_back(c);
  }
  if (out.empty()) throw Error(ExitCode::kUsage, "--columns: name at least one column");
  return out;
}

void checkFitArgs(const FitArgs& a) {
  parseColumns(a.columns);
  if (!a.plot.empty()) checkPngOutputName("fit", "--plot", a.plot, false);
  if (isStdio(a.output) || isStdio(a.report) || isStdio(a.plot))
    throw Error(ExitCode::kUsage, "fit: its outputs are files; - (standard output) is not one");
}

// The cache folder: --cache, else $XDG_CACHE_HOME/bristle/fit, else
// ~/.cache/bristle/fit (the XDG base directory default); none with --no-cache
// or when neither variable is set.
std::string cacheDir(const FitArgs& a) {
  if (a.no_cache) return "";
  if (!a.cache.empty()) return a.cache;
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg != nullptr && xdg[0] == '/') return std::string(xdg) + "/bristle/fit";
  const char* home = std::getenv("HOME");
  if (home != nullptr && home[0] == '/') return std::string(home) + "/.cache/bristle/fit";
  return "";
}

// Progress on stderr (cli/progress.h's manner): on a terminal, one line
// rewritten at most every 0.2 s; elsewhere a line at most once a minute.
class FitProgressLine {
 public:
  FitProgressLine(bool enabled, double limit_s, int max_evals)
      : enabled_(enabled), tty_(::isatty(2) == 1), limit_s_(limit_s), max_evals_(max_evals) {}

  void update(int eval, int depth, int depths, int step, int steps, double best) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    const double secs = std::chrono::duration<double>(now - start_).count();
    if (tty_ ? now - last_ < std::chrono::milliseconds(200) : now - last_ < interval()) return;
    last_ = now;
    // At most the time limit's rest, or the evaluations left at the pace so far.
    const double per_eval = eval > 1 ? secs / (eval - 1 + double(depth) / depths) : 0;
    const double left = std::min(limit_s_ - secs, per_eval * (max_evals_ - eval + 1));
    char best_mm[32] = "-", line[200];
    if (std::isfinite(best)) std::snprintf(best_mm, sizeof best_mm, "%.3f mm", best);
    const std::string eta =
        eval > 1 ? remainingText(secs, secs / (secs + std::max(0.0, left))) : std::string();
    std::snprintf(line, sizeof line,
                  "evaluation %d, depth %d/%d, step %d/%d; best RMSE %s after %.0f s%s", eval,
                  depth + 1, depths, step + 1, steps, best_mm, secs, eta.c_str());
    if (tty_)
      std::fprintf(stderr, "\rbristle: fit: %s\033[K", line);
    else
      std::fprintf(stderr, "bristle: progress: fit: %s\n", line);
    std::fflush(stderr);
  }
  void done() {
    if (enabled_ && tty_) std::fprintf(stderr, "\r\033[K");
  }

 private:
  static std::chrono::steady_clock::duration interval() {
    const char* env = std::getenv("BRISTLE_PROGRESS_SECONDS");
    const double s = env != nullptr ? std::atof(env) : 60.0;
    return std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        std::chrono::duration<double>(s > 0 && s <= 86400 ? s : 60.0));
  }
  bool enabled_, tty_;
  double limit_s_;
  int max_evals_;
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  std::chrono::steady_clock::time_point last_ = start_;
};

void writeOutputs(const FitArgs& a, const render::FitResult& r,
                  const render::MeasurementTable& table, const std::string& brush_name,
                  const std::string& brush_file) {
  {
    AtomicOutput out(a.output);
    out.stream() << r.fitted_json;
    out.commit();
  }
  if (!a.report.empty()) writeFileAtomically(a.report, fitReport(r, table, a.fit, brush_file));
  if (!a.plot.empty()) {
    MeasurePlot plot;
    plot.title = "bristle fit " + brush_name + " to " +
                 std::filesystem::path(a.table).filename().string();
    plot.curves = {{brush_name + " (before)", r.before},
                   {(a.name.empty() ? brush_name + "-fitted" : a.name) + " (fitted)", r.after}};
    plot.table = &table;
    plot.table_title = std::filesystem::path(a.table).filename().string();
    writeMeasurePlot(a.plot, "--plot", plot);
  }
}

int runFit(FitArgs a) {
  checkFitArgs(a);
  a.fit.columns = parseColumns(a.columns);
  const std::string brush_file = findBrushFile(a.brush, "");
  checkOutputs({{"-o", a.output}, {"--report", a.report}, {"--plot", a.plot}},
               {{"brush", brush_file}, {"measurements", a.table}, {"--params", a.params}});
  if (!a.plot.empty()) checkGnuplot("--plot");
  for (const std::string& out : {a.output, a.report, a.plot})
    if (!out.empty()) checkCanCreateArg(out);  // before minutes of simulation
  const std::string brush_text = readTextFile(brush_file);
  const Brush brush = loadBrush(brush_file);
  const std::vector<render::FitParam> params =
      a.params.empty() ? render::defaultFitParams(brush) : render::readFitParams(a.params, brush);
  const render::MeasurementTable table = render::readMeasurementTable(a.table, a.fit.columns);
  render::checkTableForFit(table, brush, params);

  const std::string table_name = std::filesystem::path(a.table).filename().string();
  std::string cols;
  for (const std::string& c : a.columns) cols += (cols.empty() ? "" : ", ") + c;
  a.fit.name = a.name.empty() ? brush.name + "-fitted" : a.name;
  std::string base = brush.description;
  while (!base.empty() && (base.back() == '.' || base.back() == ' ')) base.pop_back();
  a.fit.description = !a.description.empty() ? a.description
                                             : base + (base.empty() ? "" : ". ") +
                                                   "Fitted by bristle fit to " + table_name +
                                                   " (" + cols + ")";
  a.fit.cache_dir = cacheDir(a);
  FitProgressLine progress(!a.quiet, a.fit.time_limit_s, a.fit.max_evals);
  const render::FitResult r = render::fitBrush(
      brush_text, brush_file, table, params, a.fit,
      [&](int e, int d, int n, int s, int ns, double best) {
        progress.update(e, d, n, s, ns, best);
      });
  progress.done();
  if (!r.cache_warning.empty()) std::cerr << "bristle: warning: " << r.cache_warning << "\n";
  writeOutputs(a, r, table, brush.name, brush_file);
  if (!a.quiet) {
    std::fprintf(stderr,
                 "bristle: fit: RMSE %.3f -> %.3f mm in %d evaluations (%d cached or repeated, %d "
                 "strokes simulated), %.1f s: %s\n",
                 r.before_rmse, r.after_rmse, r.evaluations, r.cache_hits, r.simulated_strokes,
                 r.seconds, r.stop.c_str());
    std::cout << a.output << "\n";
  }
  if (r.converged) return 0;
  std::cerr << "bristle: warning: fit: " << r.stop << "; wrote the best brush found to "
            << a.output << " (RMSE " << r.after_rmse
            << " mm); run again with a larger limit: the cache makes the evaluations done free\n";
  return kExitNotConverged;
}

}  // namespace

Subcommand registerFit(CLI::App& app) {
  auto fa = std::make_shared<FitArgs>();
  CLI::App* fit = app.add_subcommand(
      "fit", "Fit a brush's parameters to a table of measured widths, drags and offsets");
  fit->footer(
      "Examples:\n"
      "  bristle fit calligraphy data/real-brushes/wang2020-calligraphy.csv -o fitted.json \\\n"
      "      --report fit.md --plot fit.png\n"
      "The table: depth_mm and the fitted columns (width_mm, drag_mm, offset_mm), one row\n"
      "per measured stroke, repeated depths allowed, '#' comment lines; rows at depth 0\n"
      "are left out. Each evaluation runs `bristle measure`'s protocol at the table's\n"
      "depths; BOBYQA (NLopt) minimises the squared residuals of --columns. The free\n"
      "parameters by default: stiffness_scale, stiffness_taper and tip_spread for a brush\n"
      "with hair volume, else stiffness_taper and friction_scale; a --params file names\n"
      "others with their bounds: {\"friction_scale\": [0.5, 2]}.\n"
      "--columns width_mm,drag_mm,offset_mm fits the offset too. Exit 75 when a limit\n"
      "(--time-limit-s, --max-evals) stopped the search: the best brush found is written.\n"
      "docs/fit.md tells the rest.");
  fit->add_option("brush", fa->brush, "Brush: a library name (calligraphy) or a file")->required();
  fit->add_option("measurements", fa->table, "Measurement table (CSV)")->required();
  fit->add_option("-o,--output", fa->output, "The fitted brush (bristle-brush/1 JSON)")
      ->required();
  fit->add_option("--report", fa->report, "Report (Markdown): residuals, RMSE, parameters");
  fit->add_option("--plot", fa->plot, "PNG: the data, the brush and the fit against depth");
  fit->add_option("--params", fa->params, "Free parameters and bounds (JSON)");
  fit->add_option("--columns", fa->columns, "Columns fitted, comma-separated")
      ->delimiter(',')
      ->capture_default_str();
  fit->add_option("--name", fa->name, "The fitted brush's name (default: BRUSH-fitted)");
  fit->add_option("--description", fa->description, "The fitted brush's description");
  fit->add_option("--time-limit-s", fa->fit.time_limit_s, "Stop the search after this long")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  fit->add_option("--max-evals", fa->fit.max_evals, "Stop after this many evaluations")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  fit->add_option("--cache", fa->cache,
                  "Cache folder (default $XDG_CACHE_HOME/bristle/fit or ~/.cache/bristle/fit)");
  fit->add_flag("--no-cache", fa->no_cache, "Keep no measurements on disk");
  fit->add_option("--speed-mm-s", fa->fit.protocol.speed_mm_s, "Pull speed (mm/s)")
      ->check(CLI::Range(1.0, 500.0))
      ->capture_default_str();
  fit->add_option("--pull-mm", fa->fit.protocol.pull_mm, "Pull length (mm)")
      ->check(CLI::Range(4.0, 400.0))
      ->capture_default_str();
  addPxPerMm(fit, fa->fit.protocol.px_per_mm, "Footprint resolution (pixels per mm)");
  addSolver(fit, fa->fit.solvers.kind, "Spine solver");
  addSolverMaxIterations(fit, fa->fit.solvers.max_iterations);
  fit->add_flag("-q,--quiet", fa->quiet, "No progress, no summary");
  return {fit, [fa]() { return runFit(*fa); }, [fa]() { checkFitArgs(*fa); }};
}

}  // namespace bristle::cli

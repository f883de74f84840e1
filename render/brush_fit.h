#pragma once
// Calibration of a brush against measurements of a real one (docs/fit.md): the
// free parameters of a brush file (a stiffness scale, the stiffness profile
// along the hair, friction, hair volume) chosen so that `bristle measure`'s
// protocol (render/brush_measure.h) reproduces a table of measured widths,
// drags and offsets, in the least-squares sense. The optimiser is NLopt's
// BOBYQA (Powell, "The BOBYQA algorithm for bound constrained optimization
// without derivatives", Cambridge NA report 2009/06): derivative-free, since
// each evaluation is a set of simulated strokes whose measures are read off
// rendered pixels.

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/solvers/solver_pair.h"
#include "render/brush_measure.h"

namespace bristle::render {

// The measured columns of a table, as `bristle measure` writes them.
enum class FitColumn { kWidth = 0, kDrag = 1, kOffset = 2 };
inline constexpr int kFitColumns = 3;
const char* columnName(FitColumn c);  // "width_mm", "drag_mm", "offset_mm"
// One column of a footprint's measures.
double columnOf(const FootprintShape& shape, FitColumn c);

struct MeasuredRow {
  int line = 0;  // in its file, for messages
  double depth_mm = 0;
  std::array<double, kFitColumns> value{};  // by FitColumn; 0 where the column is absent
};

// A table of measurements: `depth_mm` and some of width_mm, drag_mm, offset_mm
// (docs/fit.md, "The measurement table").
struct MeasurementTable {
  std::string path;
  std::vector<MeasuredRow> rows;          // depth > 0, in file order
  std::array<bool, kFitColumns> has{};    // which columns the header holds
  int zero_depth_rows = 0;                // depth-0 rows: read, and left out
  int last_line = 0;                      // the file's last line
  std::vector<double> depths() const;     // the distinct depths, ascending
};

// Reads a table: comment lines start with '#', the header names depth_mm and
// `required`, and may name the other measured columns and `failed_steps`
// (which `bristle measure -o` writes). Every value is a finite number >= 0.
// Throws Error(kDataError) "FILE: line L[, column C (NAME)]: RULE".
MeasurementTable parseMeasurementTable(const std::string& text, const std::string& path,
                                       const std::vector<FitColumn>& required);
MeasurementTable readMeasurementTable(const std::string& path,
                                      const std::vector<FitColumn>& required);

// The deepest press past first contact (mm) a brush held upright can take
// before its ferrule reaches the paper.
double deepestPressMm(const Brush& brush);

struct FitParam;
// Checks a table against a brush and the free parameters: every depth within
// deepestPressMm, and at least one row (depth above 0) per parameter. Throws
// Error(kDataError) naming the table's line.
void checkTableForFit(const MeasurementTable& table, const Brush& brush,
                      const std::vector<FitParam>& params);

// A free parameter: its name (docs/fit.md, "Free parameters"), its bounds and
// the brush's own value, where the search starts.
struct FitParam {
  std::string name;
  double min = 0, max = 0, start = 0;
  bool log = false;  // searched on a log scale (a factor), else linearly
};
// The names `--params` accepts, in the documented order.
std::vector<std::string> fitParamNames();
// The default set for a brush: stiffness_scale, stiffness_taper and
// tip_spread with hair volume; stiffness_taper and friction_scale without.
std::vector<FitParam> defaultFitParams(const Brush& brush);
// A `--params` file: {"NAME": [MIN, MAX], ...}. Throws Error(kDataError)
// naming the file, the key and the rule (unknown name, bounds outside the
// parameter's limits or not increasing, a parameter the brush lacks).
std::vector<FitParam> readFitParams(const std::string& path, const Brush& brush);

// The brush file's text with `values` (one per parameter) applied, each
// number it changes rounded to 4 significant digits, and its name and
// description replaced (empty: kept). A bristle-brush/1 document.
std::string applyFitParams(const std::string& brush_text, const std::vector<FitParam>& params,
                           const std::vector<double>& values, const std::string& name,
                           const std::string& description);

struct FitOptions {
  MeasureProtocol protocol;  // its depths are the table's
  SolverSettings solvers;
  std::vector<FitColumn> columns = {FitColumn::kWidth, FitColumn::kDrag};
  double time_limit_s = 600;
  int max_evals = 200;
  std::string cache_dir;  // empty: no cache
  std::string name, description;  // of the fitted brush (empty: the brush's)
};

// Called after every step of every pull: the evaluation (1-based), its depth
// index and count, the step and the pull's steps, and the best RMSE so far (mm;
// infinite before the first evaluation ends).
using FitProgress =
    std::function<void(int eval, int depth, int depths, int step, int steps, double best_rmse)>;

struct FitResult {
  std::vector<FitParam> params;
  std::vector<double> best;                    // per parameter
  std::vector<DepthMeasure> before, after;     // the table's depths, the brush and the fit
  std::string fitted_json;                     // passes validation
  double before_rmse = 0, after_rmse = 0;      // over the fitted columns and rows (mm)
  int evaluations = 0, cache_hits = 0, simulated_strokes = 0;
  double seconds = 0;
  bool converged = false;
  std::string stop;  // why the search stopped, for people
  std::string cache_warning;  // why the cache was not kept (empty: it was, or none asked)
};

// Fits; throws as measureBrush does, and Error(kUsage) for limits out of range.
FitResult fitBrush(const std::string& brush_text, const std::string& brush_path,
                   const MeasurementTable& table, const std::vector<FitParam>& params,
                   const FitOptions& options, const FitProgress& progress = {});

// The data's own scatter in one column: the pooled standard deviation of the
// rows repeated at one depth (degrees of freedom: rows less depths), and the
// RMSE that predicting each depth's mean gets (the least any model can get).
struct Scatter {
  double pooled_sd = 0, floor_rmse = 0;
  int repeated_depths = 0;
};
Scatter dataScatter(const MeasurementTable& table, FitColumn c);
// RMSE of one column over every row of the table (mm), the measures per depth
// in `measures` (the table's depths, as fitBrush returns them).
double columnRmse(const MeasurementTable& table, const std::vector<DepthMeasure>& measures,
                  FitColumn c);

// The report of a fit, Markdown (docs/fit.md, "The report").
std::string fitReport(const FitResult& r, const MeasurementTable& table, const FitOptions& o,
                      const std::string& brush_path);

}  // namespace bristle::render

// A fit's report and the statistics it gives (render/brush_fit.h; docs/fit.md,
// "The report"): the residual of every row, each column's RMSE beside the
// data's own scatter, the parameters before and after, and what it cost.

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <map>
#include <string>

#include "render/brush_fit.h"

namespace bristle::render {
namespace {

double predicted(const std::vector<DepthMeasure>& m, double depth, FitColumn c) {
  for (const DepthMeasure& d : m)
    if (d.depth_mm == depth) return d.shape.touched ? columnOf(d.shape, c) : 0;
  return 0;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

}  // namespace

Scatter dataScatter(const MeasurementTable& table, FitColumn c) {
  std::map<double, std::vector<double>> by_depth;
  for (const MeasuredRow& r : table.rows) by_depth[r.depth_mm].push_back(r.value[size_t(c)]);
  double ss = 0;
  int dof = 0;
  Scatter s;
  for (const auto& [depth, v] : by_depth) {
    if (v.size() < 2) continue;
    ++s.repeated_depths;
    double mean = 0;
    for (double x : v) mean += x / double(v.size());
    for (double x : v) ss += (x - mean) * (x - mean);
    dof += static_cast<int>(v.size()) - 1;
  }
  if (dof > 0) s.pooled_sd = std::sqrt(ss / dof);
  if (!table.rows.empty()) s.floor_rmse = std::sqrt(ss / double(table.rows.size()));
  return s;
}

double columnRmse(const MeasurementTable& table, const std::vector<DepthMeasure>& measures,
                  FitColumn c) {
  double ss = 0;
  for (const MeasuredRow& r : table.rows) {
    const double e = r.value[size_t(c)] - predicted(measures, r.depth_mm, c);
    ss += e * e;
  }
  return table.rows.empty() ? 0 : std::sqrt(ss / double(table.rows.size()));
}

namespace {

std::string paramsTable(const FitResult& r) {
  std::string out = "| parameter | min | max | before | after |\n|---|---:|---:|---:|---:|\n";
  for (size_t i = 0; i < r.params.size(); ++i) {
    const FitParam& p = r.params[i];
    out += "| `" + p.name + "` | " + fmt("%.4g", p.min) + " | " + fmt("%.4g", p.max) + " | " +
           fmt("%.4g", p.start) + " | " + fmt("%.4g", r.best[i]) + " |\n";
  }
  return out;
}

std::string rmseTable(const FitResult& r, const MeasurementTable& t, const FitOptions& o) {
  std::string out =
      "| column | fitted | RMSE before | RMSE after | data scatter (pooled SD) | floor (each "
      "depth's mean) |\n|---|---|---:|---:|---:|---:|\n";
  for (int k = 0; k < kFitColumns; ++k) {
    const FitColumn c = static_cast<FitColumn>(k);
    if (!t.has[size_t(k)]) continue;
    const bool fitted = std::find(o.columns.begin(), o.columns.end(), c) != o.columns.end();
    const Scatter s = dataScatter(t, c);
    out += std::string("| `") + columnName(c) + "` | " + (fitted ? "yes" : "no (a check)") +
           " | " + fmt("%.2f", columnRmse(t, r.before, c)) + " | " +
           fmt("%.2f", columnRmse(t, r.after, c)) + " | " + fmt("%.2f", s.pooled_sd) + " | " +
           fmt("%.2f", s.floor_rmse) + " |\n";
  }
  return out;
}

std::string residualTable(const FitResult& r, const MeasurementTable& t) {
  std::string head = "| line | depth |", rule = "|---:|---:|";
  for (int k = 0; k < kFitColumns; ++k) {
    if (!t.has[size_t(k)]) continue;
    const std::string n = columnName(static_cast<FitColumn>(k));
    head += " " + n + " data | before | after | residual |";
    rule += "---:|---:|---:|---:|";
  }
  std::string out = head + "\n" + rule + "\n";
  for (const MeasuredRow& row : t.rows) {
    char cell[160];
    std::snprintf(cell, sizeof cell, "| %d | %g |", row.line, row.depth_mm);
    out += cell;
    for (int k = 0; k < kFitColumns; ++k) {
      if (!t.has[size_t(k)]) continue;
      const FitColumn c = static_cast<FitColumn>(k);
      const double data = row.value[size_t(k)], after = predicted(r.after, row.depth_mm, c);
      std::snprintf(cell, sizeof cell, " %.2f | %.2f | %.2f | %+.2f |", data,
                    predicted(r.before, row.depth_mm, c), after, data - after);
      out += cell;
    }
    out += "\n";
  }
  return out;
}

}  // namespace

std::string fitReport(const FitResult& r, const MeasurementTable& t, const FitOptions& o,
                      const std::string& brush_path) {
  std::string columns;
  for (FitColumn c : o.columns)
    columns += (columns.empty() ? "" : ", ") + std::string(columnName(c));
  const MeasureProtocol& p = o.protocol;
  std::string out = "# bristle fit\n\n";
  out += "- brush: `" + brush_path + "`\n- measurements: `" + t.path + "` (" +
         std::to_string(t.rows.size()) + " rows at " + std::to_string(t.depths().size()) +
         " depths; " + std::to_string(t.zero_depth_rows) + " rows at depth 0 left out)\n";
  out += "- fitted columns: " + columns + "\n";
  out += "- protocol: " + fmt("%g mm/s", p.speed_mm_s) + ", " + fmt("%g mm pulls", p.pull_mm) +
         ", " + fmt("%g px/mm", p.px_per_mm) + ", solver " + solverKindName(o.solvers.kind) +
         " (docs/measure.md)\n";
  out += "- result: " + r.stop + "\n";
  out += "- RMSE over the fitted columns: " + fmt("%.3f mm", r.before_rmse) + " before, " +
         fmt("%.3f mm", r.after_rmse) + " after\n";
  out += "- evaluations: " + std::to_string(r.evaluations) + " (" +
         std::to_string(r.cache_hits) + " answered without simulating: repeated, or cached)\n";
  out += "- simulated strokes: " + std::to_string(r.simulated_strokes) + "\n";
  out += "- time: " + fmt("%.1f s", r.seconds) + "\n\n";
  out += "## Free parameters\n\n" + paramsTable(r) + "\n";
  out += "## RMSE against the data's scatter (mm)\n\n" + rmseTable(r, t, o) + "\n";
  out += "## Residuals per row (data - after, mm)\n\n" + residualTable(r, t);
  return out;
}

}  // namespace bristle::render

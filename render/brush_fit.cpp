// The measurement table, the free parameters and their application to a
// brush file (render/brush_fit.h; docs/fit.md). The search itself, its cache
// and its report are in render/brush_fit_search.cpp.

#include "render/brush_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/base/csv.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/base/json_reader.h"
#include "engine/base/spelling.h"
#include "engine/base/text_file.h"

namespace bristle::render {

const char* columnName(FitColumn c) {
  switch (c) {
    case FitColumn::kWidth: return "width_mm";
    case FitColumn::kDrag: return "drag_mm";
    case FitColumn::kOffset: return "offset_mm";
  }
  return "?";
}

double columnOf(const FootprintShape& shape, FitColumn c) {
  switch (c) {
    case FitColumn::kWidth: return shape.width_mm;
    case FitColumn::kDrag: return shape.drag_mm;
    case FitColumn::kOffset: return shape.offset_mm;
  }
  return 0;
}

std::vector<double> MeasurementTable::depths() const {
  std::vector<double> d;
  for (const MeasuredRow& r : rows) d.push_back(r.depth_mm);
  std::sort(d.begin(), d.end());
  d.erase(std::unique(d.begin(), d.end()), d.end());
  return d;
}

namespace {

// Every column a table may hold, in `bristle measure`'s order; failed_steps
// (measure's own) is read past, so that its output can be fitted to as it is.
const std::vector<std::string> kTableColumns = {"depth_mm", "width_mm", "drag_mm", "offset_mm",
                                                "failed_steps"};

// A row's cells (engine/base/csv.h: the splitter every reader of bristle
// uses, so a quoted cell holding ',' is one cell), unquoted.
std::vector<std::string> splitFields(std::string_view line) {
  std::vector<std::string> out;
  for (std::string_view cell : csv::splitLine(line)) out.emplace_back(csv::unquote(cell));
  return out;
}

std::string where(int line, size_t column, const std::string& name) {
  return csv::place(line, static_cast<int>(column) + 1, name);
}

// The header's columns as indices into kTableColumns; checks names and the
// required ones.
std::vector<int> readHeader(const std::vector<std::string>& names, int line,
                            const std::string& path, const std::vector<FitColumn>& required) {
  std::vector<int> index;
  for (size_t c = 0; c < names.size(); ++c) {
    const auto it = std::find(kTableColumns.begin(), kTableColumns.end(), names[c]);
    if (it == kTableColumns.end()) {
      std::string rule = "unknown column '" + names[c] + "'";
      if (const auto meant = closestSpelling(names[c], kTableColumns))
        rule += "; did you mean " + *meant + "?";
      else
        rule += " (known: depth_mm, width_mm, drag_mm, offset_mm, failed_steps)";
      throw dataError(path, where(line, c, names[c]), rule);
    }
    const int k = static_cast<int>(it - kTableColumns.begin());
    if (std::find(index.begin(), index.end(), k) != index.end())
      throw dataError(path, where(line, c, names[c]), "column '" + names[c] + "' given twice");
    index.push_back(k);
  }
  std::vector<std::string> needed = {"depth_mm"};
  for (FitColumn f : required) needed.push_back(columnName(f));
  for (const std::string& n : needed)
    if (std::find(names.begin(), names.end(), n) == names.end()) {
      std::string all;
      for (const std::string& m : needed) all += (all.empty() ? "" : ", ") + m;
      throw dataError(path, "line " + std::to_string(line),
                      "missing column " + n + " (the header must name " + all + ")");
    }
  return index;
}

// A cell as a length in mm: a finite number (csv::parseNumber, whose
// messages name the cell) that is not negative.
double readValue(const std::string& field, const std::string& path, int line, size_t column,
                 const std::string& name) {
  const double v = csv::parseNumber(field, path, line, static_cast<int>(column) + 1, name);
  if (v < 0)
    throw dataError(path, where(line, column, name), field + " must be >= 0 (a length in mm)");
  return v;
}

}  // namespace

MeasurementTable parseMeasurementTable(const std::string& text, const std::string& path,
                                       const std::vector<FitColumn>& required) {
  MeasurementTable t;
  t.path = path;
  std::vector<int> columns;
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  while (std::getline(in, raw)) {
    ++line;
    const std::string s(csv::trim(raw));
    if (s.empty() || s[0] == '#') continue;
    const std::vector<std::string> fields = splitFields(s);
    if (columns.empty()) {
      columns = readHeader(fields, line, path, required);
      for (int k : columns)
        if (k >= 1 && k <= kFitColumns) t.has[static_cast<size_t>(k - 1)] = true;
      continue;
    }
    if (fields.size() != columns.size())
      throw dataError(path, "line " + std::to_string(line),
                      std::to_string(fields.size()) + " fields where the header names " +
                          std::to_string(columns.size()));
    MeasuredRow row;
    row.line = line;
    for (size_t c = 0; c < fields.size(); ++c) {
      const int k = columns[c];
      if (k == 4) continue;  // failed_steps: measure's note, not a measurement
      const double v = readValue(fields[c], path, line, c, kTableColumns[size_t(k)]);
      if (k == 0)
        row.depth_mm = v;
      else
        row.value[static_cast<size_t>(k - 1)] = v;
    }
    if (row.depth_mm == 0)
      ++t.zero_depth_rows;
    else
      t.rows.push_back(row);
  }
  t.last_line = std::max(line, 1);
  if (columns.empty())
    throw dataError(path, "line " + std::to_string(t.last_line),
                    "no header (expected depth_mm,width_mm,drag_mm,offset_mm)");
  return t;
}

MeasurementTable readMeasurementTable(const std::string& path,
                                      const std::vector<FitColumn>& required) {
  return parseMeasurementTable(readTextFile(path), path, required);
}

double deepestPressMm(const Brush& brush) {
  // Upright, the ferrule is at first contact less the depth, and each spine's
  // root at that plus its own z (engine/dynamics/simulation.cpp refuses a root below 0).
  double lowest_root = 0;
  for (const SpineSpec& s : brush.spines) lowest_root = std::min(lowest_root, s.root_mm.z());
  return firstContactHeightMm(brush) + lowest_root;
}

void checkTableForFit(const MeasurementTable& table, const Brush& brush,
                      const std::vector<FitParam>& params) {
  char buf[160];
  const double deepest = deepestPressMm(brush);
  for (const MeasuredRow& r : table.rows)
    if (r.depth_mm >= deepest) {
      std::snprintf(buf, sizeof buf,
                    "%g mm is deeper than '%s' can press: its ferrule reaches the paper %.3g mm "
                    "past first contact",
                    r.depth_mm, brush.name.c_str(), deepest);
      throw dataError(table.path, where(r.line, 0, "depth_mm"), buf);
    }
  if (table.rows.size() < params.size()) {
    std::string names;
    for (const FitParam& p : params) names += (names.empty() ? "" : ", ") + p.name;
    throw dataError(table.path, "line " + std::to_string(table.last_line),
                    std::to_string(table.rows.size()) +
                        " rows with a depth above 0, fewer than the " +
                        std::to_string(params.size()) + " free parameters (" + names +
                        "): a fit needs a row per parameter at least");
  }
}

}  // namespace bristle::render

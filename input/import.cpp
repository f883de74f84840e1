#include "input/import.h"

#include "engine/base/error.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/geometry/first_contact.h"
#include "input/pen_mapping.h"
#include "input/svg_geometry.h"

namespace bristle::input {

double hairLengthMm(const Brush& brush) { return firstContactHeightMm(brush); }

std::string resolveMaxDepth(ImportOptions* options, const Brush& brush,
                            const std::string& brush_name) {
  if (options->max_depth_mm > 0) {
    options->mapping.max_depth_mm = options->max_depth_mm;
    return "--max-depth-mm " + formatNumber(options->max_depth_mm);
  }
  const double hair = hairLengthMm(brush);
  options->mapping.max_depth_mm = options->max_depth_frac * hair;
  return formatNumber(options->max_depth_frac) + " x the hair length " + formatNumber(hair) +
         " mm of " + brush_name;
}

namespace {

// A UTF-8 byte-order mark, which spreadsheet programs write at the head of a
// CSV ("CSV UTF-8"): not part of the data.
bool hasUtf8Bom(const std::string& text) { return text.rfind("\xEF\xBB\xBF", 0) == 0; }

}  // namespace

Recording readInput(const std::string& raw, const std::string& path,
                    const ImportOptions& options) {
  const std::string stripped = hasUtf8Bom(raw) ? raw.substr(3) : std::string();
  const std::string& text = hasUtf8Bom(raw) ? stripped : raw;
  const Format format = options.from ? *options.from : detectFormat(text, path);
  if (format == Format::kTrajectory)
    throw dataError(path, "line 1",
                    "is already a bristle-trajectory/1 file: there is nothing to import");
  SvgOptions svg = options.svg;
  if (svg.mm_per_unit <= 0) svg.mm_per_unit = options.mapping.mm_per_unit;
  return readRecording(text, path, format, svg);
}

Trajectory loadTrajectoryOrRecording(const std::string& raw, const std::string& path,
                                     const Brush& brush, const std::string& brush_name,
                                     std::vector<std::string>* warnings) {
  const std::string stripped = hasUtf8Bom(raw) ? raw.substr(3) : std::string();
  const std::string& text = hasUtf8Bom(raw) ? stripped : raw;
  const Format format = detectFormat(text, path);
  if (format == Format::kTrajectory) return parseTrajectory(text, path);
  ImportOptions options;
  options.from = format;
  resolveMaxDepth(&options, brush, brush_name);
  const Recording rec = readInput(text, path, options);
  if (warnings) warnings->insert(warnings->end(), rec.warnings.begin(), rec.warnings.end());
  // Through the very text `bristle import` writes, its roundings included (1e-6
  // mm, 1e-9 s and 1e-9 in the quaternion): rendering a recording and rendering
  // its import then paint the same pixels. Without it, those last digits can tip
  // a buckling hair to the other side (docs/input.md).
  return parseTrajectory(trajectoryCsv(toTrajectory(rec, options.mapping), {}), path);
}

}  // namespace bristle::input

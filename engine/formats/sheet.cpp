#include "engine/formats/sheet.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>

#include "engine/formats/brush_library.h"
#include "engine/base/error.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/geometry/first_contact.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/input_warnings.h"
#include "engine/base/json_reader.h"
#include "engine/formats/scene.h"
#include "engine/base/text_file.h"
#include "engine/dynamics/stepper.h"

namespace bristle {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSheetFormat = "bristle-sheet/1";

// A list of files ("brushes", "trajectories"): 1..kMaxSheetAxis entries, each a
// non-empty path, or (brushes only) an object {"path": ..., "lift_mm": ...}; no
// file twice (a repeated row or column says nothing new). Lifts go to *lifts.
std::vector<std::string> pathList(const JsonObject& top, const std::string& key,
                                  const std::string& base_dir, const std::string& what,
                                  std::vector<double>* lifts) {
  const nlohmann::json& list = top.raw(key);
  const std::string pointer = top.childPointer(key);
  top.requireAt(list.is_array() && !list.empty() && list.size() <= size_t(kMaxSheetAxis), pointer,
                list, "must be a list of 1.." + std::to_string(kMaxSheetAxis) + " " + what +
                          " file paths");
  std::vector<std::string> out;
  std::map<std::string, size_t> seen;
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string pi = pointer + "/" + std::to_string(i);
    std::string path;
    double lift = 0;
    if (lifts && list[i].is_object()) {
      const JsonObject entry(list[i], pi, top.file());
      entry.declareKeys({"path", "lift_mm"});
      path = entry.string("path");
      lift = entry.number("lift_mm", 0.0);
      entry.require(std::fabs(lift) <= kMaxSheetLiftMm, "lift_mm",
                    "must be within +-" + std::to_string(int(kMaxSheetLiftMm)) + " mm");
      entry.rejectUnknownKeys();
      entry.require(!path.empty(), "path", "must be a brush file path");
    } else {
      top.requireAt(list[i].is_string() && !list[i].get<std::string>().empty(), pi, list[i],
                    "must be a " + what + " file path (relative to the sheet's folder)" +
                        (lifts ? " or {\"path\": ..., \"lift_mm\": ...}" : ""));
      path = list[i].get<std::string>();
    }
    const std::string resolved = lifts && isBrushName(path)
                                     ? findBrushByName(path, top.file() + ": " + pi)
                                     : resolveInputPath(base_dir, path);
    const auto [it, fresh] = seen.emplace(resolved, i);
    if (!fresh)
      top.fail(pi, "'" + resolved + "' is listed already at " + pointer + "/" +
                       std::to_string(it->second));
    out.push_back(resolved);
    if (lifts) lifts->push_back(lift);
  }
  return out;
}

Sheet parseSheetOnly(const nlohmann::json& root, const std::string& path,
                     const std::string& base_dir) {
  const JsonObject top(root, "", path);
  top.declareKeys({"format", "name", "title", "brushes", "trajectories", "layout", "px_per_mm",
                   "cell_mm", "paint", "background", "paper", "mix", "sim", "solver", "labels"});
  Sheet sheet;
  sheet.path = path;
  const std::string format = top.string("format");
  top.require(format == kSheetFormat, "format", "unknown format version (expected \"bristle-sheet/1\")");
  sheet.name = top.string("name");
  top.require(!sheet.name.empty(), "name", "must not be empty");
  sheet.title = top.string("title", "");

  sheet.brush_paths = pathList(top, "brushes", base_dir, "brush", &sheet.brush_lift_mm);
  sheet.trajectory_paths = pathList(top, "trajectories", base_dir, "trajectory", nullptr);

  const std::string layout = top.string("layout", "brushes-in-rows");
  top.require(layout == "brushes-in-rows" || layout == "brushes-in-columns", "layout",
              "must be \"brushes-in-rows\" or \"brushes-in-columns\"");
  sheet.brushes_in_columns = layout == "brushes-in-columns";

  sheet.px_per_mm = top.number("px_per_mm", sheet.px_per_mm);
  top.require(sheet.px_per_mm > 0 && sheet.px_per_mm <= kMaxScenePxPerMm, "px_per_mm",
              "must be in (0, 100]");

  if (top.has("cell_mm")) {
    const nlohmann::json& cell = top.raw("cell_mm");
    if (cell.is_string()) {
      top.require(cell.get<std::string>() == "auto", "cell_mm",
                  "must be \"auto\" or [width, height] in mm");
    } else {
      const std::vector<double> size = top.numbers("cell_mm");
      top.require(size.size() == 2, "cell_mm", "must be \"auto\" or [width, height] in mm");
      for (size_t i = 0; i < 2; ++i)
        checkedElement(top, "cell_mm", i, size[i], size[i] > 0 && size[i] <= kMaxSheetCellMm,
                       "must be in (0, 1000] mm");
      sheet.cell_width_mm = size[0];
      sheet.cell_height_mm = size[1];
    }
  }

  if (top.has("paint")) {
    sheet.paint = PaintLoad{};
    parsePaintLoad(top.object("paint"), &sheet.paint);
  }
  sheet.paper.colour = top.string("background", sheet.paper.colour);
  if (!parseHexColour(sheet.paper.colour, &sheet.background))
    top.fail(top.childPointer("background"),
             "colour '" + sheet.paper.colour + "' does not parse (must be #rrggbb, hex digits)");
  if (top.has("paper")) parsePaperTooth(top.object("paper"), &sheet.paper);
  const std::string mix = top.string("mix", "km");
  top.require(mix == "km" || mix == "rgb", "mix",
              "must be \"km\" (Kubelka-Munk) or \"rgb\" (linear RGB)");
  sheet.mix = mix == "km" ? MixModel::kKubelkaMunk : MixModel::kLinearRgb;
  if (top.has("sim")) parseSimOptions(top.object("sim"), &sheet.sim);
  sheet.solver = parseSolverField(top, sheet.solver);
  if (top.has("labels")) {
    const JsonObject labels = top.object("labels");
    labels.declareKeys({"font_px"});
    sheet.label_px = labels.integer("font_px", sheet.label_px);
    labels.require(sheet.label_px >= kMinSheetLabelPx && sheet.label_px <= kMaxSheetLabelPx,
                   "font_px",
                   "must be in [" + std::to_string(kMinSheetLabelPx) + ", " +
                       std::to_string(kMaxSheetLabelPx) + "] px");
    labels.rejectUnknownKeys();
  }
  top.rejectUnknownKeys();
  return sheet;
}

}  // namespace

PaintLoad Sheet::defaultSheetPaint() {
  PaintLoad load;
  load.paints = {"#1c2433"};  // cli/paint_options.h: `bristle render`'s blue-black ink
  return load;
}

PaperSpec Sheet::defaultSheetPaper() {
  return PaperSpec();
}

std::string Sheet::brushLabel(size_t b) const {
  std::string label = b < brushes.size() ? brushes[b].name : fs::path(brush_paths.at(b)).stem().string();
  // A lifted row says so: its strokes are not held as the others are.
  if (b < brush_lift_mm.size() && brush_lift_mm[b] != 0) {
    std::ostringstream ss;
    ss.precision(3);
    ss << (brush_lift_mm[b] > 0 ? " +" : " ") << brush_lift_mm[b] << " mm";
    label += ss.str();
  }
  return label;
}

std::string Sheet::trajectoryLabel(size_t t) const {
  return fs::path(trajectory_paths.at(t)).stem().string();
}

Trajectory Sheet::cellTrajectory(size_t b, size_t t) const {
  Trajectory out = resolveDepths(trajectories.at(t), brushes.at(b));
  const double lift = brush_lift_mm.at(b);
  if (lift != 0)
    for (TrajectorySample& s : out.samples) s.pose.position_mm.z() += lift;
  return out;
}

bool looksLikeSheet(const std::string& text) {
  const nlohmann::json j = parseJsonOrDiscarded(text);
  if (!j.is_object()) return false;
  auto it = j.find("format");
  return it != j.end() && it->is_string() &&
         it->get<std::string>().rfind("bristle-sheet/", 0) == 0;
}

Sheet parseSheet(const std::string& text, const std::string& path_for_messages,
                 const std::string& base_dir) {
  const nlohmann::json root = parseJsonText(text, path_for_messages);
  Sheet sheet = parseSheetOnly(root, path_for_messages, base_dir);
  parseHexColour(sheet.paper.colour, &sheet.background);
  return sheet;
}

Sheet loadSheet(const std::string& path) {
  const std::string text = readTextFile(path);
  Sheet sheet = parseSheet(text, path, fs::path(path).parent_path().string());
  sheet.inputs.push_back(path);
  for (size_t i = 0; i < sheet.brush_paths.size(); ++i) {
    requireReadableInput(path, "/brushes/" + std::to_string(i), sheet.brush_paths[i]);
    sheet.brushes.push_back(loadBrush(sheet.brush_paths[i]));
    sheet.inputs.push_back(sheet.brush_paths[i]);
  }
  for (size_t i = 0; i < sheet.trajectory_paths.size(); ++i) {
    requireReadableInput(path, "/trajectories/" + std::to_string(i), sheet.trajectory_paths[i]);
    sheet.trajectories.push_back(loadTrajectory(sheet.trajectory_paths[i]));
    sheet.inputs.push_back(sheet.trajectory_paths[i]);
  }
  // Each file is sound on its own; a pair may still put the ferrule into the
  // canvas (a long brush on a trajectory written for a short one).
  for (size_t b = 0; b < sheet.brushes.size(); ++b)
    for (size_t t = 0; t < sheet.trajectories.size(); ++t) {
      try {
        validateTrajectoryForBrush(sheet.cellTrajectory(b, t), sheet.brushes[b]);
      } catch (const Error& e) {
        throw Error(e.code(), path + ": /brushes/" + std::to_string(b) + " with /trajectories/" +
                                  std::to_string(t) + ": brush '" + sheet.brushes[b].name +
                                  "': " + e.what());
      }
    }
  return sheet;
}

std::uint64_t sheetInputsHash(const Sheet& sheet) { return fnv1a64Files(sheet.inputs); }

std::vector<std::string> sheetInputWarnings(const Sheet& sheet) {
  std::vector<std::string> out;
  auto add = [&out](const std::string& w) {
    if (!w.empty() && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
  };
  for (const Brush& b : sheet.brushes) add(brushScaleWarning(b));
  for (size_t b = 0; b < sheet.brushes.size(); ++b)
    for (size_t t = 0; t < sheet.trajectories.size(); ++t) {
      const Trajectory cell = sheet.cellTrajectory(b, t);
      add(trajectoryWarning(cell, plannedStepCount(cell, sheet.brushes[b], sheet.sim),
                            &sheet.brushes[b], sheet.sim));
    }
  return out;
}

}  // namespace bristle

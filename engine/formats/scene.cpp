#include "engine/formats/scene.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>

#include "engine/formats/brush_library.h"
#include "engine/base/error.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/geometry/first_contact.h"
#include "engine/formats/input_warnings.h"
#include "engine/base/json_reader.h"
#include "engine/paint/pigments.h"
#include "engine/base/text_file.h"
#include "engine/dynamics/stepper.h"

namespace bristle {
namespace {

namespace fs = std::filesystem;

constexpr const char* kSceneFormat = "bristle-scene/1";
// Paper grain deeper than this is not paper but relief.
constexpr double kMaxToothDepthMm = 1.0;
// Simulation settings: the CLI's ranges for --min-rate-hz and --max-step-mm.
constexpr double kMinRateHz = 1, kMaxRateHz = 10000;
constexpr double kMinStepMm = 0.01, kMaxStepMm = 5;


std::string fmt(double v) {
  std::ostringstream ss;
  ss.precision(6);
  ss << v;
  return ss.str();
}

// A path as the scene names it, resolved against the scene file's folder.
std::string resolve(const std::string& base_dir, const std::string& p) {
  const fs::path path(p);
  if (path.is_absolute() || base_dir.empty()) return path.lexically_normal().string();
  return (fs::path(base_dir) / path).lexically_normal().string();
}

// A referenced file must be a readable regular file; else 66 naming the scene field.
void requireReadable(const std::string& scene, const std::string& pointer,
                     const std::string& resolved) {
  std::string why;
  const int fd = openInputFile(resolved, &why);
  if (fd >= 0) {
    ::close(fd);
    return;
  }
  throw Error(ExitCode::kNoInput,
              scene + ": " + pointer + ": cannot read '" + resolved + "': " + why);
}

void parsePlacement(const JsonObject& o, Placement* out) {
  o.declareKeys({"offset_mm", "rotate_deg"});
  if (o.has("offset_mm")) {
    const std::vector<double> off = o.numbers("offset_mm");
    o.require(off.size() == 2, "offset_mm", "must be [x, y] in mm");
    for (size_t i = 0; i < 2; ++i)
      checkedElement(o, "offset_mm", i, off[i], std::fabs(off[i]) <= kMaxPositionMm,
                     "must be within +-100000 mm (the limit)");
    out->offset_x_mm = off[0];
    out->offset_y_mm = off[1];
  }
  out->rotate_deg = o.number("rotate_deg", 0.0);
  o.require(std::fabs(out->rotate_deg) <= 3600, "rotate_deg", "must be within +-3600 degrees");
  o.rejectUnknownKeys();
}

void parseCanvas(const JsonObject& c, SceneCanvas* out) {
  c.declareKeys({"size_mm", "px_per_mm", "background", "paper"});
  SceneCanvas& cv = *out;
  const std::vector<double> size = c.numbers("size_mm");
  c.require(size.size() == 2, "size_mm", "must be [width, height] in mm");
  for (size_t i = 0; i < 2; ++i) checkedElement(c, "size_mm", i, size[i], size[i] > 0, "must be > 0");
  cv.width_mm = size[0];
  cv.height_mm = size[1];
  cv.px_per_mm = c.number("px_per_mm", 8.0);
  c.require(cv.px_per_mm > 0 && cv.px_per_mm <= kMaxScenePxPerMm, "px_per_mm",
            "must be in (0, 100]");
  // Refuse before anything is allocated (engine/model/canvas.h limits); in doubles,
  // so that absurd sizes cannot overflow the check itself.
  const double w_px = std::ceil(cv.width_mm * cv.px_per_mm - 1e-9);
  const double h_px = std::ceil(cv.height_mm * cv.px_per_mm - 1e-9);
  // A canvas of less than a pixel a side (1e-300 mm) has nothing to paint on.
  if (w_px < 1 || h_px < 1)
    c.fail(c.childPointer("size_mm"),
           fmt(cv.width_mm) + " x " + fmt(cv.height_mm) + " mm at " + fmt(cv.px_per_mm) +
               " px/mm is less than one pixel a side; each side must be at least 1 px");
  if (w_px > kMaxCanvasSidePx || h_px > kMaxCanvasSidePx ||
      w_px * h_px > static_cast<double>(kMaxCanvasPixels))
    c.fail(c.childPointer("size_mm"),
           fmt(cv.width_mm) + " x " + fmt(cv.height_mm) + " mm at " + fmt(cv.px_per_mm) +
               " px/mm is " + fmt(w_px) + " x " + fmt(h_px) + " px: larger than the limit of " +
               std::to_string(kMaxCanvasSidePx) + " px a side and " +
               std::to_string(kMaxCanvasPixels) + " px in all");

  cv.paper.colour = c.string("background", cv.paper.colour);
  if (!parseHexColour(cv.paper.colour, &cv.background))
    c.fail(c.childPointer("background"),
           "colour '" + cv.paper.colour + "' does not parse (must be #rrggbb, hex digits)");
  if (c.has("paper")) parsePaperTooth(c.object("paper"), &cv.paper);
  c.rejectUnknownKeys();
}


// The scene file alone: every rule that needs no other file.
Scene parseSceneOnly(const nlohmann::json& root, const std::string& path,
                     const std::string& base_dir) {
  const JsonObject top(root, "", path);
  top.declareKeys({"format", "name", "description", "canvas", "sim", "mix", "solver", "strokes"});
  Scene scene;
  scene.path = path;
  const std::string format = top.string("format");
  top.require(format == kSceneFormat, "format", "unknown format version (expected \"bristle-scene/1\")");
  scene.name = top.string("name");
  top.require(!scene.name.empty(), "name", "must not be empty");
  scene.description = top.string("description", "");
  parseCanvas(top.object("canvas"), &scene.canvas);
  if (top.has("sim")) parseSimOptions(top.object("sim"), &scene.sim);
  const std::string mix = top.string("mix", "km");
  top.require(mix == "km" || mix == "rgb", "mix",
              "must be \"km\" (Kubelka-Munk) or \"rgb\" (linear RGB)");
  scene.mix = mix == "km" ? MixModel::kKubelkaMunk : MixModel::kLinearRgb;
  scene.solver = parseSolverField(top, scene.solver);

  const std::vector<JsonObject> strokes = top.objects("strokes");
  top.require(!strokes.empty() && strokes.size() <= static_cast<size_t>(kMaxSceneStrokes),
              "strokes", "must have 1.." + std::to_string(kMaxSceneStrokes) + " strokes");
  for (const JsonObject& s : strokes) {
    s.declareKeys({"brush", "trajectory", "paint", "placement", "dry_before"});
    SceneStroke st;
    st.pointer = s.pointer();
    const std::string brush = s.string("brush");
    s.require(!brush.empty(), "brush", "must name a brush file");
    const std::string traj = s.string("trajectory");
    s.require(!traj.empty(), "trajectory", "must name a trajectory file");
    st.brush_path = isBrushName(brush) ? findBrushByName(brush, path + ": " + st.pointer + "/brush")
                                       : resolve(base_dir, brush);
    st.trajectory_path = resolve(base_dir, traj);
    parsePaintLoad(s.object("paint"), &st.paint);
    if (s.has("placement")) parsePlacement(s.object("placement"), &st.placement);
    st.dry_before = s.boolean("dry_before", false);
    s.rejectUnknownKeys();
    scene.strokes.push_back(std::move(st));
  }
  top.rejectUnknownKeys();
  return scene;
}

}  // namespace

void parsePaperTooth(const JsonObject& p, PaperSpec* out) {
  p.declareKeys({"tooth_depth_mm", "tooth_scale_mm", "seed"});
  PaperSpec& paper = *out;
  paper.tooth_depth_mm = p.number("tooth_depth_mm", paper.tooth_depth_mm);
  p.require(paper.tooth_depth_mm >= 0 && paper.tooth_depth_mm <= kMaxToothDepthMm,
            "tooth_depth_mm", "must be in [0, 1] mm");
  paper.tooth_scale_mm = p.number("tooth_scale_mm", paper.tooth_scale_mm);
  p.require(paper.tooth_scale_mm > 0 && paper.tooth_scale_mm <= 100, "tooth_scale_mm",
            "must be in (0, 100] mm");
  const int seed = p.integer("seed", static_cast<int>(paper.seed));
  p.require(seed >= 0, "seed", "must be >= 0");
  paper.seed = static_cast<std::uint64_t>(seed);
  p.rejectUnknownKeys();
}

void parsePaintLoad(const JsonObject& p, PaintLoad* out) {
  p.declareKeys({"mode", "paints", "amount", "tip_length", "dilution"});
  PaintLoad& load = *out;
  const std::string mode = p.string("mode", "solid");
  if (mode == "solid") {
    load.mode = PaintLoad::Mode::kSolid;
  } else if (mode == "across") {
    load.mode = PaintLoad::Mode::kAcross;
  } else if (mode == "tip") {
    load.mode = PaintLoad::Mode::kTip;
  } else {
    p.require(false, "mode", "must be \"solid\", \"across\" or \"tip\"");
  }
  const nlohmann::json& paints = p.raw("paints");
  const std::string pp = p.childPointer("paints");
  if (paints.is_array())
    for (const nlohmann::json& name : paints)
      // Not a string: a name no rule accepts, reported below as what it is.
      load.paints.push_back(name.is_string() ? name.get<std::string>() : std::string());
  // Each field as it is read, by the rules of every paint load (checkPaintLoad);
  // the fields not read yet hold valid defaults.
  auto check = [&] {
    const std::optional<PaintLoadProblem> e = checkPaintLoad(load, "mode \"" + mode + "\"");
    if (!e) return;
    if (e->field == "paints") p.requireAt(false, pp, paints, e->rule);
    if (e->field.rfind("paints/", 0) == 0) {
      const std::string index = e->field.substr(std::string("paints/").size());
      const std::string pi = pp + "/" + index;
      const nlohmann::json& given = paints[std::stoul(index)];
      p.requireAt(given.is_string(), pi, given, "must be a pigment name or a colour \"#rrggbb\"");
      p.fail(pi, e->rule);
    }
    p.require(false, e->field, e->rule);
  };
  check();
  load.amount = p.number("amount", 1.0);
  check();
  if (p.has("tip_length")) {
    p.require(load.mode == PaintLoad::Mode::kTip, "tip_length", "applies only to mode \"tip\"");
    load.tip_length = p.number("tip_length");
    check();
  }
  load.dilution = p.number("dilution", 0.0);
  check();
  p.rejectUnknownKeys();
}

void parseSimOptions(const JsonObject& s, SimOptions* sim) {
  s.declareKeys({"rate_hz", "max_step_mm", "steady_step_mm"});
  sim->min_rate_hz = s.number("rate_hz", sim->min_rate_hz);
  s.require(sim->min_rate_hz >= kMinRateHz && sim->min_rate_hz <= kMaxRateHz, "rate_hz",
            "must be in [1, 10000] steps per second");
  sim->max_step_mm = s.number("max_step_mm", sim->max_step_mm);
  s.require(sim->max_step_mm >= kMinStepMm && sim->max_step_mm <= kMaxStepMm, "max_step_mm",
            "must be in [0.01, 5] mm");
  sim->steady_step_mm = s.number("steady_step_mm", sim->steady_step_mm);
  s.require(sim->steady_step_mm >= 0 && sim->steady_step_mm <= kMaxStepMm, "steady_step_mm",
            "must be in [0, 5] mm (0: every planned step is solved)");
  s.rejectUnknownKeys();
}

SolverKind parseSolverField(const JsonObject& owner, SolverKind absent) {
  const std::optional<SolverKind> kind =
      parseSolverKind(owner.string("solver", solverKindName(absent)));
  owner.require(kind.has_value(), "solver", "must be \"ipopt\" or \"slsqp\"");
  return *kind;
}

Pose Placement::apply(const Pose& pose) const {
  if (identity()) return pose;
  const double a = rotate_deg * std::numbers::pi / 180;
  const Eigen::AngleAxisd turn(a, Eigen::Vector3d::UnitZ());
  Pose out;
  out.position_mm = turn * pose.position_mm + Eigen::Vector3d(offset_x_mm, offset_y_mm, 0);
  out.rotation = (Eigen::Quaterniond(turn) * pose.rotation).normalized();
  return out;
}

CanvasGrid SceneCanvas::grid() const {
  CanvasGrid g;
  g.px_per_mm = px_per_mm;
  g.width_px = static_cast<int>(std::ceil(width_mm * px_per_mm - 1e-9));
  g.height_px = static_cast<int>(std::ceil(height_mm * px_per_mm - 1e-9));
  return g;
}

std::string resolveInputPath(const std::string& base_dir, const std::string& path) {
  return resolve(base_dir, path);
}

void requireReadableInput(const std::string& file, const std::string& pointer,
                          const std::string& resolved) {
  requireReadable(file, pointer, resolved);
}

// The pigment table (engine/paint/pigments.h) is the one list of paint names.
bool isKnownPigment(const std::string& name) { return findPigment(name) != nullptr; }

std::string knownPigmentList() { return pigmentNames(); }

bool looksLikeScene(const std::string& text) {
  const nlohmann::json j = parseJsonOrDiscarded(text);
  if (!j.is_object()) return false;
  auto it = j.find("format");
  return it != j.end() && it->is_string() &&
         it->get<std::string>().rfind("bristle-scene/", 0) == 0;
}

Scene parseScene(const std::string& text, const std::string& path_for_messages,
                 const std::string& base_dir) {
  const nlohmann::json root = parseJsonText(text, path_for_messages);
  return parseSceneOnly(root, path_for_messages, base_dir);
}

Scene loadScene(const std::string& path) {
  const std::string text = readTextFile(path);
  Scene scene = parseScene(text, path, fs::path(path).parent_path().string());
  scene.inputs.push_back(path);

  // Each distinct file is read once; strokes share brushes and trajectories.
  std::map<std::string, int> brush_index;
  std::map<std::string, Trajectory> trajectories;
  for (SceneStroke& st : scene.strokes) {
    auto b = brush_index.find(st.brush_path);
    if (b == brush_index.end()) {
      requireReadable(path, st.pointer + "/brush", st.brush_path);
      scene.brushes.push_back(loadBrush(st.brush_path));
      scene.inputs.push_back(st.brush_path);
      b = brush_index.emplace(st.brush_path, static_cast<int>(scene.brushes.size()) - 1).first;
    }
    st.brush = b->second;

    auto t = trajectories.find(st.trajectory_path);
    if (t == trajectories.end()) {
      requireReadable(path, st.pointer + "/trajectory", st.trajectory_path);
      t = trajectories.emplace(st.trajectory_path, loadTrajectory(st.trajectory_path)).first;
      scene.inputs.push_back(st.trajectory_path);
    }
    // Depths past first contact are this stroke's brush's; the placement
    // then moves and turns the handle about z, which keeps its height.
    st.trajectory = resolveDepths(t->second, scene.brushes[st.brush]);
    for (TrajectorySample& s : st.trajectory.samples) s.pose = st.placement.apply(s.pose);
    // The trajectory and the brush are each sound; together the ferrule may
    // still dig into the canvas. Say which stroke pairs them.
    try {
      validateTrajectoryForBrush(st.trajectory, scene.brushes[st.brush]);
    } catch (const Error& e) {
      throw Error(e.code(), path + ": " + st.pointer + ": with brush '" +
                                scene.brushes[st.brush].name + "': " + e.what());
    }
  }
  return scene;
}

std::vector<std::string> sceneWarnings(const Scene& scene) {
  std::vector<std::string> out;
  auto add = [&out](const std::string& w) {
    if (!w.empty() && std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
  };
  for (const Brush& b : scene.brushes) add(brushScaleWarning(b));
  const double w = scene.canvas.width_mm, h = scene.canvas.height_mm;
  for (const SceneStroke& st : scene.strokes) {
    const Brush& brush = scene.brushes[st.brush];
    // A trajectory shared by strokes is named once, unless its brushes plan
    // different step counts.
    add(trajectoryWarning(st.trajectory, plannedStepCount(st.trajectory, brush, scene.sim), &brush,
                          scene.sim));
    // No hair reaches further from the ferrule than the brush's reach: a stroke
    // whose handle never comes that close to the canvas cannot touch it.
    if (!st.trajectory.comesWithinReach(scene.brushes[st.brush].reachMm(), w, h))
      out.push_back(scene.path + ": " + st.pointer + ": the brush never comes within reach of "
                    "the canvas (trajectory " + st.trajectory_path + ")");
  }
  return out;
}

}  // namespace bristle

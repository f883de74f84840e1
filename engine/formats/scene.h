#pragma once
// A painting as data: JSON format `bristle-scene/1` (docs/design.md, "Formats";
// docs/scene-format.md). A scene is a canvas (size, resolution, paper) and a list
// of strokes, each a brush moved along a trajectory with a paint loading and an
// optional placement on the canvas. Strokes are painted in order onto one canvas.

#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/model/canvas.h"
#include "engine/paint/paint_spec.h"
#include "engine/dynamics/simulation.h"
#include "engine/solvers/solver_pair.h"
#include "engine/model/trajectory.h"

namespace bristle {

// Limits that keep a scene file from asking for absurd work.
inline constexpr int kMaxSceneStrokes = 10000;
inline constexpr double kMaxScenePxPerMm = 100;  // as the CLI's --px-per-mm

// Rigid placement of a trajectory on the canvas: every handle pose is turned by
// rotate_deg about the canvas normal (+z) through the point (0, 0) of the
// trajectory's own coordinates, then shifted by offset_mm. Trajectories meant
// to be placed are written around (0, 0); heights (z) are never changed.
struct Placement {
  double offset_x_mm = 0, offset_y_mm = 0;
  double rotate_deg = 0;
  bool identity() const { return offset_x_mm == 0 && offset_y_mm == 0 && rotate_deg == 0; }
  Pose apply(const Pose& pose) const;
};

struct SceneStroke {
  std::string brush_path;       // resolved against the scene file's folder
  std::string trajectory_path;  // resolved likewise
  int brush = 0;                // index into Scene::brushes
  PaintLoad paint;
  Placement placement;
  bool dry_before = false;  // the canvas's wet paint dries before this stroke
  // The trajectory with the placement applied (handle poses on the canvas).
  Trajectory trajectory;
  std::string pointer;  // "/strokes/3", for messages
};

struct SceneCanvas {
  double width_mm = 0, height_mm = 0;
  double px_per_mm = 8;
  Rgb background;  // = paper.colour, parsed
  PaperSpec paper;
  // The pixel grid: origin at the canvas's bottom-left corner (world 0, 0).
  CanvasGrid grid() const;
};

struct Scene {
  std::string path;  // the scene file, for messages
  std::string name;
  std::string description;
  SceneCanvas canvas;
  std::vector<Brush> brushes;  // each distinct brush file once
  std::vector<SceneStroke> strokes;
  SimOptions sim;  // rate_hz -> min_rate_hz, max_step_mm
  MixModel mix = MixModel::kKubelkaMunk;
  SolverKind solver = SolverKind::kIpopt;  // the primary spine solver ("solver")
  // Every file the scene read (the scene first, then brushes and trajectories in
  // order of first mention), for the inputs hash of the PNG.
  std::vector<std::string> inputs;
};

// Reads a scene and everything it references; throws bristle::Error:
// 66 if the scene is missing, or a referenced file is (naming the scene field,
// e.g. `scene.json: /strokes/2/trajectory: cannot read 'x.csv': ...`); 65 for bad
// data, naming the JSON pointer and the rule. Brush and trajectory files are read
// by their own readers, whose errors name those files.
Scene loadScene(const std::string& path);

// Only the scene file itself (no referenced file is opened); relative paths are
// resolved against `base_dir`. For tests of the reader's rules.
Scene parseScene(const std::string& text, const std::string& path_for_messages,
                 const std::string& base_dir);

// What is legal but likely a mistake, one line each: a brush whose spines and
// surface differ in scale, a stroke's trajectory that lasts over 10 minutes
// or plans over a million steps (engine/formats/input_warnings.h), a stroke that
// cannot touch the canvas (the handle never comes within the brush's reach of
// it). Planning the steps throws as the render would at a step limit.
std::vector<std::string> sceneWarnings(const Scene& scene);

// Whether a JSON text declares itself a scene ("format": "bristle-scene/...");
// false for anything else, malformed JSON included.
bool looksLikeScene(const std::string& text);

// The readers of the parts a scene shares with other formats (engine/formats/sheet.h):
// each reads one JSON object strictly (unknown keys are errors) and throws
// kDataError naming the pointer and the rule.
class JsonObject;
// A stroke's "paint": mode, paints, amount, tip_length, dilution.
void parsePaintLoad(const JsonObject& paint, PaintLoad* out);
// A canvas's "paper": tooth_depth_mm, tooth_scale_mm, seed (colour is separate).
void parsePaperTooth(const JsonObject& paper, PaperSpec* out);
// "sim": rate_hz (-> min_rate_hz), max_step_mm.
void parseSimOptions(const JsonObject& sim, SimOptions* out);
// The key "solver" of `owner`: "ipopt" or "slsqp", the primary spine solver;
// `absent` when the key is not there.
SolverKind parseSolverField(const JsonObject& owner, SolverKind absent);
// A path as an input file names it, resolved against that file's folder.
std::string resolveInputPath(const std::string& base_dir, const std::string& path);
// A referenced file must be readable, else Error(kNoInput):
// "<file>: <pointer>: cannot read '<resolved>': <why>".
void requireReadableInput(const std::string& file, const std::string& pointer,
                          const std::string& resolved);

// Is `name` a pigment of the pigment table? (The one list the scene reader
// checks paint names against.)
bool isKnownPigment(const std::string& name);
// The pigment names, comma-separated, for messages.
std::string knownPigmentList();

}  // namespace bristle

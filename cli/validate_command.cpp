// `bristle validate FILE...`: checks brush, trajectory and scene files and
// reports each file's verdict, so a batch of inputs can be checked before a
// long run. A .json file is a scene or a sheet when its "format" says so, else
// a brush. Brushes and trajectories given together are then checked in pairs,
// as `render --brush B --trajectory T` would check them before its run.

#include <iostream>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "cli/commands.h"
#include "cli/options.h"
#include "cli/inputs.h"
#include "cli/run_stats.h"
#include "engine/brush.h"
#include "engine/brush_geometry.h"
#include "engine/error.h"
#include "engine/first_contact.h"
#include "engine/input_warnings.h"
#include "engine/scene.h"
#include "engine/simulation.h"
#include "engine/sheet.h"
#include "engine/text_file.h"
#include "engine/trajectory.h"

namespace bristle::cli {
namespace {

// A scene is checked with everything it references: brushes, trajectories,
// and each trajectory placed and held against its brush.
void validateScene(const std::string& f) {
  const Scene scene = loadScene(f);
  for (const Brush& b : scene.brushes) const BrushGeometry geometry(b);
  printWarnings(sceneWarnings(scene));
  const SceneCanvas& c = scene.canvas;
  std::cout << f << ": ok (scene '" << scene.name << "', " << scene.strokes.size()
            << (scene.strokes.size() == 1 ? " stroke, " : " strokes, ") << scene.brushes.size()
            << (scene.brushes.size() == 1 ? " brush, " : " brushes, ") << c.width_mm << " x "
            << c.height_mm << " mm at " << c.px_per_mm << " px/mm)\n";
}

// A sheet is checked with every brush and trajectory it lists, and every pair
// held against each other (the ferrule must stay off the canvas).
void validateSheet(const std::string& f) {
  const Sheet sheet = loadSheet(f);
  for (const Brush& b : sheet.brushes) const BrushGeometry geometry(b);
  printWarnings(sheetInputWarnings(sheet));
  const size_t nb = sheet.brushes.size(), nt = sheet.trajectories.size();
  std::cout << f << ": ok (sheet '" << sheet.name << "', " << nb
            << (nb == 1 ? " brush x " : " brushes x ") << nt
            << (nt == 1 ? " trajectory)\n" : " trajectories)\n");
}

// The checks `render` makes of a brush with a trajectory before its run
// (validateTrajectoryForBrush and the step limits: the same functions, so the
// same messages and exit codes, with render's default options): the
// trajectory for the brush, and its planned steps in *steps.
Trajectory checkPair(const Trajectory& given, const Brush& brush, double* steps) {
  Trajectory t = resolveDepths(given, brush);
  validateTrajectoryForBrush(t, brush);
  *steps = plannedStepCount(t, brush, SimOptions{});
  return t;
}

// The files (a brush as given, a trajectory's path) of the pairs checkPair refuses.
std::set<std::string> refusedFiles(const std::vector<std::pair<std::string, Brush>>& brushes,
                                   const std::vector<Trajectory>& trajectories) {
  std::set<std::string> refused;
  double steps = 0;
  for (const auto& [path, brush] : brushes)
    for (const Trajectory& given : trajectories) try {
        checkPair(given, brush, &steps);
      } catch (const Error&) {
        refused.insert(path);
        refused.insert(given.path);
      }
  return refused;
}

// Each brush with each trajectory: checkPair, a warning when the brush never
// comes within reach of the paper (render's image would be blank), and one
// when the pair plans over a million steps (a trajectory over ten minutes is
// named on its own).
int validatePairs(const std::vector<std::pair<std::string, Brush>>& brushes,
                  const std::vector<Trajectory>& trajectories) {
  int code = 0;
  for (const auto& [path, brush] : brushes)
    for (const Trajectory& given : trajectories) {
      Trajectory t;
      double steps = 0;
      try {
        t = checkPair(given, brush, &steps);
      } catch (const Error& e) {
        printError(e.what());
        if (code == 0) code = static_cast<int>(e.code());
        continue;
      }
      if (t.endTime() - t.startTime() <= kLongTrajectoryS)
        if (const std::string w = trajectoryWarning(t, steps, &brush, SimOptions{}); !w.empty())
          printWarnings({w});
      const bool reaches = t.comesWithinReach(brush.reachMm());
      if (!reaches)
        printError("warning: " + t.path + ": the brush '" + brush.name +
                   "' never comes within reach of the paper: render's image would be blank");
      std::cout << path << " with " << t.path << ": ok (starts above the paper"
                << (reaches ? ", comes within reach of it" : ", never reaches it") << ")\n";
    }
  return code;
}

}  // namespace

int runValidate(const std::vector<std::string>& files) {
  int code = 0;
  std::vector<std::pair<std::string, Brush>> brushes;
  std::vector<Trajectory> trajectories;
  // A brush's or a trajectory's own warning, by the file as a pair names it:
  // told once the pairs are known, and not for a file whose pair is refused,
  // so that a refusal stays its one line.
  std::vector<std::pair<std::string, std::string>> file_warnings;
  for (const std::string& arg : files) {
    try {
      const bool csv = arg.size() >= 4 && arg.compare(arg.size() - 4, 4, ".csv") == 0;
      const std::string f = csv ? arg : findBrushFile(arg, "");  // a library name is a brush
      const std::string text = csv ? std::string() : readTextFile(f);
      if (!csv && looksLikeScene(text)) {
        validateScene(f);
      } else if (!csv && looksLikeSheet(text)) {
        validateSheet(f);
      } else if (csv) {
        Trajectory t = loadTrajectory(f);
        file_warnings.emplace_back(f, trajectoryWarning(t, 0, nullptr, {}));
        std::cout << f << ": ok (trajectory, " << t.samples.size() << " samples, "
                  << t.endTime() - t.startTime() << " s)\n";
        trajectories.push_back(std::move(t));
      } else {
        // Every problem of the file at once, one line each.
        const std::vector<std::string> problems = checkBrush(f);
        for (const std::string& p : problems) printError(p);
        if (!problems.empty()) {
          if (code == 0) code = static_cast<int>(ExitCode::kDataError);
          continue;
        }
        const Brush b = loadBrush(f);
        // Building the geometry checks what the reader cannot: the cage's
        // topology (OpenSubdiv; non-manifold cages) and the strip layout.
        const BrushGeometry geometry(b);
        file_warnings.emplace_back(arg, brushScaleWarning(b));
        std::cout << f << ": ok (brush '" << b.name << "', " << b.spines.size() << " spines"
                  << (b.surface.present() ? ", surface" : "")
                  << (b.strips.present() ? ", " + std::to_string(b.strips.count) + " strips" : "")
                  << ")\n";
        brushes.emplace_back(arg, b);
      }
    } catch (const Error& e) {
      printError(e.what());
      if (code == 0) code = static_cast<int>(e.code());
    }
  }
  const bool pairs = code == 0 && !brushes.empty() && !trajectories.empty();
  const std::set<std::string> refused =
      pairs ? refusedFiles(brushes, trajectories) : std::set<std::string>();
  for (const auto& [file, w] : file_warnings)
    if (!w.empty() && !refused.count(file)) printWarnings({w});
  if (pairs) code = validatePairs(brushes, trajectories);
  return code;
}

Subcommand registerValidate(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  CLI::App* validate = app.add_subcommand(
      "validate", "Check brush and scene (.json) and trajectory (.csv) files");
  validate->footer(
      "Examples:\n"
      "  bristle validate round\n"
      "  bristle validate scenes/brushes/flat.json scenes/trajectories/s-curve.csv\n"
      "  bristle validate scenes/paintings/calligraphy.json scenes/sheets/small.json\n"
      "Each file is checked on its own (a .csv is a trajectory; a .json a scene or a sheet\n"
      "when its format says so, else a brush), a scene or sheet with every file it names.\n"
      "Brushes and trajectories given together are then checked in pairs as render checks\n"
      "them before its run (the same messages): a brush that starts below the paper is\n"
      "exit 65, one that never comes within reach of it a warning. So are a trajectory\n"
      "over 10 minutes or a million steps and a brush whose spines and surface differ\n"
      "tenfold in size (docs/errors.md, Warnings). Exit: the first error's.");
  validate->add_option("files", *files, "Files to check; a library brush by its name (round)")
      ->required();
  return {validate, [files] { return runValidate(*files); }};
}

}  // namespace bristle::cli

// `bristle validate FILE...`: checks brush, trajectory and scene files and
// reports each file's verdict, so a batch of inputs can be checked before a
// long run. A .json file is a scene or a sheet when its "format" says so, else
// a brush.

#include <iostream>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "engine/brush.h"
#include "engine/brush_geometry.h"
#include "engine/error.h"
#include "engine/scene.h"
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
  for (const std::string& w : sceneWarnings(scene)) printError("warning: " + w);
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
  const size_t nb = sheet.brushes.size(), nt = sheet.trajectories.size();
  std::cout << f << ": ok (sheet '" << sheet.name << "', " << nb
            << (nb == 1 ? " brush x " : " brushes x ") << nt
            << (nt == 1 ? " trajectory)\n" : " trajectories)\n");
}

}  // namespace

int runValidate(const std::vector<std::string>& files) {
  int code = 0;
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
        const Trajectory t = loadTrajectory(f);
        std::cout << f << ": ok (trajectory, " << t.samples.size() << " samples, "
                  << t.endTime() - t.startTime() << " s)\n";
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
        std::cout << f << ": ok (brush '" << b.name << "', " << b.spines.size() << " spines"
                  << (b.surface.present() ? ", surface" : "")
                  << (b.strips.present() ? ", " + std::to_string(b.strips.count) + " strips" : "")
                  << ")\n";
      }
    } catch (const Error& e) {
      printError(e.what());
      if (code == 0) code = static_cast<int>(e.code());
    }
  }
  return code;
}

}  // namespace bristle::cli

// `bristle validate FILE...`: checks brush and trajectory files and reports
// each file's verdict, so a batch of inputs can be checked before a long run.

#include <iostream>

#include "cli/commands.h"
#include "engine/brush.h"
#include "engine/brush_geometry.h"
#include "engine/error.h"
#include "engine/text_file.h"
#include "engine/trajectory.h"

namespace bristle::cli {

int runValidate(const std::vector<std::string>& files) {
  int code = 0;
  for (const std::string& f : files) {
    try {
      const bool csv = f.size() >= 4 && f.compare(f.size() - 4, 4, ".csv") == 0;
      if (csv) {
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

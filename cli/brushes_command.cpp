// `bristle brushes`: the brush library, one line per brush with its size and
// the height at which it first touches the paper held upright.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <set>
#include <vector>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "cli/options.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/formats/brush_library.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"

namespace bristle::cli {
namespace {

// Hair length and the width/thickness of the hair bundle at the ferrule (mm).
struct BrushSize {
  double length_mm = 0, width_mm = 0, thickness_mm = 0;
};
BrushSize sizeOf(const Brush& b) {
  BrushSize s;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const SpineSpec& sp : b.spines) {
    s.length_mm = std::max(s.length_mm, sp.lengthMm());
    const double r = 0.5 * sp.width_mm[0];
    x0 = std::min(x0, sp.root_mm.x() - r);
    x1 = std::max(x1, sp.root_mm.x() + r);
    y0 = std::min(y0, sp.root_mm.y() - r);
    y1 = std::max(y1, sp.root_mm.y() + r);
  }
  s.width_mm = std::max(x1 - x0, y1 - y0);
  s.thickness_mm = std::min(x1 - x0, y1 - y0);
  return s;
}

}  // namespace

// The brush files of the library's folders in lookup order: a name is listed
// from the first folder that holds it, as findBrushByName would take it.
std::vector<std::filesystem::path> libraryFiles(const std::vector<std::string>& dirs) {
  namespace fs = std::filesystem;
  std::vector<fs::path> files;
  std::set<std::string> names;
  bool any = false;
  for (const std::string& dir : dirs) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    any = true;
    std::vector<fs::path> here;
    for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".json") here.push_back(e.path());
    std::sort(here.begin(), here.end());
    for (fs::path& f : here)
      if (names.insert(f.stem().string()).second) files.push_back(std::move(f));
  }
  if (!any) {
    std::string list;
    for (const std::string& d : dirs) list += (list.empty() ? "" : ", ") + d;
    throw Error(ExitCode::kNoInput,
                (dirs.size() == 1 ? dirs.front() : "brush library") +
                    ": cannot read: not a directory" +
                    (dirs.size() == 1 ? std::string() : " (looked in " + list + ")"));
  }
  return files;
}

int runBrushes(const std::vector<std::string>& library_dirs) {
  namespace fs = std::filesystem;
  const std::vector<fs::path> files = libraryFiles(library_dirs);
  int code = 0;
  for (const fs::path& f : files) {
    try {
      const Brush b = loadBrush(f.string());
      const BrushSize s = sizeOf(b);
      std::string geometry = b.surface.present() ? "surface" : "";
      if (b.strips.present())
        geometry += (geometry.empty() ? "" : " + ") + std::to_string(b.strips.count) + " strips";
      if (geometry.empty()) geometry = "spine tubes";
      // Held upright, the ferrule's height when the hair first touches the
      // paper: what a trajectory's depth_mm counts from (docs/formats.md).
      const double contact_mm = firstContactHeightMm(b);
      char line[320];
      std::snprintf(line, sizeof line,
                    "%-12s %4.1f mm long, touches at %4.1f mm upright, %4.1f x %3.1f mm at the "
                    "ferrule, %2zu spines, %-22s",
                    f.stem().c_str(), s.length_mm, contact_mm, s.width_mm, s.thickness_mm,
                    b.spines.size(), geometry.c_str());
      std::cout << line << b.description << "\n";
    } catch (const Error& e) {
      printError(e.what());
      if (code == 0) code = static_cast<int>(e.code());
    }
  }
  return code;
}

Subcommand registerBrushes(CLI::App& app) {
  // The library is the folders every brush name is looked up in (cli/inputs.h),
  // so each name listed is one that works; --library lists one folder instead.
  auto library = std::make_shared<std::string>();
  CLI::App* brushes = app.add_subcommand("brushes", "List the brush library, one line each");
  brushes->footer(
      "Examples:\n"
      "  bristle brushes\n"
      "  bristle brushes --library my-brushes\n"
      "Each name listed works wherever a brush is taken (--brush round). A name is looked\n"
      "up as NAME.json in the install's share/bristle/brushes (a bristle run from its\n"
      "build tree looks in its source tree's brushes first), then in each folder of\n"
      "BRISTLE_BRUSH_PATH (colon-separated). A brush that contains '/' or ends in .json\n"
      "is a path, used as given. A name found in several folders is listed once, from\n"
      "the folder where it is found first.");
  brushes->add_option("--library", *library,
                      "List only this folder of brush files (default: every folder a "
                      "brush name is looked up in)");
  return {brushes, [library] {
            return runBrushes(library->empty() ? brushLibraryDirs()
                                               : std::vector<std::string>{*library});
          }};
}

}  // namespace bristle::cli

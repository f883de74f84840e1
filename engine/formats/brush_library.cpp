#include "engine/formats/brush_library.h"

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <optional>

#include "engine/base/error.h"

namespace bristle {
namespace {

namespace fs = std::filesystem;

std::mutex g_mutex;
std::optional<std::vector<std::string>> g_dirs;

}  // namespace

bool isBrushName(const std::string& ref) {
  const std::string ext = ".json";
  const bool json = ref.size() >= ext.size() &&
                    ref.compare(ref.size() - ext.size(), ext.size(), ext) == 0;
  return !ref.empty() && ref != "-" && ref != "." && ref != ".." &&
         ref.find('/') == std::string::npos && !json;
}

std::vector<std::string> brushPathDirs() {
  std::vector<std::string> dirs;
  const char* env = std::getenv("BRISTLE_BRUSH_PATH");
  if (env == nullptr) return dirs;
  const std::string path = env;
  size_t start = 0;
  while (start <= path.size()) {
    const size_t colon = std::min(path.find(':', start), path.size());
    if (colon > start) dirs.push_back(path.substr(start, colon - start));
    start = colon + 1;
  }
  return dirs;
}

void setBrushLibraryDirs(std::vector<std::string> dirs) {
  const std::lock_guard<std::mutex> lock(g_mutex);
  g_dirs = std::move(dirs);
}

std::vector<std::string> brushLibraryDirs() {
  {
    const std::lock_guard<std::mutex> lock(g_mutex);
    if (g_dirs) return *g_dirs;
  }
  return brushPathDirs();
}

std::string findBrushByName(const std::string& name, const std::string& where) {
  const std::vector<std::string> dirs = brushLibraryDirs();
  std::string looked;
  for (const std::string& d : dirs) {
    const std::string file = d + "/" + name + ".json";
    std::error_code ec;
    if (fs::exists(fs::symlink_status(file, ec))) return file;
    looked += (looked.empty() ? "" : ", ") + d;
  }
  throw Error(ExitCode::kNoInput,
              where + ": no brush named '" + name + "' in the library (looked for " + name +
                  ".json in " + (looked.empty() ? std::string("no folder") : looked) +
                  (std::getenv("BRISTLE_BRUSH_PATH") ? "" : "; BRISTLE_BRUSH_PATH is not set") +
                  "); `bristle brushes` lists the library, and a path must contain '/' or "
                  "end in .json");
}

}  // namespace bristle

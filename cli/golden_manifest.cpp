#include "cli/golden_manifest.h"

#include <filesystem>
#include <regex>
#include <set>

#include "engine/base/error.h"
#include "engine/base/json_reader.h"
#include "engine/base/text_file.h"

namespace bristle::cli {
namespace {

namespace fs = std::filesystem;

std::string resolve(const std::string& base_dir, const std::string& p) {
  return (fs::path(base_dir) / p).lexically_normal().string();
}

// One golden of /goldens, by the rules of scripts/golden.py's load_manifest.
Golden readGolden(const JsonObject& o, const std::string& base_dir) {
  o.declareKeys({"name", "scene", "brush", "trajectory", "options", "tolerance"});
  Golden g;
  g.pointer = o.pointer();
  g.name = o.string("name");
  static const std::regex kName("[a-z0-9][a-z0-9-]*");
  o.require(std::regex_match(g.name, kName), "name",
            "must be lower-case letters, digits and '-', starting with a letter or digit");
  for (const char* key : {"scene", "brush", "trajectory"})  // "brsh": say so, not "needs"
    if (!o.has(key)) o.rejectMisspellingOf(key);
  const bool scene = o.has("scene");
  if (scene == (o.has("brush") || o.has("trajectory")))
    o.fail(g.pointer, "needs either \"scene\" or both \"brush\" and \"trajectory\"");
  if (!scene && !(o.has("brush") && o.has("trajectory")))
    o.fail(g.pointer, "a stroke needs both \"brush\" and \"trajectory\"");
  const auto pathAt = [&](const std::string& key) {
    if (!o.has(key)) return std::string();
    const std::string path = o.string(key);
    o.require(!path.empty(), key, "must be a path");
    return resolve(base_dir, path);
  };
  g.scene = pathAt("scene");
  g.brush = pathAt("brush");
  g.trajectory = pathAt("trajectory");
  if (o.has("options")) {
    const nlohmann::json& options = o.raw("options");
    o.require(options.is_array(), "options", "must be a list of strings");
    for (size_t i = 0; i < options.size(); ++i) {
      o.requireAt(options[i].is_string(), o.childPointer("options") + "/" + std::to_string(i),
                  options[i], "must be a string");
      g.options.push_back(options[i].get<std::string>());
    }
    o.require(!scene || g.options.empty(), "options", "a scene carries its own options");
  }
  g.tolerance = o.string("tolerance");
  o.require(g.tolerance == "exact" || g.tolerance == "strict" || g.tolerance == "loose",
            "tolerance", "must be exact, strict or loose");
  o.rejectUnknownKeys();
  g.png = resolve(base_dir, g.name + ".png");
  return g;
}

}  // namespace

GoldenManifest loadGoldenManifest(const std::string& path) {
  const nlohmann::json doc = parseJsonText(readTextFile(path), path);
  const JsonObject root(doc, "", path);
  root.declareKeys({"format", "description", "goldens"});
  root.require(root.string("format") == kGoldenFormat, "format",
               std::string("must be \"") + kGoldenFormat + "\"");
  root.string("description", "");
  const std::vector<JsonObject> goldens = root.objects("goldens");
  root.require(!goldens.empty(), "goldens", "must list at least one golden");
  root.rejectUnknownKeys();
  GoldenManifest manifest;
  manifest.path = path;
  const std::string base_dir = fs::path(path).parent_path().string();
  std::set<std::string> names;
  for (const JsonObject& o : goldens) {
    manifest.goldens.push_back(readGolden(o, base_dir.empty() ? "." : base_dir));
    const Golden& g = manifest.goldens.back();
    if (!names.insert(g.name).second)
      o.fail(g.pointer + "/name = \"" + g.name + "\"", "is listed twice");
  }
  return manifest;
}

}  // namespace bristle::cli

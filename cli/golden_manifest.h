#pragma once
// The golden manifest, `bristle-golden/1` (golden/golden.json,
// docs/golden-tests.md): the goldens `scripts/golden.py` renders and compares.
// Read here by the rules golden.py holds it to, for `bristle validate`.

#include <string>
#include <vector>

namespace bristle::cli {

inline constexpr const char* kGoldenFormat = "bristle-golden/1";

struct Golden {
  std::string pointer;  // "/goldens/3", for messages
  std::string name;     // lower-case letters, digits, '-'; unique
  std::string scene;    // a scene's golden; or
  std::string brush, trajectory;     // a stroke's (paths resolved against the manifest's folder)
  std::vector<std::string> options;  // a stroke's `bristle render` options
  std::string tolerance;             // exact, strict or loose (bristle compare's presets)
  std::string png;                   // its image: <manifest folder>/<name>.png
};

struct GoldenManifest {
  std::string path;
  std::vector<Golden> goldens;
};

// Reads and checks a golden manifest; throws bristle::Error: 66 when it cannot
// be read, 65 naming the JSON pointer and the rule (unknown keys, a golden with
// neither or both of a scene and a stroke, a repeated name, options on a
// scene, an unknown tolerance). The files it names are not opened here.
GoldenManifest loadGoldenManifest(const std::string& path);

}  // namespace bristle::cli

#pragma once
// Brushes by name: wherever a brush is taken (the command line, a scene's
// strokes, a sheet's brushes, a batch job), a library name such as "round"
// works as well as a file. A reference that contains '/' or ends in ".json"
// is a path, used as given (a scene's, sheet's or manifest's relative to its
// folder); anything else ("-", standard input, and "." and ".." aside) is a
// name, looked up as NAME.json in the brush library's folders, in order.

#include <string>
#include <vector>

namespace bristle {

bool isBrushName(const std::string& ref);

// The library's folders. The CLI sets them at start (cli/inputs.h: the source
// tree's scenes/brushes for the build's own executable, the install's
// share/bristle/brushes, then BRISTLE_BRUSH_PATH); until then they are the
// folders of BRISTLE_BRUSH_PATH (colon-separated, empty entries skipped).
void setBrushLibraryDirs(std::vector<std::string> dirs);
std::vector<std::string> brushLibraryDirs();
// The folders of BRISTLE_BRUSH_PATH.
std::vector<std::string> brushPathDirs();

// The file of a name: DIR/NAME.json in the first library folder where it
// exists (whatever is there is the brush: its reader refuses what is not a
// regular file). Throws Error(kNoInput) "WHERE: no brush named 'NAME' in the
// library (looked for NAME.json in DIR, ...)", naming every folder looked in.
std::string findBrushByName(const std::string& name, const std::string& where);

}  // namespace bristle

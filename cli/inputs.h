#pragma once
// How the command line names its files, as users of a Unix tool expect:
//  - a brush is a file, or a library name ("round") looked up in the brush
//    library's folders (brushLibraryDirs);
//  - "-" is standard input for a trajectory and standard output for a PNG.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/atomic_output.h"
#include "engine/text_file.h"
#include "engine/trajectory.h"

namespace bristle::cli {

// "-": standard input (an input) or standard output (a PNG output).
inline bool isStdio(const std::string& path) { return path == kStdioPath; }

// True when ref is a brush name to look up, false when it is a path used as
// given: a path contains '/' or ends in ".json" ("-" is neither: standard input).
bool isBrushName(const std::string& ref);

// The folders a brush name is looked up in, in order: the source tree's
// scenes/brushes (only for the executable in the build tree: an installed
// copy does not depend on the checkout it was built from), the install's
// share/bristle/brushes (<exe dir>/../share/...), then each folder of
// BRISTLE_BRUSH_PATH (colon-separated; empty entries skipped).
std::vector<std::string> brushLibraryDirs();

// The file of a brush reference: a path as given; a name as DIR/NAME.json in the
// first folder of brushLibraryDirs() holding a regular file of that name.
// Throws Error(kNoInput) naming the option, the name and every folder looked in.
std::string findBrushFile(const std::string& ref, const std::string& option);

// The first folder of brushLibraryDirs() that exists (for `bristle brushes`),
// or the source tree's when none does.
std::string defaultBrushLibrary();


// Standard input, read whole once (readStandardInput, engine/text_file.h);
// later calls return the same text.
const std::string& stdinText();

// A trajectory file, or standard input for "-".
Trajectory loadTrajectoryArg(const std::string& path);

// The bytes of every input in order (a file, or standard input for "-"),
// hashed as the PNG's "bristle:inputs-fnv1a64" (render/compose.h).
std::uint64_t inputsHash(const std::vector<std::string>& inputs);

// A command's outputs and inputs checked as checkOutputs (engine/atomic_output.h)
// does, with "-" allowed only for the outputs named in stdout_ok (the PNG's
// option; kUsage otherwise), at most one of them, and as an input only for
// the options in stdin_ok, at most one of them. "-" entries are then left out
// of checkOutputs.
void checkCliFiles(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs,
                   const std::vector<std::string>& stdout_ok,
                   const std::vector<std::string>& stdin_ok);

// checkCanCreate (engine/atomic_output.h) for a file; nothing for "-".
void checkCanCreateArg(const std::string& path);

}  // namespace bristle::cli

#pragma once
// How the command line names its files, as users of a Unix tool expect:
//  - a brush is a file, or a library name ("round") looked up in the brush
//    library's folders (brushLibraryDirs);
//  - "-" is standard input for a trajectory and standard output for a PNG.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/base/atomic_output.h"
#include "engine/model/brush.h"
#include "engine/formats/brush_library.h"
#include "engine/base/text_file.h"
#include "engine/model/trajectory.h"

namespace bristle::cli {

// "-": standard input (an input) or standard output (a PNG output).
inline bool isStdio(const std::string& path) { return path == kStdioPath; }

// The folders a brush name is looked up in (engine/formats/brush_library.h), in order:
// the source tree's scenes/brushes (only for the executable in the build tree:
// an installed copy does not depend on the checkout it was built from), the
// install's share/bristle/brushes (<exe dir>/../share/...), then each folder of
// BRISTLE_BRUSH_PATH (colon-separated; empty entries skipped). main() gives
// them to setBrushLibraryDirs, for the command line and the files it reads.
std::vector<std::string> cliBrushLibraryDirs();

// The file of a brush reference on the command line: a path as given; a name
// through findBrushByName (kNoInput "OPTION NAME: no brush named ...").
std::string findBrushFile(const std::string& ref, const std::string& option);


// Standard input, read whole once (readStandardInput, engine/base/text_file.h);
// later calls return the same text.
const std::string& stdinText();

// A trajectory file, or standard input for "-". A pen recording or an SVG
// (docs/input.md) is imported with the default mapping for `brush`, its
// warnings printed; anything else is refused naming the formats expected.
Trajectory loadTrajectoryArg(const std::string& path, const Brush& brush);

// The bytes of every input in order (a file, or standard input for "-"),
// hashed as the PNG's "bristle:inputs-fnv1a64" (render/image/compose.h).
std::uint64_t inputsHash(const std::vector<std::string>& inputs);

// A command's outputs and inputs checked as checkOutputs (engine/base/atomic_output.h)
// does, with "-" allowed only for the outputs named in stdout_ok (the PNG's
// option; kUsage otherwise), at most one of them, and as an input only for
// the options in stdin_ok, at most one of them. "-" entries are then left out
// of checkOutputs.
void checkCliFiles(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs,
                   const std::vector<std::string>& stdout_ok,
                   const std::vector<std::string>& stdin_ok);

// checkCanCreate (engine/base/atomic_output.h) for a file; nothing for "-".
void checkCanCreateArg(const std::string& path);

// Refuses (kUsage) a PNG output named with another image format's extension
// (x.jpg, x.tiff, x.webp, ...; any case): bristle writes PNG only, and a PNG
// under such a name is a file other programs misread. A name with no
// extension or any other one is written as given. `stdout_ok`: the option
// takes "-", which the message then offers.
void checkPngOutputName(const std::string& command, const std::string& option,
                        const std::string& path, bool stdout_ok);

}  // namespace bristle::cli

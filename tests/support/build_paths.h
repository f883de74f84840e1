#pragma once
// Absolute paths of this build, for the tests, benchmarks and fuzz replays:
// the source tree they read scenes from, the bristle executable they run and
// the haptic stand-in libraries. CMake writes them into one generated source
// file (cmake/BuildPaths.cmake) instead of passing them as compile
// definitions: a definition enters every object of its target, and an object
// that holds one clone's path cannot be reused by a compiler cache in another
// (docs/PERFORMANCE.md, "The test suite").

namespace bristle::build_paths {
extern const char* const kSourceDir;
extern const char* const kBristleBin;
// Empty where the tests are not built.
extern const char* const kStandinHd;
extern const char* const kStandinHdNosym;
}  // namespace bristle::build_paths

// As macros, so that code in any namespace names them alike, as C strings.
#define BRISTLE_SOURCE_DIR (::bristle::build_paths::kSourceDir)
#define BRISTLE_BIN (::bristle::build_paths::kBristleBin)
#define STANDIN_HD (::bristle::build_paths::kStandinHd)
#define STANDIN_HD_NOSYM (::bristle::build_paths::kStandinHdNosym)

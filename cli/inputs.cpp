#include "cli/inputs.h"

#include "cli/commands.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>

#include "engine/formats/brush_library.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/base/text_file.h"
#include "input/import.h"

namespace bristle::cli {
namespace fs = std::filesystem;

namespace {

bool contains(const std::vector<std::string>& list, const std::string& s) {
  return std::find(list.begin(), list.end(), s) != list.end();
}

std::string joined(const std::vector<std::string>& list, const char* sep) {
  std::string out;
  for (const std::string& s : list) out += (out.empty() ? "" : sep) + s;
  return out;
}

// The folder of the running executable, or empty when /proc/self/exe is unreadable.
fs::path exeDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : exe.parent_path();
}

}  // namespace

std::vector<std::string> cliBrushLibraryDirs() {
  std::vector<std::string> dirs;
  const fs::path bin = exeDir();
  // The executable the build made (not an installed copy) works in its source tree.
  std::error_code ec;
  if (bin.empty() || fs::equivalent(bin, BRISTLE_BUILD_BIN_DIR, ec))
    dirs.push_back(BRISTLE_SOURCE_DIR "/scenes/brushes");
  if (!bin.empty())
    dirs.push_back((bin / BRISTLE_BIN_TO_DATADIR / "bristle/brushes").lexically_normal().string());
  for (std::string& d : brushPathDirs()) dirs.push_back(std::move(d));
  return dirs;
}

std::string findBrushFile(const std::string& ref, const std::string& option) {
  if (!isBrushName(ref)) return ref;
  return findBrushByName(ref, option.empty() ? ref : option + " " + ref);
}

const std::string& stdinText() {
  static const std::string text = readStandardInput();
  return text;
}

Trajectory loadTrajectoryArg(const std::string& path, const Brush& brush) {
  std::vector<std::string> warnings;
  Trajectory t = isStdio(path)
                     ? input::loadTrajectoryOrRecording(stdinText(), kStdinName, brush,
                                                        brush.name, &warnings)
                     : input::loadTrajectoryOrRecording(readTextFile(path), path, brush,
                                                        brush.name, &warnings);
  for (const std::string& w : warnings) printError("warning: " + w);
  return t;
}

std::uint64_t inputsHash(const std::vector<std::string>& inputs) {
  std::uint64_t h = kFnv1a64Offset;
  for (const std::string& p : inputs)
    h = fnv1a64(isStdio(p) ? stdinText() : readTextFile(p), h);
  return h;
}

namespace {

// How "-" reads for one side of a command: "standard output", "be", "writes no
// file to"; or "standard input", "read", "reads no file from".
struct StdioSide {
  const char* stream;
  const char* only_verb;
  const char* none;
};

// The files that are not "-". A "-" must be of an option in `ok`, and only one
// file may be "-" (kUsage naming the option otherwise).
std::vector<NamedFile> withoutStdio(const std::vector<NamedFile>& files,
                                    const std::vector<std::string>& ok, const StdioSide& side) {
  std::vector<NamedFile> kept;
  std::string taken_by;
  for (const NamedFile& f : files) {
    if (!isStdio(f.path)) {
      kept.push_back(f);
      continue;
    }
    const std::string stream = std::string(side.stream) + " (-)";
    if (!contains(ok, f.option))
      throw Error(ExitCode::kUsage,
                  f.option + " -: " +
                      (ok.empty() ? std::string("this command ") + side.none + " " + stream
                                  : "only " + joined(ok, ", ") + " can " + side.only_verb + " " +
                                        stream) +
                      "; give " + f.option + " a file");
    if (!taken_by.empty())
      throw Error(ExitCode::kUsage,
                  f.option + " -: " + side.stream + " is already " + taken_by);
    taken_by = f.option;
  }
  return kept;
}

}  // namespace

void checkCliFiles(const std::vector<NamedFile>& outputs, const std::vector<NamedFile>& inputs,
                   const std::vector<std::string>& stdout_ok,
                   const std::vector<std::string>& stdin_ok) {
  checkOutputs(withoutStdio(outputs, stdout_ok, {"standard output", "be", "writes no file to"}),
               withoutStdio(inputs, stdin_ok, {"standard input", "read", "reads no file from"}));
}

void checkCanCreateArg(const std::string& path) {
  if (!isStdio(path)) checkCanCreate(path);
}

void checkPngOutputName(const std::string& command, const std::string& option,
                        const std::string& path, bool stdout_ok) {
  // Raster and vector image formats a user may expect an image tool to write.
  static const char* const kOtherImages[] = {
      ".jpg", ".jpeg", ".jpe", ".jfif", ".gif", ".bmp",  ".dib",  ".tif", ".tiff",
      ".webp", ".exr", ".hdr", ".svg",  ".svgz", ".ppm", ".pgm",  ".pbm", ".pnm",
      ".tga", ".ico",  ".heic", ".heif", ".avif", ".jxl", ".jp2",  ".psd", ".pdf", ".eps"};
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* other : kOtherImages)
    if (ext == other)
      throw Error(ExitCode::kUsage, command + ": " + option + " " + path +
                                        ": bristle writes PNG only; use a .png name" +
                                        (stdout_ok ? " (or - for standard output)" : ""));
}

}  // namespace bristle::cli

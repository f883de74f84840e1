#pragma once
// Runs the bristle executable for end-to-end tests and captures its output.

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_dir.h"

namespace bristle::testing {

struct RunResult {
  int code = -1;
  std::string out, err;
};

inline std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// Runs a shell command line with stdout and stderr sent to the files out and
// err (and stdin from /dev/null unless the command redirects it), then reads them.
inline RunResult runCaptured(const std::string& command, const std::string& out,
                             const std::string& err) {
  const std::string cmd = "{ " + command + "\n} >'" + out + "' 2>'" + err + "' </dev/null";
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = readAll(out);
  r.err = readAll(err);
  return r;
}

// Runs `bristle <args>` (args are passed to the shell as written).
inline RunResult runBristle(const std::string& args) {
  static TempDir io;
  return runCaptured(std::string("env -u GALLIUM_DRIVER '") + BRISTLE_BIN + "' " + args,
                     io.file("stdout"), io.file("stderr"));
}

inline std::string sourcePath(const std::string& rel) {
  return std::string(BRISTLE_SOURCE_DIR) + "/" + rel;
}

// The library's round brush, the one most end-to-end tests paint with.
inline const std::string kRound = sourcePath("scenes/brushes/round.json");

}  // namespace bristle::testing

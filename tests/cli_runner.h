#pragma once
// Runs the bristle executable for end-to-end tests and captures its output.

#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "temp_dir.h"
#include "tests/support/build_paths.h"

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

// A trajectory file's text up to its sample at t_max_s: its comments, header
// and the samples at t_s <= t_max_s. A test whose solves are made to fail (a
// starved iteration limit) renders a short piece: every failed step is
// retried spine by spine, which is slow on a whole stroke.
inline std::string trajectoryHead(const std::string& path, double t_max_s) {
  std::istringstream in(readAll(path));
  std::string line, head;
  while (std::getline(in, line) &&
         (line.empty() || !std::isdigit(static_cast<unsigned char>(line[0])) ||
          std::stod(line) <= t_max_s))
    head += line + "\n";
  return head;
}

// The library's round brush, the one most end-to-end tests paint with.
inline const std::string kRound = sourcePath("scenes/brushes/round.json");

}  // namespace bristle::testing

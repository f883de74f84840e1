#pragma once
// bristle/error.h -- the one exception type of bristle's public API.
//
// Every function of the public API (bristle/*.h) that fails throws
// bristle::api::Error: a one-line message naming the argument (or file and
// field) and the rule it broke, as the command line prints it, and the
// category the command line would exit with (docs/errors.md). Nothing else
// escapes except std::bad_alloc.

#include <stdexcept>
#include <string>

namespace bristle::api {

// The command line's exit code for the same problem (docs/design.md, "Exit codes").
enum class ErrorCategory : int {
  kUsage = 64,        // a bad argument or option value
  kDataError = 65,    // bad input data (a brush file, trajectory, paint)
  kNoInput = 66,      // an input missing or unreadable (an unknown brush name)
  kSoftware = 70,     // an internal error
  kCantCreate = 73,   // an output cannot be created
  kIoError = 74,      // writing failed midway
};

class Error : public std::runtime_error {
 public:
  Error(ErrorCategory category, const std::string& message)
      : std::runtime_error(message), category_(category) {}
  ErrorCategory category() const noexcept { return category_; }
  int exitCode() const noexcept { return static_cast<int>(category_); }

 private:
  ErrorCategory category_;
};

}  // namespace bristle::api

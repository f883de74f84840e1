#pragma once
// Errors that reach the user: each carries the sysexits code the CLI exits with
// (docs/design.md, "Exit codes") and a one-line message that names the file,
// the field (JSON pointer or CSV line/column) and the broken rule.

#include <stdexcept>
#include <string>

namespace bristle {

enum class ExitCode : int {
  kOk = 0,
  kCheckFailed = 1,    // images differ / a check failed
  kUsage = 64,         // bad command line
  kDataError = 65,     // bad input data
  kNoInput = 66,       // input missing or unreadable
  kUnavailable = 69,   // haptic device unavailable
  kSoftware = 70,      // internal error that could not be recovered
  kCantCreate = 73,    // cannot create output
  kIoError = 74,       // I/O error while writing
};

// A message as one printable line: control characters from the input (a NUL
// would cut the message short at what(), a newline would split it) are shown
// as \u00XX.
inline std::string oneLine(const std::string& message) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(message.size());
  for (const char c : message) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u == 0x7f) {
      out += "\\u00";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    } else {
      out += c;
    }
  }
  return out;
}

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message)
      : std::runtime_error(oneLine(message)), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

// "file: where: rule" -- the house format of every input error.
inline Error dataError(const std::string& file, const std::string& where,
                       const std::string& rule) {
  return Error(ExitCode::kDataError, file + ": " + where + ": " + rule);
}

}  // namespace bristle

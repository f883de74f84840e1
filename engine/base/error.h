#pragma once
// Errors that reach the user: each carries the sysexits code the CLI exits with
// (docs/design.md, "Exit codes") and a one-line message that names the file,
// the field (JSON pointer or CSV line/column) and the broken rule.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <string_view>

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

// The length of the valid UTF-8 sequence at s[i] (1 to 4), or 0 when the
// bytes there are not UTF-8 (RFC 3629: no overlong forms, no surrogates,
// nothing past U+10FFFF).
inline size_t utf8SequenceAt(std::string_view s, size_t i) {
  const auto at = [&](size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char b = at(i);
  if (b < 0x80) return 1;
  // The sequence's length by its first byte, and its second byte's range.
  size_t n = 0;
  unsigned char lo = 0x80, hi = 0xbf;
  if (b >= 0xc2 && b <= 0xdf) {
    n = 2;
  } else if (b >= 0xe0 && b <= 0xef) {
    n = 3;
    if (b == 0xe0) lo = 0xa0;  // overlong
    if (b == 0xed) hi = 0x9f;  // surrogates
  } else if (b >= 0xf0 && b <= 0xf4) {
    n = 4;
    if (b == 0xf0) lo = 0x90;  // overlong
    if (b == 0xf4) hi = 0x8f;  // past U+10FFFF
  }
  if (n == 0 || i + n > s.size() || at(i + 1) < lo || at(i + 1) > hi) return 0;
  for (size_t k = 2; k < n; ++k)
    if (at(i + k) < 0x80 || at(i + k) > 0xbf) return 0;
  return n;
}

// A message as one printable line, by one rule for every message: the C0
// controls, DEL and the C1 controls (U+0080-U+009F; a CSI would drive the
// terminal) are shown as \u with four hex digits (\u009b), as JSON writes
// them, and each byte that is not UTF-8 as \x with two (\xff). A NUL would cut the message short at what(), a newline
// would split it.
inline std::string oneLine(std::string_view message) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(message.size());
  for (size_t i = 0; i < message.size();) {
    const size_t n = utf8SequenceAt(message, i);
    const auto b = static_cast<unsigned char>(message[i]);
    const bool c1 = n == 2 && b == 0xc2 && static_cast<unsigned char>(message[i + 1]) <= 0x9f;
    if (n == 1 && b >= 0x20 && b != 0x7f) {
      out += message[i];
    } else if (n > 1 && !c1) {
      out.append(message.substr(i, n));
    } else {
      const unsigned u = c1 ? static_cast<unsigned char>(message[i + 1]) : b;
      out += n == 0 ? "\\x" : "\\u00";
      out += kHex[u >> 4];
      out += kHex[u & 0xf];
    }
    i += n == 0 ? 1 : n;
  }
  return out;
}

// True when oneLine would change `text`: it holds a control character or is
// not UTF-8. Such text cannot go into a line of a file (a session's header)
// or be a batch job's id or output.
inline bool hasControlCharacter(std::string_view text) { return oneLine(text) != text; }

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

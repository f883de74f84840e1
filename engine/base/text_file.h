#pragma once
// Whole-file reading with the CLI's error conventions, and the rule every input
// follows: it is a regular file no larger than kMaxInputBytes (docs/errors.md).

#include <sys/types.h>

#include <cstdint>
#include <string>

namespace bristle {

// The largest input file read (256 MiB): a trajectory of about two million rows,
// a session of six hours at 100 rows/s. Larger files are refused (kDataError)
// before they are read, and a file that grows while read is cut off at this
// size plus one byte and refused too.
constexpr std::uint64_t kMaxInputBytes = std::uint64_t{256} << 20;

// Opens an input for reading without blocking (a FIFO with no writer would
// block open() for ever) and checks that it is a regular file. Returns the
// descriptor, or -1 with *why set to the reason ("No such file or directory",
// "is a FIFO; an input must be a regular file").
int openInputFile(const std::string& path, std::string* why);

// Reads a file into memory; throws bristle::Error(kNoInput) naming the file and
// the system's reason when it is missing, unreadable or not a regular file, and
// kDataError when it is larger than kMaxInputBytes.
std::string readTextFile(const std::string& path);

// What a file of this st_mode is, when not a regular file: "is a directory",
// "is a FIFO", ... (for messages about inputs and outputs alike).
const char* fileKindOf(mode_t mode);

// The name messages give standard input, and the path that means it ("-").
inline constexpr const char* kStdinName = "stdin";
inline constexpr const char* kStdioPath = "-";

// Reads standard input to its end, as readTextFile reads a file: kDataError
// over kMaxInputBytes, kNoInput when unreadable or a terminal (bristle does
// not wait for input typed by hand). Messages name it kStdinName.
std::string readStandardInput();

// "line L, column C" of a byte offset in text (1-based), for parse errors.
std::string lineColumnOf(const std::string& text, size_t byte_offset);

}  // namespace bristle

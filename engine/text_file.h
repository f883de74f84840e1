#pragma once
// Whole-file reading with the CLI's error conventions.

#include <string>

namespace bristle {

// Reads a file into memory; throws bristle::Error(kNoInput) naming the file and
// the system's reason when it is missing or unreadable.
std::string readTextFile(const std::string& path);

// "line L, column C" of a byte offset in text (1-based), for parse errors.
std::string lineColumnOf(const std::string& text, size_t byte_offset);

}  // namespace bristle

#pragma once
// Line-by-line reading shared by the text recordings (MyPaint events, Pointer
// Events CSV): lines with their numbers and fields split by whitespace. CSV
// cells, numbers and the places messages name are the engine's one CSV
// reading (engine/base/csv.h), which trajectories go through too.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "engine/base/csv.h"

namespace bristle::input::detail {

using csv::parseNumber;
using csv::place;
using csv::trim;
using csv::unquote;

// The lines of a text, '\r' stripped, each with its 1-based number.
class Lines {
 public:
  explicit Lines(std::string_view text) : text_(text) {}
  // The next line into *line (without its newline); false at the end.
  bool next(std::string_view* line, int* line_no);

 private:
  std::string_view text_;
  std::size_t pos_ = 0;
  int line_no_ = 0;
};

// The next line that is neither blank nor a '#' comment, trimmed.
bool nextDataLine(Lines& lines, std::string_view* line, int* line_no);

// Whether a line holds nothing but blanks.
bool isBlank(std::string_view s);

// Fields separated by blanks (spaces, tabs).
std::vector<std::string_view> splitBlanks(std::string_view line);

// The lines that are neither blank nor '#' comments: counted before a reader
// stores anything, so a recording over the sample limit is refused first.
std::size_t countDataLines(std::string_view text);

// Throws the limit's error when `samples` is over `max_samples`.
void checkSampleCount(std::size_t samples, std::size_t max_samples, const std::string& path,
                      const char* what);

}  // namespace bristle::input::detail

#pragma once
// Line-by-line reading shared by the text recordings (MyPaint events, Pointer
// Events CSV): lines with their numbers, fields split by whitespace or commas,
// numbers parsed strictly, and messages that name the line and column.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace bristle::input::detail {

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

std::string_view trim(std::string_view s);
// Whether a line holds nothing but blanks.
bool isBlank(std::string_view s);

// Fields separated by blanks (spaces, tabs) or, with comma, by commas (each
// field trimmed).
std::vector<std::string_view> splitBlanks(std::string_view line);
std::vector<std::string_view> splitCommas(std::string_view line);

// "line 7" or "line 7, column 3 (pressure)".
std::string place(int line_no, int column = 0, std::string_view name = {});

// The lines that are neither blank nor '#' comments: counted before a reader
// stores anything, so a recording over the sample limit is refused first.
std::size_t countDataLines(std::string_view text);

// Throws the limit's error when `samples` is over `max_samples`.
void checkSampleCount(std::size_t samples, std::size_t max_samples, const std::string& path,
                      const char* what);

// A field as a finite double: throws Error(kDataError) "path: line L, column C
// (name): 'x' is not a number" / "must be finite".
double parseNumber(std::string_view s, const std::string& path, int line_no, int column,
                   std::string_view name);

// The text of a number for a message ("0.5", "nan"), as it was written.
// (Appended piece by piece: gcc 12's -Wrestrict misreads "'" + std::string(s).)
inline std::string quoted(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out += '\'';
  out.append(s);
  out += '\'';
  return out;
}

}  // namespace bristle::input::detail

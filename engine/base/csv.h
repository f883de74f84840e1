#pragma once
// CSV lines as every text reader of bristle takes them: the trajectory
// (docs/formats.md, "Trajectory") and the pen recordings (docs/input.md).
// Cells are separated by ',' with blanks around a cell ignored; a cell in
// double quotes may hold ',' (RFC 4180; a "" inside is a quote). Numbers are
// parsed strictly, and every message names the file, the line and the column.
// One splitter and one number parser, so that a file reads the same whatever
// command is given it.

#include <string>
#include <string_view>
#include <vector>

namespace bristle::csv {

// The text without the blanks (' ', '\t', '\r') around it.
std::string_view trim(std::string_view s);

// The cells of a line, each trimmed; a ',' inside "..." belongs to its cell,
// whose quotes are kept (unquote drops them).
std::vector<std::string_view> splitLine(std::string_view line);

// A cell without the pair of double quotes around it, if it has them.
std::string_view unquote(std::string_view cell);

// "line 7" or "line 7, column 3 (z_mm)": where a message points.
std::string place(int line_no, int column = 0, std::string_view name = {});

// The text of a cell for a message ("'0.5'", "'nan'"), as it was written.
// (Appended piece by piece: gcc 12's -Wrestrict misreads "'" + std::string(s).)
std::string quoted(std::string_view s);

// A cell as a finite double. A leading '+' is taken (recordings write it);
// a value below the smallest double ("1e-400") is 0. Throws Error(kDataError)
// "path: line L, column C (name): 'x' is not a number", "'x' is outside the
// range of a double" or "'nan': must be finite".
double parseNumber(std::string_view cell, const std::string& path, int line_no, int column,
                   std::string_view name);

}  // namespace bristle::csv

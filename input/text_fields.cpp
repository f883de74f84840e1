#include "input/text_fields.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>

#include "engine/base/error.h"

namespace bristle::input::detail {

bool Lines::next(std::string_view* line, int* line_no) {
  if (pos_ >= text_.size()) return false;
  std::size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  std::string_view l = text_.substr(pos_, end - pos_);
  if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
  pos_ = end + 1;
  *line = l;
  *line_no = ++line_no_;
  return true;
}

bool nextDataLine(Lines& lines, std::string_view* line, int* line_no) {
  std::string_view raw;
  while (lines.next(&raw, line_no)) {
    const std::string_view t = trim(raw);
    if (t.empty() || t[0] == '#') continue;
    *line = t;
    return true;
  }
  return false;
}

std::string_view trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

bool isBlank(std::string_view s) { return trim(s).empty(); }

std::vector<std::string_view> splitBlanks(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

std::vector<std::string_view> splitCommas(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  bool quoted = false;  // inside "...": a comma there is the cell's ("" is a quote, twice toggled)
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i < line.size() && line[i] == '"') quoted = !quoted;
    if (i == line.size() || (line[i] == ',' && !quoted)) {
      out.push_back(trim(line.substr(start, i - start)));
      start = i + 1;
    }
  }
  return out;
}

std::string place(int line_no, int column, std::string_view name) {
  std::string w = "line " + std::to_string(line_no);
  if (column > 0) w += ", column " + std::to_string(column) + " (" + std::string(name) + ")";
  return w;
}

std::size_t countDataLines(std::string_view text) {
  Lines lines(text);
  std::string_view line;
  int no = 0;
  std::size_t n = 0;
  while (nextDataLine(lines, &line, &no)) ++n;
  return n;
}

void checkSampleCount(std::size_t samples, std::size_t max_samples, const std::string& path,
                      const char* what) {
  if (samples > max_samples)
    throw dataError(path, "size",
                    "holds " + std::to_string(samples) + " " + what +
                        ", over the limit of " + std::to_string(max_samples) +
                        " samples per recording (import a part of it at a time)");
}

double parseNumber(std::string_view s, const std::string& path, int line_no, int column,
                   std::string_view name) {
  auto fail = [&](const std::string& what) {
    return dataError(path, place(line_no, column, name), what);
  };
  // from_chars takes no leading '+', which recordings may write.
  std::string_view digits = s;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  if (!digits.empty() && (digits.front() == '+' || digits.front() == '-') && digits.size() < s.size())
    throw fail(quoted(s) + " is not a number");  // "+-5", "++5"
  double value = 0;
  const auto [ptr, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range && ptr == digits.data() + digits.size()) {
    // Below the smallest double ("1e-400") is zero as near as a double can
    // say; beyond the largest is refused.
    if (std::fabs(std::strtod(std::string(digits).c_str(), nullptr)) < 1) return 0;
    throw fail(quoted(s) + " is outside the range of a double");
  }
  if (digits.empty() || ec != std::errc() || ptr != digits.data() + digits.size())
    throw fail(quoted(s) + " is not a number");
  if (!std::isfinite(value)) throw fail(quoted(s) + ": must be finite");
  return value;
}

}  // namespace bristle::input::detail

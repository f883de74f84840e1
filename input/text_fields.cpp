#include "input/text_fields.h"

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

}  // namespace bristle::input::detail

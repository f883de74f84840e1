#include "engine/base/csv.h"

#include <charconv>
#include <cmath>
#include <cstdlib>

#include "engine/base/error.h"

namespace bristle::csv {

std::string_view trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

std::vector<std::string_view> splitLine(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t start = 0;
  bool in_quotes = false;  // inside "...": a comma there is the cell's ("" is a quote, twice toggled)
  for (std::size_t i = 0; i <= line.size(); ++i) {
    if (i < line.size() && line[i] == '"') in_quotes = !in_quotes;
    if (i == line.size() || (line[i] == ',' && !in_quotes)) {
      out.push_back(trim(line.substr(start, i - start)));
      start = i + 1;
    }
  }
  return out;
}

std::string_view unquote(std::string_view cell) {
  if (cell.size() >= 2 && cell.front() == '"' && cell.back() == '"')
    return cell.substr(1, cell.size() - 2);
  return cell;
}

std::string place(int line_no, int column, std::string_view name) {
  std::string w = "line " + std::to_string(line_no);
  if (column > 0) w += ", column " + std::to_string(column) + " (" + std::string(name) + ")";
  return w;
}

std::string quoted(std::string_view s) {
  std::string out;
  out.reserve(s.size() + 2);
  out += '\'';
  out.append(s);
  out += '\'';
  return out;
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

}  // namespace bristle::csv

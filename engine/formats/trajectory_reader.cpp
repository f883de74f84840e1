#include "engine/formats/trajectory_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "engine/base/csv.h"
#include "engine/base/error.h"
#include "engine/base/text_file.h"

namespace bristle {
namespace {

constexpr const char* kFormatLine = "# bristle-trajectory/1";
// Quaternions are normalised on read; below this norm the direction is noise.
constexpr double kMinQuaternionNorm = 1e-6;

// Field ids: the required columns 0..7, then the optional ones. z_mm (kZ) is
// required unless depth_mm (kDepth) stands in its place.
const std::array<const char*, 8> kRequired = {"t_s", "x_mm", "y_mm", "z_mm",
                                              "qw",  "qx",   "qy",   "qz"};
const std::array<const char*, 5> kOptional = {"buttons", "fx_n", "fy_n", "fz_n", "depth_mm"};
constexpr int kT = 0, kZ = 3, kQw = 4, kQz = 7, kButtons = 8, kFx = 9, kFz = 11, kDepth = 12;
constexpr int kFields = 13;

std::string columnName(int id) { return id < 8 ? kRequired[id] : kOptional[id - 8]; }

// The separator other than ',' that a line seems to use, named for a message
// ("';'", "tabs"), or "" for none. Spreadsheets set to a European locale
// write ';', others write tabs; such a line reads as one cell. A header is
// taken to use one when one of its pieces is a column name; a data line, when
// it splits into the header's `fields` pieces. A line holding a ',' uses ','
// (a space after it is padding).
std::string otherSeparator(std::string_view line, size_t fields) {
  if (line.find(',') != std::string_view::npos) return "";
  static const std::pair<char, const char*> kSeparators[] = {
      {';', "';'"}, {'\t', "tabs"}, {'|', "'|'"}, {' ', "spaces"}};
  for (const auto& [sep, name] : kSeparators) {
    if (line.find(sep) == std::string_view::npos) continue;
    std::vector<std::string_view> pieces;
    size_t start = 0;
    for (size_t i = 0; i <= line.size(); ++i)
      if (i == line.size() || line[i] == sep) {
        if (const std::string_view piece = csv::trim(line.substr(start, i - start)); !piece.empty())
          pieces.push_back(piece);
        start = i + 1;
      }
    if (fields > 0 && pieces.size() == fields) return name;
    for (const std::string_view piece : pieces)
      if (fields == 0 && (std::find(kRequired.begin(), kRequired.end(), piece) != kRequired.end() ||
                          std::find(kOptional.begin(), kOptional.end(), piece) != kOptional.end()))
        return name;
  }
  return "";
}

// Refuses a line whose columns are not separated by ',' (otherSeparator).
void rejectOtherSeparator(std::string_view line, size_t fields, const std::string& path,
                          int line_no) {
  const std::string sep = otherSeparator(line, fields);
  if (!sep.empty())
    throw dataError(path, "line " + std::to_string(line_no),
                    "columns are separated by " + sep + "; bristle trajectories use ','");
}

// The first non-blank line must be the format line, of this version.
void checkFormatLine(const std::string& line, const std::string& path, int line_no) {
  if (line.rfind("# bristle-trajectory/", 0) == 0 && line != kFormatLine)
    throw dataError(path, csv::place(line_no), "unknown format version '" + line.substr(2) +
                                              "' (expected bristle-trajectory/1)");
  if (line != kFormatLine)
    throw dataError(path, csv::place(line_no), "the first line must be '# bristle-trajectory/1'");
}

// The header: each cell's field id, every required column present once, the
// height as z_mm or depth_mm (not both), the forces all three or none.
std::vector<int> parseHeader(const std::vector<std::string_view>& cells, const std::string& path,
                             int line_no) {
  std::vector<int> column_of;
  std::array<int, kFields> count{};
  for (size_t c = 0; c < cells.size(); ++c) {
    const std::string_view name = csv::unquote(cells[c]);
    int id = -1;
    for (int f = 0; f < kFields; ++f)
      if (name == columnName(f)) id = f;
    const std::string here = csv::place(line_no, static_cast<int>(c) + 1, name);
    if (id < 0) throw dataError(path, here, "unknown column " + csv::quoted(name));
    if (++count[id] > 1) throw dataError(path, here, "duplicate column");
    if ((id == kZ && count[kDepth] > 0) || (id == kDepth && count[kZ] > 0))
      throw dataError(path, here,
                      "z_mm and depth_mm both give the handle's height; give one of them");
    column_of.push_back(id);
  }
  for (int r = 0; r < static_cast<int>(kRequired.size()); ++r)
    if (count[r] == 0 && !(r == kZ && count[kDepth] > 0))
      throw dataError(path, csv::place(line_no),
                      std::string("header lacks the required column '") + kRequired[r] + "'" +
                          (r == kZ ? " (or depth_mm in its place)" : ""));
  const int nforce = count[kFx] + count[kFx + 1] + count[kFz];
  if (nforce != 0 && nforce != 3)
    throw dataError(path, csv::place(line_no), "force columns fx_n,fy_n,fz_n come all three or none");
  return column_of;
}

// One cell (1-based `column` of line `line_no`) as the number of field `id`,
// within that field's limits. The place is spelt out only for an error: a
// trajectory may hold millions of cells.
double parseCell(std::string_view cell, int id, const std::string& path, int line_no, int column) {
  const std::string name = columnName(id);
  const std::string_view s = csv::unquote(cell);
  const double value = csv::parseNumber(s, path, line_no, column, name);
  auto fail = [&](const std::string& what) {
    return dataError(path, csv::place(line_no, column, name), what);
  };
  auto text = [&] { return std::string(s); };
  if (id == kT && std::fabs(value) > kMaxTimeS)
    throw fail("t_s = " + text() + " is outside the limit of +-1e9 s");
  if (((id >= 1 && id <= kZ) || id == kDepth) && std::fabs(value) > kMaxPositionMm)
    throw fail(name + " = " + text() + " is outside the limit of +-100000 mm");
  if (id >= kQw && id <= kQz && std::fabs(value) > kMaxQuaternionComponent)
    throw fail(name + " = " + text() +
               " is outside the limit of +-1e6 (quaternions are normalised on read)");
  if (id == kButtons && (value < 0 || value != std::floor(value) || value > 65535))
    throw fail("must be a non-negative integer bitmask");
  return value;
}

// One data line as a sample; `previous` is the sample before it, if any (time
// must increase strictly).
TrajectorySample parseRow(const std::vector<std::string_view>& cells, const std::vector<int>& column_of,
                          const std::string& path, int line_no,
                          const TrajectorySample* previous) {
  if (cells.size() != column_of.size()) {
    // Name the first column that is missing or extra.
    const size_t c = std::min(cells.size(), column_of.size());
    const std::string name =
        c < column_of.size() ? columnName(column_of[c]) : std::string("not in the header");
    throw dataError(path, csv::place(line_no, static_cast<int>(c) + 1, name),
                    "has " + std::to_string(cells.size()) + " fields, the header has " +
                        std::to_string(column_of.size()));
  }
  std::array<double, kFields> v{};
  std::array<bool, kFields> present{};
  size_t t_column = 0;
  for (size_t c = 0; c < cells.size(); ++c) {
    const int id = column_of[c];
    v[id] = parseCell(cells[c], id, path, line_no, static_cast<int>(c) + 1);
    present[id] = true;
    if (id == kT) t_column = c;
  }
  TrajectorySample s;
  s.line = line_no;
  s.t_s = v[kT];
  if (previous && !(s.t_s > previous->t_s))
    throw dataError(path, csv::place(line_no, static_cast<int>(t_column) + 1, "t_s"),
                    "t_s = " + std::string(csv::unquote(cells[t_column])) +
                        " is not after the previous sample's time (time must increase strictly)");
  s.pose.position_mm = Eigen::Vector3d(v[1], v[2], v[kZ]);
  Eigen::Quaterniond q(v[kQw], v[kQw + 1], v[kQw + 2], v[kQz]);
  if (q.norm() < kMinQuaternionNorm)
    throw dataError(path, csv::place(line_no), "quaternion (qw,qx,qy,qz) has near-zero norm");
  s.pose.rotation = q.normalized();
  s.buttons = static_cast<int>(v[kButtons]);
  if (present[kFx]) s.force_n = Eigen::Vector3d(v[kFx], v[kFx + 1], v[kFz]);
  s.depth_mm = v[kDepth];
  return s;
}

}  // namespace

Trajectory parseTrajectory(const std::string& text, const std::string& path) {
  Trajectory traj;
  traj.path = path;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  bool seen_format = false;
  std::vector<int> column_of;  // column index -> field id
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line(csv::trim(raw));
    if (line.empty()) continue;
    if (!seen_format) {
      checkFormatLine(line, path, line_no);
      seen_format = true;
      continue;
    }
    if (line[0] == '#') continue;
    const std::vector<std::string_view> cells = csv::splitLine(line);
    if (column_of.empty()) {
      rejectOtherSeparator(line, 0, path, line_no);
      column_of = parseHeader(cells, path, line_no);
      for (size_t c = 0; c < column_of.size(); ++c) {
        if (column_of[c] == kT) traj.t_column = static_cast<int>(c) + 1;
        if (column_of[c] == kDepth) traj.depth_column = static_cast<int>(c) + 1;
      }
      continue;
    }
    if (cells.size() != column_of.size()) rejectOtherSeparator(line, column_of.size(), path, line_no);
    traj.samples.push_back(parseRow(cells, column_of, path, line_no,
                                    traj.samples.empty() ? nullptr : &traj.samples.back()));
  }
  if (!seen_format) throw dataError(path, "line 1", "empty file (expected '# bristle-trajectory/1')");
  if (column_of.empty()) throw dataError(path, "header", "missing header line");
  if (traj.samples.size() < 2)
    throw dataError(path, "line " + std::to_string(line_no),
                    "a trajectory needs at least 2 samples");
  return traj;
}

Trajectory loadTrajectory(const std::string& path) {
  return parseTrajectory(readTextFile(path), path);
}

}  // namespace bristle

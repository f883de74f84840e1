#include "engine/trajectory.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "engine/error.h"
#include "engine/text_file.h"

namespace bristle {
namespace {

constexpr const char* kFormatLine = "# bristle-trajectory/1";
// Quaternions are normalised on read; below this norm the direction is noise.
constexpr double kMinQuaternionNorm = 1e-6;

const std::array<const char*, 8> kRequired = {"t_s", "x_mm", "y_mm", "z_mm",
                                              "qw",  "qx",   "qy",   "qz"};
const std::array<const char*, 4> kOptional = {"buttons", "fx_n", "fy_n", "fz_n"};

std::string trim(std::string_view s) {
  size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return std::string(s.substr(b, e - b));
}

std::string columnName(int id) { return id < 8 ? kRequired[id] : kOptional[id - 8]; }

std::vector<std::string> splitCsv(std::string_view line) {
  std::vector<std::string> out;
  size_t start = 0;
  for (size_t i = 0; i <= line.size(); ++i) {
    if (i == line.size() || line[i] == ',') {
      out.push_back(trim(line.substr(start, i - start)));
      start = i + 1;
    }
  }
  return out;
}

}  // namespace

size_t Trajectory::segmentAt(double t_s) const {
  if (samples.size() < 2 || t_s <= samples.front().t_s) return 0;
  if (t_s >= samples.back().t_s) return samples.size() - 2;
  auto it = std::upper_bound(samples.begin(), samples.end(), t_s,
                             [](double t, const TrajectorySample& s) { return t < s.t_s; });
  return static_cast<size_t>(it - samples.begin()) - 1;
}

Pose Trajectory::poseAt(double t_s) const {
  if (samples.size() == 1 || t_s <= samples.front().t_s) return samples.front().pose;
  if (t_s >= samples.back().t_s) return samples.back().pose;
  const size_t k = segmentAt(t_s);
  const TrajectorySample& a = samples[k];
  const TrajectorySample& b = samples[k + 1];
  return interpolatePose(a.pose, b.pose, (t_s - a.t_s) / (b.t_s - a.t_s));
}

Trajectory parseTrajectory(const std::string& text, const std::string& path) {
  Trajectory traj;
  traj.path = path;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  bool seen_format = false;
  std::vector<int> column_of;  // column index -> field id (0..11)
  auto where = [&](int col, const std::string& name) {
    std::string w = "line " + std::to_string(line_no);
    if (col > 0) w += ", column " + std::to_string(col) + " (" + name + ")";
    return w;
  };

  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    if (line.empty()) continue;
    if (!seen_format) {
      if (line.rfind("# bristle-trajectory/", 0) == 0 && line != kFormatLine)
        throw dataError(path, where(0, ""), "unknown format version '" + line.substr(2) +
                                                "' (expected bristle-trajectory/1)");
      if (line != kFormatLine)
        throw dataError(path, where(0, ""),
                        "the first line must be '# bristle-trajectory/1'");
      seen_format = true;
      continue;
    }
    if (line[0] == '#') continue;
    const std::vector<std::string> cells = splitCsv(line);
    if (column_of.empty()) {  // header line
      std::array<int, 12> count{};
      for (size_t c = 0; c < cells.size(); ++c) {
        int id = -1;
        for (size_t r = 0; r < kRequired.size(); ++r)
          if (cells[c] == kRequired[r]) id = static_cast<int>(r);
        for (size_t o = 0; o < kOptional.size(); ++o)
          if (cells[c] == kOptional[o]) id = static_cast<int>(kRequired.size() + o);
        if (id < 0)
          throw dataError(path, where(static_cast<int>(c) + 1, cells[c]),
                          "unknown column '" + cells[c] + "'");
        if (++count[id] > 1)
          throw dataError(path, where(static_cast<int>(c) + 1, cells[c]), "duplicate column");
        column_of.push_back(id);
      }
      for (size_t r = 0; r < kRequired.size(); ++r)
        if (count[r] == 0)
          throw dataError(path, where(0, ""),
                          std::string("header lacks the required column '") + kRequired[r] + "'");
      const int nforce = count[9] + count[10] + count[11];
      if (nforce != 0 && nforce != 3)
        throw dataError(path, where(0, ""), "force columns fx_n,fy_n,fz_n come all three or none");
      continue;
    }
    if (cells.size() != column_of.size()) {
      // Name the first column that is missing or extra.
      const size_t c = std::min(cells.size(), column_of.size());
      const std::string name =
          c < column_of.size() ? columnName(column_of[c]) : std::string("not in the header");
      throw dataError(path, where(static_cast<int>(c) + 1, name),
                      "has " + std::to_string(cells.size()) + " fields, the header has " +
                          std::to_string(column_of.size()));
    }
    std::array<double, 12> v{};
    std::array<bool, 12> present{};
    size_t t_column = 0;
    for (size_t c = 0; c < cells.size(); ++c) {
      const int id = column_of[c];
      const std::string name = columnName(id);
      const std::string& s = cells[c];
      double value = 0;
      auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
      if (ec == std::errc::result_out_of_range && ptr == s.data() + s.size())
        throw dataError(path, where(static_cast<int>(c) + 1, name),
                        "'" + s + "' is outside the range of a double");
      if (s.empty() || ec != std::errc() || ptr != s.data() + s.size())
        throw dataError(path, where(static_cast<int>(c) + 1, name),
                        "'" + s + "' is not a number");
      if (!std::isfinite(value))
        throw dataError(path, where(static_cast<int>(c) + 1, name), "must be finite");
      if (id == 0 && std::fabs(value) > kMaxTimeS)
        throw dataError(path, where(static_cast<int>(c) + 1, name),
                        "t_s = " + s + " is outside the limit of +-1e9 s");
      if (id >= 1 && id <= 3 && std::fabs(value) > kMaxPositionMm)
        throw dataError(path, where(static_cast<int>(c) + 1, name),
                        name + " = " + s + " is outside the limit of +-100000 mm");
      if (id >= 4 && id <= 7 && std::fabs(value) > kMaxQuaternionComponent)
        throw dataError(path, where(static_cast<int>(c) + 1, name),
                        name + " = " + s + " is outside the limit of +-1e6 (quaternions are "
                        "normalised on read)");
      if (id == 8 && (value < 0 || value != std::floor(value) || value > 65535))
        throw dataError(path, where(static_cast<int>(c) + 1, name),
                        "must be a non-negative integer bitmask");
      v[id] = value;
      present[id] = true;
      if (id == 0) {
        t_column = c;
        traj.t_column = static_cast<int>(c) + 1;
      }
    }
    TrajectorySample s;
    s.line = line_no;
    s.t_s = v[0];
    if (!traj.samples.empty() && !(s.t_s > traj.samples.back().t_s))
      throw dataError(path, where(static_cast<int>(t_column) + 1, "t_s"),
                      "t_s = " + cells[t_column] +
                          " is not after the previous sample's time (time must increase strictly)");
    s.pose.position_mm = Eigen::Vector3d(v[1], v[2], v[3]);
    Eigen::Quaterniond q(v[4], v[5], v[6], v[7]);
    if (q.norm() < kMinQuaternionNorm)
      throw dataError(path, where(0, ""), "quaternion (qw,qx,qy,qz) has near-zero norm");
    s.pose.rotation = q.normalized();
    s.buttons = static_cast<int>(v[8]);
    if (present[9]) s.force_n = Eigen::Vector3d(v[9], v[10], v[11]);
    traj.samples.push_back(s);
  }
  if (!seen_format) throw dataError(path, "line 1", "empty file (expected '# bristle-trajectory/1')");
  if (column_of.empty()) throw dataError(path, "header", "missing header line");
  if (traj.samples.size() < 2)
    throw dataError(path, "line " + std::to_string(line_no),
                    "a trajectory needs at least 2 samples");
  // Ensure time order is strictly increasing (checked above); order samples'
  // quaternions along the shortest path is done by slerp itself.
  return traj;
}

Trajectory loadTrajectory(const std::string& path) {
  return parseTrajectory(readTextFile(path), path);
}

bool Trajectory::comesWithinReach(double r, double w, double h) const {
  for (const TrajectorySample& s : samples) {
    const Eigen::Vector3d& p = s.pose.position_mm;
    if (p.z() <= r && p.x() >= -r && p.x() <= w + r && p.y() >= -r && p.y() <= h + r) return true;
  }
  return false;
}

}  // namespace bristle

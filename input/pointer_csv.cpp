// Pointer Events CSV (docs/input.md, "Pointer Events CSV"): a header of W3C
// Pointer Events field names, as a web canvas logs its pointerdown,
// pointermove and pointerup events, then one event a line. timeStamp is in
// milliseconds (DOMHighResTimeStamp), positions in CSS pixels (y down),
// tiltX/tiltY and twist in degrees, altitudeAngle/azimuthAngle in radians.

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "engine/base/error.h"
#include "input/pen_axis.h"
#include "input/recording.h"
#include "input/sample_checks.h"
#include "input/text_fields.h"

namespace bristle::input {

using namespace detail;

namespace {

enum Field {
  kTime, kX, kY, kPressure, kTiltX, kTiltY, kTwist, kAltitude, kAzimuth, kButtons,
  kPointerType, kPointerId, kFields,
  kUnused = -1,   // a known field bristle has no use for (width, isPrimary, ...)
  kOtherXY = -2,  // a position of another family than the one used
};

// Position columns, most local first: the first family with both x and y is used.
const std::array<std::array<const char*, 2>, 5> kPositionFamilies = {{
    {"offsetX", "offsetY"}, {"x", "y"}, {"clientX", "clientY"}, {"pageX", "pageY"},
    {"screenX", "screenY"}}};

const std::array<const char*, 12> kFieldNames = {
    "timeStamp",    "x",       "y",           "pressure",    "tiltX",     "tiltY",
    "twist",        "altitudeAngle", "azimuthAngle", "buttons", "pointerType", "pointerId"};

const std::array<const char*, 14> kUnusedNames = {
    "type",   "isPrimary", "width",   "height",   "tangentialPressure", "button", "movementX",
    "movementY", "altKey", "ctrlKey", "metaKey", "shiftKey", "detail", "isTrusted"};

std::string knownList() {
  std::string s = "timeStamp, pressure, tiltX, tiltY, twist, altitudeAngle, azimuthAngle, "
                  "buttons, pointerType, pointerId; positions";
  for (const auto& f : kPositionFamilies) s += std::string(" ") + f[0] + "/" + f[1];
  s += "; ignored";
  for (const char* n : kUnusedNames) s += std::string(" ") + n;
  return s;
}

struct Header {
  std::vector<int> field_of;  // per column
  std::array<int, kFields> column{};  // 1-based column of each field, 0 when absent
};

Header parseHeader(const std::vector<std::string_view>& cells, const std::string& path,
                   int line) {
  Header h;
  h.field_of.assign(cells.size(), kUnused);
  // Which position family: the first with both columns.
  int family = -1;
  for (std::size_t f = 0; f < kPositionFamilies.size() && family < 0; ++f) {
    bool hx = false, hy = false;
    for (std::string_view c : cells) {
      hx = hx || unquote(c) == kPositionFamilies[f][0];
      hy = hy || unquote(c) == kPositionFamilies[f][1];
    }
    if (hx && hy) family = static_cast<int>(f);
  }
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::string_view name = unquote(cells[c]);
    const std::string where = place(line, static_cast<int>(c) + 1, name);
    int id = kUnused;
    bool known = false;
    for (int f = 0; f < kFields; ++f)
      if (f != kX && f != kY && name == kFieldNames[f]) id = f, known = true;
    for (std::size_t f = 0; f < kPositionFamilies.size(); ++f)
      for (int axis = 0; axis < 2; ++axis)
        if (name == kPositionFamilies[f][axis]) {
          known = true;
          id = static_cast<int>(f) == family ? (axis == 0 ? kX : kY) : kOtherXY;
        }
    for (const char* n : kUnusedNames) known = known || name == n;
    if (!known)
      throw dataError(path, where,
                      "unknown column '" + std::string(name) + "' (Pointer Events fields: " +
                          knownList() + ")");
    if (id >= 0) {
      if (h.column[id] != 0) throw dataError(path, where, "duplicate column");
      h.column[id] = static_cast<int>(c) + 1;
    }
    h.field_of[c] = id;
  }
  auto require = [&](int id, const std::string& what) {
    if (h.column[id] == 0)
      throw dataError(path, place(line), "header lacks " + what + " (a Pointer Events CSV needs "
                                         "timeStamp, a position pair such as x,y and pressure)");
  };
  require(kTime, "the column 'timeStamp'");
  require(kX, "a position pair (offsetX,offsetY or x,y or clientX,clientY ...)");
  require(kPressure, "the column 'pressure'");
  if ((h.column[kTiltX] == 0) != (h.column[kTiltY] == 0))
    throw dataError(path, place(line), "tiltX and tiltY come both or neither");
  if ((h.column[kAltitude] == 0) != (h.column[kAzimuth] == 0))
    throw dataError(path, place(line), "altitudeAngle and azimuthAngle come both or neither");
  return h;
}

// The pen's axis from tiltX/tiltY or altitudeAngle/azimuthAngle, and its
// twist, when the file has those columns; each checked against its range.
void readPenOrientation(const Header& h, const std::array<double, kFields>& v,
                        const std::array<std::string_view, kFields>& written,
                        const std::string& path, int no, PenSample* out) {
  PenSample& s = *out;
  auto col = [&](int id) { return h.column[id]; };
  if (col(kTiltX)) {
    const std::string rule = "a tilt must be in [-90, 90] degrees";
    const double tx = checkRange(v[kTiltX], -90, 90, written[kTiltX], path, no, col(kTiltX),
                                 "tiltX", rule);
    const double ty = checkRange(v[kTiltY], -90, 90, written[kTiltY], path, no, col(kTiltY),
                                 "tiltY", rule);
    s.axis = penAxisFromTilt(tx, ty);
    s.has_tilt = true;
  } else if (col(kAltitude)) {
    const double alt = checkRange(v[kAltitude], 0, M_PI / 2, written[kAltitude], path, no,
                                  col(kAltitude), "altitudeAngle",
                                  "an altitude must be in [0, pi/2] radians");
    const double az = checkRange(v[kAzimuth], 0, 2 * M_PI, written[kAzimuth], path, no,
                                 col(kAzimuth), "azimuthAngle",
                                 "an azimuth must be in [0, 2 pi] radians");
    s.axis = penAxisFromAltitudeAzimuth(alt, az);
    s.has_tilt = true;
  }
  if (col(kTwist)) {
    s.twist_deg = checkRange(v[kTwist], 0, 360, written[kTwist], path, no, col(kTwist),
                             "twist", "a twist must be in [0, 360] degrees");
    s.has_twist = true;
  }
}

}  // namespace

Recording readPointerCsv(const std::string& text, const std::string& path,
                         std::size_t max_samples) {
  const std::size_t data_lines = countDataLines(text);
  checkSampleCount(data_lines > 0 ? data_lines - 1 : 0, max_samples, path, "event lines");
  Recording rec = newRecording(path, Format::kPointerCsv, "CSS pixels, 96 per inch");
  Lines lines(text);
  std::string_view t;
  int no = 0;
  Header h;
  bool have_header = false;
  double pointer_id = 0;
  std::string pointer_id_written;  // as the first row wrote it, for messages
  int pointer_id_line = 0;
  while (nextDataLine(lines, &t, &no)) {
    const std::vector<std::string_view> cells = csv::splitLine(t);
    if (!have_header) {
      h = parseHeader(cells, path, no);
      have_header = true;
      continue;
    }
    if (cells.size() != h.field_of.size())
      throw dataError(path, place(no, static_cast<int>(std::min(cells.size(), h.field_of.size())) + 1,
                                  "row"),
                      "has " + std::to_string(cells.size()) + " fields, the header has " +
                          std::to_string(h.field_of.size()));
    std::array<double, kFields> v{};
    std::array<std::string_view, kFields> written{};
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const int id = h.field_of[c];
      if (id < 0) continue;
      const std::string_view cell = unquote(cells[c]);
      written[id] = cell;
      const int col = static_cast<int>(c) + 1;
      if (id == kPointerType) {
        if (cell != "pen" && cell != "mouse" && cell != "touch" && !cell.empty())
          throw dataError(path, place(no, col, "pointerType"),
                          "'" + std::string(cell) + "': must be pen, mouse or touch");
        continue;
      }
      v[id] = parseNumber(cell, path, no, col, kFieldNames[id]);
    }
    auto col = [&](int id) { return h.column[id]; };
    PenSample s;
    s.line = no;
    s.t_s = checkTime(v[kTime] / 1000, written[kTime], rec, path, no, col(kTime), "timeStamp");
    s.x = checkCoordinate(v[kX], written[kX], path, no, col(kX), "x");
    s.y = checkCoordinate(v[kY], written[kY], path, no, col(kY), "y");
    s.pressure = checkPressure(v[kPressure], written[kPressure], path, no, col(kPressure),
                               "pressure");
    readPenOrientation(h, v, written, path, no, &s);
    if (col(kButtons)) {
      const double b = v[kButtons];
      if (b < 0 || b > 65535 || b != std::floor(b))
        throw dataError(path, place(no, col(kButtons), "buttons"),
                        "buttons = " + std::string(written[kButtons]) +
                            ": must be a non-negative integer bitmask");
      s.down = (static_cast<int>(b) & 1) != 0;
    } else {
      s.down = s.pressure > 0;
    }
    if (col(kPointerId)) {
      if (pointer_id_line == 0) {
        pointer_id = v[kPointerId];
        pointer_id_written = std::string(written[kPointerId]);
        pointer_id_line = no;
      } else if (v[kPointerId] != pointer_id) {
        throw dataError(path, place(no, col(kPointerId), "pointerId"),
                        "pointerId = " + std::string(written[kPointerId]) +
                            " is a second pointer (line " + std::to_string(pointer_id_line) +
                            " has " + pointer_id_written +
                            "): record one pointer per file");
      }
    }
    rec.samples.push_back(s);
  }
  if (!have_header)
    throw dataError(path, "line 1", "empty: a Pointer Events CSV starts with its header");
  return rec;
}

}  // namespace bristle::input

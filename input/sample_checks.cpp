#include "input/sample_checks.h"

#include <cmath>

#include "engine/base/error.h"
#include "input/text_fields.h"

namespace bristle::input::detail {

Recording newRecording(const std::string& path, Format format, const std::string& units_note) {
  Recording rec;
  rec.path = path;
  rec.format = format;
  rec.units_note = units_note;
  return rec;
}

double checkTime(double t_s, std::string_view written, const Recording& rec,
                 const std::string& path, int line, int column, std::string_view name) {
  const std::string where = place(line, column, name);
  if (std::fabs(t_s) > kMaxSourceTimeS)
    throw dataError(path, where,
                    std::string(name) + " = " + std::string(written) +
                        " is outside the limit of +-1e9 s");
  // The trajectory written counts time from the first sample (plus a hover of
  // at most 10 s, --lead-s), and its own limit is 1e9 s.
  if (!rec.samples.empty() && t_s - rec.samples.front().t_s > kMaxSourceTimeS - 10)
    throw dataError(path, where,
                    std::string(name) + " = " + std::string(written) + " is more than 1e9 s - 10 s "
                        "after the first sample's (line " +
                        std::to_string(rec.samples.front().line) +
                        "): a recording spans at most that");
  if (!rec.samples.empty() && t_s < rec.samples.back().t_s)
    throw dataError(path, where,
                    std::string(name) + " = " + std::string(written) +
                        " is before the previous sample's (line " +
                        std::to_string(rec.samples.back().line) +
                        "): times must not decrease (equal times are merged)");
  return t_s;
}

double checkCoordinate(double v, std::string_view written, const std::string& path, int line,
                       int column, std::string_view name) {
  if (std::fabs(v) > kMaxSourceCoordinate)
    throw dataError(path, place(line, column, name),
                    std::string(name) + " = " + std::string(written) +
                        " is outside the limit of +-1e9 source units");
  return v;
}

double checkPressure(double v, std::string_view written, const std::string& path, int line,
                     int column, std::string_view name) {
  return checkRange(v, 0, 1, written, path, line, column, name,
                    "a pressure must be in [0, 1]");
}

double checkRange(double v, double lo, double hi, std::string_view written,
                  const std::string& path, int line, int column, std::string_view name,
                  const std::string& rule) {
  if (v < lo || v > hi)
    throw dataError(path, place(line, column, name),
                    std::string(name) + " = " + std::string(written) + ": " + rule);
  return v;
}

}  // namespace bristle::input::detail

#pragma once
// The rules every pen sample's fields follow, whatever the format
// (docs/input.md, "Rules"): each failure is exit 65 naming the file, the line
// and column, the value as written and the rule.

#include <string>
#include <string_view>

#include "input/recording.h"

namespace bristle::input::detail {

// Positions in source units: beyond this no scale can bring them onto a canvas
// (the trajectory limit is 1e5 mm; a source unit is rarely below 0.01 mm).
inline constexpr double kMaxSourceCoordinate = 1e9;
// Times: bristle-trajectory/1's own limit (engine/model/trajectory.h), 31 years.
inline constexpr double kMaxSourceTimeS = 1e9;

// A recording of `format` with no samples yet, its units described by `units_note`.
Recording newRecording(const std::string& path, Format format, const std::string& units_note);

// A time in seconds (`written` as in the file): within the limit, and not
// before the previous sample of `rec` (equal is merged later). Returns t_s.
double checkTime(double t_s, std::string_view written, const Recording& rec,
                 const std::string& path, int line, int column, std::string_view name);
double checkCoordinate(double v, std::string_view written, const std::string& path, int line,
                       int column, std::string_view name);
// Pressure in [0, 1].
double checkPressure(double v, std::string_view written, const std::string& path, int line,
                     int column, std::string_view name);
// A value in [lo, hi] (`rule` says what it is: "a tilt in degrees").
double checkRange(double v, double lo, double hi, std::string_view written,
                  const std::string& path, int line, int column, std::string_view name,
                  const std::string& rule);

}  // namespace bristle::input::detail

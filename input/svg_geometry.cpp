#include "input/svg_geometry.h"

#include <2geom/bezier-curve.h>
#include <2geom/elliptical-arc.h>
#include <2geom/transforms.h>
#include <gsl/gsl_errno.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "engine/base/error.h"

namespace bristle::input {

namespace {

bool isSeparator(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == ','; }

// One number at text[*i] (after separators), strictly; false at the end.
bool nextNumber(const std::string& text, std::size_t* i, double* v, const std::string& path,
                const std::string& where) {
  while (*i < text.size() && isSeparator(text[*i])) ++*i;
  if (*i >= text.size()) return false;
  std::size_t b = *i;
  if (text[b] == '+') ++b;
  const auto [ptr, ec] = std::from_chars(text.data() + b, text.data() + text.size(), *v);
  const std::size_t end = static_cast<std::size_t>(ptr - text.data());
  if (ec != std::errc() || end == b || !std::isfinite(*v)) {
    std::size_t e = *i;
    while (e < text.size() && !isSeparator(text[e])) ++e;
    throw dataError(path, where, "'" + text.substr(*i, e - *i) + "' is not a finite number");
  }
  *i = end;
  return true;
}

Geom::Affine transformOf(const std::string& name, const std::vector<double>& a,
                         const std::string& path, const std::string& where) {
  auto need = [&](std::size_t lo, std::size_t hi) {
    if (a.size() < lo || a.size() > hi)
      throw dataError(path, where,
                      name + "(...) takes " + std::to_string(lo) +
                          (hi > lo ? " to " + std::to_string(hi) : "") + " numbers, not " +
                          std::to_string(a.size()));
  };
  constexpr double kRad = M_PI / 180;
  if (name == "matrix") {
    need(6, 6);
    return Geom::Affine(a[0], a[1], a[2], a[3], a[4], a[5]);
  }
  if (name == "translate") {
    need(1, 2);
    return Geom::Affine(1, 0, 0, 1, a[0], a.size() > 1 ? a[1] : 0);
  }
  if (name == "scale") {
    need(1, 2);
    return Geom::Affine(a[0], 0, 0, a.size() > 1 ? a[1] : a[0], 0, 0);
  }
  if (name == "rotate") {
    if (a.size() != 1 && a.size() != 3)
      throw dataError(path, where,
                      "rotate(...) takes 1 number (the angle) or 3 (the angle and a centre), not " +
                          std::to_string(a.size()));
    const double c = std::cos(a[0] * kRad), s = std::sin(a[0] * kRad);
    const Geom::Affine r(c, s, -s, c, 0, 0);
    if (a.size() == 1) return r;
    return Geom::Affine(1, 0, 0, 1, -a[1], -a[2]) * r * Geom::Affine(1, 0, 0, 1, a[1], a[2]);
  }
  if (name == "skewX") {
    need(1, 1);
    return Geom::Affine(1, 0, std::tan(a[0] * kRad), 1, 0, 0);
  }
  if (name == "skewY") {
    need(1, 1);
    return Geom::Affine(1, std::tan(a[0] * kRad), 0, 1, 0, 0);
  }
  throw dataError(path, where,
                  "unknown transform '" + name +
                      "' (known: matrix, translate, scale, rotate, skewX, skewY)");
}

}  // namespace

std::vector<double> parseNumberList(const std::string& text, const std::string& path,
                                    const std::string& where) {
  std::vector<double> out;
  std::size_t i = 0;
  double v = 0;
  while (nextNumber(text, &i, &v, path, where)) out.push_back(v);
  return out;
}

Geom::Affine parseTransform(const std::string& text, const std::string& path,
                            const std::string& where) {
  Geom::Affine m = Geom::identity();
  std::size_t i = 0;
  while (true) {
    while (i < text.size() && isSeparator(text[i])) ++i;
    if (i >= text.size()) break;
    const std::size_t open = text.find('(', i);
    const std::size_t close = open == std::string::npos ? open : text.find(')', open);
    if (close == std::string::npos)
      throw dataError(path, where, "'" + text.substr(i) + "' is not a transform 'name(numbers)'");
    std::string name = text.substr(i, open - i);
    while (!name.empty() && isSeparator(name.back())) name.pop_back();
    const std::vector<double> args =
        parseNumberList(text.substr(open + 1, close - open - 1), path, where);
    // The list applies right to left: the last transform acts first.
    m = transformOf(name, args, path, where) * m;
    i = close + 1;
  }
  for (int k = 0; k < 6; ++k)
    if (!std::isfinite(m[k])) throw dataError(path, where, "'" + text + "' is not a finite transform");
  return m;
}

double lengthMm(const std::string& text) {
  double v = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || !std::isfinite(v) || v <= 0) return 0;
  const std::string unit(ptr, text.data() + text.size());
  if (unit == "mm") return v;
  if (unit == "cm") return v * 10;
  if (unit == "Q") return v * 0.25;
  if (unit == "in") return v * 25.4;
  if (unit == "pt") return v * 25.4 / 72;
  if (unit == "pc") return v * 25.4 / 6;
  if (unit == "px" || unit.empty()) return v * 25.4 / 96;
  return 0;
}

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

std::vector<ProfilePoint> parsePressureProfile(const std::string& text, const std::string& path,
                                               const std::string& where) {
  const std::string rule =
      " (a pressure profile is 'u:p u:p ...', u the fraction of the stroke's length in "
      "[0, 1] increasing, p a pressure in [0, 1]; or one pressure)";
  std::vector<ProfilePoint> out;
  std::size_t i = 0;
  while (true) {
    while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == ',')) ++i;
    if (i >= text.size()) break;
    std::size_t e = i;
    while (e < text.size() && text[e] != ' ' && text[e] != '\t' && text[e] != ',') ++e;
    const std::string item = text.substr(i, e - i);
    i = e;
    const std::size_t colon = item.find(':');
    auto number = [&](const std::string& s) {
      double v = 0;
      const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
      if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(v))
        throw dataError(path, where, "'" + item + "' does not parse" + rule);
      return v;
    };
    ProfilePoint p;
    if (colon == std::string::npos) {
      p.p = number(item);
    } else {
      p.u = number(item.substr(0, colon));
      p.p = number(item.substr(colon + 1));
    }
    if (colon == std::string::npos && !out.empty())
      throw dataError(path, where, "'" + text + "' mixes a lone pressure with u:p points" + rule);
    if (p.u < 0 || p.u > 1 || (!out.empty() && p.u <= out.back().u))
      throw dataError(path, where, "'" + item + "': u must be in [0, 1] and increase" + rule);
    if (p.p < 0 || p.p > 1)
      throw dataError(path, where, "'" + item + "': the pressure must be in [0, 1]" + rule);
    out.push_back(p);
    if (out.size() > kMaxProfilePoints)
      throw dataError(path, where,
                      "has more than " + std::to_string(kMaxProfilePoints) + " points" + rule);
  }
  if (out.empty()) throw dataError(path, where, "is empty" + rule);
  return out;
}

double profilePressure(const std::vector<ProfilePoint>& profile, double u) {
  if (u <= profile.front().u) return profile.front().p;
  // The first point at or beyond u (u increases strictly along the profile).
  const auto it = std::lower_bound(profile.begin(), profile.end(), u,
                                   [](const ProfilePoint& p, double x) { return p.u < x; });
  if (it == profile.end()) return profile.back().p;
  const ProfilePoint& a = *(it - 1);
  const ProfilePoint& b = *it;
  return a.p + (b.p - a.p) * (u - a.u) / (b.u - a.u);
}

namespace {

// lib2geom integrates arc lengths with GSL, whose default error handler
// aborts the process when an integral misses its tolerance. A reader must
// refuse, not abort: GSL's handler is switched off once (bristle uses GSL
// nowhere else), and a failed measure shows as a length that is not finite.
void quietGsl() {
  static std::once_flag once;
  std::call_once(once, [] { gsl_set_error_handler_off(); });
}

bool withinLimits(const Geom::Point& p) {
  return std::isfinite(p[Geom::X]) && std::isfinite(p[Geom::Y]) &&
         std::fabs(p[Geom::X]) <= kMaxSvgUnits && std::fabs(p[Geom::Y]) <= kMaxSvgUnits;
}

// The map that takes the path's bounding box into the unit box: translated
// to its corner, scaled by its larger side. Identity for a path of no extent.
struct UnitBox {
  Geom::Affine to_unit = Geom::identity();
  double extent = 1;
};
UnitBox unitBox(const Geom::Path& path) {
  UnitBox u;
  const Geom::OptRect b = path.boundsFast();
  if (!b) return u;
  const double extent = std::max(b->width(), b->height());
  if (!(extent > 0)) return u;
  u.extent = extent;
  u.to_unit = Geom::Translate(-b->min()) * Geom::Scale(1 / extent);
  return u;
}

}  // namespace

// Curve lengths' tolerance in the unit box: 1e-9 of the path's extent. (A
// circle still measures 1.4e-7 short, from lib2geom's polynomial form of an
// elliptical arc, not from the integral.)
constexpr double kLengthTolUnit = 1e-9;

bool pathWithinLimits(const Geom::Path& path) {
  if (!withinLimits(path.initialPoint())) return false;
  for (const Geom::Curve& c : path) {
    if (const auto* bezier = dynamic_cast<const Geom::BezierCurve*>(&c)) {
      for (const Geom::Point& p : bezier->controlPoints())
        if (!withinLimits(p)) return false;
    } else if (const auto* arc = dynamic_cast<const Geom::EllipticalArc*>(&c)) {
      if (!withinLimits(arc->rays()) || !withinLimits(arc->center()) ||
          !withinLimits(arc->finalPoint()))
        return false;
    } else if (!withinLimits(c.finalPoint())) {
      return false;
    }
  }
  return true;
}

double pathLength(const Geom::Path& path) {
  quietGsl();
  const UnitBox box = unitBox(path);
  const Geom::Path unit = path * box.to_unit;
  double length = 0;
  for (const Geom::Curve& c : unit) length += c.length(kLengthTolUnit);
  return length * box.extent;
}

namespace {

// Arc length along one curve against its time, tabulated: the chords between
// `steps` + 1 points at equal time steps, summed and scaled to the curve's
// measured length. Only points on the curve are evaluated (no polynomial
// refit of the whole path, and no integral per entry), so any curve lib2geom
// holds can be tabulated; a length maps back to a time by interpolating.
std::vector<double> lengthTable(const Geom::Curve& unit_curve, double length, std::size_t steps) {
  std::vector<double> table(steps + 1, 0.0);
  Geom::Point prev = unit_curve.initialPoint();
  for (std::size_t k = 1; k <= steps; ++k) {
    const Geom::Point p = unit_curve.pointAt(static_cast<double>(k) / static_cast<double>(steps));
    table[k] = table[k - 1] + Geom::distance(prev, p);
    prev = p;
  }
  const double chords = table.back();
  for (double& v : table) v = chords > 0 ? v * length / chords : 0;
  return table;
}

// The time at which a curve has come `along` of its tabulated arc length.
double timeAtLength(const std::vector<double>& table, double along) {
  const std::size_t steps = table.size() - 1;
  const auto it = std::upper_bound(table.begin(), table.end(), along);
  if (it == table.begin()) return 0;
  if (it == table.end()) return 1;
  const std::size_t k = static_cast<std::size_t>(it - table.begin()) - 1;
  const double span = table[k + 1] - table[k];
  const double f = span > 0 ? (along - table[k]) / span : 0;
  return (static_cast<double>(k) + f) / static_cast<double>(steps);
}

}  // namespace

std::vector<Geom::Point> samplePath(const Geom::Path& path, double segments) {
  quietGsl();
  const std::size_t n =
      std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(std::max(segments, 1.0))) + 1);
  // Each curve is measured on its own, in the unit box (relative tolerance);
  // a curve of no length or no finite length has no direction and is passed
  // over. Points are evaluated on the path itself, at the curve's time.
  const Geom::Path unit = path * unitBox(path).to_unit;
  std::vector<double> lengths(path.size(), 0.0);
  double total = 0;
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double len = unit[i].length(kLengthTolUnit);
    lengths[i] = std::isfinite(len) && len > 0 ? len : 0;
    total += lengths[i];
  }
  std::vector<Geom::Point> out;
  out.reserve(n);
  out.push_back(path.initialPoint());
  std::size_t i = 0;
  double start = 0;  // arc length where curve i begins
  std::vector<double> table;
  std::size_t table_of = path.size();  // the curve `table` belongs to
  for (std::size_t k = 1; k + 1 < n && total > 0; ++k) {
    const double s = total * static_cast<double>(k) / static_cast<double>(n - 1);
    while (i + 1 < path.size() && (lengths[i] == 0 || s > start + lengths[i])) start += lengths[i++];
    const double along = std::clamp(s - start, 0.0, lengths[i]);
    double t = lengths[i] > 0 ? along / lengths[i] : 0;
    if (!dynamic_cast<const Geom::LineSegment*>(&path[i]) && lengths[i] > 0) {
      if (table_of != i) {
        // Eight entries a sample on the curve, 32 to 8192: interpolation then
        // errs far below the sample spacing.
        const double on_curve = static_cast<double>(n - 1) * lengths[i] / total;
        const double steps = std::clamp(std::ceil(8 * on_curve), 32.0, 8192.0);
        table = lengthTable(unit[i], lengths[i], static_cast<std::size_t>(steps));
        table_of = i;
      }
      t = timeAtLength(table, along);
    }
    out.push_back(path[i].pointAt(t));
  }
  while (out.size() + 1 < n) out.push_back(path.initialPoint());  // a path of no length
  out.push_back(path.finalPoint());
  return out;
}

}  // namespace bristle::input

#include "input/svg_geometry.h"

#include <2geom/bezier-curve.h>
#include <2geom/elliptical-arc.h>
#include <2geom/sbasis-geometric.h>
#include <2geom/transforms.h>
#include <gsl/gsl_errno.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <mutex>

#include "engine/error.h"

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
// The arc-length parametrisation's tolerance in the unit box: 1e-8 of the
// path's extent keeps samples within 1e-6 of a 100-unit circle's radius (the
// test "import: lib2geom's arc length of a circle is 2 pi r").
constexpr double kSampleTolUnit = 1e-8;

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

std::vector<Geom::Point> samplePath(const Geom::Path& path, double segments) {
  quietGsl();
  const std::size_t n =
      std::max<std::size_t>(2, static_cast<std::size_t>(std::ceil(std::max(segments, 1.0))) + 1);
  const UnitBox box = unitBox(path);
  const Geom::Affine from_unit = box.to_unit.inverse();
  // Degenerate pieces (zero-length segments) have no direction to follow:
  // the arc-length parametrisation is made without them.
  const Geom::Path unit = path * box.to_unit;
  Geom::Path solid(unit.initialPoint());
  for (const Geom::Curve& c : unit)
    if (c.length(kLengthTolUnit) > 0) solid.append(c);
  const Geom::Piecewise<Geom::D2<Geom::SBasis>> by_length =
      Geom::arc_length_parametrization(solid.toPwSb(), 3, kSampleTolUnit);
  const double total = by_length.domain().max();
  std::vector<Geom::Point> out;
  out.reserve(n);
  out.push_back(path.initialPoint());
  for (std::size_t k = 1; k + 1 < n; ++k)
    out.push_back(by_length(total * static_cast<double>(k) / static_cast<double>(n - 1)) *
                  from_unit);
  out.push_back(path.finalPoint());
  return out;
}

}  // namespace bristle::input

#pragma once
// The geometry of SVG import (input/svg_paths.cpp), apart so that tests can
// hold it against closed forms: transforms, lengths with units, pressure
// profiles, and lib2geom's arc length and sampling of a path.

#include <2geom/affine.h>
#include <2geom/path.h>

#include <string>
#include <vector>

namespace bristle::input {

// Numbers separated by blanks and/or commas ("0,0 10 20"): an SVG points list,
// viewBox or transform arguments. Throws Error(kDataError) "path: where: ..."
// naming the first item that is not a finite number.
std::vector<double> parseNumberList(const std::string& text, const std::string& path,
                                    const std::string& where);

// An SVG transform list ("translate(10 20) rotate(45) scale(2)"; matrix,
// translate, scale, rotate with an optional centre, skewX, skewY) as a
// lib2geom affine map from the element's user units to its parent's.
Geom::Affine parseTransform(const std::string& text, const std::string& path,
                            const std::string& where);

// An SVG length with an absolute unit ("210mm", "8.5in", "600px", "600") in
// mm, px and plain numbers taken as CSS px (96 per inch); 0 when it has a
// relative unit (%, em) or does not parse.
double lengthMm(const std::string& text);

// A number as a message or a header shows it (up to 9 significant digits).
std::string formatNumber(double v);

// A pressure profile: pressure p at fraction u of a stroke's arc length.
struct ProfilePoint {
  double u = 0, p = 0;
};
// "u:p u:p ..." (u in [0, 1] increasing, p in [0, 1]) or a single pressure
// "p" (held the whole stroke), at most kMaxProfilePoints points. Throws
// naming `where` and the broken rule.
inline constexpr std::size_t kMaxProfilePoints = 1000;
std::vector<ProfilePoint> parsePressureProfile(const std::string& text, const std::string& path,
                                               const std::string& where);
// Linear between the points, the end points' pressures held beyond them.
double profilePressure(const std::vector<ProfilePoint>& profile, double u);

// The largest coordinate or arc radius an SVG path may have, in root user
// units: the recordings' limit on positions (docs/input.md, "Rules and
// limits"). lib2geom's measures work to absolute tolerances, and beyond this
// they recurse without end or fail inside GSL.
inline constexpr double kMaxSvgUnits = 1e9;

// Whether every point, control point and arc radius of the path is finite and
// within +-kMaxSvgUnits.
bool pathWithinLimits(const Geom::Path& path);

// Arc length of a path in its own units (lib2geom's, each curve's length to
// 1e-9 of the path's extent: the path is measured scaled into a unit box, so
// that the tolerance is relative; a circle comes out 1.4e-7 short). Not
// finite when lib2geom cannot measure it.
double pathLength(const Geom::Path& path);
// Points along the path at equal arc-length steps, the ends included:
// max(2, ceil(segments) + 1) of them. Each curve is measured on its own (in
// the same unit box) and a length along it found by its own table of chords,
// so straight, collinear, zero-length and very long paths all sample; curves
// of no length are passed over, and a path of no length repeats its start.
std::vector<Geom::Point> samplePath(const Geom::Path& path, double segments);

}  // namespace bristle::input

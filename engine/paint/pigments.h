#pragma once
// Pigments and their optics. Paint colour follows the Kubelka-Munk two-flux
// model (Kubelka & Munk 1931; Kubelka 1948): a pigment has an absorption K and a
// scattering S per unit of optical thickness, per colour channel (the RGB
// approximation of Curtis et al. 1997, "Computer-Generated Watercolor", §5).
// Mixtures average K and S by volume; a film of optical thickness d over a
// background of reflectance Rg reflects R and transmits T (kmLayer below).
// Sources and the derivation of each table entry: docs/paint.md.

#include <array>
#include <string>
#include <vector>

#include "engine/model/canvas.h"  // Rgb, parseHexColour
#include "engine/paint/paint_spec.h"

namespace bristle {

// Optical thickness of one unit of paint film: a film t_mm thick has
// d = t_mm / kKmUnitFilmMm in the units the pigment table's K and S are given in.
// Curtis et al.'s K, S describe layers of d ~ 0.1 .. 3 (thin wash .. masstone); with
// 0.02 mm per unit, the 0.02 .. 0.06 mm films a loaded brush lays down span 1 .. 3.
inline constexpr double kKmUnitFilmMm = 0.02;

// What a cell of paint (a brush texel or a canvas pixel) carries per unit of
// volume, in the canvas's mix model:
//  kKubelkaMunk: k = absorption K, s = scattering S (per unit optical thickness);
//  kLinearRgb:   k = the paint's masstone colour (linear-light RGB, 0..1),
//                s = its hiding power (per unit optical thickness).
// Both mix linearly by volume, which is exact for KM (K and S of a mixture are
// the concentration-weighted sums) and is what "linear RGB mixing" means.
struct Optics {
  std::array<float, 3> k{0, 0, 0};
  std::array<float, 3> s{0, 0, 0};
};

struct Pigment {
  std::string name;
  std::array<double, 3> k, s;  // Kubelka-Munk, per unit optical thickness (R, G, B)
  std::string source;          // short citation; docs/paint.md has the details
};

// The built-in table, in a fixed order.
const std::vector<Pigment>& pigmentTable();
// nullptr when there is no pigment of that name.
const Pigment* findPigment(const std::string& name);
// "a, b, c": the table's names, for error messages and --help.
std::string pigmentNames();

// Kubelka-Munk layer (Kubelka 1948, hyperbolic form): a = 1 + K/S,
// b = sqrt(a^2 - 1); for a film of optical thickness d over a background of
// reflectance rg,
//   R = (1 - rg (a - b coth(b S d))) / (a - rg + b coth(b S d))
//   T = b / (a sinh(b S d) + b cosh(b S d)).
// d = 0 gives R = rg, T = 1; d -> infinity gives R = R_inf = a - b, T = 0.
// S is floored at kKmMinScattering (a purely absorbing film is the limit S -> 0).
struct KmLayer {
  double r = 0, t = 1;
};
inline constexpr double kKmMinScattering = 1e-6;
KmLayer kmLayer(double k, double s, double d, double rg);
// Reflectance of an infinitely thick film: a - b.
double kmRinf(double k, double s);

// Linear-light <-> sRGB encoding (IEC 61966-2-1).
double srgbToLinear(double c);
double linearToSrgb(double c);

// Scattering given to "#rrggbb" paints: an opaque paint hiding the paper at about
// one unit of thickness (R within 1% of R_inf for masstone colours at d >= 1.5).
inline constexpr double kHexPaintScattering = 4.0;

// Resolves a paint name ("ultramarine") or a colour ("#1c2433", an opaque paint
// whose R_inf is that colour) into per-volume optics for `model`. Returns false
// and sets *why (one phrase) when it is neither.
bool resolvePaint(const std::string& text, MixModel model, Optics* out, std::string* why);

// Reflectance (linear RGB) of a film of `optics` and optical thickness d over a
// background of linear reflectance bg, in `model`.
std::array<double, 3> filmOver(const Optics& optics, double d, const std::array<double, 3>& bg,
                               MixModel model);

}  // namespace bristle

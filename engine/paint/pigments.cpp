#include "engine/paint/pigments.h"

#include <algorithm>
#include <cmath>

namespace bristle {
namespace {

// Curtis, Anderson, Seims, Fleischer, Salesin: "Computer-Generated Watercolor",
// SIGGRAPH 1997, §5.1 and Fig. 5: K and S per RGB channel of watercolour pigments
// (fitted to swatches painted over white and black).
constexpr const char* kCurtis = "Curtis et al. 1997, Fig. 5";
constexpr const char* kDerivedOpaque =
    "KM inversion K = S (1 - R)^2 / (2 R) of the masstone colour, docs/paint.md";
constexpr const char* kDerivedGlaze =
    "KM glaze K = -ln(C) / 2 of the colour over white at d = 1, docs/paint.md";

// An opaque pigment whose infinitely thick film has sRGB colour `hex` and whose
// scattering is `s` per channel: K from the KM remission function.
Pigment opaque(const std::string& name, const char* hex, double s) {
  Rgb c;
  parseHexColour(hex, &c);
  Pigment p{name, {}, {s, s, s}, kDerivedOpaque};
  const double srgb[3] = {c.r, c.g, c.b};
  for (int i = 0; i < 3; ++i) {
    const double r = std::clamp(srgbToLinear(srgb[i]), 1e-3, 0.999);
    p.k[i] = s * (1 - r) * (1 - r) / (2 * r);
  }
  return p;
}

// A transparent (glazing) pigment: little scattering; a unit film over white
// shows sRGB colour `hex`. Light crosses the film twice, so C = exp(-2 K).
Pigment glaze(const std::string& name, const char* hex, double s) {
  Rgb c;
  parseHexColour(hex, &c);
  Pigment p{name, {}, {s, s, s}, kDerivedGlaze};
  const double srgb[3] = {c.r, c.g, c.b};
  for (int i = 0; i < 3; ++i) {
    const double r = std::clamp(srgbToLinear(srgb[i]), 1e-3, 0.999);
    p.k[i] = -std::log(r) / 2;
  }
  return p;
}

std::vector<Pigment> buildTable() {
  std::vector<Pigment> t = {
      {"ultramarine", {0.86, 0.86, 0.06}, {0.005, 0.005, 0.09}, kCurtis},
      {"cadmium-yellow", {0.10, 0.36, 3.45}, {0.97, 0.65, 0.007}, kCurtis},
      {"cadmium-red", {0.14, 1.08, 1.68}, {0.77, 0.015, 0.018}, kCurtis},
      {"quinacridone-rose", {0.22, 1.47, 0.57}, {0.05, 0.003, 0.03}, kCurtis},
      {"indian-red", {0.46, 1.07, 1.50}, {1.28, 0.38, 0.21}, kCurtis},
      {"burnt-umber", {0.74, 1.54, 2.10}, {0.09, 0.09, 0.004}, kCurtis},
      {"hookers-green", {1.62, 0.61, 1.64}, {0.01, 0.012, 0.003}, kCurtis},
      {"phthalo-green", {1.55, 0.47, 0.63}, {0.01, 0.05, 0.035}, kCurtis},
      {"cerulean-blue", {1.52, 0.32, 0.25}, {0.06, 0.26, 0.40}, kCurtis},
      {"hansa-yellow", {0.06, 0.21, 1.78}, {0.50, 0.88, 0.009}, kCurtis},
      {"brilliant-orange", {0.13, 0.81, 3.45}, {0.005, 0.009, 0.035}, kCurtis},
  };
  // Pigments Curtis et al. do not list, derived from representative swatch
  // colours (docs/paint.md gives the reasoning for each scattering value).
  t.push_back(opaque("titanium-white", "#f4f3ee", 6.0));
  t.push_back(opaque("ivory-black", "#1f1e1d", 1.0));
  t.push_back(opaque("yellow-ochre", "#c8922e", 1.5));
  t.push_back(opaque("burnt-sienna", "#8a3b1c", 0.6));
  t.push_back(glaze("phthalo-blue", "#0c3f9c", 0.02));
  t.push_back(glaze("alizarin-crimson", "#b3203a", 0.02));
  t.push_back(glaze("viridian", "#1f8a6a", 0.05));
  t.push_back(glaze("sumi-ink", "#1b1b1d", 0.01));
  return t;
}

// Linear-RGB fallback: every paint hides the background as 1 - exp(-h d).
// h = 1.5 lets a typical 2-unit film hide 95% of what is under it.
constexpr double kRgbHiding = 1.5;
// ... and shows the colour KM gives a film of this thickness over white.
constexpr double kRgbMasstoneThickness = 2.0;
constexpr double kWhiteGround = 0.9;

}  // namespace

const std::vector<Pigment>& pigmentTable() {
  static const std::vector<Pigment> table = buildTable();
  return table;
}

const Pigment* findPigment(const std::string& name) {
  for (const Pigment& p : pigmentTable())
    if (p.name == name) return &p;
  return nullptr;
}

std::string pigmentNames() {
  std::string out;
  for (const Pigment& p : pigmentTable()) out += (out.empty() ? "" : ", ") + p.name;
  return out;
}

double srgbToLinear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
double linearToSrgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

KmLayer kmLayer(double k, double s, double d, double rg) {
  if (d <= 0) return {rg, 1};
  s = std::max(s, kKmMinScattering);
  const double a = 1 + k / s;
  const double b = std::sqrt(a * a - 1);
  const double x = b * s * d;
  if (b < 1e-12) {
    // K = 0: a non-absorbing film, the limit b -> 0 of the same equations
    // (R = (S d (1 - rg) + rg) / (1 + S d (1 - rg)), T = 1 / (1 + S d)).
    const double sd = s * d;
    return {(sd * (1 - rg) + rg) / (1 + sd * (1 - rg)), 1 / (1 + sd)};
  }
  if (x > 40) {
    // coth(x) = 1 and sinh(x) overflows: an infinitely thick film to double precision.
    return {a - b, 0};
  }
  const double coth = std::cosh(x) / std::sinh(x);
  KmLayer out;
  out.r = (1 - rg * (a - b * coth)) / (a - rg + b * coth);
  out.t = b / (a * std::sinh(x) + b * std::cosh(x));
  return out;
}

double kmRinf(double k, double s) {
  s = std::max(s, kKmMinScattering);
  const double a = 1 + k / s;
  return a - std::sqrt(a * a - 1);
}

bool resolvePaint(const std::string& text, MixModel model, Optics* out, std::string* why) {
  Pigment p;
  if (!text.empty() && text[0] == '#') {
    Rgb c;
    if (!parseHexColour(text, &c)) {
      *why = "'" + text + "' is not a colour like #1c2433";
      return false;
    }
    p = opaque(text, text.c_str(), kHexPaintScattering);
  } else if (const Pigment* found = findPigment(text)) {
    p = *found;
  } else {
    *why = "unknown pigment '" + text + "' (known: " + pigmentNames() + ", or #rrggbb)";
    return false;
  }
  for (int i = 0; i < 3; ++i) {
    if (model == MixModel::kKubelkaMunk) {
      out->k[i] = static_cast<float>(p.k[i]);
      out->s[i] = static_cast<float>(p.s[i]);
    } else {
      out->k[i] =
          static_cast<float>(kmLayer(p.k[i], p.s[i], kRgbMasstoneThickness, kWhiteGround).r);
      out->s[i] = static_cast<float>(kRgbHiding);
    }
  }
  return true;
}

std::array<double, 3> filmOver(const Optics& o, double d, const std::array<double, 3>& bg,
                               MixModel model) {
  std::array<double, 3> r;
  for (int i = 0; i < 3; ++i) {
    if (model == MixModel::kKubelkaMunk) {
      r[i] = kmLayer(o.k[i], o.s[i], d, bg[i]).r;
    } else {
      const double alpha = 1 - std::exp(-o.s[i] * d);
      r[i] = bg[i] + alpha * (o.k[i] - bg[i]);
    }
  }
  return r;
}

}  // namespace bristle

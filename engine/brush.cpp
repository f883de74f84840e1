#include "engine/brush.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/error.h"
#include "engine/json_reader.h"
#include "engine/text_file.h"

namespace bristle {
namespace {

constexpr const char* kFormat = "bristle-brush/1";
// Joint angles beyond this are on the Euler-XYZ singularity at the horizon (§3.2).
constexpr double kMaxRestAngleRad = 1.2;
// Friction coefficients beyond this are not paint on paper.
constexpr double kMaxFriction = 2.0;

std::vector<double> positiveArray(const JsonObject& o, const std::string& key, size_t n,
                                  bool allow_zero) {
  std::vector<double> v = o.numbers(key);
  o.require(v.size() == n, key,
            "must have " + std::to_string(n) + " entries (one per " +
                (key == "width_mm" ? std::string("joint, root included") : "segment") + ")");
  for (size_t i = 0; i < v.size(); ++i)
    checkedElement(o, key, i, v[i], allow_zero ? v[i] >= 0 : v[i] > 0,
                   allow_zero ? "must be >= 0" : "must be > 0");
  return v;
}

SpineSpec parseSpine(const JsonObject& o) {
  SpineSpec s;
  const std::vector<double> root = o.numbers("root_mm");
  o.require(root.size() == 3, "root_mm", "must be [x, y, z]");
  s.root_mm = Eigen::Vector3d(root[0], root[1], root[2]);
  s.segment_lengths_mm = o.numbers("segment_lengths_mm");
  const size_t n = s.segment_lengths_mm.size();
  o.require(n >= 1 && n <= static_cast<size_t>(kMaxJointsPerSpine), "segment_lengths_mm",
            "must have 1.." + std::to_string(kMaxJointsPerSpine) + " segments");
  for (size_t i = 0; i < n; ++i)
    checkedElement(o, "segment_lengths_mm", i, s.segment_lengths_mm[i],
                   s.segment_lengths_mm[i] > 0, "must be > 0");
  s.stiffness_nmm_per_rad = positiveArray(o, "stiffness_nmm_per_rad", n, false);
  s.damping_nmm = o.has("damping_nmm") ? positiveArray(o, "damping_nmm", n, true)
                                       : std::vector<double>(n, 0.0);
  s.width_mm = positiveArray(o, "width_mm", n + 1, true);
  o.require(s.width_mm[0] > 0, "width_mm", "the root width must be > 0");
  s.rest_angles_rad.assign(n, Eigen::Vector2d::Zero());
  if (o.has("rest_angles_rad")) {
    const nlohmann::json& ra = o.raw("rest_angles_rad");
    const std::string p = o.childPointer("rest_angles_rad");
    o.requireAt(ra.is_array() && ra.size() == n, p, ra,
                "must be an array of " + std::to_string(n) + " [theta, phi] pairs");
    for (size_t i = 0; i < n; ++i) {
      const std::string pi = p + "/" + std::to_string(i);
      o.requireAt(ra[i].is_array() && ra[i].size() == 2 && ra[i][0].is_number() &&
                      ra[i][1].is_number(),
                  pi, ra[i], "must be [theta, phi] in radians");
      for (int k = 0; k < 2; ++k) {
        const double a = ra[i][k].get<double>();
        o.requireAt(std::isfinite(a) && std::fabs(a) <= kMaxRestAngleRad,
                    pi + "/" + std::to_string(k), ra[i][k],
                    "must be finite with |angle| <= 1.2 rad");
        s.rest_angles_rad[i][k] = a;
      }
    }
  }
  o.rejectUnknownKeys();
  return s;
}

}  // namespace

double SpineSpec::lengthMm() const {
  double l = 0;
  for (double s : segment_lengths_mm) l += s;
  return l;
}

double Brush::reachMm() const {
  double r = 0;
  for (const SpineSpec& s : spines) r = std::max(r, s.root_mm.norm() + s.lengthMm());
  return r;
}

Brush parseBrush(const std::string& text, const std::string& path) {
  const nlohmann::json doc = parseJsonText(text, path);
  const JsonObject top(doc, "", path);
  Brush b;
  b.path = path;
  const std::string format = top.string("format");
  top.require(format == kFormat, "format",
              "unknown format version (expected \"bristle-brush/1\")");
  b.name = top.string("name");
  top.require(!b.name.empty(), "name", "must not be empty");
  b.description = top.string("description", "");

  const std::vector<JsonObject> spines = top.objects("spines");
  top.require(!spines.empty() && spines.size() <= static_cast<size_t>(kMaxSpines), "spines",
              "must have 1.." + std::to_string(kMaxSpines) + " spines");
  for (const JsonObject& s : spines) {
    b.spines.push_back(parseSpine(s));
    top.requireAt(b.spines.back().root_mm.z() <= 0, s.childPointer("root_mm") + "/2",
                  b.spines.back().root_mm.z(),
                  "roots sit at or inside the ferrule mouth (z <= 0 in the brush frame)");
  }

  if (top.has("friction")) {
    const JsonObject f = top.object("friction");
    FrictionSpec& fr = b.friction;
    fr.mu_static = f.number("mu_static");
    f.require(fr.mu_static >= 0 && fr.mu_static <= kMaxFriction, "mu_static", "must be in [0, 2]");
    fr.mu_kinetic = f.number("mu_kinetic", fr.mu_static);
    f.require(fr.mu_kinetic >= 0 && fr.mu_kinetic <= kMaxFriction, "mu_kinetic",
              "must be in [0, 2]");
    f.require(fr.mu_kinetic <= fr.mu_static, "mu_kinetic", "must not exceed mu_static");
    if (f.has("anisotropy")) {
      const JsonObject a = f.object("anisotropy");
      fr.anisotropy_strength = a.number("strength");
      a.require(fr.anisotropy_strength >= 0 && fr.anisotropy_strength <= 1, "strength",
                "must be in [0, 1] (C_eta, paper eq. 14)");
      fr.anisotropy_exponent = a.number("exponent", 2.0);
      a.require(fr.anisotropy_exponent >= 1, "exponent", "must be >= 1 (k, paper eq. 14)");
      a.rejectUnknownKeys();
    }
    f.rejectUnknownKeys();
  }
  if (top.has("paint")) {
    const JsonObject p = top.object("paint");
    b.paint_capacity = p.number("capacity", 1.0);
    p.require(b.paint_capacity > 0, "capacity", "must be > 0");
    p.rejectUnknownKeys();
  }
  top.rejectUnknownKeys();
  return b;
}

Brush loadBrush(const std::string& path) { return parseBrush(readTextFile(path), path); }

}  // namespace bristle

// The free parameters of a fit and how each changes a brush file
// (render/brush_fit.h; docs/fit.md, "Free parameters").

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <nlohmann/json.hpp>

#include "engine/base/error.h"
#include "engine/base/json_reader.h"
#include "engine/base/text_file.h"
#include "engine/formats/brush_reader.h"
#include "render/brush_fit.h"

namespace bristle::render {
namespace {

// Friction coefficients a brush may hold (engine/model/brush.cpp's limit).
constexpr double kMaxMu = 2.0;

// One parameter's definition: its default bounds and the hard limits a
// `--params` file's bounds must keep inside (those of the brush format, or
// factors beyond which the brush is no longer the one it was).
struct ParamInfo {
  const char* name;
  double min, max;          // default bounds
  double hard_min, hard_max;
  bool log;
};

// In the documented order (docs/fit.md). Factors (log) multiply the brush's
// own values; the others replace them.
//   stiffness_scale  every joint's K_i (eq. 2) times the factor;
//   stiffness_taper  joint i of n times taper^(i/(n-1)): 1 at the root, the
//                    factor at the tip, so the profile along the hair bends;
//   friction_scale   mu_static and mu_kinetic (§3.4.1) times the factor;
//   volume_stiffness the hair volume's push-back, N/mm (docs/dynamics.md);
//   tip_spread       how far converging tips may spread, [0, 1].
const ParamInfo kParams[] = {
    {"stiffness_scale", 0.25, 4, 0.01, 100, true},
    {"stiffness_taper", 0.25, 4, 0.01, 100, true},
    {"friction_scale", 0.25, 2, 0.01, 100, true},
    {"volume_stiffness", 0.25, 25, 0.001, 1000, true},
    {"tip_spread", 0, 1, 0, 1, false},
};

const ParamInfo& info(const std::string& name) {
  for (const ParamInfo& p : kParams)
    if (name == p.name) return p;
  throw std::logic_error("unknown fit parameter " + name);
}

// The brush's own value (where the search starts), and why the brush cannot
// take the parameter (empty when it can).
double startOf(const std::string& name, const Brush& b, std::string* lacks) {
  if (name == "friction_scale" && b.friction.mu_static <= 0)
    *lacks = "the brush has no friction to scale (mu_static is 0)";
  if ((name == "volume_stiffness" || name == "tip_spread") && !b.volume.present())
    *lacks = "the brush has no hair volume (/volume/min_separation)";
  if (name == "volume_stiffness") return b.volume.stiffness_n_per_mm;
  if (name == "tip_spread") return b.volume.tip_spread;
  return 1;
}

// The largest friction factor the format allows this brush.
double frictionCeiling(const Brush& b) {
  return b.friction.mu_static > 0 ? kMaxMu / b.friction.mu_static : 1;
}

FitParam makeParam(const ParamInfo& p, double min, double max, double start) {
  return {p.name, min, max, std::clamp(start, min, max), p.log};
}

double round4(double v) {
  if (v == 0 || !std::isfinite(v)) return v;
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return std::strtod(buf, nullptr);
}

}  // namespace

std::vector<std::string> fitParamNames() {
  std::vector<std::string> n;
  for (const ParamInfo& p : kParams) n.emplace_back(p.name);
  return n;
}

std::vector<FitParam> defaultFitParams(const Brush& brush) {
  // Pressed to a depth and pulled steadily, a brush of bending stiffness and
  // Coulomb friction alone takes the same shape at any scale of its stiffness
  // (every force scales with it, friction too): the scale means something only
  // against the hair volume's push-back, given in N/mm. So a brush with hair
  // volume fits its stiffness scale, profile and tip spread; one without, its
  // profile and friction (docs/fit.md, "Free parameters").
  const std::vector<const char*> names =
      brush.volume.present()
          ? std::vector<const char*>{"stiffness_scale", "stiffness_taper", "tip_spread"}
          : std::vector<const char*>{"stiffness_taper", "friction_scale"};
  std::vector<FitParam> out;
  for (const char* name : names) {
    const ParamInfo& p = info(name);
    std::string lacks;
    const double start = startOf(name, brush, &lacks);
    if (!lacks.empty()) continue;  // a frictionless brush fits its profile alone
    const double max = name == std::string("friction_scale")
                           ? std::min(p.max, frictionCeiling(brush))
                           : p.max;
    out.push_back(makeParam(p, p.min, max, start));
  }
  return out;
}

std::vector<FitParam> readFitParams(const std::string& path, const Brush& brush) {
  const nlohmann::json doc = parseJsonText(readTextFile(path), path);
  if (!doc.is_object() || doc.empty())
    throw dataError(path, "/", "must be an object naming each free parameter with its "
                               "[min, max], e.g. {\"stiffness_scale\": [0.5, 2]}");
  const JsonObject o(doc, "", path);
  o.declareKeys({"stiffness_scale", "stiffness_taper", "friction_scale", "volume_stiffness",
                 "tip_spread"});
  std::vector<FitParam> out;
  for (const ParamInfo& p : kParams) {
    if (!o.has(p.name)) continue;
    const nlohmann::json& v = o.raw(p.name);
    o.require(v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number(), p.name,
              "must be [min, max], two numbers");
    const double lo = v[0].get<double>(), hi = v[1].get<double>();
    o.require(std::isfinite(lo) && std::isfinite(hi) && lo < hi, p.name,
              "must be [min, max] with min < max");
    const double ceiling = p.name == std::string("friction_scale")
                               ? std::min(p.hard_max, frictionCeiling(brush))
                               : p.hard_max;
    char rule[160];
    std::snprintf(rule, sizeof rule, "must lie within [%g, %g]%s", p.hard_min, ceiling,
                  ceiling < p.hard_max ? " (friction up to 2, the brush format's limit)" : "");
    o.require(lo >= p.hard_min && hi <= ceiling && (!p.log || lo > 0), p.name, rule);
    std::string lacks;
    const double start = startOf(p.name, brush, &lacks);
    o.require(lacks.empty(), p.name, lacks);
    out.push_back(makeParam(p, lo, hi, start));
  }
  o.rejectUnknownKeys();
  return out;
}

namespace {

void scaleStiffness(nlohmann::ordered_json& doc, double scale, double taper) {
  for (auto& spine : doc["spines"]) {
    auto& k = spine["stiffness_nmm_per_rad"];
    const size_t n = k.size();
    for (size_t i = 0; i < n; ++i) {
      const double u = n > 1 ? double(i) / double(n - 1) : 0;
      k[i] = round4(k[i].get<double>() * scale * std::pow(taper, u));
    }
  }
}

void setFriction(nlohmann::ordered_json& doc, const Brush& b, double factor) {
  auto& f = doc["friction"];
  f["mu_static"] = round4(b.friction.mu_static * factor);
  f["mu_kinetic"] = round4(b.friction.mu_kinetic * factor);
}

// Arrays of numbers (and of arrays of numbers) on one line, everything else
// indented: the layout of the library's brush files.
bool flat(const nlohmann::ordered_json& j) {
  if (j.is_object()) return false;
  if (!j.is_array()) return true;
  return std::none_of(j.begin(), j.end(), [](const auto& e) { return e.is_structured(); });
}

void writeJson(std::string& out, const nlohmann::ordered_json& j, int indent) {
  const std::string pad(static_cast<size_t>(indent) + 2, ' ');
  const bool inline_array =
      j.is_array() && std::all_of(j.begin(), j.end(), [](const auto& e) { return flat(e); });
  if (j.is_object() && !j.empty()) {
    out += "{\n";
    size_t i = 0;
    for (auto it = j.begin(); it != j.end(); ++it, ++i) {
      out += pad + nlohmann::ordered_json(it.key()).dump() + ": ";
      writeJson(out, it.value(), indent + 2);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<size_t>(indent), ' ') + "}";
  } else if (j.is_array() && !inline_array && !j.empty()) {
    out += "[\n";
    for (size_t i = 0; i < j.size(); ++i) {
      out += pad;
      writeJson(out, j[i], indent + 2);
      out += i + 1 < j.size() ? ",\n" : "\n";
    }
    out += std::string(static_cast<size_t>(indent), ' ') + "]";
  } else if (j.is_array()) {
    out += "[";
    for (size_t i = 0; i < j.size(); ++i) {
      if (i > 0) out += ", ";
      writeJson(out, j[i], indent);
    }
    out += "]";
  } else {
    out += j.dump();
  }
}

}  // namespace

std::string applyFitParams(const std::string& brush_text, const std::vector<FitParam>& params,
                           const std::vector<double>& values, const std::string& name,
                           const std::string& description) {
  const Brush base = parseBrush(brush_text, "the brush");
  nlohmann::ordered_json doc = nlohmann::ordered_json::parse(brush_text);
  double scale = 1, taper = 1;
  for (size_t i = 0; i < params.size(); ++i) {
    const std::string& p = params[i].name;
    const double v = values[i];
    if (p == "stiffness_scale") scale = v;
    if (p == "stiffness_taper") taper = v;
    if (p == "friction_scale") setFriction(doc, base, v);
    if (p == "volume_stiffness") doc["volume"]["stiffness_n_per_mm"] = round4(v);
    if (p == "tip_spread") doc["volume"]["tip_spread"] = round4(v);
  }
  if (scale != 1 || taper != 1) scaleStiffness(doc, scale, taper);
  if (!name.empty()) doc["name"] = name;
  if (!description.empty()) doc["description"] = description;
  std::string out;
  writeJson(out, doc, 0);
  return out + "\n";
}

}  // namespace bristle::render

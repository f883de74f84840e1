#include "engine/formats/brush_reader.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "engine/base/error.h"
#include "engine/base/json_reader.h"
#include "engine/base/text_file.h"
#include "engine/mechanics/spine_kinematics.h"

namespace bristle {
namespace {

constexpr const char* kBrushFormat = "bristle-brush/1";
// Joint angles beyond this are on the Euler-XYZ singularity at the horizon (§3.2).
constexpr double kMaxRestAngleRad = 1.2;
// Friction coefficients beyond this are not paint on paper.
constexpr double kMaxFriction = 2.0;
// Roots closer together than this are one point for strip placement.
constexpr double kMinRootSpreadMm = 0.01;

std::vector<double> positiveArray(const JsonObject& o, const std::string& key, size_t n,
                                  bool allow_zero) {
  std::vector<double> v = o.numbers(key);
  o.require(v.size() == n, key,
            "must have " + std::to_string(n) + " entries (one per " +
                (key == "width_mm" || key == "thickness_mm" ? std::string("joint, root included")
                                                             : "segment") +
                ")");
  for (size_t i = 0; i < v.size(); ++i) {
    checkedElement(o, key, i, v[i], allow_zero ? v[i] >= 0 : v[i] > 0,
                   allow_zero ? "must be >= 0" : "must be > 0");
    if (key == "width_mm" || key == "thickness_mm")
      checkedElement(o, key, i, v[i], v[i] <= kMaxBrushMm, "must be <= 1000 mm (the limit)");
  }
  return v;
}

SpineSpec parseSpine(const JsonObject& o) {
  o.declareKeys({"root_mm", "segment_lengths_mm", "stiffness_nmm_per_rad", "damping_nmm",
                 "width_mm", "thickness_mm", "rest_angles_rad", "flat_load_n",
                 "bundle_bears_load"});
  SpineSpec s;
  const std::vector<double> root = o.numbers("root_mm");
  o.require(root.size() == 3, "root_mm", "must be [x, y, z]");
  for (size_t i = 0; i < 3; ++i)
    checkedElement(o, "root_mm", i, root[i], std::fabs(root[i]) <= kMaxBrushMm,
                   "must be within +-1000 mm (the limit)");
  s.root_mm = Eigen::Vector3d(root[0], root[1], root[2]);
  s.segment_lengths_mm = o.numbers("segment_lengths_mm");
  const size_t n = s.segment_lengths_mm.size();
  o.require(n >= 1 && n <= static_cast<size_t>(kMaxJointsPerSpine), "segment_lengths_mm",
            "must have 1.." + std::to_string(kMaxJointsPerSpine) + " segments");
  for (size_t i = 0; i < n; ++i) {
    checkedElement(o, "segment_lengths_mm", i, s.segment_lengths_mm[i],
                   s.segment_lengths_mm[i] > 0, "must be > 0");
    checkedElement(o, "segment_lengths_mm", i, s.segment_lengths_mm[i],
                   s.segment_lengths_mm[i] <= kMaxBrushMm, "must be <= 1000 mm (the limit)");
  }
  s.stiffness_nmm_per_rad = positiveArray(o, "stiffness_nmm_per_rad", n, false);
  s.damping_nmm = o.has("damping_nmm") ? positiveArray(o, "damping_nmm", n, true)
                                       : std::vector<double>(n, 0.0);
  s.width_mm = positiveArray(o, "width_mm", n + 1, true);
  o.require(s.width_mm[0] > 0, "width_mm", "the root width must be > 0");
  if (o.has("thickness_mm")) {
    s.thickness_mm = positiveArray(o, "thickness_mm", n + 1, true);
    for (size_t j = 0; j <= n; ++j)
      checkedElement(o, "thickness_mm", j, s.thickness_mm[j],
                     (s.thickness_mm[j] > 0) == (s.width_mm[j] > 0),
                     "must be > 0 where width_mm is, and 0 where it is 0");
  }
  if (o.has("flat_load_n")) {
    s.flat_load_n = o.number("flat_load_n", 0.0);
    o.require(s.flat_load_n > 0 && s.flat_load_n <= kMaxFlatLoadN, "flat_load_n",
              "must be in (0, 1] (N that press the bundle flat)");
  }
  s.bundle_bears_load = o.boolean("bundle_bears_load", false);
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

void parseSurface(const JsonObject& o, const std::vector<SpineSpec>& spines, SurfaceSpec* out) {
  o.declareKeys({"cage_vertices_mm", "faces", "skin", "refinement_level"});
  SurfaceSpec& sf = *out;
  const nlohmann::json& verts = o.raw("cage_vertices_mm");
  const std::string vp = o.childPointer("cage_vertices_mm");
  o.requireAt(verts.is_array() && !verts.empty() && verts.size() <= size_t(kMaxCageVertices), vp,
              verts, "must be an array of 1.." + std::to_string(kMaxCageVertices) + " [x, y, z]");
  for (size_t i = 0; i < verts.size(); ++i) {
    const nlohmann::json& v = verts[i];
    const std::string pi = vp + "/" + std::to_string(i);
    o.requireAt(v.is_array() && v.size() == 3 && v[0].is_number() && v[1].is_number() &&
                    v[2].is_number(),
                pi, v, "must be [x, y, z] in mm");
    const Eigen::Vector3d p(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
    o.requireAt(p.allFinite(), pi, v, "must be finite");
    o.requireAt(p.cwiseAbs().maxCoeff() <= kMaxBrushMm, pi, v,
                "must be within +-1000 mm (the limit)");
    sf.cage_mm.push_back(p);
  }
  const int nv = static_cast<int>(sf.cage_mm.size());
  const nlohmann::json& faces = o.raw("faces");
  const std::string fp = o.childPointer("faces");
  o.requireAt(faces.is_array() && !faces.empty(), fp, faces, "must be a non-empty array of faces");
  for (size_t f = 0; f < faces.size(); ++f) {
    const nlohmann::json& face = faces[f];
    const std::string pf = fp + "/" + std::to_string(f);
    o.requireAt(face.is_array() && (face.size() == 3 || face.size() == 4), pf, face,
                "must list 3 or 4 vertex indices");
    std::vector<int> idx;
    for (size_t k = 0; k < face.size(); ++k) {
      const nlohmann::json& e = face[k];
      o.requireAt(e.is_number_integer() && e.get<long>() >= 0 && e.get<long>() < nv,
                  pf + "/" + std::to_string(k), e,
                  "must be a vertex index in [0, " + std::to_string(nv - 1) + "]");
      idx.push_back(e.get<int>());
    }
    for (size_t a = 0; a < idx.size(); ++a)
      for (size_t b = a + 1; b < idx.size(); ++b)
        o.requireAt(idx[a] != idx[b], pf, face, "repeats a vertex");
    sf.faces.push_back(idx);
  }
  const nlohmann::json& skin = o.raw("skin");
  const std::string sp = o.childPointer("skin");
  o.requireAt(skin.is_array() && skin.size() == size_t(nv), sp, skin,
              "must have one list of [spine, point, weight] per cage vertex (" +
                  std::to_string(nv) + ")");
  for (size_t i = 0; i < skin.size(); ++i) {
    const std::string pi = sp + "/" + std::to_string(i);
    o.requireAt(skin[i].is_array() && !skin[i].empty(), pi, skin[i],
                "must be a non-empty list of [spine, point, weight]");
    std::vector<SkinInfluence> inf;
    double sum = 0;
    for (size_t k = 0; k < skin[i].size(); ++k) {
      const nlohmann::json& e = skin[i][k];
      const std::string pk = pi + "/" + std::to_string(k);
      o.requireAt(e.is_array() && e.size() == 3 && e[0].is_number_integer() &&
                      e[1].is_number_integer() && e[2].is_number(),
                  pk, e, "must be [spine, point, weight]");
      SkinInfluence s{e[0].get<int>(), e[1].get<int>(), e[2].get<double>()};
      o.requireAt(s.spine >= 0 && s.spine < int(spines.size()), pk + "/0", e[0],
                  "names no spine (the brush has " + std::to_string(spines.size()) + ")");
      o.requireAt(s.point >= 0 && s.point <= spines[s.spine].jointCount(), pk + "/1", e[1],
                  "names no point of spine " + std::to_string(s.spine) + " (0.." +
                      std::to_string(spines[s.spine].jointCount()) + ")");
      o.requireAt(std::isfinite(s.weight) && s.weight >= 0, pk + "/2", e[2],
                  "must be a finite weight >= 0");
      sum += s.weight;
      inf.push_back(s);
    }
    o.requireAt(std::fabs(sum - 1) <= kSkinWeightSumTol, pi, skin[i],
                "weights must sum to 1 (within 1e-3)");
    sf.skin.push_back(inf);
  }
  sf.refinement_level = o.integer("refinement_level", 2);
  o.require(sf.refinement_level >= 0 && sf.refinement_level <= kMaxRefinementLevel,
            "refinement_level", "must be in [0, " + std::to_string(kMaxRefinementLevel) + "]");
  o.rejectUnknownKeys();
}

void parseStrips(const JsonObject& o, StripSpec* out) {
  o.declareKeys({"count", "root_width_mm", "tip_width_mm", "seed", "placement", "length_jitter",
                 "clumps", "clumping"});
  StripSpec& st = *out;
  st.count = o.integer("count");
  o.require(st.count >= 1 && st.count <= kMaxStrips, "count",
            "must be in [1, " + std::to_string(kMaxStrips) + "]");
  st.root_width_mm = o.number("root_width_mm", st.root_width_mm);
  o.require(st.root_width_mm > 0 && st.root_width_mm <= 5, "root_width_mm",
            "must be in (0, 5] mm");
  st.tip_width_mm = o.number("tip_width_mm", st.tip_width_mm);
  o.require(st.tip_width_mm >= 0 && st.tip_width_mm <= st.root_width_mm, "tip_width_mm",
            "must be in [0, root_width_mm]");
  const int seed = o.integer("seed", 1);
  o.require(seed >= 0, "seed", "must be >= 0");
  st.seed = static_cast<std::uint64_t>(seed);
  st.placement = o.string("placement", "auto");
  o.require(st.placement == "auto" || st.placement == "line" || st.placement == "area",
            "placement", "must be \"auto\", \"line\" or \"area\"");
  st.length_jitter = o.number("length_jitter", 0.0);
  o.require(st.length_jitter >= 0 && st.length_jitter < 1, "length_jitter", "must be in [0, 1)");
  st.clumps = o.integer("clumps", 0);
  o.require(st.clumps >= 0 && st.clumps <= st.count, "clumps", "must be in [0, count]");
  st.clumping = o.number("clumping", st.clumps > 0 ? 0.8 : 0.0);
  o.require(st.clumping >= 0 && st.clumping <= 1, "clumping", "must be in [0, 1]");
  o.require(st.clumping == 0 || st.clumps > 0, "clumping", "needs clumps >= 1");
  o.rejectUnknownKeys();
}

void parseFriction(const JsonObject& f, FrictionSpec* out) {
  f.declareKeys({"mu_static", "mu_kinetic", "anisotropy"});
  FrictionSpec& fr = *out;
  fr.mu_static = f.number("mu_static");
  f.require(fr.mu_static >= 0 && fr.mu_static <= kMaxFriction, "mu_static", "must be in [0, 2]");
  fr.mu_kinetic = f.number("mu_kinetic", fr.mu_static);
  f.require(fr.mu_kinetic >= 0 && fr.mu_kinetic <= kMaxFriction, "mu_kinetic",
            "must be in [0, 2]");
  f.require(fr.mu_kinetic <= fr.mu_static, "mu_kinetic", "must not exceed mu_static");
  if (f.has("anisotropy")) {
    const JsonObject a = f.object("anisotropy");
    a.declareKeys({"strength", "exponent"});
    fr.anisotropy_strength = a.number("strength");
    a.require(fr.anisotropy_strength >= 0 && fr.anisotropy_strength <= 1, "strength",
              "must be in [0, 1] (C_eta, paper eq. 14)");
    fr.anisotropy_exponent = a.number("exponent", 2.0);
    a.require(fr.anisotropy_exponent >= 1, "exponent", "must be >= 1 (k, paper eq. 14)");
    a.rejectUnknownKeys();
  }
  f.rejectUnknownKeys();
}

// Strips are interpolated between spine roots (§4.2.2): the roots must span
// at least a line.
void requireRootSpread(const JsonObject& top, const std::vector<SpineSpec>& spines) {
  double spread = 0;
  for (const SpineSpec& sp : spines)
    spread = std::max(spread, (sp.root_mm - spines[0].root_mm).head<2>().norm());
  top.require(spread > kMinRootSpreadMm, "strips",
              "need spine roots spread over at least 0.01 mm in x-y to place strips between "
              "(all roots are in one point)");
}

void parseVolume(const JsonObject& v, VolumeSpec* out) {
  v.declareKeys({"min_separation", "stiffness_n_per_mm", "max_separation", "cohesion_n_per_mm",
                 "tip_spread", "spread_n_per_mm", "squash_after_mm", "spread_ramp"});
  VolumeSpec& vol = *out;
  vol.min_separation = v.number("min_separation");
  v.require(vol.min_separation > 0 && vol.min_separation < 1, "min_separation",
            "must be in (0, 1): a fraction of the spines' spacing at rest (at 1 or more "
            "the hairs would push each other apart at rest)");
  vol.stiffness_n_per_mm = v.number("stiffness_n_per_mm", vol.stiffness_n_per_mm);
  v.require(vol.stiffness_n_per_mm > 0 && vol.stiffness_n_per_mm <= 1000,
            "stiffness_n_per_mm", "must be in (0, 1000] N/mm");
  if (v.has("max_separation")) {
    vol.max_separation = v.number("max_separation");
    v.require(vol.max_separation > 1 && vol.max_separation <= 100, "max_separation",
              "must be in (1, 100]: a multiple of the spines' spacing at rest (at 1 or less "
              "the hairs would pull each other together at rest)");
  }
  vol.cohesion_n_per_mm = v.number("cohesion_n_per_mm", vol.cohesion_n_per_mm);
  v.require(vol.cohesion_n_per_mm > 0 && vol.cohesion_n_per_mm <= 1000, "cohesion_n_per_mm",
            "must be in (0, 1000] N/mm");
  vol.tip_spread = v.number("tip_spread", vol.tip_spread);
  v.require(vol.tip_spread >= 0 && vol.tip_spread <= 1, "tip_spread",
            "must be in [0, 1]: 0 holds each joint to its own spacing at rest, 1 to the "
            "widest");
  vol.spread_n_per_mm = v.number("spread_n_per_mm", vol.spread_n_per_mm);
  v.require(vol.spread_n_per_mm >= 0 && vol.spread_n_per_mm <= 1000, "spread_n_per_mm",
            "must be in [0, 1000] N/mm (0: a squashed bundle does not spread)");
  vol.squash_after_mm = v.number("squash_after_mm", vol.squash_after_mm);
  v.require(vol.squash_after_mm >= 0 && vol.squash_after_mm <= 100, "squash_after_mm",
            "must be in [0, 100] mm of press past first contact");
  vol.spread_ramp = v.number("spread_ramp", vol.spread_ramp);
  v.require(vol.spread_ramp >= 0 && vol.spread_ramp <= 10, "spread_ramp",
            "must be in [0, 10] (of the squash past 1; 0: full stiffness at once)");
  v.rejectUnknownKeys();
}

}  // namespace

Brush parseBrush(const std::string& text, const std::string& path,
                 std::vector<std::string>* problems) {
  const nlohmann::json doc = parseJsonText(text, path);
  const JsonObject top(doc, "", path);
  top.declareKeys({"format", "name", "description", "spines", "friction", "surface", "strips",
                   "volume", "solver", "paint"});
  Brush b;
  b.path = path;
  // With `problems`, each independent part (the header, every spine, each
  // section) reports its first problem and reading goes on with the next part.
  auto part = [&](const auto& read) {
    if (!problems) return read();
    try {
      read();
    } catch (const Error& e) {
      problems->push_back(e.what());
    }
  };
  part([&] {
    const std::string format = top.string("format");
    top.require(format == kBrushFormat, "format",
                "unknown format version (expected \"bristle-brush/1\")");
  });
  part([&] {
    b.name = top.string("name");
    top.require(!b.name.empty(), "name", "must not be empty");
    b.description = top.string("description", "");
  });

  std::vector<JsonObject> spines;
  part([&] {
    spines = top.objects("spines");
    top.require(!spines.empty() && spines.size() <= static_cast<size_t>(kMaxSpines), "spines",
                "must have 1.." + std::to_string(kMaxSpines) + " spines");
  });
  bool spines_ok = !spines.empty();
  for (const JsonObject& s : spines) {
    const size_t before = problems ? problems->size() : 0;
    part([&] {
      b.spines.push_back(parseSpine(s));
      top.requireAt(b.spines.back().root_mm.z() <= 0, s.childPointer("root_mm") + "/2",
                    b.spines.back().root_mm.z(),
                    "must be <= 0 (z <= 0: roots sit at the ferrule mouth or below it, where the hairs hang)");
    });
    if (problems && problems->size() != before) spines_ok = false;
  }

  if (top.has("friction")) part([&] { parseFriction(top.object("friction"), &b.friction); });
  // The geometry refers to the spines: it is only checked against sound ones.
  if (top.has("surface") && spines_ok)
    part([&] { parseSurface(top.object("surface"), b.spines, &b.surface); });
  if (top.has("strips")) part([&] {
    parseStrips(top.object("strips"), &b.strips);
    if (spines_ok) requireRootSpread(top, b.spines);
  });
  if (top.has("volume")) part([&] {
    const JsonObject v = top.object("volume");
    parseVolume(v, &b.volume);
    // The squash counts from the point's allowance (docs/dynamics.md, "A
    // squashed bundle spreads"): an allowance as long as the hair leaves the
    // squash no length to act on, and the spread would never start.
    if (spines_ok && b.volume.spread_n_per_mm > 0) {
      const double hair = restHairLengthMm(b);
      std::ostringstream msg;
      msg << "must be below the hair's length at rest (" << hair
          << " mm) where spread_n_per_mm is above 0: at or past it the bundle never squashes";
      v.require(b.volume.squash_after_mm < hair, "squash_after_mm", msg.str());
    }
  });
  if (top.has("solver")) part([&] {
    const JsonObject h = top.object("solver");
    h.declareKeys({"friction_form"});
    b.solver.friction_form = h.string("friction_form", "");
    const std::string& f = b.solver.friction_form;
    h.require(f.empty() || parseFrictionForm(f).has_value(), "friction_form",
              std::string("must be ") + kFrictionFormNames);
    h.rejectUnknownKeys();
  });
  if (top.has("paint")) part([&] {
    const JsonObject p = top.object("paint");
    p.declareKeys({"capacity", "flag_mm", "wicking"});
    b.paint_capacity = p.number("capacity", 1.0);
    p.require(b.paint_capacity > 0, "capacity", "must be > 0");
    b.paint_flag_mm = p.number("flag_mm", 0.0);
    p.require(b.paint_flag_mm >= 0 && b.paint_flag_mm <= kMaxFlagMm, "flag_mm",
              "must be in [0, 5] (mm of split hair ends)");
    b.paint_wicking = p.number("wicking", 1.0);
    p.require(b.paint_wicking >= 0 && b.paint_wicking <= 1, "wicking",
              "must be in [0, 1] (share of the reservoir flow)");
    p.rejectUnknownKeys();
  });
  for (const char* key : {"surface", "strips"})  // known even when skipped above
    if (top.has(key)) top.raw(key);
  part([&] { top.rejectUnknownKeys(); });
  return b;
}
Brush loadBrush(const std::string& path) { return parseBrush(readTextFile(path), path); }

std::vector<std::string> checkBrush(const std::string& path) {
  std::vector<std::string> problems;
  parseBrush(readTextFile(path), path, &problems);
  return problems;
}

}  // namespace bristle

#pragma once
// Brush description, the model of the JSON format `bristle-brush/1`
// (docs/brush-format.md; its reader is engine/formats/brush_reader.h). A brush is a few simulated spines (paper §3) in the
// brush frame: origin at the ferrule mouth, hairs hanging along -z at rest.

#include <Eigen/Core>
#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace bristle {

// Limits that keep a brush file from asking for absurd work.
inline constexpr int kMaxSpines = 64;
// Lengths in a brush (root positions, segment lengths, widths, cage vertices)
// are within +-1000 mm: the library's brushes are 20-60 mm long and a house
// painter's brush 150 mm, while a hair of 1e308 mm would overflow the geometry.
inline constexpr double kMaxBrushMm = 1000;
inline constexpr int kMaxJointsPerSpine = 16;

// The load (N) that presses a spine's hair bundle flat onto the canvas
// unless the spine declares its own (SpineSpec::flat_load_n). The
// solver holds each joint on the canvas (eq. 5) and the bundle around it
// reaches a radius below, whatever the load; the load itself is the canvas
// constraint forces (the multipliers of eq. 8, recovered as in §3.1). A bundle
// is pressed into the paper only as far as its load can press it: depth
// r * load / kBundleFlatLoadN, at most r (the axis on the canvas, flat, spread
// twice as wide). A tip that just touches -- the load fading as a moving brush
// lifts off -- is pressed in by nothing: it rests on the paper and leaves a
// thin line, and the stroke tapers to a point. 0.05 N is below what every
// spine of the round presses with through a steady stroke's body (the tenth
// percentile of its per-spine load along straight-pull.csv is 0.07 N, the
// flat's 0.17 N, the bright's 0.24 N), so those bodies keep their width.
inline constexpr double kBundleFlatLoadN = 0.05;

struct SpineSpec {
  Eigen::Vector3d root_mm = Eigen::Vector3d::Zero();  // in the brush frame
  // Joint i (0-based) bends segment i relative to its parent (segment i-1, or
  // the ferrule for i = 0). All per-joint arrays have one entry per segment.
  std::vector<double> segment_lengths_mm;
  std::vector<double> stiffness_nmm_per_rad;  // K_i, eq. 2
  std::vector<double> damping_nmm;            // D_i, eq. 4 (joint friction torque)
  std::vector<Eigen::Vector2d> rest_angles_rad;  // (theta, phi) of the unloaded joint
  // The hair bundle around the spine at the root and at the end of each
  // segment (n + 1 each): its extent along the brush frame's x axis (across a
  // flat's width) and along its y axis (across a flat's face). A round bundle
  // has both the same: an empty thickness_mm means thickness = width.
  std::vector<double> width_mm;
  std::vector<double> thickness_mm;
  // The load (N) that presses this bundle flat onto the paper, 0 for the
  // default (kBundleFlatLoadN above):
  // fine, soft hair splays under less (docs/brush-format.md, `flat_load_n`).
  double flat_load_n = 0;
  // Whether the hair under each joint bears load in the solve before the
  // joint reaches the paper, as a spring that flat_load_n (or the default)
  // sets (HairCushion, engine/mechanics/spine_energy.h; docs/brush-format.md,
  // `bundle_bears_load`). Off, a bundle bears no force until its joint does.
  bool bundle_bears_load = false;

  // The load (N) that presses this bundle flat: flat_load_n, or the default.
  double flatLoadN() const { return flat_load_n > 0 ? flat_load_n : kBundleFlatLoadN; }

  double thicknessMm(size_t j) const {
    return thickness_mm.empty() ? width_mm[j] : thickness_mm[j];
  }
  // Half the bundle's larger extent at point j: how far its geometry reaches
  // from the spine there.
  double bundleReachMm(size_t j) const { return 0.5 * std::max(width_mm[j], thicknessMm(j)); }

  int jointCount() const { return static_cast<int>(segment_lengths_mm.size()); }
  double lengthMm() const;
};

struct FrictionSpec {
  double mu_static = 0.4;    // used while a contact joint sticks (§3.4.1)
  double mu_kinetic = 0.35;  // used while it slides
  double anisotropy_strength = 0;  // C_eta of eq. 14, in [0, 1]
  double anisotropy_exponent = 2;  // k of eq. 14, >= 1
};

// Limits of the geometry (paper §4): refinement level 4 of a 200-face cage is
// already ~50k triangles; 1000 strips is five times the paper's 200.
inline constexpr int kMaxRefinementLevel = 4;
inline constexpr int kMaxStrips = 1000;
inline constexpr int kMaxCageVertices = 4096;
// Longest flagged hair end a brush may declare (paint.flag_mm): a badger's or
// hog's flags are a millimetre or two; 5 mm would be split hair for a third of
// a short brush's length.
inline constexpr double kMaxFlagMm = 5.0;

// Largest load a spine may declare to press its bundle flat (flat_load_n):
// 1 N is twenty times what presses a round's bundle flat.
inline constexpr double kMaxFlatLoadN = 1.0;
// Skin weights of a cage vertex must sum to 1 within this (weights are
// written with a few decimals in brush files).
inline constexpr double kSkinWeightSumTol = 1e-3;

// One influence of linear-blend skinning: the cage vertex follows the frame of
// spine `spine` at its point `point` (0 = root, n = tip): positioned at that
// point, oriented as the segment that starts there (the last segment at the tip).
struct SkinInfluence {
  int spine = 0;
  int point = 0;
  double weight = 1;
};

// Optional Catmull-Clark surface (paper §4.1): a control cage in the brush frame
// at rest, skinned to the spines and refined with OpenSubdiv.
struct SurfaceSpec {
  std::vector<Eigen::Vector3d> cage_mm;
  std::vector<std::vector<int>> faces;              // 3 or 4 vertex indices each
  std::vector<std::vector<SkinInfluence>> skin;     // per cage vertex
  int refinement_level = 2;
  bool present() const { return !cage_mm.empty(); }
};

// Optional bristle strips (paper §4.2): thin quad strips interpolated from the
// spines, placed automatically (§4.2.2).
struct StripSpec {
  int count = 0;                 // 0 = none
  double root_width_mm = 0.15;   // strip width at the root, tapering to
  double tip_width_mm = 0.05;    // this at the tip
  std::uint64_t seed = 1;        // placement is random but reproducible
  std::string placement = "auto";  // auto (OBB decides) | line (1-D) | area (2-D)
  double length_jitter = 0;      // strips end at (1 - U(0, jitter)) of the spine
  // Wet hair clumps (paper Fig. 2): the strips gather into `clumps` bunches,
  // each strip drawn towards its bunch's mean centre line by clumping * s (0 at
  // the ferrule, `clumping` at the tip). 0 clumps = none.
  int clumps = 0;
  double clumping = 0;           // [0, 1]
  bool present() const { return count > 0; }
};

// Hair volume (docs/dynamics.md, "Hair volume"): hair cannot pass through
// hair. Corresponding joints of neighbouring spines keep at least
// min_separation times their distance at rest; squeezed closer, the bundle
// pushes back with a smoothed stiffness.
struct VolumeSpec {
  double min_separation = 0;      // fraction of the rest spacing, in (0, 1); 0 = off
  double stiffness_n_per_mm = 5;  // force per mm squeezed past the minimum
  // Cohesion of the wet bundle: pairs pulled further apart than max_separation
  // times their rest distance pull back with this stiffness. 0 = none.
  double max_separation = 0;      // > 1, or 0 = no cohesion
  double cohesion_n_per_mm = 0.5;
  // What max_separation multiplies at joint j: the pair's rest distance there,
  // raised towards its widest rest spacing (the belly's) by this fraction.
  // 1: the widest everywhere, so converging tips may spread as wide as the
  // belly; 0: each joint's own, so the tips keep their point.
  double tip_spread = 1;
  // Incompressibility (docs/dynamics.md, "A squashed bundle spreads"): with the
  // ferrule nearer the paper than the hair is long, the bundle's volume must
  // fit in a shorter height, so its section across the handle's axis grows by
  // the squash s = rest length / height, and each joint's distance from the
  // axis by sqrt(s). A joint nearer the axis than that is pushed out with this
  // stiffness, and cohesion's limit grows by sqrt(s). 0 = off.
  double spread_n_per_mm = 0;
  // The point's lie-down (docs/dynamics.md, "The point lies down before the
  // belly squashes"): the first this many mm of a press past first contact
  // fold the soft point over along the paper; only the press beyond them
  // squashes the belly, so the squash's rest length is the hair's less this.
  double squash_after_mm = 0;
  // How far past 1 the squash s goes before the spread's push has its full
  // stiffness (docs/dynamics.md, "The spread ramps in"): spread_n_per_mm
  // times min(1, (s - 1) / spread_ramp). 0 = full stiffness at once.
  double spread_ramp = 0;
  bool present() const { return min_separation > 0; }
};

// Ipopt's form for friction (docs/dynamics.md, "Friction in epigraph form"),
// as a brush file's "solver" block and --ipopt-option friction_form spell it.
enum class FrictionForm { kAuto, kObjective, kEpigraph };
inline constexpr const char* kFrictionFormNames = "\"auto\", \"objective\" or \"epigraph\"";
std::optional<FrictionForm> parseFrictionForm(const std::string& name);

// Hints to the solvers (docs/brush-format.md, "solver"): numerical choices
// that leave the brush's equilibria where they are and change only how fast a
// solver reaches them. Like a MuJoCo model's <option>, they travel with the
// model they were tuned on; a run's own options override them.
struct SolverHints {
  // Ipopt's friction form (docs/dynamics.md, "Friction in epigraph form"):
  // "auto", "objective" or "epigraph"; empty leaves the run's default.
  std::string friction_form;
};

struct Brush {
  std::string path;  // for messages
  std::string name;
  std::string description;
  std::vector<SpineSpec> spines;
  FrictionSpec friction;
  SurfaceSpec surface;
  StripSpec strips;
  VolumeSpec volume;
  SolverHints solver;
  double paint_capacity = 1.0;  // relative amount of paint the brush holds
  // Length (mm) of the hairs' flagged (split) ends, 0 for none: where only the
  // flags reach the paper, within this distance of the footprint's outline,
  // the brush lays a thinner film (docs/brush-format.md, `paint.flag_mm`).
  double paint_flag_mm = 0.0;
  // How much of the paint the hair takes up is drawn up into the belly, in
  // [0, 1]: 1 (the default) the full reservoir flow; below 1 the hair keeps
  // it at its ends and lays it again, and the rest of the flow only runs
  // down towards the tips (docs/brush-format.md, `paint.wicking`).
  double paint_wicking = 1.0;

  // Largest distance from the ferrule centre any hair can reach (mm).
  double reachMm() const;
};

}  // namespace bristle

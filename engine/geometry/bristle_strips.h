#pragma once
// Bristle strips (paper §4.2): a few hundred thin quad strips, each a hair
// interpolated from the simulated spines.
//
// Once per brush, layoutStrips() places the strip roots at random between the
// spine roots (§4.2.2) and fixes each strip's weights over the spines
// (eqs. 17-20). Every step, buildStrips() evaluates the strips' centre lines
// p(s) = sum_i w_i p_i(s) (eq. 16), turns each strip's flat side to the canvas
// and emits the strips back to front as seen from the canvas (§4.2.1, Fig. 8).
//
// Draw order. The paper renders the strips "back-to-front with respect to the
// canvas", sorted by root position along the principal bend direction (the
// mean tip deflection, projected onto the brush cross-section). We take
// "front" to be the side of the hair bundle that faces the canvas, and that is
// the side *opposite* the bend: when the bundle bends towards +d (a stroke
// dragged towards -d), the hairs rooted on the -d side go down further before
// they turn and so wrap under the hairs rooted on the +d side, which lie on top
// of them. So strips are emitted in decreasing order of root . d: the hairs
// on the side the brush bends towards first, the hairs on the leading side of
// the stroke last. Rendered without depth test, the last-drawn (canvas-nearest)
// strip is the one whose paint row reaches the canvas. With no bend to speak
// of (|d| < kStripBendEpsMm) the layout order is kept.

#include <Eigen/Core>
#include <vector>

#include "engine/model/brush.h"
#include "engine/geometry/brush_vertex.h"
#include "engine/dynamics/simulation.h"

namespace bristle {

// The automatic placement samples along the best-fit line (1-D) when the
// oriented bounding box of the spine roots is thinner than this fraction of its
// length (§4.2.2 "a very narrow bounding box"): flat, bright and fan brushes.
inline constexpr double kStripThinBoxRatio = 0.10;
// A sampled root this close to a spine root is that spine root (weight 1 on it):
// eq. 17 has a zero coefficient there, and nearby the weight problem is
// ill-conditioned (cost ratio ~ (reach / distance)^2). 1 um is far below a pixel.
inline constexpr double kStripSnapMm = 1e-3;
// Mean tip deflections shorter than this leave the strips in layout order (a
// brush at rest shows only rounding noise, ~1e-14 mm).
inline constexpr double kStripBendEpsMm = 1e-6;
// A strip samples its centre line at the union of the spines' joint parameters
// (two vertices per joint, as in §4.2); brushes whose spines disagree on more
// than this many distinct parameters are sampled uniformly instead.
inline constexpr int kMaxStripSamples = 33;

struct StripLayout {
  int count = 0;   // strips
  int spines = 0;  // spines of the brush (columns of `weights`)
  // Placement domain (§4.2.2), in the brush frame's x-y plane:
  bool one_dimensional = false;  // roots sampled along the best-fit line
  Eigen::Vector2d line_from_mm = Eigen::Vector2d::Zero();  // 1-D: the segment of the
  Eigen::Vector2d line_to_mm = Eigen::Vector2d::Zero();    // line the roots span
  std::vector<Eigen::Vector3i> triangles;  // 2-D: Delaunay triangles (spine indices)

  // Per strip, in layout order (this order also picks the strip's texture row).
  std::vector<Eigen::Vector2d> roots_mm;  // (count) brush frame x-y
  std::vector<double> weights;            // (count x spines) row-major, eqs. 17-19
  std::vector<double> length_factor;      // (count) the strip ends at s = this (<= 1)
  // Clumps (StripSpec::clumps): each strip's bunch, and per bunch the mean of
  // its strips' weights, whose centre line (eq. 16) is the bunch's mean centre
  // line. Empty without clumping.
  std::vector<int> clump;                 // (count)
  std::vector<double> clump_weights;      // (clumps x spines) row-major

  // Arc-length parameters s in [0, 1] at which a full-length strip is sampled;
  // a strip with length factor f is sampled at f * sample_s (same count).
  std::vector<double> sample_s;
  // Arc-length parameter of every spine joint, root (0) to tip (1), flattened:
  // spine i's joints are joint_s[joint_begin[i] .. joint_begin[i + 1]).
  std::vector<double> joint_s;
  std::vector<int> joint_begin;  // (spines + 1)
  std::vector<double> joint_inv_ds;  // 1 / (joint_s[k + 1] - joint_s[k]), 0 past a tip
  // Per spine, the first spine whose joint parameters (joint_s, joint_inv_ds)
  // are bit for bit its own: a strip's samples fall on the same segments at
  // the same fractions of both, so buildStrips finds them once for the two.
  std::vector<int> joint_group;  // (spines)
  // Spine tips at rest in the brush frame, for the tip deflections of §4.2.1.
  std::vector<Eigen::Vector3d> rest_tips_mm;

  double weight(int strip, int spine) const { return weights[strip * spines + spine]; }
  int samples() const { return static_cast<int>(sample_s.size()); }
  // Triangles buildStrips() emits per step: two per quad.
  int triangleCount() const { return 2 * (samples() - 1) * count; }
};

// Places brush.strips.count strips (§4.2.2) with a seeded generator: the same
// brush gives the same layout bit for bit. An empty layout when the brush has
// no strips. With clumps, `clumps` strips picked at random (a second generator
// from the same seed, so the roots do not move) are the bunches' seeds, and
// every strip joins the bunch whose seed's root is nearest its own.
StripLayout layoutStrips(const Brush& brush);

// Weights of eqs. 17-20 for a root p among spine roots (the columns of `roots`,
// 1-D or 2-D): minimise sum_i |p - p_i|^2 w_i^2 subject to sum_i w_i = 1,
// w_i >= 0 and sum_i w_i p_i = p, solved exactly by a primal active-set method.
// `start` must be feasible (e.g. barycentric coordinates of p in a triangle).
Eigen::VectorXd solveStripWeights(const Eigen::MatrixXd& roots, const Eigen::VectorXd& p,
                                  const Eigen::VectorXd& start);

// Principal bend direction (§4.2.1): the mean over spines of the tip
// deflection (tip minus rest tip under the current handle pose), in the brush
// frame's x-y plane (mm, not normalised).
Eigen::Vector2d stripBendDirection(const StripLayout& layout, const BrushState& state);

// Appends layout.triangleCount() triangles (3 vertices each, world mm) to
// `triangles`: each strip a quad strip along its centre line, width tapering
// linearly from root_width_mm to tip_width_mm, flat side towards the canvas,
// wound counter-clockwise as seen from the canvas (geometric normal towards -z).
// u = (strip + 0.5) / count is the strip's texture row, v = s the arc-length
// parameter along the spines. A clumped strip's centre line is drawn towards
// its bunch's by clumping * s. Allocates nothing but the growth of `triangles`.
// With below_mm, only the triangles that reach down to it (reachesDown): a
// strip's quads above it are not built.
void buildStrips(const Brush& brush, const StripLayout& layout, const BrushState& state,
                 std::vector<BrushVertex>* triangles, double below_mm = kAllHeights);

}  // namespace bristle

#pragma once
// The hair bundles around the simulated spines, drawn with the surface (§4.1)
// and the strips (§4.2): each spine is dressed in the lower half of a tube whose
// section is the hair bundle around that spine at each joint -- a circle of
// the brush file's width_mm, or for a flat's slab (thickness_mm) a rounded
// rectangle -- the canvas-facing side of that bundle. The footprint is whatever
// lies within the contact band above the canvas (§4.2.1). Where the bundle would reach below the canvas
// it flattens and spreads instead (bundleSpread), so a spine pressed flatter
// leaves a wider mark -- as far as the spine's load presses it
// (kBundleFlatLoadN): a bundle that barely touches rests on the paper.

#include <vector>

#include "engine/model/brush.h"
#include "engine/geometry/brush_vertex.h"
#include "engine/dynamics/simulation.h"

namespace bristle {

// Facets around the half tube: 8 keeps the polygon within 2% of the circle's
// radius (1 - cos(pi / 16)), below a pixel at 8 px/mm for hairs under 6 mm.
inline constexpr int kTubeFacets = 8;
// Latitude rings of the half solid (a half sphere, for a round bundle) that
// rounds the bundle off at each joint.
inline constexpr int kCapRings = 3;
// How far the cap at a spine's tip reaches past the tip along a lying hair,
// as a fraction of the bundle's radius there: the hairs end in a cut face,
// so a flat bundle's end is nearly square (buildSpineGeometry).
inline constexpr double kTipCapDepth = 0.3;

// A spine whose bundle has its own thickness (SpineSpec::thickness_mm) stands
// for a slab of a flat's row of hair, cut square: its section is the
// superellipse |x/a|^p + |y/b|^p = 1, a rectangle whose corners are rounded
// only at the scale of a few hairs. With p = 24 its face lies within 1 % of
// the thickness of flat over 94 % of its width, and at 45 degrees it reaches
// 0.97 of the way to the rectangle's corner (an ellipse: 0.71).
//
// The corners matter where the hair meets the paper at a shallow angle: a
// corner that rises h above the face moves the edge of the contact back by
// h / tan(angle), about 2 h for a flat's chisel lifting off at 28 degrees.
// With p = 6 the row's outer corners ended a broadside stroke up to 0.75 mm
// early; with 24 the stop end varies by 0.75 mm over the whole width
// instead of 1.0 (test "marks: a flat's broadside pull has square ends").
inline constexpr double kSlabSectionExponent = 24;
// How much of bundleSpread's sideways widening a slab takes. A flat's slabs
// lie side by side in the ferrule and press against each other, so pressed
// flat the row only flares at its edges; a round's bundle is free to spread
// (1). With 0.25 a flat's row of five 2.76 mm slabs flares by 0.35 mm a side
// pressed flat, from 12.4 to 13.1 mm: about a tenth, where the round-bundle
// spread gave 15 mm.
inline constexpr double kSlabFlare = 0.25;

// How much a spine's hair bundle widens, pressed against the canvas. At rest
// the bundle is round, of radius r. The solver keeps the spine itself above
// the canvas (eq. 5), and the bundle around it may reach below; as in the
// paper, what reaches below the canvas stands for how hard the hair presses
// (the footprint's depth, §4.2.1, drives paint transfer). But hair does not
// pass through paper and a bundle's hair is not lost: the part of the section
// beyond the canvas is pressed aside, so the section widens across the hair
// until the part on the brush's side of the canvas has the bundle's whole
// area pi r^2 again. `reach` is how far the canvas is from the spine along the
// section's downward direction. Lying on the paper (reach 0) the bundle is
// twice as wide as it was round; clear of the paper (reach >= r) it is round
// (1). This is the belly flattening and spreading under a press.
double bundleSpread(double radius_mm, double reach_mm);


// How deep (mm) a bundle of radius r may reach below the canvas under a load
// (N): r * load / flat_load_n, within [0, r]. A spine's SpineSpec::flat_load_n
// replaces kBundleFlatLoadN: a badger's fine, soft hair splays under a fifth
// of the load, so that a light touch lays its dome down over a patch.
double bundlePressDepth(double radius_mm, double load_n, double flat_load_n = kBundleFlatLoadN);


// Where buildSpineGeometry draws the bundle around each point 0..n of a
// spine: its centre raised above the joint (raise_mm, >= 0) until it reaches
// only bundlePressDepth of the spine's load below the canvas, and how far
// below the canvas it then reaches (depth_mm, >= 0).
struct BundlePlacement {
  std::vector<double> raise_mm, depth_mm;
};
BundlePlacement bundlePlacement(const SpineSpec& spec, const SpineState& spine,
                                const Pose& handle);

// How far (mm) below each point 0..n of a spine (joints_mm, root first, in the
// world) its hair bundle reaches, unpressed, as buildSpineGeometry draws it for a
// brush held at `handle`: at the root the tube's section, at each joint the
// half solid that rounds the bundle off (for a round bundle of radius r, r
// whichever way the hair points). With the points, the lowest the bundle
// reaches: where it first touches the paper (engine/geometry/first_contact.h).
std::vector<double> bundleReachBelowPoints(const SpineSpec& spec,
                                           const std::vector<Eigen::Vector3d>& joints_mm,
                                           const Pose& handle);

// Which half solids buildSpineGeometry draws: caps[s][j] for joint j = 1..n
// of spine s (index 0 unused); the tubes are always drawn. A sweep's stamps
// between two steps draw a joint's half solid only as often as keeps the
// notches between its copies small (render/stroke_renderer.cpp).
using JointCaps = std::vector<std::vector<char>>;

// The smallest radius of curvature (mm) of the outline of each joint's half
// solid where it reaches into the contact band `band_mm` above the canvas,
// rho_mm[j] for j = 1..n: the disc it is cut in there (as drawn: a polygon of
// flat facets), a squashed one at the tip; 0 where it does not reach the
// band, and for a slab's rounded rectangle, whose corners turn within a few
// hairs. Copies of an outline whose curvature radius is at least rho, d
// apart, leave notches rho - sqrt(rho^2 - d^2 / 4) deep between them.
void capPatchRoundness(const SpineSpec& spec, const SpineState& spine, const Pose& handle,
                       double band_mm, std::vector<double>* rho_mm);

// Appends the triangles of every spine's half tube (and the half solids at its
// joints) to `triangles`; with `caps`, only those half solids. Each spine's load is the sum of its canvas forces
// (SpineState::solution.normal_force_n; none given is no load): where a joint's
// bundle would reach further below the canvas than bundlePressDepth allows, it
// is raised until it reaches only that far, and it spreads (bundleSpread) for
// the depth it keeps. Triangles that do not reach down to below_mm are left
// out (reachesDown).
void buildSpineGeometry(const Brush& brush, const BrushState& state,
                        std::vector<BrushVertex>* triangles, double below_mm = kAllHeights,
                        const JointCaps* caps = nullptr);

}  // namespace bristle

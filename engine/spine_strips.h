#pragma once
// The simulated spines' own geometry, drawn with the surface (§4.1) and the
// strips (§4.2): each spine is dressed in the lower half of a tube whose
// diameter is the width the brush file gives at each joint, the canvas-facing
// side of the hair bundle around that spine. The footprint is whatever lies
// below the clip plane (§4.2.1). Where the bundle would reach below the canvas
// it flattens and spreads instead (bundleSpread), so a spine pressed flatter
// leaves a wider mark.

#include <vector>

#include "engine/brush.h"
#include "engine/simulation.h"

namespace bristle {

// A vertex of brush geometry in world mm with its brush texture coordinate:
// u runs across the brush (spine s covers [s, s + 1] / spines, side to side,
// from the side towards the brush frame's -x to the side towards its +x),
// v along it (0 at the root, 1 at the tip).
struct BrushVertex {
  float x_mm, y_mm, z_mm;
  float u, v;
};

// Facets around the half tube: 8 keeps the polygon within 2% of the circle's
// radius (1 - cos(pi / 16)), below a pixel at 8 px/mm for hairs under 6 mm.
inline constexpr int kTubeFacets = 8;
// Latitude rings of the half sphere that rounds the bundle at each joint.
inline constexpr int kCapRings = 3;
// How far the cap at a spine's tip reaches past the tip along a lying hair,
// as a fraction of the bundle's radius there: the hairs end in a cut face,
// so a flat bundle's end is nearly square (buildSpineGeometry).
inline constexpr double kTipCapDepth = 0.3;

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


// Appends the triangles of every spine's half tube (and the half spheres at its
// joints) to `triangles`.
void buildSpineGeometry(const Brush& brush, const BrushState& state,
                        std::vector<BrushVertex>* triangles);

}  // namespace bristle

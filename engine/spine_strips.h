#pragma once
// First-cut brush geometry for the footprint (the geometry issue replaces it
// with the subdivision surface and bristle strips of paper §4). Each spine is
// dressed in the lower half of a tube whose diameter is the width the brush file
// gives at each joint: the canvas-facing side of the hair bundle around that
// spine. As in the paper, the spines are constrained to stay above the canvas
// (eq. 5) while the geometry around them may reach below it; the footprint is
// whatever lies below the clip plane (§4.2.1), so a spine pressed flatter leaves
// a wider mark.

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

// Appends the triangles of every spine's half tube (and the half spheres at its
// joints) to `triangles`.
void buildSpineGeometry(const Brush& brush, const BrushState& state,
                        std::vector<BrushVertex>* triangles);

}  // namespace bristle

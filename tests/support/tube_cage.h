#pragma once
// A Catmull-Clark cage (paper §4.1) around any brush's spines, so that tests
// can give a surface to brushes they build in code.

#include "engine/model/brush.h"

namespace bristle {

// A cage for tests and benchmarks (the brush library's cages come from
// scenes/brushes/generate.py, which builds them along the same lines):
// a closed-ended tube around the spines, open at the ferrule.
//  - One ring of `ring_vertices` per point level j = 0 (root) .. N (N = the most
//    joints of any spine; a shorter spine contributes its tip to deeper rings).
//    Rings lie in horizontal planes of the brush frame at rest, centred on the
//    mean of the spines' rest point j. In direction d, the ring reaches the hull
//    of the spines' points plus each spine's width_mm[j] / 2 (its support
//    function), scaled by 6 / (4 + 2 cos(2 pi / ring_vertices)) so that the
//    Catmull-Clark limit of a round ring has radius width / 2, not ~10% less.
//  - Quads join consecutive rings; a fan of triangles closes the tip around one
//    vertex half the tip width beyond the mean tip, along the last segments.
//  - Ring vertices get weight 1 on point j of the spine nearest to them at rest;
//    the tip vertex weights every spine's tip equally.
// Faces are oriented outwards. Throws Error(kUsage) unless 3 <= ring_vertices
// <= 64, the brush has spines and refinement_level is in [0, kMaxRefinementLevel].
SurfaceSpec makeTubeCage(const Brush& brush, int ring_vertices, int refinement_level = 2);

}  // namespace bristle

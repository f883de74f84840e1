#pragma once
// The vertex every part of the brush head is drawn with, and how its texture
// coordinate says which part it belongs to.
//
// The footprint renderer (render/gl/footprint_renderer.h) writes one texture
// coordinate (u, v) per covered pixel, and the paint model (engine/paint/paint.h)
// needs to know from it whether the pixel shows the subdivision surface (paper
// §4.1), a bristle strip (§4.2) or one of the simulated spines' own half tubes
// (engine/geometry/spine_bundles.h): each maps to the brush's paint texture its own way.
// Rather than add a channel to the footprint image, the part rides in u as a
// whole-number offset, since every part's own u lies in [0, 2):
//
//   part      own u                                       u written
//   surface   angle around the brush axis, [0, 1] (a      u
//             little past 1 across the seam)
//   strip     texture row k / strips, [0, 1)              u + 2
//   spine     spine s covers [s, s + 1) / spines          u + 4
//
// encodeTextureU and the decoders below are the only places that know the
// offsets.

#include <algorithm>
#include <limits>

namespace bristle {

// A vertex of brush geometry in world mm with its brush texture coordinate:
// u runs across the part (see above; for a spine's tube, from the side towards
// the brush frame's -x to the side towards its +x), v along the hairs (0 at
// the root, 1 at the tip).
struct BrushVertex {
  float x_mm, y_mm, z_mm;
  float u, v;
};

// Whether a triangle reaches down to z_mm: its lowest vertex at or below it,
// by the footprint renderer's own test (a vertex's float z against a double
// height; render/stroke_renderer.cpp draws only such triangles). The brush
// geometry's builders take such a height and leave out the triangles above
// it: the footprint is the same to the bit, and what is far above the paper
// (most of a pressed brush) is not built. kAllHeights keeps every triangle
// (previews, exporters).
inline constexpr double kAllHeights = std::numeric_limits<double>::infinity();
inline bool reachesDown(const BrushVertex& a, const BrushVertex& b, const BrushVertex& c,
                        double z_mm) {
  return !(std::min({a.z_mm, b.z_mm, c.z_mm}) > z_mm);
}

enum class BrushPart { kSurface, kStrip, kSpine };

namespace texture_u {
inline constexpr float kStripOffset = 2.0f;
inline constexpr float kSpineOffset = 4.0f;
}  // namespace texture_u

// The u a vertex of `part` is written with, from the part's own u.
constexpr float encodeTextureU(BrushPart part, float own_u) {
  switch (part) {
    case BrushPart::kStrip: return own_u + texture_u::kStripOffset;
    case BrushPart::kSpine: return own_u + texture_u::kSpineOffset;
    case BrushPart::kSurface: break;
  }
  return own_u;
}

// The part a written u belongs to.
constexpr BrushPart partOfTextureU(float u) {
  return u >= texture_u::kSpineOffset   ? BrushPart::kSpine
         : u >= texture_u::kStripOffset ? BrushPart::kStrip
                                        : BrushPart::kSurface;
}

// The part's own u from a written u of that part.
constexpr float ownTextureU(BrushPart part, float u) {
  switch (part) {
    case BrushPart::kStrip: return u - texture_u::kStripOffset;
    case BrushPart::kSpine: return u - texture_u::kSpineOffset;
    case BrushPart::kSurface: break;
  }
  return u;
}

// The written-u range [begin, end) of a part that is not the surface.
constexpr float textureUBegin(BrushPart part) { return encodeTextureU(part, 0.0f); }
constexpr float textureUEnd(BrushPart part) {
  return part == BrushPart::kStrip ? texture_u::kSpineOffset : 1e30f;
}

}  // namespace bristle

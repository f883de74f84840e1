#pragma once
// The brush head's geometry for one step (paper §4): the skinned Catmull-Clark
// surface (§4.1) and/or the interpolated bristle strips (§4.2), plus the
// simulated spines themselves, each dressed in a half tube of its width
// (engine/spine_strips.h).
// Built once per brush; build() per step appends triangles in world mm.
//
// Texture coordinates tell the two apart for paint transfer: the surface's
// (u, v) lie in [0, 1] x [0, 1] (u may run a little past 1 across its seam);
// strips use u + 2, so u >= 2 means "strip texture, row u - 2" (§4.2.1: one
// texture row per strip); the spines' own half tubes use u + 4 (u >= 4: spine
// (u - 4) * spines), so the paint model (engine/paint.h) can tell all three apart.

#include <memory>
#include <vector>

#include "engine/brush.h"
#include "engine/simulation.h"
#include "engine/spine_strips.h"

namespace bristle {

class BrushSurface;
struct StripLayout;

inline constexpr float kStripTextureOffsetU = 2.0f;
inline constexpr float kSpineTextureOffsetU = 4.0f;

class BrushGeometry {
 public:
  // Throws bristle::Error(kDataError) naming /surface when the cage is unusable.
  explicit BrushGeometry(const Brush& brush);
  ~BrushGeometry();
  BrushGeometry(BrushGeometry&&) noexcept;
  BrushGeometry& operator=(BrushGeometry&&) noexcept;

  // Appends the triangles of the brush in `state` (3 vertices each).
  void build(const BrushState& state, std::vector<BrushVertex>* triangles);
  // The parts separately, for previews: surface (or spine tubes) and strips.
  void buildSurface(const BrushState& state, std::vector<BrushVertex>* triangles);
  void buildStrips(const BrushState& state, std::vector<BrushVertex>* triangles);
  // Everything but the subdivision surface: the spines' tubes and the strips,
  // the parts fine enough to leave gaps between a step's stamps.
  void buildHair(const BrushState& state, std::vector<BrushVertex>* triangles);

  const Brush& brush() const { return *brush_; }

 private:
  void buildSpineTubes(const BrushState& state, std::vector<BrushVertex>* triangles);

  const Brush* brush_;
  std::unique_ptr<BrushSurface> surface_;
  std::unique_ptr<StripLayout> strips_;  // placed once per brush (§4.2.2)
  std::vector<BrushVertex> scratch_;
};

}  // namespace bristle

#pragma once
// The brush head's geometry for one step (paper §4): the skinned Catmull-Clark
// surface (§4.1) and/or the interpolated bristle strips (§4.2), plus the
// simulated spines themselves, each dressed in a half tube of its width
// (engine/geometry/spine_bundles.h).
// Built once per brush; build() per step appends triangles in world mm.
//
// Each part's vertices carry its BrushPart in their texture coordinate u
// (engine/geometry/brush_vertex.h), so the paint model (engine/paint/paint.h) can tell the
// surface, the strips (§4.2.1: one texture row per strip) and the spines' own
// half tubes apart.

#include <memory>
#include <vector>

#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/geometry/brush_vertex.h"
#include "engine/geometry/spine_bundles.h"

namespace bristle {

class BrushSurface;
struct StripLayout;

class BrushGeometry {
 public:
  // Throws bristle::Error(kDataError) naming /surface when the cage is unusable.
  explicit BrushGeometry(const Brush& brush);
  ~BrushGeometry();
  BrushGeometry(BrushGeometry&&) noexcept;
  BrushGeometry& operator=(BrushGeometry&&) noexcept;

  // Appends the triangles of the brush in `state` (3 vertices each). With
  // below_mm, the hair's (strips' and spine tubes') triangles that do not
  // reach down to it are left out (reachesDown); the surface's are all kept.
  void build(const BrushState& state, std::vector<BrushVertex>* triangles,
             double below_mm = kAllHeights);
  // The parts separately, for previews: surface (or spine tubes) and strips.
  void buildSurface(const BrushState& state, std::vector<BrushVertex>* triangles,
                    double below_mm = kAllHeights);
  void buildStrips(const BrushState& state, std::vector<BrushVertex>* triangles,
                   double below_mm = kAllHeights);
  // Everything but the subdivision surface: the spines' tubes and the strips,
  // the parts fine enough to leave gaps between a step's stamps. With
  // `caps`, only those half solids at the joints (buildSpineGeometry).
  void buildHair(const BrushState& state, std::vector<BrushVertex>* triangles,
                 double below_mm = kAllHeights, const JointCaps* caps = nullptr);

  const Brush& brush() const { return *brush_; }

 private:
  void buildSpineTubes(const BrushState& state, std::vector<BrushVertex>* triangles,
                       double below_mm, const JointCaps* caps = nullptr);

  const Brush* brush_;
  std::unique_ptr<BrushSurface> surface_;
  std::unique_ptr<StripLayout> strips_;  // placed once per brush (§4.2.2)
  std::vector<BrushVertex> scratch_;
};

}  // namespace bristle

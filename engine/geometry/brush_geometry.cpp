#include "engine/geometry/brush_geometry.h"

#include "engine/geometry/bristle_strips.h"
#include "engine/geometry/brush_surface.h"

namespace bristle {

BrushGeometry::BrushGeometry(const Brush& brush) : brush_(&brush) {
  if (brush.surface.present()) surface_ = std::make_unique<BrushSurface>(brush);
  if (brush.strips.present()) strips_ = std::make_unique<StripLayout>(layoutStrips(brush));
}
BrushGeometry::~BrushGeometry() = default;
BrushGeometry::BrushGeometry(BrushGeometry&&) noexcept = default;
BrushGeometry& BrushGeometry::operator=(BrushGeometry&&) noexcept = default;

void BrushGeometry::buildSurface(const BrushState& state, std::vector<BrushVertex>* triangles,
                                 double below_mm) {
  if (surface_) surface_->update(state, triangles);
  buildSpineTubes(state, triangles, below_mm);
}

void BrushGeometry::buildHair(const BrushState& state, std::vector<BrushVertex>* triangles,
                              double below_mm, const JointCaps* caps) {
  buildSpineTubes(state, triangles, below_mm, caps);
  buildStrips(state, triangles, below_mm);
}

void BrushGeometry::buildSpineTubes(const BrushState& state, std::vector<BrushVertex>* triangles,
                                    double below_mm, const JointCaps* caps) {
  // The simulated spines are hairs too: dressed in their own width they mark
  // the paper wherever the solver puts them in contact, also where an
  // approximating surface (§4.1) rounds off inside them, at a splayed tip.
  const size_t first = triangles->size();
  buildSpineGeometry(*brush_, state, triangles, below_mm, caps);
  for (size_t i = first; i < triangles->size(); ++i) {
    (*triangles)[i].u = encodeTextureU(BrushPart::kSpine, (*triangles)[i].u);
  }
}

void BrushGeometry::buildStrips(const BrushState& state, std::vector<BrushVertex>* triangles,
                                double below_mm) {
  if (!strips_) return;
  const size_t first = triangles->size();
  bristle::buildStrips(*brush_, *strips_, state, triangles, below_mm);
  for (size_t i = first; i < triangles->size(); ++i) {
    (*triangles)[i].u = encodeTextureU(BrushPart::kStrip, (*triangles)[i].u);
  }
}

void BrushGeometry::build(const BrushState& state, std::vector<BrushVertex>* triangles,
                          double below_mm) {
  buildSurface(state, triangles, below_mm);
  buildStrips(state, triangles, below_mm);
}

}  // namespace bristle

#include "engine/brush_geometry.h"

#include "engine/bristle_strips.h"
#include "engine/brush_surface.h"

namespace bristle {

BrushGeometry::BrushGeometry(const Brush& brush) : brush_(&brush) {
  if (brush.surface.present()) surface_ = std::make_unique<BrushSurface>(brush);
  if (brush.strips.present()) strips_ = std::make_unique<StripLayout>(layoutStrips(brush));
}
BrushGeometry::~BrushGeometry() = default;
BrushGeometry::BrushGeometry(BrushGeometry&&) noexcept = default;
BrushGeometry& BrushGeometry::operator=(BrushGeometry&&) noexcept = default;

void BrushGeometry::buildSurface(const BrushState& state, std::vector<BrushVertex>* triangles) {
  if (surface_) surface_->update(state, triangles);
  buildSpineTubes(state, triangles);
}

void BrushGeometry::buildHair(const BrushState& state, std::vector<BrushVertex>* triangles) {
  buildSpineTubes(state, triangles);
  buildStrips(state, triangles);
}

void BrushGeometry::buildSpineTubes(const BrushState& state,
                                    std::vector<BrushVertex>* triangles) {
  // The simulated spines are hairs too: dressed in their own width they mark
  // the paper wherever the solver puts them in contact, also where an
  // approximating surface (§4.1) rounds off inside them, at a splayed tip.
  const size_t first = triangles->size();
  buildSpineGeometry(*brush_, state, triangles);
  for (size_t i = first; i < triangles->size(); ++i) {
    (*triangles)[i].u = encodeTextureU(BrushPart::kSpine, (*triangles)[i].u);
  }
}

void BrushGeometry::buildStrips(const BrushState& state, std::vector<BrushVertex>* triangles) {
  if (!strips_) return;
  const size_t first = triangles->size();
  bristle::buildStrips(*brush_, *strips_, state, triangles);
  for (size_t i = first; i < triangles->size(); ++i) {
    (*triangles)[i].u = encodeTextureU(BrushPart::kStrip, (*triangles)[i].u);
  }
}

void BrushGeometry::build(const BrushState& state, std::vector<BrushVertex>* triangles) {
  buildSurface(state, triangles);
  buildStrips(state, triangles);
}

}  // namespace bristle

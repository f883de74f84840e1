#include "engine/model/brush.h"

#include <algorithm>

namespace bristle {

std::optional<FrictionForm> parseFrictionForm(const std::string& name) {
  if (name == "auto") return FrictionForm::kAuto;
  if (name == "objective") return FrictionForm::kObjective;
  if (name == "epigraph") return FrictionForm::kEpigraph;
  return std::nullopt;
}

double SpineSpec::lengthMm() const {
  double l = 0;
  for (double s : segment_lengths_mm) l += s;
  return l;
}

double Brush::reachMm() const {
  double r = 0;
  for (const SpineSpec& s : spines) r = std::max(r, s.root_mm.norm() + s.lengthMm());
  return r;
}

}  // namespace bristle

#pragma once
// The paint and paper options a single-stroke render takes (docs/paint.md):
// shared by `bristle render --brush`, `record --png` and `replay`, so that a
// replay given the same options paints what the live run painted.

#include <string>

#include "engine/paint_spec.h"

namespace bristle::cli {

struct PaintOptions {
  // Comma-separated pigment names or #rrggbb colours.
  std::string paint = "#1c2433";  // a blue-black ink
  std::string load = "solid";     // solid | across | tip
  double amount = 1.0;            // fraction of the brush's paint capacity
  double tip_length = 0.3;        // --load tip: share of the hair length
  std::string mix = "km";         // km | rgb
  double paper_tooth_mm = 0.03;
  double paper_scale_mm = 0.4;
  unsigned long long paper_seed = 1;
  bool impasto = false;
  int bits = 8;
  std::string background = kDefaultPaperColour;  // paper
};

}  // namespace bristle::cli

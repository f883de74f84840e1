#pragma once
// The paint and paper options a single-stroke render takes (docs/paint.md):
// shared by `bristle render --brush`, `record --png` and `replay`, so that a
// replay given the same options paints what the live run painted.

#include <string>
#include <vector>

#include "engine/solvers/solver_pair.h"

#include "engine/paint/paint_spec.h"

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

// The options of a session's render (`record --png`, `replay`): every one that
// changes its pixels. record writes them into the session's header, so that
// replay without options paints what record --png painted (cli/session_render.h).
struct SessionRender : PaintOptions {
  double px_per_mm = 8;
  SolverKind solver = SolverKind::kIpopt;  // primary; the other one is the fallback
  int solver_max_iterations = kDefaultSolverMaxIterations;
  std::vector<std::string> ipopt_options;  // NAME=VALUE
};

}  // namespace bristle::cli

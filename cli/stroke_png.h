#pragma once
// The one way a single stroke becomes a PNG: `bristle render --brush
// --trajectory`, `bristle record --png` and `bristle replay` all come through
// here, so a replayed session renders exactly what the live run rendered.

#include <string>
#include <vector>

#include "engine/brush.h"
#include "engine/trajectory.h"
#include "render/stroke_renderer.h"

namespace bristle::cli {

struct StrokePngOptions {
  std::string solver = "ipopt";  // primary; the other one is the fallback
  int solver_max_iterations = 200;
  std::vector<std::string> ipopt_options;  // NAME=VALUE
  double px_per_mm = 8;
  double clip_mm = 0.1;
  double max_step_mm = 0.25;
  double min_rate_hz = 120;
  // Paint and paper (docs/paint.md), as `bristle render`'s options.
  std::string paint = "#1c2433";
  std::string load = "solid";  // solid | across | tip
  double amount = 1.0;
  double tip_length = 0.3;
  std::string mix = "km";  // km | rgb
  double paper_tooth_mm = 0.03;
  double paper_scale_mm = 0.4;
  unsigned long long paper_seed = 1;
  bool impasto = false;
  int bits = 8;
  std::string background = "#f6f1e6";
  std::vector<std::string> inputs;  // files named in the PNG's provenance text
};

struct StrokePngResult {
  render::StrokeResult stroke;
  double left_on_brush_mm3 = 0, loaded_mm3 = 0;
};

// Checks the options (kUsage / kDataError naming the option) before anything long runs.
void checkStrokePngOptions(const StrokePngOptions& options);

render::StrokeOptions strokeOptions(const StrokePngOptions& options);

// Simulates the brush along the trajectory, paints and writes the PNG at
// output (atomically). on_step sees every simulation step.
StrokePngResult renderStrokePng(const Brush& brush, const Trajectory& trajectory,
                                const StrokePngOptions& options, const std::string& output,
                                const render::StepCallback& on_step = {});

}  // namespace bristle::cli

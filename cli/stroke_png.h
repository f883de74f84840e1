#pragma once
// The one way a single stroke becomes a PNG: `bristle render --brush
// --trajectory`, `bristle record --png` and `bristle replay` all come through
// here, so a replayed session renders exactly what the live run rendered. The
// command line's part: options to a StrokeSetup, and the PNG with its provenance;
// the stroke itself is render::paintStroke (render/stroke_pipeline.h).

#include <functional>
#include <string>
#include <vector>

#include "cli/paint_options.h"
#include "engine/model/brush.h"
#include "engine/solvers/solver_pair.h"
#include "engine/model/trajectory.h"
#include "render/image/png_io.h"
#include "render/stroke_renderer.h"

namespace bristle::cli {

struct StrokePngOptions : PaintOptions {  // paint and paper, as `bristle render`'s
  SolverKind solver = SolverKind::kIpopt;  // primary; the other one is the fallback
  int solver_max_iterations = kDefaultSolverMaxIterations;
  std::vector<std::string> ipopt_options;  // NAME=VALUE
  double px_per_mm = 8;
  double contact_band_mm = 0.1;
  double max_step_mm = 0.25;
  double steady_step_mm = SimOptions{}.steady_step_mm;
  double min_rate_hz = 120;
  int threads = 0;  // render::StrokeOptions::threads
  std::vector<std::string> inputs;  // files named in the PNG's provenance text
};

struct StrokePngResult {
  render::StrokeResult stroke;
  double left_on_brush_mm3 = 0, loaded_mm3 = 0;
  long ink_pixels = 0, pixels = 0;  // visible paint, of the image (render/image/compose.h)
};

// Checks the options (kUsage / kDataError naming the option) before anything long runs.
void checkStrokePngOptions(const StrokePngOptions& options);

render::StrokeOptions strokeOptions(const StrokePngOptions& options);

// More PNG text, from what the stroke painted (e.g. its warnings), made just
// before the PNG is written.
using MorePngText = std::function<render::PngText(const StrokePngResult&)>;

// Simulates the brush along the trajectory, paints and writes the PNG at
// output (atomically). on_step sees every simulation step.
StrokePngResult renderStrokePng(const Brush& brush, const Trajectory& trajectory,
                                const StrokePngOptions& options, const std::string& output,
                                const StepCallback& on_step = {},
                                const MorePngText& more_text = {});

}  // namespace bristle::cli

#include "cli/stroke_png.h"

#include "api/stroke_setup.h"

#include <memory>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "engine/model/canvas.h"
#include "engine/base/error.h"
#include "engine/paint/paint.h"
#include "render/image/compose.h"
#include "render/image/png_io.h"
#include "render/stroke_pipeline.h"

namespace bristle::cli {

namespace {

// The command line's options as the public API's (include/bristle/render.h):
// one conversion to a StrokeSetup for both (api/stroke_setup.h), so that
// bristle::api::renderStroke paints what `bristle render` paints.
api::RenderOptions renderOptionsOf(const StrokePngOptions& o) {
  api::RenderOptions r;
  r.paint = o.paint;
  r.load = o.load == "across" ? api::PaintLoad::kAcross
           : o.load == "tip"  ? api::PaintLoad::kTip
                              : api::PaintLoad::kSolid;
  r.amount = o.amount;
  r.tip_length = o.tip_length;
  r.mix = o.mix == "rgb" ? api::PaintMix::kLinearRgb : api::PaintMix::kKubelkaMunk;
  r.paper_colour = o.background;
  r.paper_tooth_mm = o.paper_tooth_mm;
  r.paper_scale_mm = o.paper_scale_mm;
  r.paper_seed = o.paper_seed;
  r.impasto = o.impasto;
  r.px_per_mm = o.px_per_mm;
  r.solver = o.solver == SolverKind::kSlsqp ? api::Solver::kSlsqp : api::Solver::kIpopt;
  r.solver_max_iterations = o.solver_max_iterations;
  r.max_step_mm = o.max_step_mm;
  r.steady_step_mm = o.steady_step_mm;
  r.min_rate_hz = o.min_rate_hz;
  r.contact_band_mm = o.contact_band_mm;
  return r;
}

render::StrokeSetup strokeSetup(const StrokePngOptions& o) {
  render::StrokeSetup setup =
      api::strokeSetupOf(renderOptionsOf(o), o.ipopt_options, api::cliOptionNames());
  setup.stroke.threads = o.threads;  // how, not what: the same pixels on any count
  return setup;
}

}  // namespace

void checkStrokePngOptions(const StrokePngOptions& o) { strokeSetup(o); }

render::StrokeOptions strokeOptions(const StrokePngOptions& o) {
  render::StrokeOptions options = api::strokeOptionsOf(renderOptionsOf(o));
  options.threads = o.threads;
  return options;
}

StrokePngResult renderStrokePng(const Brush& brush, const Trajectory& trajectory,
                                const StrokePngOptions& o, const std::string& output,
                                const StepCallback& on_step,
                                const MorePngText& more_text) {
  const render::StrokeSetup setup = strokeSetup(o);
  const api::StrokePixels pixels =
      api::paintStrokePixels(brush, trajectory, setup, o.impasto, on_step);
  const PaintCanvas& canvas = pixels.painted.canvas;
  const CanvasGrid& grid = canvas.grid();
  StrokePngResult r;
  r.stroke = pixels.painted.stroke;
  r.left_on_brush_mm3 = pixels.painted.left_on_brush_mm3;
  r.loaded_mm3 = pixels.painted.loaded_mm3;

  render::ComposeOptions compose;
  compose.impasto = o.impasto;
  render::PngText text = render::provenanceText(inputsHash(o.inputs));
  text.push_back({"bristle:brush", brush.name});
  text.push_back({"bristle:canvas", canvasText(grid)});
  text.push_back({"bristle:paint", o.paint + " load=" + o.load + " mix=" + o.mix});
  const render::Image8& image8 = pixels.image;
  r.ink_pixels = pixels.ink_pixels;
  r.pixels = long(image8.width) * image8.height;
  if (more_text)
    for (auto& entry : more_text(r)) text.push_back(std::move(entry));
  render::writeCanvasPng(output, canvas, image8, compose, o.bits, text);
  return r;
}

}  // namespace bristle::cli

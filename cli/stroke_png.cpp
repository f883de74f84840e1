#include "cli/stroke_png.h"

#include <memory>
#include <optional>
#include <string>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "engine/model/canvas.h"
#include "engine/base/error.h"
#include "engine/solvers/ipopt/ipopt_options.h"
#include "engine/paint/paint.h"
#include "render/compose.h"
#include "render/png_io.h"
#include "render/stroke_pipeline.h"

namespace bristle::cli {

namespace {

MixModel mixOf(const StrokePngOptions& o) {
  return o.mix == "rgb" ? MixModel::kLinearRgb : MixModel::kKubelkaMunk;
}

// Paint options are input data: a paint, colour or amount that makes no sense
// is a data error (65), named by its option, by the rules a scene's paint meets
// (checkPaintLoad, engine/paint/paint_spec.h).
PaintLoad paintLoadArgs(const StrokePngOptions& args) {
  PaintLoad load;
  load.mode = args.load == "across" ? PaintLoad::Mode::kAcross
              : args.load == "tip"  ? PaintLoad::Mode::kTip
                                    : PaintLoad::Mode::kSolid;
  size_t start = 0;
  while (true) {
    const size_t comma = args.paint.find(',', start);
    load.paints.push_back(args.paint.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  load.amount = args.amount;
  load.tip_length = args.tip_length;
  if (const std::optional<PaintLoadProblem> e = checkPaintLoad(load, "--load " + args.load)) {
    std::string option = "--paint " + args.paint;
    if (e->field == "amount") option = "--amount " + std::to_string(args.amount);
    if (e->field == "tip_length") option = "--tip-length " + std::to_string(args.tip_length);
    throw Error(ExitCode::kDataError, option + ": " + e->rule);
  }
  return load;
}

PaperSpec paperArgs(const StrokePngOptions& args) {
  PaperSpec paper;
  Rgb c;
  if (!parseHexColour(args.background, &c))
    throw Error(ExitCode::kDataError,
                "--background " + args.background + ": must be a colour like " + kDefaultPaperColour);
  if (!(args.paper_tooth_mm >= 0 && args.paper_tooth_mm <= 1))
    throw Error(ExitCode::kDataError, "--paper-tooth: must be in [0, 1] mm");
  if (!(args.paper_scale_mm > 0 && args.paper_scale_mm <= 100))
    throw Error(ExitCode::kDataError, "--paper-scale: must be in (0, 100] mm");
  paper.colour = args.background;
  paper.tooth_depth_mm = args.paper_tooth_mm;
  paper.tooth_scale_mm = args.paper_scale_mm;
  paper.seed = args.paper_seed;
  return paper;
}

// The chosen solver is the primary; a spine it fails on is tried with the other.
// --solver-max-iterations limits both: Ipopt's iterations, SLSQP's energy evaluations.
SolverSettings solverSettings(const StrokePngOptions& o) {
  SolverSettings solvers;
  solvers.kind = o.solver;
  solvers.max_iterations = o.solver_max_iterations;
  // Each one checked here, before any input is read (engine/solvers/ipopt/ipopt_options.h).
  for (const std::string& kv : o.ipopt_options) {
    if (const std::optional<std::string> problem = ipoptOptionTextProblem(kv))
      throw Error(ExitCode::kUsage, "--ipopt-option " + *problem);
    solvers.ipopt_options.push_back(*splitIpoptOption(kv));
  }
  return solvers;
}

}  // namespace

void checkStrokePngOptions(const StrokePngOptions& o) {
  paintLoadArgs(o);
  paperArgs(o);
  solverSettings(o);
}

render::StrokeOptions strokeOptions(const StrokePngOptions& o) {
  render::StrokeOptions options;
  options.px_per_mm = o.px_per_mm;
  options.contact_band_mm = o.contact_band_mm;
  options.sim.max_step_mm = o.max_step_mm;
  options.sim.steady_step_mm = o.steady_step_mm;
  options.sim.min_rate_hz = o.min_rate_hz;
  options.threads = o.threads;
  return options;
}

StrokePngResult renderStrokePng(const Brush& brush, const Trajectory& trajectory,
                                const StrokePngOptions& o, const std::string& output,
                                const StepCallback& on_step,
                                const MorePngText& more_text) {
  render::StrokeSetup setup;
  setup.load = paintLoadArgs(o);
  setup.load_where = "--paint";
  setup.mix = mixOf(o);
  setup.paper = paperArgs(o);
  setup.solvers = solverSettings(o);
  setup.stroke = strokeOptions(o);
  render::StrokeRenderer renderer;
  const render::PaintedStroke painted =
      render::paintStroke(renderer, brush, trajectory, setup, on_step);
  const PaintCanvas& canvas = painted.canvas;
  const CanvasGrid& grid = canvas.grid();
  StrokePngResult r;
  r.stroke = painted.stroke;
  r.left_on_brush_mm3 = painted.left_on_brush_mm3;
  r.loaded_mm3 = painted.loaded_mm3;

  render::ComposeOptions compose;
  compose.impasto = o.impasto;
  render::PngText text = render::provenanceText(inputsHash(o.inputs));
  text.push_back({"bristle:brush", brush.name});
  text.push_back({"bristle:canvas", canvasText(grid)});
  text.push_back({"bristle:paint", o.paint + " load=" + o.load + " mix=" + o.mix});
  const render::Image8 image8 = render::composeRgb8(canvas, compose);
  r.ink_pixels = render::inkPixels(
      image8, render::paperColour8(setup.paper, setup.mix, grid.px_per_mm, compose));
  r.pixels = long(image8.width) * image8.height;
  if (more_text)
    for (auto& entry : more_text(r)) text.push_back(std::move(entry));
  if (o.bits == 16)
    render::writePng(output, render::composeRgb16(canvas, compose), text);
  else
    render::writePng(output, image8, text);
  return r;
}

}  // namespace bristle::cli

#include "api/stroke_setup.h"

#include <optional>
#include <string>

#include "engine/base/error.h"
#include "engine/paint/paint.h"
#include "engine/paint/paint_spec.h"
#include "engine/solvers/ipopt/ipopt_options.h"
#include "render/image/compose.h"

namespace bristle::api {

namespace {

// Paint options are input data: a paint, colour or amount that makes no sense
// is a data error (65), named by its option, by the rules a scene's paint meets
// (checkPaintLoad, engine/paint/paint_spec.h).
bristle::PaintLoad paintLoadOf(const RenderOptions& o, const OptionNames& names) {
  bristle::PaintLoad load;
  load.mode = o.load == PaintLoad::kAcross ? bristle::PaintLoad::Mode::kAcross
              : o.load == PaintLoad::kTip  ? bristle::PaintLoad::Mode::kTip
                                           : bristle::PaintLoad::Mode::kSolid;
  size_t start = 0;
  while (true) {
    const size_t comma = o.paint.find(',', start);
    load.paints.push_back(o.paint.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  load.amount = o.amount;
  load.tip_length = o.tip_length;
  const std::string where = names.load + " " + loadName(o.load);
  if (const std::optional<PaintLoadProblem> e = checkPaintLoad(load, where)) {
    std::string option = names.paint + " " + o.paint;
    if (e->field == "amount") option = names.amount + " " + std::to_string(o.amount);
    if (e->field == "tip_length") option = names.tip_length + " " + std::to_string(o.tip_length);
    throw bristle::Error(ExitCode::kDataError, option + ": " + e->rule);
  }
  return load;
}

PaperSpec paperOf(const RenderOptions& o, const OptionNames& names) {
  PaperSpec paper;
  Rgb c;
  if (!parseHexColour(o.paper_colour, &c))
    throw bristle::Error(ExitCode::kDataError, names.paper_colour + " " + o.paper_colour +
                                                   ": must be a colour like " +
                                                   kDefaultPaperColour);
  if (!(o.paper_tooth_mm >= 0 && o.paper_tooth_mm <= 1))
    throw bristle::Error(ExitCode::kDataError, names.paper_tooth + ": must be in [0, 1] mm");
  if (!(o.paper_scale_mm > 0 && o.paper_scale_mm <= 100))
    throw bristle::Error(ExitCode::kDataError, names.paper_scale + ": must be in (0, 100] mm");
  paper.colour = o.paper_colour;
  paper.tooth_depth_mm = o.paper_tooth_mm;
  paper.tooth_scale_mm = o.paper_scale_mm;
  paper.seed = o.paper_seed;
  return paper;
}

// The chosen solver is the primary; a spine it fails on is tried with the other.
// solver_max_iterations limits both: Ipopt's iterations, SLSQP's energy evaluations.
SolverSettings solverSettingsOf(const RenderOptions& o, const std::vector<std::string>& ipopt,
                                const OptionNames& names) {
  SolverSettings solvers;
  solvers.kind = o.solver == Solver::kSlsqp ? SolverKind::kSlsqp : SolverKind::kIpopt;
  solvers.max_iterations = o.solver_max_iterations;
  // Each one checked here, before any input is read (engine/solvers/ipopt/ipopt_options.h).
  for (const std::string& kv : ipopt) {
    if (const std::optional<std::string> problem = ipoptOptionTextProblem(kv))
      throw bristle::Error(ExitCode::kUsage, names.ipopt_option + " " + *problem);
    solvers.ipopt_options.push_back(*splitIpoptOption(kv));
  }
  return solvers;
}

}  // namespace

const OptionNames& cliOptionNames() {
  static const OptionNames names{"--paint",        "--load",        "--amount",
                                 "--tip-length",   "--background",  "--paper-tooth",
                                 "--paper-scale",  "--ipopt-option"};
  return names;
}

const OptionNames& apiOptionNames() {
  static const OptionNames names{
      "RenderOptions.paint",          "RenderOptions.load",
      "RenderOptions.amount",         "RenderOptions.tip_length",
      "RenderOptions.paper_colour",   "RenderOptions.paper_tooth_mm",
      "RenderOptions.paper_scale_mm", "RenderOptions.ipopt_option"};
  return names;
}

const char* loadName(PaintLoad load) {
  switch (load) {
    case PaintLoad::kAcross: return "across";
    case PaintLoad::kTip: return "tip";
    case PaintLoad::kSolid: break;
  }
  return "solid";
}

const char* mixName(PaintMix mix) { return mix == PaintMix::kLinearRgb ? "rgb" : "km"; }

render::StrokeOptions strokeOptionsOf(const RenderOptions& o) {
  render::StrokeOptions stroke;
  stroke.px_per_mm = o.px_per_mm;
  stroke.contact_band_mm = o.contact_band_mm;
  stroke.sim.max_step_mm = o.max_step_mm;
  stroke.sim.steady_step_mm = o.steady_step_mm;
  stroke.sim.min_rate_hz = o.min_rate_hz;
  stroke.threads = o.threads;
  return stroke;
}

render::StrokeSetup strokeSetupOf(const RenderOptions& o,
                                  const std::vector<std::string>& ipopt_options,
                                  const OptionNames& names) {
  render::StrokeSetup setup;
  setup.load = paintLoadOf(o, names);
  setup.load_where = names.paint;
  setup.mix = o.mix == PaintMix::kLinearRgb ? MixModel::kLinearRgb : MixModel::kKubelkaMunk;
  setup.paper = paperOf(o, names);
  setup.solvers = solverSettingsOf(o, ipopt_options, names);
  setup.stroke = strokeOptionsOf(o);
  return setup;
}

StrokePixels paintStrokePixels(const bristle::Brush& brush, const bristle::Trajectory& trajectory,
                               const render::StrokeSetup& setup, bool impasto,
                               const StepCallback& on_step) {
  render::StrokeRenderer renderer;
  return paintStrokePixels(renderer, brush, trajectory, setup, impasto, on_step);
}

StrokePixels paintStrokePixels(render::StrokeRenderer& renderer, const bristle::Brush& brush,
                               const bristle::Trajectory& trajectory,
                               const render::StrokeSetup& setup, bool impasto,
                               const StepCallback& on_step) {
  render::PaintedStroke painted = render::paintStroke(renderer, brush, trajectory, setup, on_step);
  render::ComposeOptions compose;
  compose.impasto = impasto;
  render::Image8 image = render::composeRgb8(painted.canvas, compose);
  const std::array<std::uint8_t, 3> paper =
      render::paperColour8(setup.paper, setup.mix, painted.canvas.grid().px_per_mm, compose);
  const long ink = render::inkPixels(image, paper);
  return StrokePixels{std::move(painted), std::move(image), paper, ink};
}

}  // namespace bristle::api

#include "cli/stroke_png.h"

#include <cstdio>
#include <memory>

#include "bristle/version.h"
#include "engine/canvas.h"
#include "engine/error.h"
#include "render/png_io.h"

namespace bristle::cli {

namespace {

Rgb colourArg(const std::string& option, const std::string& text) {
  Rgb c;
  if (!parseHexColour(text, &c))
    throw Error(ExitCode::kUsage, option + " = '" + text + "': must be a colour like #1c2433");
  return c;
}

// World placement of the image, so that pixels can be mapped back to canvas mm.
std::string canvasText(const CanvasGrid& g) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x0_mm=%.6f y0_mm=%.6f px_per_mm=%.6f width_px=%d height_px=%d",
                g.x0_mm, g.y0_mm, g.px_per_mm, g.width_px, g.height_px);
  return buf;
}

IpoptSettings ipoptSettings(const StrokePngOptions& o) {
  IpoptSettings ipopt;
  ipopt.max_iterations = o.solver_max_iterations;
  for (const std::string& kv : o.ipopt_options) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(ExitCode::kUsage, "--ipopt-option " + kv + ": expected NAME=VALUE");
    ipopt.extra_options.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  return ipopt;
}

}  // namespace

void checkStrokePngOptions(const StrokePngOptions& o) {
  colourArg("--colour", o.colour);
  colourArg("--background", o.background);
  if (o.solver != "ipopt" && o.solver != "slsqp")
    throw Error(ExitCode::kUsage, "--solver " + o.solver + ": available: ipopt, slsqp");
  ipoptSettings(o);
}

render::StrokeOptions strokeOptions(const StrokePngOptions& o) {
  render::StrokeOptions options;
  options.px_per_mm = o.px_per_mm;
  options.clip_mm = o.clip_mm;
  options.sim.max_step_mm = o.max_step_mm;
  options.sim.min_rate_hz = o.min_rate_hz;
  return options;
}

render::StrokeResult renderStrokePng(const Brush& brush, const Trajectory& trajectory,
                                     const StrokePngOptions& o, const std::string& output,
                                     const render::StepCallback& on_step) {
  const Rgb paint = colourArg("--colour", o.colour);
  const Rgb background = colourArg("--background", o.background);
  const render::StrokeOptions options = strokeOptions(o);
  const CanvasGrid grid = render::canvasForStroke(brush, trajectory, options);
  Canvas canvas(grid);
  render::StrokeRenderer renderer;
  // The chosen solver is the primary; a spine it fails on is tried with the other.
  std::unique_ptr<SpineSolver> primary = makeIpoptSolver(ipoptSettings(o)),
                               fallback = makeSlsqpSolver();
  if (o.solver == "slsqp") std::swap(primary, fallback);
  const render::StrokeResult result = renderer.render(
      brush, trajectory, std::move(primary), options, &canvas, on_step, std::move(fallback));

  render::Image8 image;
  image.width = grid.width_px;
  image.height = grid.height_px;
  image.channels = 3;
  image.pixels = canvas.composeRgb8(paint, background);
  render::writePng(output, image,
                   {{"Software", std::string("bristle ") + kVersion},
                    {"bristle:brush", brush.name},
                    {"bristle:canvas", canvasText(grid)}});
  return result;
}

}  // namespace bristle::cli

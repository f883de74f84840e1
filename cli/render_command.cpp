// `bristle render --brush B.json --trajectory T.csv -o out.png`

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "bristle/version.h"
#include "cli/commands.h"
#include "engine/atomic_output.h"
#include "engine/brush.h"
#include "engine/canvas.h"
#include "engine/paint.h"
#include "engine/pigments.h"
#include "engine/error.h"
#include "engine/trace.h"
#include "engine/trajectory.h"
#include "render/compose.h"
#include "render/png_io.h"
#include "render/stroke_renderer.h"

namespace bristle::cli {
namespace {

// Progress on stderr, only when it is a terminal, at most every 0.2 s.
class Progress {
 public:
  explicit Progress(bool enabled) : enabled_(enabled && ::isatty(2)) {}
  void update(int step, int steps) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (step + 1 < steps && now - last_ < std::chrono::milliseconds(200)) return;
    last_ = now;
    std::fprintf(stderr, "\rbristle: step %d/%d (%3.0f%%)", step + 1, steps,
                 100.0 * (step + 1) / steps);
    if (step + 1 == steps) std::fprintf(stderr, "\n");
  }

 private:
  bool enabled_;
  std::chrono::steady_clock::time_point last_{};
};

// Paint options are input data: a paint, colour or amount that makes no sense
// is a data error (65), named by its option.
PaintLoad paintLoadArgs(const RenderArgs& args, MixModel model) {
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
  for (const std::string& p : load.paints) {
    Optics optics;
    std::string why;
    if (!resolvePaint(p, model, &optics, &why))
      throw Error(ExitCode::kDataError, "--paint " + args.paint + ": " + why);
  }
  const size_t lo = load.mode == PaintLoad::Mode::kAcross ? 2 : 1;
  const size_t hi = load.mode == PaintLoad::Mode::kSolid ? 1 : load.mode == PaintLoad::Mode::kTip ? 2 : 3;
  if (load.paints.size() < lo || load.paints.size() > hi)
    throw Error(ExitCode::kDataError,
                "--paint " + args.paint + ": --load " + args.load + " takes " +
                    std::to_string(lo) + (hi > lo ? " to " + std::to_string(hi) : "") +
                    " paints, got " + std::to_string(load.paints.size()));
  if (!(args.amount > 0 && args.amount <= 1))
    throw Error(ExitCode::kDataError, "--amount " + std::to_string(args.amount) +
                                          ": must be in (0, 1], a fraction of the brush's "
                                          "paint capacity");
  if (!(args.tip_length >= 0 && args.tip_length <= 1))
    throw Error(ExitCode::kDataError, "--tip-length: must be in [0, 1]");
  load.amount = args.amount;
  load.tip_length = args.tip_length;
  return load;
}

PaperSpec paperArgs(const RenderArgs& args) {
  PaperSpec paper;
  Rgb c;
  if (!parseHexColour(args.background, &c))
    throw Error(ExitCode::kDataError,
                "--background " + args.background + ": must be a colour like #f6f1e6");
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


}  // namespace

// World placement of the image, so that pixels can be mapped back to canvas mm.
std::string canvasText(const CanvasGrid& g) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "x0_mm=%.6f y0_mm=%.6f px_per_mm=%.6f width_px=%d height_px=%d",
                g.x0_mm, g.y0_mm, g.px_per_mm, g.width_px, g.height_px);
  return buf;
}

void printError(const std::string& message) { std::cerr << "bristle: " << message << "\n"; }

int runRender(const RenderArgs& args) {
  if (!args.scene.empty()) return runRenderScene(args);
  if (args.brush.empty() || args.trajectory.empty())
    throw Error(ExitCode::kUsage,
                "render: give a SCENE.json, or --brush and --trajectory (see bristle render --help)");
  const MixModel mix = args.mix == "rgb" ? MixModel::kLinearRgb : MixModel::kKubelkaMunk;
  const PaintLoad load = paintLoadArgs(args, mix);
  const PaperSpec paper = paperArgs(args);
  if (args.solver != "ipopt" && args.solver != "slsqp")
    throw Error(ExitCode::kUsage, "--solver " + args.solver + ": available: ipopt, slsqp");

  const Brush brush = loadBrush(args.brush);
  Trajectory trajectory = loadTrajectory(args.trajectory);
  if (args.offset_mm.size() == 3) {
    const Eigen::Vector3d offset(args.offset_mm[0], args.offset_mm[1], args.offset_mm[2]);
    if (!offset.allFinite()) throw Error(ExitCode::kUsage, "--offset-mm: must be finite");
    for (TrajectorySample& s : trajectory.samples) s.pose.position_mm += offset;
  }
  validateTrajectoryForBrush(trajectory, brush);

  render::StrokeOptions options;
  options.px_per_mm = args.px_per_mm;
  options.clip_mm = args.clip_mm;
  options.sim.max_step_mm = args.max_step_mm;
  options.sim.min_rate_hz = args.min_rate_hz;
  const CanvasGrid grid = render::canvasForStroke(brush, trajectory, options);

  // Fail before the long run if an output cannot be created; each output is
  // written to a temporary file and renamed only when everything succeeded.
  checkCanCreate(args.output);
  std::unique_ptr<AtomicOutput> trace, forces;
  if (!args.trace.empty()) trace = std::make_unique<AtomicOutput>(args.trace);
  if (!args.forces.empty()) {
    forces = std::make_unique<AtomicOutput>(args.forces);
    forces->stream() << "t_s,fx_n,fy_n,fz_n\n";
    forces->stream().precision(9);
  }

  IpoptSettings ipopt;
  ipopt.max_iterations = args.solver_max_iterations;
  for (const std::string& kv : args.ipopt_options) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0)
      throw Error(ExitCode::kUsage, "--ipopt-option " + kv + ": expected NAME=VALUE");
    ipopt.extra_options.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
  }
  PaintCanvas canvas(grid, paper, mix);
  BrushPaint paint(brush);
  paint.load(load, mix, "--paint");
  render::StrokeRenderer renderer;
  Progress progress(!args.quiet);
  int failed_reported = 0;
  constexpr int kMaxFailureLines = 5;  // then only the summary
  auto on_step = [&](const BrushState& st, int step, int steps) {
    if (trace) trace->stream() << traceLine(st) << '\n';
    if (forces)
      forces->stream() << st.t_s << ',' << st.force_n.x() << ',' << st.force_n.y() << ','
                       << st.force_n.z() << '\n';
    for (size_t s = 0; s < st.spines.size(); ++s)
      if (!st.spines[s].summary.usable() && failed_reported++ < kMaxFailureLines)
        printError("warning: step " + std::to_string(st.step) + " (t = " +
                   std::to_string(st.t_s) + " s): spine " + std::to_string(s) +
                   " solve failed (" + st.spines[s].summary.message +
                   "); continuing from its last good state");
    progress.update(step, steps);
  };
  // The chosen solver is the primary; a spine it fails on is tried with the other.
  std::unique_ptr<SpineSolver> primary = makeIpoptSolver(ipopt), fallback = makeSlsqpSolver();
  if (args.solver == "slsqp") std::swap(primary, fallback);
  const render::StrokeResult result = renderer.render(
      brush, trajectory, std::move(primary), options, &canvas, &paint, on_step,
      std::move(fallback));

  render::ComposeOptions compose;
  compose.impasto = args.impasto;
  render::PngText text = render::provenanceText({args.brush, args.trajectory});
  text.push_back({"bristle:brush", brush.name});
  text.push_back({"bristle:canvas", canvasText(grid)});
  text.push_back({"bristle:paint", args.paint + " load=" + args.load + " mix=" + args.mix});
  if (args.bits == 16)
    render::writePng(args.output, render::composeRgb16(canvas, compose), text);
  else
    render::writePng(args.output, render::composeRgb8(canvas, compose), text);
  if (trace) trace->commit();
  if (forces) forces->commit();

  if (!result.touched)
    printError("warning: the brush never touched the canvas (" + args.trajectory +
               "): the image is blank");
  if (result.stats.failed_steps > 0)
    printError("warning: " + std::to_string(result.stats.failed_steps) + " of " +
               std::to_string(result.stats.steps) + " steps had a failed solve (" +
               std::to_string(result.stats.failed_spine_solves) +
               " spine solves); those spines continued from their last good state");
  if (!args.quiet) {
    const SimStats& st = result.stats;
    std::fprintf(stderr,
                 "bristle: %d steps (%d solved, %d stiction re-solves, %d rescued by the "
                 "fallback solver), %ld solver iterations\n",
                 st.steps, st.solved_steps, st.resolves, st.fallback_solves, st.iterations);
    std::fprintf(stderr,
                 "bristle: paint: %.3g mm^3 laid down, %.3g mm^3 picked up; %.3g of %.3g mm^3 "
                 "left on the brush\n",
                 result.deposited_mm3, result.picked_up_mm3, paint.totalVolumeMm3(),
                 paint.capacityMm3() * args.amount);
    std::cout << args.output << "\n";
  }
  return 0;
}

}  // namespace bristle::cli

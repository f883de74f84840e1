// `bristle preview B.json [--trajectory T.csv --at 1.2] -o brush.png`: the brush
// in 3D (surface, strips, spines, ferrule), at rest or deformed at a time of a
// trajectory, with its footprint as an inset. For people designing brushes.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "engine/atomic_output.h"
#include "engine/brush.h"
#include "engine/brush_geometry.h"
#include "engine/error.h"
#include "engine/first_contact.h"
#include "engine/simulation.h"
#include "engine/solver_pair.h"
#include "engine/trajectory.h"
#include "render/png_io.h"
#include "render/preview_renderer.h"
#include "render/stroke_renderer.h"

namespace bristle::cli {

int runPreview(const PreviewArgs& args) {
  const std::string brush_file = findBrushFile(args.brush, "");
  checkCliFiles({{"-o", args.output}}, {{"brush", brush_file}, {"--trajectory", args.trajectory}},
                {"-o"}, {"--trajectory"});
  const Brush brush = loadBrush(brush_file);
  BrushGeometry geometry(brush);
  // The simulation of `bristle render --brush --trajectory` with its defaults and
  // the same --px-per-mm, stepped as that render steps.
  render::StrokeOptions options;
  options.px_per_mm = args.px_per_mm;
  options.clip_mm = args.clip_mm;
  SolverPair solvers = makeSolverPair();
  Simulation sim(brush, options.sim, std::move(solvers.primary), std::move(solvers.fallback));
  double t_s = 0;
  if (args.trajectory.empty()) {
    // At rest, held vertically with the tips 2 mm above the paper.
    Pose rest;
    rest.position_mm = Eigen::Vector3d(0, 0, brush.reachMm() + 2);
    sim.reset(rest, 0);
  } else {
    Trajectory traj = resolveDepths(loadTrajectoryArg(args.trajectory), brush);
    if (args.offset_mm.size() == 3 &&
        !(std::fabs(args.offset_mm[0]) <= kMaxPositionMm &&
          std::fabs(args.offset_mm[1]) <= kMaxPositionMm &&
          std::fabs(args.offset_mm[2]) <= kMaxPositionMm))
      throw Error(ExitCode::kUsage, "--offset-mm: must be within +-100000 mm (the limit)");
    if (args.offset_mm.size() == 3)
      for (TrajectorySample& s : traj.samples)
        s.pose.position_mm += Eigen::Vector3d(args.offset_mm[0], args.offset_mm[1],
                                              args.offset_mm[2]);
    validateTrajectoryForBrush(traj, brush);
    if (args.at_s < traj.startTime() || args.at_s > traj.endTime())
      throw Error(ExitCode::kUsage, "--at " + std::to_string(args.at_s) +
                                        ": outside the trajectory's time span [" +
                                        std::to_string(traj.startTime()) + ", " +
                                        std::to_string(traj.endTime()) + "] s");
    // The render's last step at or before --at: a state the render painted.
    render::stepAlongTrajectory(sim, traj, options, options.px_per_mm, {}, args.at_s);
    t_s = sim.state().t_s;
  }
  const BrushState& st = sim.state();

  render::PreviewScene scene;
  geometry.buildSurface(st, &scene.surface);
  geometry.buildStrips(st, &scene.strips);
  for (const SpineState& s : st.spines) scene.spines.push_back(s.joints_mm);
  scene.handle = st.handle;

  // Footprint on a canvas window around the handle.
  const double half_mm = brush.reachMm() + 2;
  CanvasGrid grid;
  grid.px_per_mm = args.px_per_mm;
  grid.x0_mm = st.handle.position_mm.x() - half_mm;
  grid.y0_mm = st.handle.position_mm.y() - half_mm;
  grid.width_px = grid.height_px = static_cast<int>(std::ceil(2 * half_mm * grid.px_per_mm));
  render::StrokeRenderer footprints;
  render::FootprintImage fp;
  if (footprints.footprint(geometry, st, grid, args.clip_mm, &fp)) scene.footprint = &fp;

  char title[256];
  std::snprintf(title, sizeof title, "%s: %zu spines%s%s, %s", brush.name.c_str(),
                brush.spines.size(), brush.surface.present() ? ", surface" : "",
                brush.strips.present()
                    ? (", " + std::to_string(brush.strips.count) + " strips").c_str()
                    : "",
                args.trajectory.empty() ? "at rest" : ("t = " + std::to_string(t_s).substr(0, 5) + " s").c_str());
  scene.title = title;
  render::PreviewOptions opt;
  opt.width_px = args.width_px;
  opt.height_px = args.height_px;
  const render::Image8 image = render::renderPreview(scene, opt);
  render::writePng(args.output, image, {{"Software", "bristle preview"}, {"bristle:brush", brush.name}});
  if (!args.quiet && !isStdio(args.output)) std::cout << args.output << "\n";
  return 0;
}

}  // namespace bristle::cli

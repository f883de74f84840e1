// `bristle preview B.json [--trajectory T.csv --at 1.2] -o brush.png`: the brush
// in 3D (surface, strips, spines, ferrule), at rest or deformed at a time of a
// trajectory, with its footprint as an inset. For people designing brushes.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "batch/job_key.h"
#include "cli/commands.h"
#include "cli/options.h"
#include "cli/inputs.h"
#include "cli/run_stats.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/formats/input_warnings.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/model/trajectory.h"
#include "render/image/png_io.h"
#include "render/preview/preview_renderer.h"
#include "render/stroke_pipeline.h"
#include "render/stroke_renderer.h"

namespace bristle::cli {

int runPreview(const PreviewArgs& args) {
  checkPngOutputName("preview", "-o", args.output, true);
  const std::string brush_file = findBrushFile(args.brush, "");
  checkCliFiles({{"-o", args.output}}, {{"brush", brush_file}, {"--trajectory", args.trajectory}},
                {"-o"}, {"--trajectory"});
  const Brush brush = loadBrush(brush_file);
  BrushGeometry geometry(brush);
  std::vector<std::string> warnings;
  if (std::string w = brushScaleWarning(brush); !w.empty()) warnings.push_back(std::move(w));
  // The simulation of `bristle render --brush --trajectory` with its defaults and
  // the same --px-per-mm, stepped as that render steps.
  render::StrokeOptions options;
  options.px_per_mm = args.px_per_mm;
  options.contact_band_mm = args.contact_band_mm;
  BrushState st;
  if (args.trajectory.empty()) {
    st = render::strokeStateAt(brush, nullptr, options, 0);
  } else {
    Trajectory traj = resolveDepths(loadTrajectoryArg(args.trajectory, brush), brush);
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
    st = render::strokeStateAt(brush, &traj, options, args.at_s);
  }
  const double t_s = st.t_s;
  warnings = printWarnings(std::move(warnings));

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
  if (footprints.footprint(geometry, st, grid, args.contact_band_mm, &fp)) scene.footprint = &fp;

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
  render::PngText text = {{"Software", "bristle preview"}, {"bristle:brush", brush.name}};
  for (auto& entry : batchPngText(args.batch_key, warnings)) text.push_back(std::move(entry));
  render::writePng(args.output, image, text);
  if (!args.quiet && !isStdio(args.output)) std::cout << args.output << "\n";
  return 0;
}

Subcommand registerPreview(CLI::App& app) {
  auto pv = std::make_shared<PreviewArgs>();
  CLI::App* preview = app.add_subcommand(
      "preview", "Draw a brush in 3D, at rest or at a time of a trajectory");
  preview->footer(
      "Examples:\n"
      "  bristle preview fan -o fan.png\n"
      "  bristle preview round --trajectory scenes/trajectories/s-curve.csv \\\n"
      "      --at 1.2 -o round-1.2s.png\n"
      "The inset shows the footprint: what of the brush touches the paper.");
  preview->add_option("brush", pv->brush,
                      "Brush: a library name (round) or a file (bristle-brush/1 JSON)")
      ->required();
  addPngOutput(preview, pv->output);
  CLI::Option* trajectory = preview->add_option(
      "--trajectory", pv->trajectory, "Simulate along this trajectory (- reads stdin) ...");
  // Without a trajectory there is no time to go to and nothing to shift: refused
  // (exit 64), not silently ignored.
  preview->add_option("--at", pv->at_s,
                      "... up to this time (s): the last step at or before it of `bristle "
                      "render` (same --px-per-mm)")
      ->capture_default_str()
      ->needs(trajectory);
  preview->add_option("--offset-mm", pv->offset_mm, "Shift the trajectory by X Y Z mm")
      ->expected(3)
      ->needs(trajectory);
  preview->add_option("--width", pv->width_px, "Image width (px)")
      ->capture_default_str()
      ->check(CLI::Range(64, 4096));
  preview->add_option("--height", pv->height_px, "Image height (px)")
      ->capture_default_str()
      ->check(CLI::Range(64, 4096));
  addPxPerMm(preview, pv->px_per_mm,
             "Footprint resolution; as render's, it also sets how finely a step is split");
  preview->add_flag("-q,--quiet", pv->quiet, "No output path on stdout");
  addBatchKey(preview, pv->batch_key);
  return {preview, [pv] { return runPreview(*pv); }};
}

}  // namespace bristle::cli

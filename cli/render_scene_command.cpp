// `bristle render SCENE.json -o out.png`: a whole painting, stroke by stroke on
// one canvas (engine/formats/scene.h, render/scene_renderer.h).

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "bristle/version.h"
#include "batch/job_key.h"
#include "cli/commands.h"
#include "cli/inputs.h"
#include "cli/progress.h"
#include "cli/run_stats.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/formats/scene.h"
#include "engine/formats/trace.h"
#include "render/image/compose.h"
#include "render/image/png_io.h"
#include "render/scene_renderer.h"

namespace bristle::cli {
namespace {

// The options that make sense with a scene: the scene says everything else
// (--batch-key is the batch's own, cli/options.h).
constexpr const char* kSceneOptions[] = {"--output", "--trace",   "--stats", "--impasto",
                                         "--bits",   "--quiet",   "--help",
                                         "--solver-max-iterations", "--threads",
                                         "--batch-key"};

// Was a stroke (its pointer, "/strokes/3") already named in a warning?
bool warnedAbout(const std::vector<std::string>& warnings, const std::string& pointer) {
  const std::string tag = ": " + pointer + ":";
  for (const std::string& w : warnings)
    if (w.find(tag) != std::string::npos) return true;
  return false;
}

// The figures and warnings of a painting: those found before the run
// (already printed), then the ones it brought (printed as they are found).
RunStats sceneStats(const Scene& scene, const render::SceneResult& result,
                    const std::vector<std::string>& warnings, const render::Image8& image8,
                    const std::array<std::uint8_t, 3>& paper) {
  RunStats stats;
  stats.painted_pixels = render::inkPixels(image8, paper);
  stats.pixels = long(image8.width) * image8.height;
  stats.planned_steps = result.planned_steps;
  stats.sim = result.stats;
  stats.paint_laid_mm3 = result.deposited_mm3;
  stats.paint_picked_up_mm3 = result.picked_up_mm3;
  stats.warnings = warnings;  // printed before the run
  // Strokes out of reach were named before the run; the others are news.
  for (int i : result.untouched)
    if (!warnedAbout(warnings, scene.strokes[size_t(i)].pointer))
      stats.warn(scene.path + ": " + scene.strokes[size_t(i)].pointer +
                 ": the brush never touched the canvas (trajectory " +
                 scene.strokes[size_t(i)].trajectory_path + ")");
  if (stats.painted_pixels == 0) stats.warn(scene.path + ": the painting holds no visible paint");
  if (const std::string w = failedSolvesWarning(result.stats); !w.empty()) stats.warn(w);
  return stats;
}

}  // namespace

void checkSceneOptions(const RenderArgs& args) {
  for (const std::string& given : args.given) {
    bool ok = false;
    for (const char* allowed : kSceneOptions) ok = ok || given == allowed;
    if (!ok)
      throw Error(ExitCode::kUsage,
                  "render " + args.scene + ": " + given +
                      " cannot be used with a scene (the scene sets it); with a scene only -o, "
                      "--trace, --stats, --impasto, --bits, --solver-max-iterations, --threads and "
                      "--quiet are allowed");
  }
}

int runRenderScene(const RenderArgs& args) {
  checkSceneOptions(args);
  if (args.output.empty()) throw Error(ExitCode::kUsage, "render: -o/--output is required");
  checkCliFiles({{"-o", args.output}, {"--trace", args.trace}, {"--stats", args.stats}},
                {{"scene", args.scene}}, {"-o"}, {});
  const Scene scene = loadScene(args.scene);
  std::vector<NamedFile> inputs;
  for (const SceneStroke& st : scene.strokes) {
    inputs.push_back({args.scene + ": " + st.pointer + "/brush", st.brush_path});
    inputs.push_back({args.scene + ": " + st.pointer + "/trajectory", st.trajectory_path});
  }
  checkCliFiles({{"-o", args.output}, {"--trace", args.trace}, {"--stats", args.stats}}, inputs,
                {"-o"}, {});
  std::vector<std::string> warnings = sceneWarnings(scene);

  checkCanCreateArg(args.output);
  if (!args.stats.empty()) checkCanCreate(args.stats);
  warnings = printWarnings(std::move(warnings));
  CommitGroup outputs;  // -o, --trace and --stats appear together (engine/base/atomic_output.h)
  std::unique_ptr<AtomicOutput> trace;
  if (!args.trace.empty()) trace = std::make_unique<AtomicOutput>(args.trace);

  PaintCanvas canvas = render::makeSceneCanvas(scene);
  PartProgress progress(!args.quiet, "stroke");
  const int strokes = static_cast<int>(scene.strokes.size());
  auto on_step = [&](int stroke, const BrushState& st, long step, long steps) {
    // Each trace line says which stroke it belongs to.
    if (trace) trace->stream() << "{\"stroke\":" << stroke << ',' << traceLine(st).substr(1) << '\n';
    progress.update(stroke, strokes, step, steps);
  };
  render::SceneRenderOptions options;
  options.solver_max_iterations = args.solver_max_iterations;
  options.threads = args.threads;
  const render::SceneResult result = render::renderScene(scene, options, &canvas, on_step);

  render::ComposeOptions compose;
  compose.impasto = args.impasto;
  const render::Image8 image8 = render::composeRgb8(canvas, compose);
  const RunStats stats = sceneStats(scene, result, warnings, image8,
      render::paperColour8(canvas.paper(), canvas.model(), canvas.grid().px_per_mm, compose));
  // The hash covers the scene and every brush and trajectory it read.
  render::PngText text = render::provenanceText(scene.inputs);
  text.push_back({"bristle:scene", scene.name});
  text.push_back({"bristle:canvas", canvasText(canvas.grid())});
  for (auto& entry : batchPngText(args.batch_key, stats.warnings)) text.push_back(std::move(entry));
  render::writeCanvasPng(args.output, canvas, image8, compose, args.bits, text);
  if (trace) trace->commit();
  writeRunStats(args.stats, stats);
  outputs.commit();
  if (!args.quiet) {
    const SimStats& st = result.stats;
    std::fprintf(stderr,
                 "bristle: %d strokes, %ld planned steps; %d simulation steps (%d solved, %d at "
                 "rest, %d stiction re-solves, %d rescued by the fallback solver), %ld solver "
                 "iterations\n",
                 strokes, result.planned_steps, st.steps, st.solved_steps, st.settled_steps,
                 st.resolves, st.fallback_solves, st.iterations);
    std::fprintf(stderr, "bristle: paint: %.3g mm^3 laid down, %.3g mm^3 picked up\n",
                 result.deposited_mm3, result.picked_up_mm3);
    if (!isStdio(args.output)) std::cout << args.output << "\n";
  }
  return 0;
}

}  // namespace bristle::cli

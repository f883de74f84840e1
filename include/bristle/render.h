#pragma once
// bristle/render.h -- a stroke rendered to an image in memory: the brush
// simulated along the trajectory, its footprints painted onto paper (docs/paint.md),
// composed to 8-bit sRGB. The same pixels as
//   bristle render --brush B --trajectory T -o out.png
// with the same options (tests/api/test_api.cpp checks it byte for byte), given
// the command line's process-wide set-up (docs/api.md).
//
// The canvas is sized to everything the brush can reach along the trajectory,
// plus a 5 mm margin; Image says where it lies on the canvas (mm).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "bristle/brush.h"
#include "bristle/simulation.h"
#include "bristle/trajectory.h"

namespace bristle::api {

enum class PaintLoad { kSolid, kAcross, kTip };  // docs/paint.md, "Loading a brush"
enum class PaintMix { kKubelkaMunk, kLinearRgb };

// `bristle render`'s options of the same names, with its defaults. Each is
// checked (Error naming the field and its range) before anything is simulated.
struct RenderOptions {
  std::string paint = "#1c2433";     // pigment names or #rrggbb, comma-separated
  PaintLoad load = PaintLoad::kSolid;
  double amount = 1.0;               // (0, 1] of the brush's paint capacity
  double tip_length = 0.3;           // kTip: share of the hair length
  PaintMix mix = PaintMix::kKubelkaMunk;
  std::string paper_colour = "#f6f1e6";
  double paper_tooth_mm = 0.03;      // [0, 1]
  double paper_scale_mm = 0.4;       // (0, 100]
  unsigned long long paper_seed = 1;
  bool impasto = false;              // paint relief lit from the upper left
  double px_per_mm = 8;              // [0.5, 100]
  Solver solver = Solver::kIpopt;
  int solver_max_iterations = 200;   // [1, 100000]
  double max_step_mm = 0.25;         // [0.01, 5]
  double steady_step_mm = 0;         // [0, 5]; 0 solves every planned step
  double min_rate_hz = 120;          // [1, 10000]
  double contact_band_mm = 0.1;      // [0.001, 2]
  // Ipopt options as NAME=VALUE, `bristle render --ipopt-option`'s (`bristle
  // help ipopt-option` lists those allowed); each checked, an Error naming it.
  // Empty by default; the "thumbnail" preset's loosens Ipopt's tol.
  std::vector<std::string> ipopt_options;
  // `bristle render --threads`: 1 simulates and draws in turns, 2 simulates
  // the next steps on a second thread; 0 is 2 where the process may use 2+
  // CPUs. The same pixels on any count. [0, 2]
  int threads = 0;
};

// Named sets of RenderOptions (docs/python.md, "Presets"; `bristle render
// --preset`): "default" is RenderOptions{}; "thumbnail" takes coarser
// simulation steps (max_step_mm, min_rate_hz, steady_step_mm) and a looser
// Ipopt tolerance (ipopt_options) for small data-set images, within SSIM 0.95 of the default's at 2 px/mm
// (docs/PERFORMANCE.md, "A thumbnail preset"). Throws Error (kUsage) naming
// the known presets for another name.
RenderOptions presetOptions(const std::string& name);

// 8-bit sRGB, RGB (3 channels), row 0 at the top, rows packed.
struct Image {
  int width_px = 0, height_px = 0, channels = 3;
  std::vector<std::uint8_t> pixels;
  double px_per_mm = 0;
  double x0_mm = 0, y0_mm = 0;  // canvas position of the image's lower-left corner
};

struct RenderResult {
  Image image;
  bool touched = false;             // the brush reached the paper
  long ink_pixels = 0;              // pixels visibly unlike the bare paper
  double paint_laid_mm3 = 0;        // paint the stroke left on the paper
  int failed_spine_solves = 0;      // kept unchanged after failing (docs/dynamics.md)
};

// Throws Error: kUsage / kDataError naming the option or the trajectory's
// sample, kDataError for a canvas too large (16384 px a side).
RenderResult renderStroke(const Brush& brush, const Trajectory& trajectory,
                          const RenderOptions& options = {});

// Strokes rendered one after another on one OSMesa context, made at the first
// stroke: renderStroke makes a context for each call, and llvmpipe compiles
// its shaders anew for each (about a sixth of a small stroke's CPU time). The
// same pixels as renderStroke. Used from one thread at a time; a program that
// renders on several threads keeps one per thread.
class StrokeRenderer {
 public:
  StrokeRenderer();
  ~StrokeRenderer();
  StrokeRenderer(StrokeRenderer&&) noexcept;
  StrokeRenderer& operator=(StrokeRenderer&&) noexcept;
  StrokeRenderer(const StrokeRenderer&) = delete;
  StrokeRenderer& operator=(const StrokeRenderer&) = delete;

  // As renderStroke (the same checks and errors).
  RenderResult render(const Brush& brush, const Trajectory& trajectory,
                      const RenderOptions& options = {});

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

struct StrokeFacts {
  bool touched = false;
  double paint_laid_mm3 = 0;
  int failed_spine_solves = 0;
};

// A painting: a bristle-scene/1 file (docs/scene-format.md), its strokes
// painted in order on the scene's own canvas with the scene's paper, paints
// and solvers, as `bristle render SCENE -o out.png` paints it (the same
// pixels). A scene sets everything else, so only these are open.
struct SceneOptions {
  bool impasto = false;             // the paint's relief lit (render --impasto)
  int solver_max_iterations = 200;  // [1, 100000], per solve
  int threads = 0;                  // [0, 2], as RenderOptions::threads
};

struct SceneResult {
  Image image;                      // the whole canvas
  double paint_laid_mm3 = 0;        // laid down by all the strokes
  double paint_picked_up_mm3 = 0;   // wet paint the brushes took up again
  std::vector<int> untouched;       // strokes (from 0) whose brush never touched
  int failed_spine_solves = 0;
};

// Throws Error: kNoInput for a missing file, kDataError naming the file and
// field (the scene's, or a brush's or trajectory's it names), kUsage for an
// option out of its range.
SceneResult renderScene(const std::string& path, const SceneOptions& options = {});

// A canvas that accumulates strokes, as a painting's does: each stroke loads
// its brush afresh and paints onto the paint already there, wet into wet
// until dry() (docs/paint.md). One stroke on a canvas placed and sized as
// renderStroke's image paints renderStroke's pixels.
class Canvas {
 public:
  // The canvas's lower-left corner at (x0_mm, y0_mm) in canvas mm, width_px x
  // height_px at paper.px_per_mm, with paper's paper_colour, paper_tooth_mm,
  // paper_scale_mm, paper_seed and mix. Throws Error (kUsage) for a size
  // outside 1..16384 px a side or over 64 Mpx, or as renderStroke for a field.
  Canvas(double x0_mm, double y0_mm, int width_px, int height_px,
         const RenderOptions& paper = {});
  ~Canvas();
  Canvas(Canvas&&) noexcept;
  Canvas& operator=(Canvas&&) noexcept;
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;

  // One stroke with options' paint, solver and steps; the canvas keeps its
  // own paper, mix and px_per_mm (those fields of options are not read). A
  // stroke may reach past the canvas's edge: what lies outside is lost.
  StrokeFacts addStroke(const Brush& brush, const Trajectory& trajectory,
                        const RenderOptions& options = {});
  void dry();  // the wet paint becomes the dry layer under later strokes
  Image image(bool impasto = false) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bristle::api

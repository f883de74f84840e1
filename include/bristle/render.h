#pragma once
// bristle/render.h -- a stroke rendered to an image in memory: the brush
// simulated along the trajectory, its footprints painted onto paper (docs/paint.md),
// composed to 8-bit sRGB. The same pixels as
//   bristle render --brush B --trajectory T -o out.png
// with the same options (tests/test_api.cpp checks it byte for byte), given
// the command line's process-wide set-up (docs/api.md).
//
// The canvas is sized to everything the brush can reach along the trajectory,
// plus a 5 mm margin; Image says where it lies on the canvas (mm).

#include <cstdint>
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
};

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

}  // namespace bristle::api

#pragma once
// A single stroke's options to render::StrokeSetup, and the stroke to 8-bit
// pixels: the one path `bristle render --brush --trajectory`
// (cli/stroke_png.cpp) and the public bristle::api::renderStroke both take, so
// that they paint the same pixels (tests/api/test_api.cpp). Never installed.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bristle/render.h"
#include "engine/model/brush.h"
#include "engine/model/trajectory.h"
#include "render/image/png_io.h"
#include "render/stroke_pipeline.h"

namespace bristle::api {

// How the errors name each option: the command line's "--paint", the API's
// "RenderOptions.paint".
struct OptionNames {
  std::string paint, load, amount, tip_length, paper_colour, paper_tooth, paper_scale,
      ipopt_option;
};
const OptionNames& cliOptionNames();
const OptionNames& apiOptionNames();

const char* loadName(PaintLoad load);  // "solid", "across", "tip" (the CLI's --load)
const char* mixName(PaintMix mix);     // "km", "rgb"

// Resolution, contact band and simulation steps, as given (no check).
render::StrokeOptions strokeOptionsOf(const RenderOptions& options);

// Checks the paint, the paper and the Ipopt options (NAME=VALUE) as it goes:
// bristle::Error kDataError (kUsage for an Ipopt option) naming the option.
render::StrokeSetup strokeSetupOf(const RenderOptions& options,
                                  const std::vector<std::string>& ipopt_options,
                                  const OptionNames& names);

struct StrokePixels {
  render::PaintedStroke painted;
  render::Image8 image;  // composeRgb8 of the canvas
  std::array<std::uint8_t, 3> paper{};  // bare paper's colour (render/image/compose.h)
  long ink_pixels = 0;
};

// The stroke painted (render::paintStroke) and composed to 8-bit sRGB RGB.
// `trajectory` has its depths resolved and was validated for the brush.
StrokePixels paintStrokePixels(const bristle::Brush& brush, const bristle::Trajectory& trajectory,
                               const render::StrokeSetup& setup, bool impasto,
                               const StepCallback& on_step = {});
// The same on a renderer (a GL context) that has painted other strokes before:
// the same pixels (one StrokeRenderer serves any number of strokes).
StrokePixels paintStrokePixels(render::StrokeRenderer& renderer, const bristle::Brush& brush,
                               const bristle::Trajectory& trajectory,
                               const render::StrokeSetup& setup, bool impasto,
                               const StepCallback& on_step = {});

}  // namespace bristle::api

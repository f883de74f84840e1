#pragma once
// A recording as a trajectory, with every default of docs/input.md: what
// `bristle import` does step by step, and what `render --trajectory` does at
// once when it is given a recording instead of a bristle-trajectory/1 file.

#include <optional>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/model/trajectory.h"
#include "input/pen_mapping.h"
#include "input/recording.h"

namespace bristle::input {

// The default press depth at full pressure: this fraction of the brush's hair
// length (its first contact held upright: how far its hairs reach below the
// ferrule), so that a recording presses a short brush and a long one alike.
inline constexpr double kDefaultMaxDepthFrac = 0.4;

struct ImportOptions {
  std::optional<Format> from;  // the input's format; detected when not given
  SvgOptions svg;
  MappingOptions mapping;      // its max_depth_mm is set by resolveMaxDepth
  double max_depth_mm = 0;     // > 0: the depth at full pressure, whatever the brush
  double max_depth_frac = kDefaultMaxDepthFrac;
};

// The brush's hair length for --max-depth-frac: firstContactHeightMm upright.
double hairLengthMm(const Brush& brush);

// Sets options->mapping.max_depth_mm from max_depth_mm or from the fraction
// of the brush's hair length, and returns how, for the output's notes
// ("0.4 x the hair length 20.3 mm of round").
std::string resolveMaxDepth(ImportOptions* options, const Brush& brush,
                            const std::string& brush_name);

// The recording in `text` (named `path` in messages), its format given or
// detected; readRecording's rules and limits.
Recording readInput(const std::string& text, const std::string& path,
                    const ImportOptions& options);

// What `render --trajectory` reads: a bristle-trajectory/1 file as it is
// (parseTrajectory), or a recording imported with the default mapping for
// `brush` (its depths resolved later, as a depth_mm trajectory's are), exactly
// as the CSV `bristle import` writes would read back. The recording's warnings
// are appended to *warnings.
Trajectory loadTrajectoryOrRecording(const std::string& text, const std::string& path,
                                     const Brush& brush, const std::string& brush_name,
                                     std::vector<std::string>* warnings);

}  // namespace bristle::input

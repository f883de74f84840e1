#pragma once
// Pen recordings and vector paths as bristle reads them (docs/input.md): the
// formats `bristle import` and `render --trajectory` take besides
// bristle-trajectory/1, each read into one form, a Recording of PenSamples in
// the source's own units, which input/pen_mapping.h then turns into a
// trajectory.
//
//  - MyPaint stroke-player event files: lines `t x y pressure` (libmypaint's
//    tests/events/*.dat), times in seconds, positions in screen pixels;
//  - Pointer Events CSV: a header of W3C Pointer Events fields (timeStamp in
//    milliseconds, x/clientX, y/clientY, pressure, tiltX, tiltY, twist,
//    altitudeAngle, azimuthAngle, buttons, pointerType, ...), as a web canvas
//    records them;
//  - SVG: each <path> subpath, <polyline> and <line> a stroke, drawn at a
//    constant speed with a pressure profile (input/svg_paths.h).
//
// Every reader is strict as bristle's others are: an error is one line naming
// the file, the line and column (or the SVG element) and the rule, exit 65.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace bristle::input {

enum class Format { kTrajectory, kMyPaint, kPointerCsv, kSvg };

// "bristle-trajectory/1", "MyPaint events", "Pointer Events CSV", "SVG".
const char* formatName(Format format);

// The most samples a recording may hold (docs/input.md, "Limits"): 83 minutes
// at 200 Hz, the fastest tablets' rate. A recording is counted (its lines, or
// an SVG's sampled length) before any sample is stored, and one over the limit
// is refused with exit 65: the 10^7 samples of a day-long log never take the
// ~6 GB they would (a million take 658 MiB to import, docs/input.md).
inline constexpr std::size_t kMaxRecordingSamples = 1'000'000;
// The most tags ('<') an SVG may hold: pugixml reads the whole document into
// memory, and a drawable element takes at least a few samples, so an SVG
// near the sample limit has far fewer.
inline constexpr std::size_t kMaxSvgTags = 1'000'000;
// The most path segments (each move, line, curve and arc of a `d`, each point
// of a `points` list) an SVG may hold, all its elements together: lib2geom
// holds a path whole at ~500 bytes a segment while it is parsed, transformed
// and measured, so the count is kept as the data is read and the file is
// refused at the first segment over it, before that segment is allocated.
inline constexpr std::size_t kMaxSvgSegments = 1'000'000;

// One pen event. Positions are in the source's units (screen or SVG user
// units) and its axes (y down for all three formats).
struct PenSample {
  double t_s = 0;
  double x = 0, y = 0;
  double pressure = 0;  // [0, 1]
  bool down = false;    // the pen touches the surface
  // The pen's axis, from its tip towards its top, in the source's axes with z
  // out of the surface (0, 0, 1: upright). Set from tilt or altitude/azimuth.
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double twist_deg = 0;  // clockwise about the pen's axis, seen from above
  bool has_tilt = false, has_twist = false;
  int line = 0;  // 1-based line of the source, for messages (SVG: the element's)
};

struct Recording {
  std::string path;  // for messages
  Format format = Format::kMyPaint;
  std::vector<PenSample> samples;
  // Millimetres per source unit the source itself implies: an SVG's
  // width/height against its viewBox, else a CSS pixel (25.4 / 96 mm).
  double mm_per_unit = 25.4 / 96;
  std::string units_note;  // how mm_per_unit was found, for the output's header
  int merged_duplicates = 0;  // samples merged into the one after at the same time
  std::vector<std::string> warnings;
};

// How an SVG becomes pen motion (input/svg_paths.h; docs/input.md, "SVG").
struct SvgOptions {
  double speed_mm_s = 40;   // along each stroke
  double sample_mm = 0.5;   // sample spacing along a stroke
  double lead_s = 0.15;     // pen-up pause before and after each stroke
  double mm_per_unit = 0;   // 0: from the document's width/height and viewBox
  // The default pressure profile "u:p ..." (fraction of arc length : pressure),
  // overridden per element by data-bristle-pressure.
  std::string pressure_profile = "0:0.15 0.15:0.6 0.85:0.6 1:0.15";
  std::size_t max_segments = kMaxSvgSegments;  // the limit above (smaller in tests)
};

// Which format `text` (the bytes of `path`, "stdin" for standard input) is in,
// from its content and its file name's extension (.csv, .dat, .txt, .svg).
// Throws Error(kDataError) naming the file when the content is none of them,
// or when the extension promises one format and the content is another
// (".dat holds a Pointer Events CSV header"): both name what was expected.
Format detectFormat(const std::string& text, const std::string& path);

// Reads a recording of a known format (not kTrajectory). `max_samples` is the
// limit above (smaller in tests). Duplicate timestamps are merged into the
// later sample and counted; a timestamp before the previous one is refused,
// naming its line and column (docs/input.md, "Time").
Recording readRecording(const std::string& text, const std::string& path, Format format,
                        const SvgOptions& svg = {},
                        std::size_t max_samples = kMaxRecordingSamples);

// The readers themselves (input/mypaint_events.cpp, pointer_csv.cpp, svg_paths.cpp).
Recording readMyPaintEvents(const std::string& text, const std::string& path,
                            std::size_t max_samples);
Recording readPointerCsv(const std::string& text, const std::string& path,
                         std::size_t max_samples);
Recording readSvg(const std::string& text, const std::string& path, const SvgOptions& options,
                  std::size_t max_samples);

}  // namespace bristle::input

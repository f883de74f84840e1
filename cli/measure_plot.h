#pragma once
// Plots of `bristle measure` and `bristle fit` (docs/measure.md, docs/fit.md):
// width, drag and offset against press depth, three panels side by side, each
// brush's measures as a line and a table of measurements as points. Drawn by
// gnuplot (Debian: gnuplot-nox), run without a shell on a script of our own in
// a private temporary folder; the PNG is then written as an atomic output.

#include <string>
#include <vector>

#include "render/brush_fit.h"
#include "render/brush_measure.h"

namespace bristle::cli {

struct PlotCurve {
  std::string title;  // shown in the key (characters gnuplot could read as markup are replaced)
  std::vector<render::DepthMeasure> measures;
};

struct MeasurePlot {
  std::string title;
  std::vector<PlotCurve> curves;                     // lines
  const render::MeasurementTable* table = nullptr;  // points, or none
  std::string table_title;
};

// Throws Error(kUnavailable) naming `option` when no gnuplot is on PATH: a
// long run checks it before it starts.
void checkGnuplot(const std::string& option);

// Draws the plot and writes it to `path` (an AtomicOutput: it joins the
// command's outputs). Throws Error(kUnavailable) when gnuplot cannot be
// started, kSoftware when it fails (its first line of errors quoted).
void writeMeasurePlot(const std::string& path, const std::string& option, const MeasurePlot& plot);

}  // namespace bristle::cli

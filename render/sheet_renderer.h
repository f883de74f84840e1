#pragma once
// A stroke sheet (engine/formats/sheet.h) as one picture: a grid of cells, brushes x
// trajectories, each cell one stroke painted on its own canvas through the same
// simulation -> geometry -> footprint -> paint path as `bristle render --brush
// --trajectory` (render/stroke_renderer.h), shown at one scale for every cell
// (mm -> px as the sheet says) and centred on its inked area, so the strokes
// compare honestly. Rows and columns are labelled with FreeType text
// (render/image/text.h): brush names and trajectory file stems; a title on top.

#include <functional>
#include <string>
#include <vector>

#include "engine/formats/sheet.h"
#include "render/image/compose.h"
#include "render/image/png_io.h"
#include "render/stroke_renderer.h"
#include "render/image/text.h"

namespace bristle::render {

struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;  // top-left corner, row 0 at the top
  bool contains(int px, int py) const {
    return px >= x && px < x + width && py >= y && py < y + height;
  }
};

// Where everything lies on the sheet image.
struct SheetLayout {
  int width_px = 0, height_px = 0;
  int rows = 0, cols = 0;
  int cell_width_px = 0, cell_height_px = 0;
  PixelRect title;                // height 0 when the sheet has no title
  std::vector<PixelRect> cells;   // row-major: cells[row * cols + col]
  std::vector<PixelRect> row_labels, column_labels;  // the text boxes
  PixelRect grid;                 // the cells and the 1 px lines around them
};

struct SheetCell {
  size_t brush = 0, trajectory = 0;  // indices into the sheet's lists
  int row = 0, col = 0;
  StrokeResult stroke;
  // The inked area on the stroke's own canvas (px of its canvas, row 0 at the
  // top); empty (width 0) when the brush left no visible paint.
  PixelRect ink;
  // The window of the stroke's canvas the cell shows (same size as the cell).
  PixelRect window;
  bool clipped = false;  // the ink is larger than the cell: its middle is shown
};

struct SheetImage {
  Image8 image;  // RGB
  SheetLayout layout;
  std::vector<SheetCell> cells;  // in layout order (row-major)
  double cell_width_mm = 0, cell_height_mm = 0;
  SimStats stats;  // summed over the cells
};

struct SheetRenderOptions {
  ComposeOptions compose;  // impasto or not
  double contact_band_mm = 0.1;    // the contact band (StrokeOptions::contact_band_mm)
  // Per solve, for both solvers (SolverSettings::max_iterations).
  int solver_max_iterations = kDefaultSolverMaxIterations;
  int threads = 0;  // StrokeOptions::threads
};

// After every simulation step: the cell (in layout order), and the steps of the
// whole sheet done so far and planned in all.
using SheetStepCallback = std::function<void(int cell, int cells, long step, long steps)>;

// A pixel of a cell is ink by the rule of render/image/compose.h (kInkLevels).
inline constexpr int kSheetInkLevels = kInkLevels;

// Auto cells: the largest inked area plus this much paper on every side (mm).
inline constexpr double kSheetCellPadMm = 3;

// Renders every cell and lays the sheet out. Throws bristle::Error(kDataError)
// naming the sheet when the picture would exceed the canvas limits of
// engine/model/canvas.h, and whatever the stroke pipeline throws.
SheetImage renderSheet(const Sheet& sheet, const SheetRenderOptions& options = {},
                       const SheetStepCallback& on_step = {});

// The colour of bare paper for the sheet's paper and compose options.
Rgb8 sheetPaperColour(const Sheet& sheet, const ComposeOptions& compose);

}  // namespace bristle::render

#pragma once
// A stroke sheet as data: JSON format `bristle-sheet/1` (docs/sheet-format.md).
// A sheet is a grid of strokes, brushes x trajectories, every cell one brush
// along one trajectory with the same paint, paper and simulation settings, all
// at one scale: the "Figure 2" of Baxter & Lin (2004) for any set of brushes.
// Rendering is render/sheet_renderer.h; this reader opens no GL.

#include <cstdint>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/model/canvas.h"
#include "engine/paint/paint_spec.h"
#include "engine/dynamics/simulation.h"
#include "engine/solvers/solver_pair.h"
#include "engine/model/trajectory.h"

namespace bristle {

// Limits that keep a sheet file from asking for absurd work or pictures.
inline constexpr int kMaxSheetAxis = 64;       // brushes, and trajectories
inline constexpr int kMinSheetLabelPx = 8;     // smaller is not legible
inline constexpr int kMaxSheetLabelPx = 96;
inline constexpr double kMaxSheetCellMm = 1000;
inline constexpr double kMaxSheetLiftMm = 100;

struct Sheet {
  std::string path;  // the sheet file, for messages
  std::string name;
  std::string title;  // drawn above the grid; empty: no title line
  std::vector<std::string> brush_paths;       // resolved against the sheet's folder
  std::vector<std::string> trajectory_paths;  // resolved likewise
  // Per brush: every handle position of its row raised by this much (mm), as
  // `bristle render --offset-mm 0 0 LIFT`: the standard trajectories are made
  // for the 20 mm round; longer brushes are held higher to press as deep.
  std::vector<double> brush_lift_mm;
  std::vector<Brush> brushes;                 // loadSheet fills these, in order
  std::vector<Trajectory> trajectories;
  bool brushes_in_columns = false;  // "layout": rows are brushes unless this is set
  // Cell size (mm); 0 x 0 = "auto": the largest stroke's inked area plus a pad.
  double cell_width_mm = 0, cell_height_mm = 0;
  double px_per_mm = 8;
  // As `bristle render --brush --trajectory` paints by default, so a sheet cell
  // and a single render of the same pair agree.
  PaintLoad paint = defaultSheetPaint();
  PaperSpec paper = defaultSheetPaper();
  Rgb background;  // = paper.colour, parsed
  MixModel mix = MixModel::kKubelkaMunk;
  SimOptions sim;
  SolverKind solver = SolverKind::kIpopt;  // primary spine solver; the other is the fallback
  int label_px = 14;             // label text size (em height, px)
  // Every file the sheet read: the sheet, then the brushes and the trajectories
  // in the order listed (the inputs of sheetInputsHash).
  std::vector<std::string> inputs;

  bool autoCell() const { return cell_width_mm == 0 && cell_height_mm == 0; }
  // Row and column label of the cell of brush b, trajectory t: the brush's
  // "name" (with its lift, "badger +6 mm", if any) and the trajectory file's stem.
  std::string brushLabel(size_t b) const;
  std::string trajectoryLabel(size_t t) const;
  // The trajectory of the cell of brush b and trajectory t: as recorded, raised
  // by the brush's lift.
  Trajectory cellTrajectory(size_t b, size_t t) const;

  static PaintLoad defaultSheetPaint();
  static PaperSpec defaultSheetPaper();
};

// Reads a sheet and every brush and trajectory it lists; throws bristle::Error:
// 66 if the sheet is missing or a listed file is unreadable (naming the sheet
// field, `sheet.json: /brushes/2: cannot read 'x.json': ...`); 65 for bad data,
// naming the JSON pointer and the rule (brush and trajectory files are read by
// their own readers, whose errors name those files); a pair whose ferrule would
// dig into the canvas names both pointers.
Sheet loadSheet(const std::string& path);

// The sheet file alone (no listed file is opened); relative paths are resolved
// against base_dir. For tests of the reader's rules.
Sheet parseSheet(const std::string& text, const std::string& path_for_messages,
                 const std::string& base_dir);

// FNV-1a 64 over the bytes of sheet.inputs, in order: the PNG's
// "bristle:inputs-fnv1a64" text, and what `bristle batch` compares to decide
// whether a sheet's PNG is up to date. Throws Error(kNoInput) for an input that
// can no longer be read.
std::uint64_t sheetInputsHash(const Sheet& sheet);

// What is legal but likely a mistake, one line each (engine/formats/input_warnings.h):
// a brush whose spines and surface differ in scale, a cell's trajectory that
// lasts over 10 minutes or plans over a million steps (a trajectory named once
// for all its cells when they say the same). Planning the steps throws as the
// render would at a step limit.
std::vector<std::string> sheetInputWarnings(const Sheet& sheet);

// Whether a JSON text declares itself a sheet ("format": "bristle-sheet/...");
// false for anything else, malformed JSON included.
bool looksLikeSheet(const std::string& text);

}  // namespace bristle

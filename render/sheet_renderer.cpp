#include "render/sheet_renderer.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "engine/base/error.h"
#include "engine/dynamics/stepper.h"
#include "render/stroke_pipeline.h"
#include "render/image/text.h"

namespace bristle::render {
namespace {

constexpr Rgb8 kLabelColour{0x2a, 0x2a, 0x2a};
constexpr Rgb8 kGridColour{0x8c, 0x87, 0x7d};  // a mid warm grey, clear on the paper
constexpr int kGridLinePx = 1;

// The box of pixels whose colour differs visibly from the paper's.
PixelRect inkBox(const Image8& img, Rgb8 paper) {
  int x0 = img.width, y0 = img.height, x1 = -1, y1 = -1;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t* p = &img.pixels[(size_t(y) * img.width + x) * size_t(img.channels)];
      if (!isInk(p, {paper.r, paper.g, paper.b})) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x);
      y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  if (x1 < 0) return {};
  return {x0, y0, x1 - x0 + 1, y1 - y0 + 1};
}

void fill(Image8* img, const PixelRect& r, Rgb8 c) {
  for (int y = std::max(0, r.y); y < std::min(img->height, r.y + r.height); ++y)
    for (int x = std::max(0, r.x); x < std::min(img->width, r.x + r.width); ++x) {
      std::uint8_t* p = &img->pixels[(size_t(y) * img->width + x) * size_t(img->channels)];
      p[0] = c.r, p[1] = c.g, p[2] = c.b;
    }
}

// Drops whole UTF-8 characters from the end and appends an ellipsis until the
// text fits in max_width px (a trajectory stem wider than its column).
Image8 fittedText(Font& font, std::string text, int size_px, int max_width) {
  Image8 mask = font.rasterize(text, size_px);
  while (mask.width > max_width && !text.empty()) {
    while (!text.empty() && (static_cast<unsigned char>(text.back()) & 0xC0) == 0x80)
      text.pop_back();  // continuation bytes of the last character
    if (!text.empty()) text.pop_back();  // and its lead byte
    mask = font.rasterize(text + "\u2026", size_px);
  }
  return mask;
}

// The sheet's picture must stay within the canvas limits of engine/model/canvas.h.
// What makes it too large is named: the title when it alone is wider than
// the limit, else the cells' size.
void checkSheetSize(const Sheet& sheet, double width, double height, double title_width) {
  if (title_width > kMaxCanvasSidePx)
    throw dataError(sheet.path, "/title",
                    "the title alone makes the sheet " + std::to_string(long(title_width)) +
                        " px wide, above the limit of 16384 px a side; shorten it");
  if (width <= kMaxCanvasSidePx && height <= kMaxCanvasSidePx &&
      width * height <= double(kMaxCanvasPixels))
    return;
  throw dataError(sheet.path, sheet.autoCell() ? "/px_per_mm" : "/cell_mm",
                  "the sheet would be " + std::to_string(long(width)) + " x " +
                      std::to_string(long(height)) +
                      " px or more, above the limit of 16384 px a side and 64 Mpx; lower "
                      "px_per_mm or the cell size");
}

// The title's size and the margins around it (the title is 1.5 times the labels).
int labelMarginPx(const Sheet& sheet) { return std::max(8, sheet.label_px); }
int titlePx(const Sheet& sheet) { return sheet.label_px * 3 / 2; }

}  // namespace

Rgb8 sheetPaperColour(const Sheet& sheet, const ComposeOptions& compose) {
  const std::array<std::uint8_t, 3> c = paperColour8(sheet.paper, sheet.mix, sheet.px_per_mm, compose);
  return {c[0], c[1], c[2]};
}

namespace {

// The cells in layout order, each with the steps its simulation will plan
// (for progress).
struct PlannedCells {
  std::vector<SheetCell> cells;
  std::vector<long> steps;
  long total_steps = 0;
};

PlannedCells planCells(const Sheet& sheet, const SheetLayout& L) {
  PlannedCells plan;
  for (int r = 0; r < L.rows; ++r)
    for (int c = 0; c < L.cols; ++c) {
      SheetCell cell;
      cell.row = r, cell.col = c;
      cell.brush = size_t(sheet.brushes_in_columns ? c : r);
      cell.trajectory = size_t(sheet.brushes_in_columns ? r : c);
      plan.steps.push_back(static_cast<long>(
          planStepTimes(sheet.cellTrajectory(cell.brush, cell.trajectory),
                        sheet.brushes[cell.brush], sheet.sim)
              .size()));
      plan.total_steps += plan.steps.back();
      plan.cells.push_back(cell);
    }
  return plan;
}

// Every stroke on its own canvas by the function `bristle render --brush
// --trajectory` paints with (paintStroke): the canvas the stroke needs, a fresh
// brush load, fresh paper. Fills each cell's stroke and ink box and the sheet's
// stats; returns each cell's composed canvas.
std::vector<Image8> paintCells(const Sheet& sheet, const SheetRenderOptions& options,
                               const PlannedCells& plan, const SheetStepCallback& on_step,
                               SheetImage* out) {
  StrokeOptions stroke_options;
  stroke_options.px_per_mm = sheet.px_per_mm;
  stroke_options.contact_band_mm = options.contact_band_mm;
  stroke_options.sim = sheet.sim;
  stroke_options.threads = options.threads;
  const Rgb8 paper = sheetPaperColour(sheet, options.compose);
  StrokeSetup setup;
  setup.load = sheet.paint;
  setup.load_where = sheet.path + ": /paint";
  setup.mix = sheet.mix;
  setup.paper = sheet.paper;
  setup.solvers = {sheet.solver, options.solver_max_iterations, {}};
  setup.stroke = stroke_options;
  StrokeRenderer renderer;  // one GL context for the whole sheet
  std::vector<Image8> strokes;
  const int n = static_cast<int>(out->cells.size());
  long done = 0;
  for (int i = 0; i < n; ++i) {
    SheetCell& cell = out->cells[size_t(i)];
    const Brush& brush = sheet.brushes[cell.brush];
    const Trajectory trajectory = sheet.cellTrajectory(cell.brush, cell.trajectory);
    StepCallback step_cb;
    if (on_step)
      step_cb = [&](const BrushState&, int step, int) {
        on_step(i, n, done + step, plan.total_steps);
      };
    const PaintedStroke painted = paintStroke(renderer, brush, trajectory, setup, step_cb);
    cell.stroke = painted.stroke;
    done += plan.steps[size_t(i)];
    strokes.push_back(composeRgb8(painted.canvas, options.compose));
    cell.ink = inkBox(strokes.back(), paper);
    out->stats.add(cell.stroke.stats);
  }
  return strokes;
}

// One cell size for all: the sheet's, or the largest ink plus a pad.
void sizeCells(const Sheet& sheet, SheetImage* out) {
  SheetLayout& L = out->layout;
  const double ppm = sheet.px_per_mm;
  if (sheet.autoCell()) {
    int w = 0, h = 0;
    for (const SheetCell& c : out->cells)
      w = std::max(w, c.ink.width), h = std::max(h, c.ink.height);
    const int pad = static_cast<int>(std::ceil(kSheetCellPadMm * ppm));
    L.cell_width_px = std::max(w, 1) + 2 * pad;
    L.cell_height_px = std::max(h, 1) + 2 * pad;
  } else {
    L.cell_width_px = std::max(1, static_cast<int>(std::lround(sheet.cell_width_mm * ppm)));
    L.cell_height_px = std::max(1, static_cast<int>(std::lround(sheet.cell_height_mm * ppm)));
  }
  out->cell_width_mm = L.cell_width_px / ppm;
  out->cell_height_mm = L.cell_height_px / ppm;
}

// The rasterised labels and where the grid goes: title, column labels above
// the grid, row labels left of it.
struct Labels {
  std::vector<Image8> rows, cols;
  Image8 title;
  int margin = 0, header_y = 0, pitch_x = 0, pitch_y = 0;
};

// Places the title (`title`, rasterised at titlePx), labels and grid in L and
// sizes the picture.
Labels layOutLabels(const Sheet& sheet, Image8 title, SheetLayout* L) {
  Font font;
  Labels labels;
  const int label_px = sheet.label_px;
  labels.margin = labelMarginPx(sheet);
  const int margin = labels.margin;
  const int gap = std::max(4, label_px / 2);
  const int line_h = font.rasterize("Ag", label_px).height;
  int row_label_w = 0;
  for (int r = 0; r < L->rows; ++r) {
    const size_t k = size_t(r);
    labels.rows.push_back(font.rasterize(
        sheet.brushes_in_columns ? sheet.trajectoryLabel(k) : sheet.brushLabel(k), label_px));
    row_label_w = std::max(row_label_w, labels.rows.back().width);
  }
  for (int c = 0; c < L->cols; ++c) {
    const size_t k = size_t(c);
    labels.cols.push_back(fittedText(
        font, sheet.brushes_in_columns ? sheet.brushLabel(k) : sheet.trajectoryLabel(k), label_px,
        L->cell_width_px));
  }
  int y = margin;
  if (!sheet.title.empty()) {
    labels.title = std::move(title);
    L->title = {margin, y, labels.title.width, labels.title.height};
    y += labels.title.height + gap;
  }
  const int grid_x = margin + row_label_w + gap;
  labels.header_y = y;
  const int grid_y = labels.header_y + line_h + gap / 2;
  labels.pitch_x = L->cell_width_px + kGridLinePx;
  labels.pitch_y = L->cell_height_px + kGridLinePx;
  L->grid = {grid_x, grid_y, L->cols * labels.pitch_x + kGridLinePx,
             L->rows * labels.pitch_y + kGridLinePx};
  const double width = std::max<double>(double(grid_x) + L->grid.width + margin,
                                        2.0 * margin + labels.title.width);
  const double height = double(grid_y) + L->grid.height + margin;
  checkSheetSize(sheet, width, height, 2.0 * margin + labels.title.width);
  L->width_px = static_cast<int>(width);
  L->height_px = static_cast<int>(height);
  return labels;
}

// Copies each stroke's window, centred on its ink (on its canvas's centre when
// there is none), into its cell; outside the canvas is bare paper.
void drawCells(const std::vector<Image8>& strokes, const Labels& labels, Rgb8 paper,
               SheetImage* out) {
  SheetLayout& L = out->layout;
  Image8& img = out->image;
  for (SheetCell& cell : out->cells) {
    const PixelRect dst{L.grid.x + kGridLinePx + cell.col * labels.pitch_x,
                        L.grid.y + kGridLinePx + cell.row * labels.pitch_y, L.cell_width_px,
                        L.cell_height_px};
    L.cells.push_back(dst);
    const Image8& src = strokes[L.cells.size() - 1];
    const int cx = cell.ink.width > 0 ? cell.ink.x + cell.ink.width / 2 : src.width / 2;
    const int cy = cell.ink.width > 0 ? cell.ink.y + cell.ink.height / 2 : src.height / 2;
    cell.window = {cx - dst.width / 2, cy - dst.height / 2, dst.width, dst.height};
    cell.clipped = cell.ink.width > dst.width || cell.ink.height > dst.height;
    for (int dy = 0; dy < dst.height; ++dy)
      for (int dx = 0; dx < dst.width; ++dx) {
        const int sx = cell.window.x + dx, sy = cell.window.y + dy;
        std::uint8_t* p = &img.pixels[(size_t(dst.y + dy) * img.width + dst.x + dx) * 3];
        if (sx < 0 || sy < 0 || sx >= src.width || sy >= src.height) {
          p[0] = paper.r, p[1] = paper.g, p[2] = paper.b;
        } else {
          const std::uint8_t* q = &src.pixels[(size_t(sy) * src.width + sx) * size_t(src.channels)];
          p[0] = q[0], p[1] = q[1], p[2] = q[2];
        }
      }
  }
}

void drawLabels(const Sheet& sheet, const Labels& labels, SheetLayout* L, Image8* img) {
  if (!sheet.title.empty()) blendMask(labels.title, L->title.x, L->title.y, kLabelColour, img);
  for (int r = 0; r < L->rows; ++r) {
    const Image8& m = labels.rows[size_t(r)];
    const PixelRect box{labels.margin,
                        L->grid.y + kGridLinePx + r * labels.pitch_y +
                            (L->cell_height_px - m.height) / 2,
                        m.width, m.height};
    blendMask(m, box.x, box.y, kLabelColour, img);
    L->row_labels.push_back(box);
  }
  for (int c = 0; c < L->cols; ++c) {
    const Image8& m = labels.cols[size_t(c)];
    const PixelRect box{L->grid.x + kGridLinePx + c * labels.pitch_x +
                            (L->cell_width_px - m.width) / 2,
                        labels.header_y, m.width, m.height};
    blendMask(m, box.x, box.y, kLabelColour, img);
    L->column_labels.push_back(box);
  }
}

}  // namespace

// Plan the cells, paint every stroke, size the cells, lay out the labels, then
// draw: paper, grid lines, the cells' windows, the labels.
SheetImage renderSheet(const Sheet& sheet, const SheetRenderOptions& options,
                       const SheetStepCallback& on_step) {
  SheetImage out;
  SheetLayout& L = out.layout;
  L.rows = static_cast<int>(sheet.brushes_in_columns ? sheet.trajectories.size()
                                                     : sheet.brushes.size());
  L.cols = static_cast<int>(sheet.brushes_in_columns ? sheet.brushes.size()
                                                     : sheet.trajectories.size());
  PlannedCells plan = planCells(sheet, L);
  out.cells = std::move(plan.cells);

  // A fixed cell size says how large the grid is before anything is simulated:
  // refuse a picture past the limits now rather than after every stroke.
  const double ppm = sheet.px_per_mm;
  if (!sheet.autoCell()) {
    const double grid_w = L.cols * (std::lround(sheet.cell_width_mm * ppm) + 1.0) + 1;
    const double grid_h = L.rows * (std::lround(sheet.cell_height_mm * ppm) + 1.0) + 1;
    checkSheetSize(sheet, grid_w, grid_h, 0);
  }
  // So does the title's width.
  Image8 title;
  if (!sheet.title.empty()) {
    Font font;
    title = font.rasterize(sheet.title, titlePx(sheet));
    checkSheetSize(sheet, 0, 0, 2.0 * labelMarginPx(sheet) + title.width);
  }

  const std::vector<Image8> strokes = paintCells(sheet, options, plan, on_step, &out);
  sizeCells(sheet, &out);
  const Labels labels = layOutLabels(sheet, std::move(title), &L);

  const Rgb8 paper = sheetPaperColour(sheet, options.compose);
  Image8& img = out.image;
  img.width = L.width_px, img.height = L.height_px, img.channels = 3;
  img.pixels.assign(size_t(img.width) * img.height * 3, 0);
  fill(&img, {0, 0, img.width, img.height}, paper);
  fill(&img, L.grid, kGridColour);
  drawCells(strokes, labels, paper, &out);
  drawLabels(sheet, labels, &L, &img);
  return out;
}

}  // namespace bristle::render

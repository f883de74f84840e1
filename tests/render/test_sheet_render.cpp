// The stroke sheet as a picture (render/sheet_renderer.h): the small sheet of
// scenes/sheets/ laid out as its grid, every stroke inside its own cell and
// nowhere else, labels drawn in their boxes, the same pixels every run, the
// brushes-in-columns layout the transpose of the default, and a fixed cell that
// is too small said to be clipped (docs/sheet-format.md).

#include <catch2/catch.hpp>
#include <filesystem>
#include <cstdint>
#include <string>

#include "engine/base/fnv1a64.h"
#include "engine/formats/sheet.h"
#include "engine/formats/trajectory_reader.h"
#include "render/sheet_renderer.h"
#include "render/image/text.h"
#include "temp_dir.h"
#include "tests/support/build_paths.h"

using namespace bristle;
using namespace bristle::render;

namespace {

const std::string kSmall = std::string(BRISTLE_SOURCE_DIR) + "/scenes/sheets/small.json";

// Label and title text: pixels at least this much darker than the paper (sum
// of R, G, B levels) are glyph ink; anti-aliased glyph edges fade out below.
constexpr int kTextLevels = 200;

const std::uint8_t* px(const Image8& img, int x, int y) {
  return &img.pixels[(size_t(y) * img.width + x) * size_t(img.channels)];
}

int diff(const std::uint8_t* p, Rgb8 c) {
  return std::abs(p[0] - c.r) + std::abs(p[1] - c.g) + std::abs(p[2] - c.b);
}

bool insideAny(const std::vector<PixelRect>& rects, int x, int y) {
  for (const PixelRect& r : rects)
    if (r.contains(x, y)) return true;
  return false;
}

std::uint64_t pixelHash(const Image8& img) {
  return fnv1a64(std::string_view(reinterpret_cast<const char*>(img.pixels.data()),
                                  img.pixels.size()));
}

// The small sheet renders in about a second (4 px/mm, SLSQP, 60 Hz); the
// tests share one render.
const SheetImage& smallSheet() {
  static const SheetImage image = renderSheet(loadSheet(kSmall));
  return image;
}

}  // namespace

TEST_CASE("a sheet's image is its grid: cells, lines, labels and title laid out", "[sheet]") {
  const Sheet sheet = loadSheet(kSmall);
  const SheetImage& s = smallSheet();
  const SheetLayout& L = s.layout;
  CHECK(s.image.width == L.width_px);
  CHECK(s.image.height == L.height_px);
  CHECK(s.image.channels == 3);
  CHECK(L.rows == 2);  // brushes in rows
  CHECK(L.cols == 2);
  REQUIRE(L.cells.size() == 4);
  REQUIRE(L.row_labels.size() == 2);
  REQUIRE(L.column_labels.size() == 2);
  // The grid: cells of one size, 1 px lines between and around them.
  CHECK(L.grid.width == 2 * L.cell_width_px + 3);
  CHECK(L.grid.height == 2 * L.cell_height_px + 3);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      const PixelRect& cell = L.cells[size_t(r * 2 + c)];
      CHECK(cell.x == L.grid.x + 1 + c * (L.cell_width_px + 1));
      CHECK(cell.y == L.grid.y + 1 + r * (L.cell_height_px + 1));
      CHECK(cell.width == L.cell_width_px);
      CHECK(cell.height == L.cell_height_px);
      CHECK(s.cells[size_t(r * 2 + c)].brush == size_t(r));
      CHECK(s.cells[size_t(r * 2 + c)].trajectory == size_t(c));
    }
  // Auto cells: the largest inked area plus kSheetCellPadMm of paper each side,
  // so no stroke is clipped and the widest one just fits.
  int widest = 0, tallest = 0;
  for (const SheetCell& c : s.cells) {
    CHECK(c.ink.width > 0);
    CHECK_FALSE(c.clipped);
    widest = std::max(widest, c.ink.width);
    tallest = std::max(tallest, c.ink.height);
  }
  const int pad = int(std::ceil(kSheetCellPadMm * sheet.px_per_mm));
  CHECK(L.cell_width_px == widest + 2 * pad);
  CHECK(L.cell_height_px == tallest + 2 * pad);
  // A 55 mm pull is the widest: the cell is at least that long (px_per_mm 4).
  CHECK(s.cell_width_mm > 55);
  // Title on top, column labels above the grid, row labels left of it.
  CHECK(L.title.height > 0);
  for (const PixelRect& b : L.column_labels) CHECK(b.y + b.height <= L.grid.y);
  for (const PixelRect& b : L.row_labels) CHECK(b.x + b.width <= L.grid.x);
  CHECK(L.title.y + L.title.height <= L.column_labels[0].y);
}

TEST_CASE("every stroke is inside its cell, centred, and nothing is outside the cells",
          "[sheet]") {
  const Sheet sheet = loadSheet(kSmall);
  const SheetImage& s = smallSheet();
  const SheetLayout& L = s.layout;
  const Rgb8 paper = sheetPaperColour(sheet, {});
  std::vector<PixelRect> text = L.row_labels;
  text.insert(text.end(), L.column_labels.begin(), L.column_labels.end());
  text.push_back(L.title);
  for (size_t i = 0; i < L.cells.size(); ++i) {
    INFO("cell " << i);
    const PixelRect& cell = L.cells[i];
    // Ink in the cell, its box centred (to a pixel of rounding) with at least
    // the pad of paper on every side of the largest stroke's axis.
    int x0 = cell.x + cell.width, x1 = -1, y0 = cell.y + cell.height, y1 = -1, inked = 0;
    for (int y = cell.y; y < cell.y + cell.height; ++y)
      for (int x = cell.x; x < cell.x + cell.width; ++x)
        if (diff(px(s.image, x, y), paper) > kSheetInkLevels) {
          ++inked;
          x0 = std::min(x0, x), x1 = std::max(x1, x);
          y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
    CHECK(inked > 50);  // a stroke, not a speck (4 px/mm: 50 px is ~3 mm^2)
    CHECK(x1 - x0 + 1 == s.cells[i].ink.width);
    CHECK(y1 - y0 + 1 == s.cells[i].ink.height);
    const int left = x0 - cell.x, right = cell.x + cell.width - 1 - x1;
    const int top = y0 - cell.y, bottom = cell.y + cell.height - 1 - y1;
    CHECK(std::abs(left - right) <= 1);
    CHECK(std::abs(top - bottom) <= 1);
  }
  // Outside the cells: the grid lines are the line colour, and everything
  // else is bare paper except glyphs inside the label and title boxes.
  int label_ink = 0;
  for (int y = 0; y < s.image.height; ++y)
    for (int x = 0; x < s.image.width; ++x) {
      if (insideAny(L.cells, x, y)) continue;
      const std::uint8_t* p = px(s.image, x, y);
      if (L.grid.contains(x, y)) {
        CHECK(diff(p, paper) > kSheetInkLevels);  // a line, not paper
        continue;
      }
      if (insideAny(text, x, y)) {
        label_ink += diff(p, paper) > kTextLevels;
        continue;
      }
      if (diff(p, paper) != 0) FAIL("mark outside every cell and label at " << x << ", " << y);
    }
  CHECK(label_ink > 0);
}

TEST_CASE("every label box has glyph ink", "[sheet]") {
  const Sheet sheet = loadSheet(kSmall);
  const SheetImage& s = smallSheet();
  const Rgb8 paper = sheetPaperColour(sheet, {});
  std::vector<PixelRect> boxes = s.layout.row_labels;
  boxes.insert(boxes.end(), s.layout.column_labels.begin(), s.layout.column_labels.end());
  boxes.push_back(s.layout.title);
  for (const PixelRect& b : boxes) {
    int dark = 0;
    for (int y = b.y; y < b.y + b.height; ++y)
      for (int x = b.x; x < b.x + b.width; ++x) dark += diff(px(s.image, x, y), paper) > kTextLevels;
    // A word at 14 px has a few hundred glyph pixels; 20 is any letter at all.
    CHECK(dark > 20);
  }
  // Wider labels draw wider boxes: "straight-pull" against "press-lift".
  CHECK(s.layout.column_labels[0].width > s.layout.column_labels[1].width);
}

TEST_CASE("a sheet renders to the same pixels every run", "[sheet]") {
  const SheetImage again = renderSheet(loadSheet(kSmall));
  CHECK(pixelHash(again.image) == pixelHash(smallSheet().image));
}

TEST_CASE("brushes-in-columns is the transpose: each cell the same stroke", "[sheet]") {
  Sheet sheet = loadSheet(kSmall);
  sheet.brushes_in_columns = true;
  const SheetImage t = renderSheet(sheet);
  const SheetImage& s = smallSheet();
  REQUIRE(t.layout.rows == 2);
  CHECK(t.layout.cell_width_px == s.layout.cell_width_px);
  CHECK(t.layout.cell_height_px == s.layout.cell_height_px);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      const SheetCell& tc = t.cells[size_t(r * 2 + c)];
      CHECK(tc.trajectory == size_t(r));
      CHECK(tc.brush == size_t(c));
      // The cell of brush c on trajectory r, pixel for pixel.
      const PixelRect& a = t.layout.cells[size_t(r * 2 + c)];
      const PixelRect& b = s.layout.cells[size_t(c * 2 + r)];
      bool same = true;
      for (int y = 0; y < a.height && same; ++y)
        for (int x = 0; x < a.width && same; ++x)
          same = std::equal(px(t.image, a.x + x, a.y + y), px(t.image, a.x + x, a.y + y) + 3,
                            px(s.image, b.x + x, b.y + y));
      CHECK(same);
    }
}

TEST_CASE("a fixed cell smaller than a stroke shows its middle and says so", "[sheet]") {
  Sheet sheet = loadSheet(kSmall);
  // 30 x 20 mm: the 55 mm pulls do not fit, the press-lift dabs (~10 mm) do.
  sheet.cell_width_mm = 30;
  sheet.cell_height_mm = 20;
  const SheetImage s = renderSheet(sheet);
  CHECK(s.layout.cell_width_px == 120);  // 30 mm at 4 px/mm
  CHECK(s.layout.cell_height_px == 80);
  for (const SheetCell& c : s.cells) {
    INFO("trajectory " << c.trajectory << ", brush " << c.brush << ": ink " << c.ink.width << " x "
                       << c.ink.height << " px");
    CHECK(c.clipped == (c.trajectory == 0));
    CHECK(c.window.width == 120);
  }
}

TEST_CASE("a column label wider than its cell is shortened to fit it", "[sheet]") {
  namespace fs = std::filesystem;
  const bristle::testing::TempDir tmp("bristle-sheet-label");
  const fs::path& dir = tmp.path();
  const fs::path traj = dir / "a-press-and-lift-with-a-name-far-longer-than-its-cell.csv";
  fs::copy_file(std::string(BRISTLE_SOURCE_DIR) + "/scenes/trajectories/press-lift.csv", traj);
  Sheet sheet = loadSheet(kSmall);
  sheet.brushes.resize(1);
  sheet.brush_paths.resize(1);
  sheet.brush_lift_mm.resize(1);
  sheet.trajectories = {loadTrajectory(traj.string())};
  sheet.trajectory_paths = {traj.string()};
  sheet.cell_width_mm = 20;  // 80 px at 4 px/mm: room for a few characters only
  sheet.cell_height_mm = 20;
  const SheetImage s = renderSheet(sheet);
  fs::remove_all(dir);
  REQUIRE(s.layout.column_labels.size() == 1);
  const PixelRect& label = s.layout.column_labels[0];
  CHECK(label.width > 0);
  CHECK(label.width <= s.layout.cell_width_px);
  // Centred over its cell.
  const PixelRect& cell = s.layout.cells[0];
  CHECK(std::abs((label.x + label.width / 2) - (cell.x + cell.width / 2)) <= 1);
  // The whole name would not have fitted: it was shortened, not just placed.
  Font font;
  CHECK(font.rasterize(sheet.trajectoryLabel(0), sheet.label_px).width > s.layout.cell_width_px);
}

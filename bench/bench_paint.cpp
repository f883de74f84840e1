// Paint transfer per step (engine/paint/paint.h) on footprints of 256^2 and 512^2
// pixels: the flat brush of the library (surface + strips + spines, so every
// texture-coordinate kind is mapped), a footprint shaped like a pressed brush
// (an ellipse filling ~79% of the window, depth falling off towards its rim,
// texture coordinates of all three geometry kinds), moving 2 px per step over a
// canvas with paper tooth, as a stroke does; and a footprint of separate
// bundles, laid by the badger with and without the flagged hair that fills
// the gaps between them. Figures in docs/PERFORMANCE.md, "Paint transfer and
// composing".

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/paint/paint.h"
#include "tests/support/build_paths.h"

namespace {

using namespace bristle;

std::vector<float> pressedFootprint(int n) {
  std::vector<float> t(static_cast<size_t>(n) * n * 4, 0.0f);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = (c + 0.5) / n * 2 - 1, y = (r + 0.5) / n * 2 - 1;
      const double rr = x * x + y * y;
      if (rr >= 1) continue;
      float* p = &t[(static_cast<size_t>(r) * n + c) * 4];
      const double across = 0.5 * (x + 1), along = 0.5 * (y + 1);
      // Thirds of the window: surface (u an angle), strips, spine tubes.
      const int kind = (c * 3) / n;
      p[0] = kind == 0   ? static_cast<float>(0.5 * across)
             : kind == 1 ? encodeTextureU(BrushPart::kStrip, static_cast<float>(across))
                         : encodeTextureU(BrushPart::kSpine, static_cast<float>(across));
      p[1] = static_cast<float>(0.6 + 0.4 * along);
      p[2] = static_cast<float>(0.8 * (1 - rr));  // mm: deepest in the middle
      p[3] = 1;
    }
  return t;
}

// A head pressed into separate bundles: seven discs, one in the middle and
// six round it, with paper between them inside their hull, as the badger's
// bundles print pressed straight down. A flagged brush fills those gaps with
// hair (hullHair) and scrubs a rim round the hull (flagRim).
std::vector<float> bundledFootprint(int n) {
  std::vector<float> t(static_cast<size_t>(n) * n * 4, 0.0f);
  const double disc = 0.22, ring = 0.6;  // of the half window
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      const double x = (c + 0.5) / n * 2 - 1, y = (r + 0.5) / n * 2 - 1;
      bool inside = std::hypot(x, y) < disc;
      for (int k = 0; k < 6 && !inside; ++k)
        inside = std::hypot(x - ring * std::cos(k * M_PI / 3), y - ring * std::sin(k * M_PI / 3)) <
                 disc;
      if (!inside) continue;
      float* p = &t[(static_cast<size_t>(r) * n + c) * 4];
      p[0] = encodeTextureU(BrushPart::kStrip, static_cast<float>(0.5 * (x + 1)));
      p[1] = static_cast<float>(0.6 + 0.2 * (y + 1));
      p[2] = 0.05f;  // mm: on the paper
      p[3] = 1;
    }
  return t;
}

// range(1): 0 the flat over a pressed footprint; the badger over the bundled
// one, 1 with its flags cut off (paint.flag_mm 0) and 2 as it is, so that 2
// over 1 is what the flags' rim and the hair between the bundles cost.
void BM_Transfer(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const int kind = static_cast<int>(state.range(1));
  Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" +
                          (kind == 0 ? "flat" : "badger") + ".json");
  if (kind == 1) brush.paint_flag_mm = 0;
  BrushPaint paint(brush);
  PaintLoad load;
  load.mode = PaintLoad::Mode::kAcross;
  load.paints = {"cadmium-red", "titanium-white"};
  paint.load(load, MixModel::kKubelkaMunk, "bench");
  CanvasGrid grid;
  grid.width_px = n + 64;
  grid.height_px = 3 * n;
  PaperSpec paper;
  paper.tooth_depth_mm = 0.05;
  PaintCanvas canvas(grid, paper, MixModel::kKubelkaMunk);
  const std::vector<float> texels = kind == 0 ? pressedFootprint(n) : bundledFootprint(n);
  const TransferParams params;
  int row = 0;
  long contact = 0;
  for (auto _ : state) {
    const FootprintView view{32, row, n, n, texels.data()};
    const TransferStats st = transfer(view, paint, canvas, params);
    contact += st.contact_px;
    row = (row + 2) % (2 * n);
    // A stroke reloads nothing; past the canvas end, start over on fresh paper.
    if (row == 0) {
      state.PauseTiming();
      canvas = PaintCanvas(grid, paper, MixModel::kKubelkaMunk);
      paint.load(load, MixModel::kKubelkaMunk, "bench");
      state.ResumeTiming();
    }
  }
  state.counters["contact_px"] =
      benchmark::Counter(double(contact) / std::max<double>(1, state.iterations()));
}
BENCHMARK(BM_Transfer)->ArgNames({"footprint_px", "kind"})
    ->ArgsProduct({{256, 512}, {0, 1, 2}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

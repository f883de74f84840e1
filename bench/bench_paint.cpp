// Paint transfer per step (engine/paint/paint.h) on footprints of 256^2 and 512^2
// pixels: the flat brush of the library (surface + strips + spines, so every
// texture-coordinate kind is mapped), a footprint shaped like a pressed brush
// (an ellipse filling ~79% of the window, depth falling off towards its rim,
// texture coordinates of all three geometry kinds), moving 2 px per step over a
// canvas with paper tooth, as a stroke does. Figures in docs/PERFORMANCE.md,
// "Paint transfer and composing".

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/paint/paint.h"

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

void BM_Transfer(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/flat.json");
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
  const std::vector<float> texels = pressedFootprint(n);
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
BENCHMARK(BM_Transfer)->ArgName("footprint_px")->Arg(256)->Arg(512)
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();

// Brush preview (render/preview/preview_renderer.h): framing, what shows where, the
// footprint inset, determinism, the empty scene, coexistence with the footprint
// renderer's context; and the FreeType label helper (render/image/text.h).

#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "llvmpipe.h"
#include "render/gl/footprint_renderer.h"
#include "render/image/png_io.h"
#include "render/preview/preview_renderer.h"
#include "render/image/text.h"

using bristle::BrushVertex;
using bristle::render::FootprintImage;
using bristle::render::Image8;
using bristle::render::PreviewOptions;
using bristle::render::PreviewScene;

namespace {

constexpr int kWidth = 400, kHeight = 300;

BrushVertex vertex(double x, double y, double z) {
  return BrushVertex{static_cast<float>(x), static_cast<float>(y), static_cast<float>(z), 0, 0};
}

// Three spines hanging from the ferrule (z = 20) to the paper, a closed tapered
// box around them as the "surface" and two thin quads as "strips".
PreviewScene handMadeScene() {
  PreviewScene scene;
  scene.handle.position_mm = Eigen::Vector3d(0, 0, 20);
  for (double x : {-3.0, 0.0, 3.0}) {
    std::vector<Eigen::Vector3d> spine;
    for (double z : {20.0, 15.0, 10.0, 5.0, 0.3}) spine.emplace_back(x * (0.4 + z / 33), 0, z);
    scene.spines.push_back(spine);
  }
  const auto corner = [](int k, bool top) {
    const double hx = top ? 4.0 : 1.5, hy = top ? 2.0 : 0.8, z = top ? 20.0 : 0.3;
    return vertex((k == 1 || k == 2) ? hx : -hx, k >= 2 ? hy : -hy, z);
  };
  const auto quad = [](std::vector<BrushVertex>* out, BrushVertex a, BrushVertex b, BrushVertex c,
                       BrushVertex d) {
    for (const BrushVertex& v : {a, b, c, a, c, d}) out->push_back(v);
  };
  for (int k = 0; k < 4; ++k) {
    quad(&scene.surface, corner(k, false), corner((k + 1) % 4, false), corner((k + 1) % 4, true),
         corner(k, true));
  }
  quad(&scene.surface, corner(3, false), corner(2, false), corner(1, false), corner(0, false));
  quad(&scene.surface, corner(0, true), corner(1, true), corner(2, true), corner(3, true));
  for (double x : {-1.0, 1.0}) {
    quad(&scene.strips, vertex(x - 0.2, 0.3, 19), vertex(x + 0.2, 0.3, 19),
         vertex(x * 0.5 + 0.2, 0.3, 0.5), vertex(x * 0.5 - 0.2, 0.3, 0.5));
  }
  scene.title = "test — 3 spines, 2 strips";
  return scene;
}

// A contact ellipse 6 x 3 mm around the origin, deepest in the middle.
FootprintImage handMadeFootprint() {
  FootprintImage fp;
  fp.window.x0_mm = -10;
  fp.window.y0_mm = -10;
  fp.window.width_px = fp.window.height_px = 160;
  fp.window.px_per_mm = 8;
  fp.texels.assign(160 * 160 * 4, 0.0f);
  for (int r = 0; r < 160; ++r) {
    for (int c = 0; c < 160; ++c) {
      const double x = -10 + (c + 0.5) / 8, y = -10 + (160 - r - 0.5) / 8;
      const double e = (x / 3) * (x / 3) + (y / 1.5) * (y / 1.5);
      if (e > 1) continue;
      float* t = &fp.texels[(static_cast<std::size_t>(r) * 160 + c) * 4];
      t[0] = 0.5f, t[1] = 0.5f, t[2] = static_cast<float>(0.1 * (1 - e)), t[3] = 1;
    }
  }
  return fp;
}

using Pixel = std::function<bool(int r, int g, int b)>;

// Pixels in [x0, x1) x [y0, y1) (clipped to the image) that satisfy `is`.
int count(const Image8& img, int x0, int y0, int x1, int y1, const Pixel& is) {
  int n = 0;
  for (int y = std::max(0, y0); y < std::min(img.height, y1); ++y) {
    for (int x = std::max(0, x0); x < std::min(img.width, x1); ++x) {
      const std::uint8_t* p = &img.pixels[(static_cast<std::size_t>(y) * img.width + x) * 3];
      n += is(p[0], p[1], p[2]) ? 1 : 0;
    }
  }
  return n;
}
int countAll(const Image8& img, const Pixel& is) {
  return count(img, 0, 0, img.width, img.height, is);
}

// Deep red spines (not sable hair, which has g ~ 0.6 r).
const Pixel kSpineRed = [](int r, int g, int b) { return r > 100 && g < 0.35 * r && b < 0.35 * r; };
// Sable hair: warm brown, clearly darker and more saturated than the paper.
const Pixel kHair = [](int r, int g, int b) { return r > g && g > b && r - b > 50 && r < 215; };
// Footprint ink: indigo.
const Pixel kInk = [](int r, int g, int b) { return b > r + 25 && b > g + 20 && r < 160; };

void save(const Image8& img, const char* name) {
  // For eyeballing while developing; failures to write are not test failures.
  try {
    bristle::render::writePng(std::string("/tmp/") + name, img);
  } catch (...) {
  }
}

}  // namespace

TEST_CASE("preview: an image of the requested size with the brush where the camera puts it",
          "[preview]") {
  const PreviewScene scene = handMadeScene();
  const PreviewOptions options{kWidth, kHeight};
  const Image8 img = bristle::render::renderPreview(scene, options);
  save(img, "bristle_test_preview.png");
  REQUIRE(img.width == kWidth);
  REQUIRE(img.height == kHeight);
  REQUIRE(img.channels == 3);
  REQUIRE(img.pixels.size() == static_cast<std::size_t>(kWidth * kHeight * 3));

  const auto cam = bristle::render::framePreview(scene, options);
  // Every spine shows in deep red around its projected middle joint.
  for (const auto& spine : scene.spines) {
    const auto p = cam.project(spine[2]);
    REQUIRE(p);
    const int x = static_cast<int>(p->x()), y = static_cast<int>(p->y());
    REQUIRE(x > 0);
    REQUIRE(x < kWidth);
    CHECK(count(img, x - 8, y - 8, x + 8, y + 8, kSpineRed) >= 5);
  }
  // Hair colour around the projected surface, not in the sky above the ferrule.
  const auto mid = cam.project(Eigen::Vector3d(2.5, 0, 12));
  REQUIRE(mid);
  CHECK(count(img, static_cast<int>(mid->x()) - 15, static_cast<int>(mid->y()) - 15,
              static_cast<int>(mid->x()) + 15, static_cast<int>(mid->y()) + 15, kHair) > 50);
  CHECK(count(img, 0, 0, 40, 40, kHair) == 0);
  // The framed geometry stays inside the image.
  for (const Eigen::Vector3d& corner :
       {Eigen::Vector3d(-4, -2, 20), Eigen::Vector3d(1.5, 0.8, 0.3)}) {
    const auto q = cam.project(corner);
    REQUIRE(q);
    CHECK(q->x() > 0);
    CHECK(q->x() < kWidth);
    CHECK(q->y() > 0);
    CHECK(q->y() < kHeight);
  }
  CHECK(countAll(img, kInk) == 0);  // no footprint given, no inset
}

TEST_CASE("preview: the footprint inset appears in the bottom-right corner", "[preview]") {
  PreviewScene scene = handMadeScene();
  const FootprintImage fp = handMadeFootprint();
  scene.footprint = &fp;
  const Image8 img = bristle::render::renderPreview(scene, {kWidth, kHeight});
  save(img, "bristle_test_preview_inset.png");
  const int ink = countAll(img, kInk);
  CHECK(ink > 100);
  CHECK(count(img, kWidth / 2, kHeight / 2, kWidth, kHeight, kInk) == ink);
  CHECK(countAll(img, kSpineRed) > 20);  // the brush is still there, beside the inset
}

TEST_CASE("preview: two renders are byte-identical", "[preview]") {
  PreviewScene scene = handMadeScene();
  const FootprintImage fp = handMadeFootprint();
  scene.footprint = &fp;
  bristle::render::PreviewRenderer renderer;
  const Image8 a = renderer.render(scene, {kWidth, kHeight});
  const Image8 b = renderer.render(scene, {kWidth, kHeight});
  const Image8 c = bristle::render::renderPreview(scene, {kWidth, kHeight});  // fresh context
  CHECK(a.pixels == b.pixels);
  CHECK(a.pixels == c.pixels);
}

TEST_CASE("preview: an empty scene renders the paper only", "[preview]") {
  const Image8 img = bristle::render::renderPreview(PreviewScene{}, {kWidth, kHeight});
  save(img, "bristle_test_preview_empty.png");
  REQUIRE(img.width == kWidth);
  REQUIRE(img.height == kHeight);
  CHECK(countAll(img, kSpineRed) == 0);
  CHECK(countAll(img, kHair) == 0);
  // Not one flat colour: backdrop, paper and grid differ.
  const auto first = [&](int x, int y) {
    return img.pixels[(static_cast<std::size_t>(y) * kWidth + x) * 3];
  };
  CHECK(first(5, 5) != first(kWidth / 2, kHeight - 60));
}

TEST_CASE("preview: coexists with a footprint renderer in one process", "[preview]") {
  bristle::render::FootprintRenderer footprints(64);
  const std::vector<bristle::render::FootprintVertex> tri = {
      {0, 0, 0, 0, 0}, {4, 0, 0, 1, 0}, {0, 4, 0, 0, 1}};
  bristle::render::FootprintWindow window;
  window.width_px = window.height_px = 32;
  FootprintImage before, after;
  footprints.render(tri, window, 0.1, &before);
  bristle::render::PreviewRenderer preview;  // a second context, now current
  const Image8 img = preview.render(handMadeScene(), {kWidth, kHeight});
  footprints.render(tri, window, 0.1, &after);  // switches back by itself
  CHECK(before.texels == after.texels);
  CHECK(countAll(preview.render(handMadeScene(), {kWidth, kHeight}), kSpineRed) ==
        countAll(img, kSpineRed));
}

TEST_CASE("preview: bad sizes and ragged triangle lists are refused", "[preview]") {
  CHECK_THROWS_AS(bristle::render::renderPreview(PreviewScene{}, {10, 300}), std::invalid_argument);
  CHECK_THROWS_AS(bristle::render::renderPreview(PreviewScene{}, {400, 5000}),
                  std::invalid_argument);
  PreviewScene ragged;
  ragged.surface.push_back(vertex(0, 0, 1));
  CHECK_THROWS_AS(bristle::render::renderPreview(ragged, {kWidth, kHeight}), std::invalid_argument);
}

TEST_CASE("text: labels rasterise on a common line with DejaVu Sans", "[preview][text]") {
  bristle::render::Font font;
  const Image8 short_label = font.rasterize("strip", 16);
  const Image8 long_label = font.rasterize("strips — 150", 16);
  CHECK(short_label.channels == 1);
  CHECK(short_label.height == long_label.height);  // one line box per size
  CHECK(long_label.width > short_label.width);
  int ink = 0;
  for (std::uint8_t v : short_label.pixels) ink += v > 128 ? 1 : 0;
  CHECK(ink > 20);
  CHECK(font.rasterize("strip", 16).pixels == short_label.pixels);
  CHECK(font.rasterize("", 16).width == 0);
  CHECK(font.rasterize("bad \xff\xfe utf-8", 16).width > 0);  // replacement glyphs, no throw
  CHECK_THROWS_AS(font.rasterize("x", 2), std::invalid_argument);
  CHECK_THROWS_AS(bristle::render::Font("/nonexistent/font.ttf"), std::runtime_error);
}

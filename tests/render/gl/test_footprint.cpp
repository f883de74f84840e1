// Footprint renderer (paper §4.2.1): pixel-exact orthographic mapping, the clip
// plane at contact_band_mm, nearest-to-canvas wins, attribute interpolation, determinism.

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <vector>

#include "llvmpipe.h"
#include "render/gl/footprint_renderer.h"

using bristle::render::FootprintImage;
using bristle::render::FootprintRenderer;
using bristle::render::FootprintVertex;
using bristle::render::FootprintWindow;

namespace {

// Attributes (u, v, depth) are interpolated in float at pixel centres from
// float vertex positions: measured error <= 1e-7 near the origin and 1e-6 with
// the geometry 300 mm away (float mm carry ~3e-5 mm there); 1e-5 leaves room.
constexpr double kInterpolationTol = 1e-5;

FootprintRenderer& sharedRenderer() {
  static FootprintRenderer renderer;
  return renderer;
}

FootprintWindow makeWindow(double x0_mm, double y0_mm, int width_px, int height_px,
                           double px_per_mm) {
  FootprintWindow w;
  w.x0_mm = x0_mm;
  w.y0_mm = y0_mm;
  w.width_px = width_px;
  w.height_px = height_px;
  w.px_per_mm = px_per_mm;
  return w;
}

// World position of a pixel centre, straight from the FootprintWindow contract.
double centreX(const FootprintWindow& w, int col) { return w.x0_mm + (col + 0.5) / w.px_per_mm; }
double centreY(const FootprintWindow& w, int row) {
  return w.y0_mm + (w.height_px - row - 0.5) / w.px_per_mm;
}

// An axis-aligned rectangle [xa, xb] x [ya, yb] as two triangles; z(x) and the
// texture coordinate (u, v)(x, y) are affine, given by their corner values.
struct QuadSpec {
  double xa, ya, xb, yb;
  double z_at_xa, z_at_xb;
  double u_at_xa = 0, u_at_xb = 0, v_at_ya = 0, v_at_yb = 0;
};

void addQuad(std::vector<FootprintVertex>* tris, const QuadSpec& q) {
  auto corner = [&](bool right, bool top) {
    return FootprintVertex{static_cast<float>(right ? q.xb : q.xa),
                           static_cast<float>(top ? q.yb : q.ya),
                           static_cast<float>(right ? q.z_at_xb : q.z_at_xa),
                           static_cast<float>(right ? q.u_at_xb : q.u_at_xa),
                           static_cast<float>(top ? q.v_at_yb : q.v_at_ya)};
  };
  const FootprintVertex bl = corner(false, false), br = corner(true, false),
                        tr = corner(true, true), tl = corner(false, true);
  tris->insert(tris->end(), {bl, br, tr, bl, tr, tl});
}

QuadSpec flatQuad(double xa, double ya, double xb, double yb, double z, double u, double v) {
  return {xa, ya, xb, yb, z, z, u, u, v, v};
}

std::uint64_t hashTexels(const FootprintImage& image) {
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a 64
  const auto* bytes = reinterpret_cast<const unsigned char*>(image.texels.data());
  for (std::size_t i = 0; i < image.texels.size() * sizeof(float); ++i) {
    h = (h ^ bytes[i]) * 1099511628211ull;
  }
  return h;
}

bool allZero(const float* t) { return t[0] == 0 && t[1] == 0 && t[2] == 0 && t[3] == 0; }

// A reproducible soup of triangles (own LCG: std distributions differ across
// standard libraries) around and through the clip plane.
std::vector<FootprintVertex> triangleSoup(const FootprintWindow& w, int count) {
  std::uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;  // [0, 1)
  };
  const double width_mm = w.width_px / w.px_per_mm, height_mm = w.height_px / w.px_per_mm;
  std::vector<FootprintVertex> tris;
  for (int i = 0; i < 3 * count; ++i) {
    tris.push_back({static_cast<float>(w.x0_mm + (1.2 * next() - 0.1) * width_mm),
                    static_cast<float>(w.y0_mm + (1.2 * next() - 0.1) * height_mm),
                    static_cast<float>(-0.5 + 1.5 * next()), static_cast<float>(next()),
                    static_cast<float>(next())});
  }
  return tris;
}

}  // namespace

TEST_CASE("footprint: a flat quad covers exactly the pixels whose centres it contains",
          "[footprint]") {
  REQUIRE(kGalliumDriverCleared);
  // 0.25 mm pixels; window x in [10, 20], y in [20, 27.5]. The quad sits in the
  // upper left, its edges 0.1-0.3 px away from any pixel centre.
  const FootprintWindow window = makeWindow(10, 20, 40, 30, 4);
  const double contact_band_mm = 0.5;
  std::vector<FootprintVertex> tris;
  addQuad(&tris, flatQuad(10.6, 24.35, 14.1, 27.2, 0.0, 0.3, 0.7));
  FootprintImage image;
  sharedRenderer().render(tris, window, contact_band_mm, &image);
  REQUIRE(image.texels.size() == 40u * 30u * 4u);

  int covered = 0, first_col = -1, first_row = -1, last_col = -1, last_row = -1;
  for (int row = 0; row < window.height_px; ++row) {
    for (int col = 0; col < window.width_px; ++col) {
      const double x = centreX(window, col), y = centreY(window, row);
      const bool inside = x > 10.6 && x < 14.1 && y > 24.35 && y < 27.2;
      const float* t = image.at(col, row);
      INFO("col " << col << " row " << row);
      if (!inside) {
        REQUIRE(allZero(t));
        continue;
      }
      REQUIRE(t[3] == 1.0f);
      REQUIRE(t[0] == Approx(0.3f).margin(kInterpolationTol));
      REQUIRE(t[1] == Approx(0.7f).margin(kInterpolationTol));
      REQUIRE(t[2] == Approx(contact_band_mm - 0.0).margin(kInterpolationTol));
      if (covered++ == 0) first_col = col, first_row = row;
      last_col = col, last_row = row;
    }
  }
  // Known answer, by hand: x centres 10.625..13.875 are columns 2..15; y centres
  // 27.125..24.375 are rows 1..12 (row 0 is the top, y = 27.375).
  CHECK(covered == 14 * 12);
  CHECK(first_col == 2);
  CHECK(first_row == 1);
  CHECK(last_col == 15);
  CHECK(last_row == 12);
}

TEST_CASE("footprint: geometry above the clip plane leaves no trace", "[footprint]") {
  const FootprintWindow window = makeWindow(0, 0, 32, 16, 4);
  const double contact_band_mm = 0.5;
  std::vector<FootprintVertex> tris;
  addQuad(&tris, flatQuad(1.1, 0.6, 7.1, 3.6, contact_band_mm + 0.1, 0.5, 0.5));
  FootprintImage image;
  sharedRenderer().render(tris, window, contact_band_mm, &image);
  for (float value : image.texels) REQUIRE(value == 0.0f);
}

TEST_CASE("footprint: a quad tilted through the clip plane keeps its lower half",
          "[footprint]") {
  // z rises from 0 at x = 1.1 to 2 * clip at x = 7.1, so z <= clip for x <= 4.1.
  const FootprintWindow window = makeWindow(0, 0, 32, 16, 4);
  const double contact_band_mm = 0.5, xa = 1.1, xb = 7.1;
  std::vector<FootprintVertex> tris;
  addQuad(&tris, {xa, 0.6, xb, 3.6, 0.0, 2 * contact_band_mm, 0.2, 0.8, 0.1, 0.9});
  FootprintImage image;
  sharedRenderer().render(tris, window, contact_band_mm, &image);

  const double dz_dx_per_mm = 2 * contact_band_mm / (xb - xa);
  int covered = 0;
  for (int row = 0; row < window.height_px; ++row) {
    for (int col = 0; col < window.width_px; ++col) {
      const double x = centreX(window, col), y = centreY(window, row);
      const float* t = image.at(col, row);
      INFO("col " << col << " row " << row);
      if (!(x > xa && x < 4.1 && y > 0.6 && y < 3.6)) {
        REQUIRE(allZero(t));
        continue;
      }
      ++covered;
      REQUIRE(t[3] == 1.0f);
      const double z = dz_dx_per_mm * (x - xa);
      REQUIRE(t[2] == Approx(contact_band_mm - z).margin(kInterpolationTol));
      REQUIRE(t[2] > 0.0f);
    }
  }
  CHECK(covered == 12 * 12);  // columns 4..15 (x 1.125..3.875), rows 2..13
}

TEST_CASE("footprint: where quads overlap, the one nearer the canvas wins", "[footprint]") {
  const FootprintWindow window = makeWindow(0, 0, 32, 16, 4);
  const double contact_band_mm = 0.5;
  const QuadSpec low = flatQuad(1.1, 0.6, 5.1, 3.6, 0.1, 0.25, 0.25);
  const QuadSpec high = flatQuad(3.1, 0.6, 7.1, 3.6, 0.3, 0.75, 0.5);
  std::vector<FootprintVertex> low_first, high_first;
  addQuad(&low_first, low);
  addQuad(&low_first, high);
  addQuad(&high_first, high);
  addQuad(&high_first, low);

  FootprintImage a, b;
  sharedRenderer().render(low_first, window, contact_band_mm, &a);
  sharedRenderer().render(high_first, window, contact_band_mm, &b);
  // The depth test, not the draw order, decides.
  REQUIRE(hashTexels(a) == hashTexels(b));

  const int row = 8;  // y = 1.875, inside both quads
  for (int col = 0; col < window.width_px; ++col) {
    const double x = centreX(window, col);
    const float* t = a.at(col, row);
    INFO("col " << col);
    if (x > 1.1 && x < 5.1) {
      REQUIRE(t[0] == Approx(0.25f).margin(kInterpolationTol));
      REQUIRE(t[1] == Approx(0.25f).margin(kInterpolationTol));
      REQUIRE(t[2] == Approx(contact_band_mm - 0.1).margin(kInterpolationTol));
    } else if (x > 5.1 && x < 7.1) {
      REQUIRE(t[0] == Approx(0.75f).margin(kInterpolationTol));
      REQUIRE(t[1] == Approx(0.5f).margin(kInterpolationTol));
      REQUIRE(t[2] == Approx(contact_band_mm - 0.3).margin(kInterpolationTol));
    } else {
      REQUIRE(allZero(t));
    }
  }
}

TEST_CASE("footprint: u and v interpolate linearly across a quad", "[footprint]") {
  // Also far from the origin, where float millimetres are coarsest.
  const double x0_mm = GENERATE(0.0, 300.0);
  const FootprintWindow window = makeWindow(x0_mm, 0, 32, 16, 4);
  const double xa = x0_mm + 1.1, xb = x0_mm + 7.1, ya = 0.6, yb = 3.6;
  std::vector<FootprintVertex> tris;
  addQuad(&tris, {xa, ya, xb, yb, 0.2, 0.2, 0.0, 1.0, 0.0, 1.0});
  FootprintImage image;
  sharedRenderer().render(tris, window, 0.5, &image);

  int covered = 0;
  for (int row = 0; row < window.height_px; ++row) {
    for (int col = 0; col < window.width_px; ++col) {
      const double x = centreX(window, col), y = centreY(window, row);
      if (!(x > xa && x < xb && y > ya && y < yb)) continue;
      ++covered;
      const float* t = image.at(col, row);
      INFO("col " << col << " row " << row);
      REQUIRE(t[0] == Approx((x - xa) / (xb - xa)).margin(kInterpolationTol));
      REQUIRE(t[1] == Approx((y - ya) / (yb - ya)).margin(kInterpolationTol));
    }
  }
  CHECK(covered == 24 * 12);
}

TEST_CASE("footprint: the same geometry renders to the same bytes", "[footprint]") {
  const FootprintWindow window = makeWindow(3, 5, 64, 48, 8);
  const std::vector<FootprintVertex> tris = triangleSoup(window, 200);
  const double contact_band_mm = 0.4;
  FootprintImage first, second, fresh;
  sharedRenderer().render(tris, window, contact_band_mm, &first);
  sharedRenderer().render(tris, window, contact_band_mm, &second);
  FootprintRenderer other;
  other.render(tris, window, contact_band_mm, &fresh);

  int covered = 0;
  for (int row = 0; row < window.height_px; ++row) {
    for (int col = 0; col < window.width_px; ++col) covered += first.at(col, row)[3] > 0;
  }
  CHECK(covered > 100);  // not vacuous: the soup does reach below the clip plane
  CHECK(covered < 64 * 48);
  CHECK(hashTexels(first) == hashTexels(second));
  CHECK(hashTexels(first) == hashTexels(fresh));
}

TEST_CASE("footprint: triangles that can mark no pixel are left out, and the bytes stay the same",
          "[footprint]") {
  const FootprintWindow window = makeWindow(2, 3, 48, 40, 4);
  const double px = 1.0 / window.px_per_mm;  // mm per pixel
  const double contact_band_mm = 0.4;
  std::uint64_t state = 777;
  auto next = [&state] {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(state >> 11) / 9007199254740992.0;  // [0, 1)
  };
  // A triangle inside the box [xa, xb] x [ya, yb] (mm), touching the paper.
  auto triangle = [&](std::vector<FootprintVertex>* tris, double xa, double ya, double xb,
                      double yb, float u) {
    tris->push_back({float(xa), float(ya), 0.0f, u, 0.5f});
    tris->push_back({float(xb), float(ya + 0.3 * (yb - ya)), 0.1f, u, 0.5f});
    tris->push_back({float(xa + 0.6 * (xb - xa)), float(yb), 0.2f, u, 0.5f});
  };
  std::vector<FootprintVertex> tris;
  int must_draw = 0, between = 0;
  // Inside the open square between four pixel centres, 0.1 px clear of each:
  // no centre to mark. Not hair: left out; hair: drawn (its band marks pixels).
  // The triangles are counter-clockwise; the slivers below clockwise.
  for (int i = 0; i < 60; ++i) {
    const int col = static_cast<int>(next() * (window.width_px - 1));
    const int row = static_cast<int>(next() * (window.height_px - 1));
    const double xa = window.x0_mm + (col + 0.6) * px, ya = window.y0_mm + (row + 0.6) * px;
    const bool hair = i % 3 == 0;
    triangle(&tris, xa, ya, xa + 0.8 * px, ya + 0.8 * px, hair ? 2.5f : 0.5f);
    if (hair) ++must_draw; else ++between;
  }
  // Slivers along a diagonal halfway between rows of centres (0.35 px from the
  // nearest): their boxes hold centres, the triangles none. Not hair: left out.
  for (int i = 0; i < 20; ++i) {
    const int col = static_cast<int>(next() * (window.width_px - 4));
    const int row = static_cast<int>(next() * (window.height_px - 4));
    auto at = [&](double c, double r, float z) {
      return FootprintVertex{float(window.x0_mm + c * px), float(window.y0_mm + r * px), z, 0.5f,
                             0.5f};
    };
    tris.push_back(at(col + 0.5, row + 1.0, 0.0f));
    tris.push_back(at(col + 2.5, row + 3.0, 0.1f));
    tris.push_back(at(col + 2.55, row + 2.95, 0.2f));
    ++between;
  }
  // Holding a pixel centre: always drawn.
  for (int i = 0; i < 40; ++i) {
    const int col = static_cast<int>(next() * window.width_px);
    const int row = static_cast<int>(next() * window.height_px);
    const double cx = window.x0_mm + (col + 0.5) * px, cy = window.y0_mm + (row + 0.5) * px;
    triangle(&tris, cx - 0.3 * px, cy - 0.3 * px, cx + 0.7 * px, cy + 0.7 * px, 0.25f);
    ++must_draw;
  }
  // A sub-pixel soup anywhere, many of its boxes just reaching a centre or
  // just short of one: the bytes must not tell whether it was sorted.
  const std::size_t before_soup = tris.size() / 3;
  for (int i = 0; i < 600; ++i) {
    const double x = window.x0_mm + next() * window.width_px * px;
    const double y = window.y0_mm + next() * window.height_px * px;
    const double size = (0.1 + 1.2 * next()) * px;
    triangle(&tris, x, y, x + size, y + size * (0.3 + next()), next() < 0.2 ? 3.0f : 0.75f);
  }
  const std::size_t soup = tris.size() / 3 - before_soup;

  FootprintRenderer& renderer = sharedRenderer();
  renderer.setHairTextureRange(2.0f, 4.0f);
  FootprintImage all, sorted;
  renderer.setSkipUnmarking(false);
  renderer.render(tris, window, contact_band_mm, &all);
  const std::size_t drawn_all = renderer.lastDrawnTriangles();
  renderer.setSkipUnmarking(true);
  renderer.render(tris, window, contact_band_mm, &sorted);
  const std::size_t drawn_sorted = renderer.lastDrawnTriangles();
  // Only the "between" triangles and the slivers: exactly those go.
  std::vector<FootprintVertex> fixed(tris.begin(), tris.begin() + 3 * before_soup);
  FootprintImage fixed_image;
  renderer.setSkipUnmarking(true);  // testing, whatever the draw before dropped
  renderer.render(fixed, window, contact_band_mm, &fixed_image);
  const std::size_t drawn_fixed = renderer.lastDrawnTriangles();
  renderer.setHairTextureRange(std::numeric_limits<float>::lowest(),
                               std::numeric_limits<float>::max());

  int covered = 0;
  for (std::size_t i = 3; i < all.texels.size(); i += 4) covered += all.texels[i] > 0;
  CHECK(covered > 200);  // not vacuous: the triangles do mark pixels
  CHECK(drawn_all == tris.size() / 3);
  CHECK(drawn_fixed == static_cast<std::size_t>(must_draw));
  CHECK(between > 0);
  CHECK(drawn_sorted < drawn_all - between);  // some of the soup went too
  CHECK(drawn_sorted > drawn_all - between - soup);  // and some of it stayed
  CHECK(hashTexels(all) == hashTexels(sorted));
}

TEST_CASE("footprint: after a footprint that drops few triangles, the next 15 are sent whole",
          "[footprint]") {
  const FootprintWindow window = makeWindow(0, 0, 32, 32, 4);
  const double px = 1.0 / window.px_per_mm;
  std::vector<FootprintVertex> dense, sparse;
  // 64 quads over the window: every triangle holds a centre, none is dropped.
  for (int i = 0; i < 8; ++i)
    for (int j = 0; j < 8; ++j)
      addQuad(&dense, flatQuad(4 * i * px, 4 * j * px, (4 * i + 3) * px, (4 * j + 3) * px, 0.0,
                               0.5, 0.5));
  // The same, and as many triangles between centres, each of which could go.
  sparse = dense;
  for (int k = 0; k < 128; ++k) {
    const double x = (k % 30 + 0.6) * px, y = (k / 30 + 0.6) * px;
    sparse.push_back({float(x), float(y), 0.0f, 0.5f, 0.5f});
    sparse.push_back({float(x + 0.8 * px), float(y), 0.0f, 0.5f, 0.5f});
    sparse.push_back({float(x), float(y + 0.8 * px), 0.0f, 0.5f, 0.5f});
  }
  FootprintRenderer& renderer = sharedRenderer();
  renderer.setHairTextureRange(2.0f, 4.0f);  // none of these is hair
  renderer.setSkipUnmarking(true);
  FootprintImage image, whole;
  renderer.render(dense, window, 0.5, &image);  // nothing dropped: a rest follows
  CHECK(renderer.lastDrawnTriangles() == dense.size() / 3);
  std::vector<std::size_t> drawn;
  for (int k = 0; k < 17; ++k) {
    renderer.render(sparse, window, 0.5, &image);
    drawn.push_back(renderer.lastDrawnTriangles());
  }
  for (int k = 0; k < 15; ++k) CHECK(drawn[k] == sparse.size() / 3);  // sent whole
  CHECK(drawn[15] == dense.size() / 3);  // tested again: the 128 dropped
  CHECK(drawn[16] == dense.size() / 3);  // half of them dropped: it keeps testing
  renderer.setSkipUnmarking(false);
  renderer.render(sparse, window, 0.5, &whole);
  renderer.setSkipUnmarking(true);
  renderer.setHairTextureRange(std::numeric_limits<float>::lowest(),
                               std::numeric_limits<float>::max());
  CHECK(hashTexels(image) == hashTexels(whole));
}

TEST_CASE("footprint: a hair finer than a pixel covers its share where it misses every centre",
          "[footprint]") {
  // A strip 0.3 px wide, 32 px long, centred on the boundary between two rows
  // of pixel centres (y = 5 px): sampling centres alone, it left no footprint
  // at all (a fan dragged along its own row of hairs did exactly this).
  const FootprintWindow window = makeWindow(0, 0, 40, 10, 4);  // 0.25 mm pixels
  const double contact_band_mm = 0.5, width_px = 0.3, y_mid = 5.0 / 4;
  const double half_mm = 0.5 * width_px / window.px_per_mm;
  std::vector<FootprintVertex> tris;
  addQuad(&tris, flatQuad(1.0, y_mid - half_mm, 9.0, y_mid + half_mm, 0.1, 0.25, 0.5));
  FootprintImage image;
  sharedRenderer().render(tris, window, contact_band_mm, &image);

  double claimed = 0;  // covered area, in pixels
  for (int row = 0; row < window.height_px; ++row)
    for (int col = 0; col < window.width_px; ++col) {
      const float* t = image.at(col, row);
      if (t[3] == 0) continue;
      INFO("col " << col << " row " << row << " coverage " << t[3]);
      // Only the two rows beside the line, only within its length (one pixel
      // of slack at each end, where the stretched triangles' tips fall).
      CHECK((row == 4 || row == 5));
      CHECK((col >= 3 && col <= 36));
      // A share of the pixel, never more than the whole.
      CHECK(t[3] > 0.0f);
      CHECK(t[3] <= 1.0f);
      // The hair's own texture coordinate and depth, not a neighbour's.
      CHECK(t[0] == Approx(0.25f).margin(kInterpolationTol));
      CHECK(t[2] == Approx(contact_band_mm - 0.1).margin(kInterpolationTol));
      claimed += t[3];
    }
  // Every column the hair crosses is touched: a continuous line, not dots.
  for (int col = 4; col < 36; ++col) {
    INFO("col " << col);
    CHECK((image.at(col, 4)[3] > 0 || image.at(col, 5)[3] > 0));
  }
  // Area: what the hair covers (32 x 0.3 px), within one column's share at
  // either end (where the band's end meets a column part-way).
  const double area = 32 * width_px;
  INFO("claimed " << claimed << " px of " << area);
  CHECK(claimed == Approx(area).margin(width_px));
}

TEST_CASE("footprint: only hair triangles mark the pixels their centres miss", "[footprint]") {
  // The stroke renderer counts the strips (u in [2, 4)) as single hairs; the
  // surface and the bundles (here u = 0.25) are sampled at pixel centres only.
  const FootprintWindow window = makeWindow(0, 0, 40, 10, 4);
  const double half_mm = 0.5 * 0.3 / window.px_per_mm;  // 0.3 px wide
  auto covered = [&](double u) {
    std::vector<FootprintVertex> tris;
    addQuad(&tris, flatQuad(1.0, 1.25 - half_mm, 9.0, 1.25 + half_mm, 0.0, u, 0.5));
    FootprintImage image;
    sharedRenderer().render(tris, window, 0.5, &image);
    int n = 0;
    for (std::size_t i = 3; i < image.texels.size(); i += 4) n += image.texels[i] > 0;
    return n;
  };
  sharedRenderer().setHairTextureRange(2.0f, 4.0f);
  const int bundle = covered(0.25), hair = covered(2.5);
  sharedRenderer().setHairTextureRange(std::numeric_limits<float>::lowest(),
                                       std::numeric_limits<float>::max());
  CHECK(bundle == 0);   // between two rows of centres: none covered
  CHECK(hair >= 32);    // a pixel in each of the 32 columns it crosses
}

TEST_CASE("footprint: a hair finer than a pixel never lowers the coverage of real geometry",
          "[footprint]") {
  // A wide quad under the pixel centres and a hair nearer the canvas that
  // covers no centre: the pixels keep the quad's full coverage and texel.
  const FootprintWindow window = makeWindow(0, 0, 20, 10, 4);
  const double contact_band_mm = 0.5;
  std::vector<FootprintVertex> tris;
  addQuad(&tris, flatQuad(0.0, 0.0, 5.0, 2.5, 0.3, 0.75, 0.75));
  addQuad(&tris, flatQuad(0.5, 1.25 - 0.02, 4.5, 1.25 + 0.02, 0.0, 0.25, 0.25));
  FootprintImage image;
  sharedRenderer().render(tris, window, contact_band_mm, &image);
  for (int row = 0; row < window.height_px; ++row)
    for (int col = 0; col < window.width_px; ++col) {
      INFO("col " << col << " row " << row);
      const float* t = image.at(col, row);
      CHECK(t[3] == 1.0f);
      CHECK(t[0] == Approx(0.75f).margin(kInterpolationTol));
    }
}

TEST_CASE("footprint: a smaller window after a bigger one", "[footprint]") {
  const FootprintWindow big = makeWindow(3, 5, 64, 48, 8);
  const FootprintWindow small = makeWindow(3, 5, 24, 16, 8);  // bottom-left of big
  const std::vector<FootprintVertex> tris = triangleSoup(big, 200);
  const double contact_band_mm = 0.4;
  FootprintRenderer renderer;
  FootprintImage big_image, small_image, reference;
  renderer.render(tris, big, contact_band_mm, &big_image);
  renderer.render(tris, small, contact_band_mm, &small_image);
  FootprintRenderer().render(tris, small, contact_band_mm, &reference);

  REQUIRE(small_image.texels.size() == 24u * 16u * 4u);
  CHECK(small_image.window.width_px == 24);
  CHECK(hashTexels(small_image) == hashTexels(reference));
  // The same pixels of the big window saw the same geometry. The NDC scale
  // differs, so float rounding may move values by a few ulps; coverage must agree.
  for (int row = 0; row < small.height_px; ++row) {
    for (int col = 0; col < small.width_px; ++col) {
      const float* s = small_image.at(col, row);
      const float* b = big_image.at(col, row + big.height_px - small.height_px);
      INFO("col " << col << " row " << row);
      REQUIRE(s[3] == b[3]);
      for (int k = 0; k < 3; ++k) REQUIRE(s[k] == Approx(b[k]).margin(kInterpolationTol));
    }
  }
}

TEST_CASE("footprint: empty input and bad arguments", "[footprint]") {
  FootprintRenderer& renderer = sharedRenderer();
  FootprintImage image;
  renderer.render({}, makeWindow(0, 0, 8, 4, 4), 0.5, &image);
  REQUIRE(image.texels.size() == 8u * 4u * 4u);
  for (float value : image.texels) REQUIRE(value == 0.0f);

  renderer.render({}, makeWindow(0, 0, 0, 4, 4), 0.5, &image);
  CHECK(image.texels.empty());

  std::vector<FootprintVertex> two(2, FootprintVertex{0, 0, 0, 0, 0});
  CHECK_THROWS_AS(renderer.render(two, makeWindow(0, 0, 8, 4, 4), 0.5, &image),
                  std::invalid_argument);
  CHECK_THROWS_AS(renderer.render({}, makeWindow(0, 0, 4096, 4, 4), 0.5, &image),
                  std::invalid_argument);
  CHECK_THROWS_AS(renderer.render({}, makeWindow(0, 0, 8, 4, 0), 0.5, &image),
                  std::invalid_argument);
  CHECK_THROWS_AS(FootprintRenderer(0), std::invalid_argument);
}

TEST_CASE("footprint: an unusable GALLIUM_DRIVER is an error, not a crash", "[footprint]") {
  REQUIRE(::setenv("GALLIUM_DRIVER", "no-such-driver", 1) == 0);
  std::string message;
  try {
    FootprintRenderer renderer;
  } catch (const std::runtime_error& e) {
    message = e.what();
  }
  ::unsetenv("GALLIUM_DRIVER");
  CHECK_THAT(message, Catch::Contains("GALLIUM_DRIVER=no-such-driver"));
}

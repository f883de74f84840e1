#include "engine/paint/paint.h"

#include <libqhull_r/qhull_ra.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <utility>

#include "engine/geometry/bristle_strips.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/geometry/brush_surface.h"
#include "engine/base/error.h"

namespace bristle {
namespace {

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// Half-width (in w) of the blend between two paints loaded side by side: a
// painter dabs a double-loaded brush back and forth on the palette, which works
// the two colours into each other over a band in the middle of the brush.
constexpr double kAcrossBlendHalfWidth = 0.15;
// Half-width (in v) of the blend between body and tip paint.
constexpr double kTipBlendHalfWidth = 0.05;
// How much a fully diluted paint (dilution 1) thins its pigment: K and S scaled
// by 1 - this, and how much faster it flows (flow = 1 + dilution).
constexpr double kDilutionThinning = 0.7;
// How far apart the hairs' dry thresholds lie (see transfer): a fully dry
// texel's barest hair (hair noise 0) needs tooth 0.9 + 1.0, which no paper
// has, and its best (1) needs 0.9 - 1.0, which all has; so a spent brush
// draws the lines of its best hairs, broken by the grain, not the grain's
// dots (docs/paint.md, "Hair streaks").
constexpr float kHairVariation = 2.0f;
// The width of the tooth band over which a drying hair goes from no paint to full paint.
constexpr float kInvDryEdge = 1 / 0.15f;
// Volumes below this (mm^3) are treated as no paint (float noise, ~1e-6 of a pixel's film).
constexpr float kVolumeEpsMm3 = 1e-12f;

void mixInto(PaintCell& cell, float keep_mm3, const Optics& add, float add_mm3) {
  const float total = keep_mm3 + add_mm3;
  if (total <= kVolumeEpsMm3) {
    cell.volume_mm3 = std::max(total, 0.0f);
    return;
  }
  const float a = keep_mm3 / total, b = add_mm3 / total;
  for (int i = 0; i < 3; ++i) {
    cell.optics.k[i] = a * cell.optics.k[i] + b * add.k[i];
    cell.optics.s[i] = a * cell.optics.s[i] + b * add.s[i];
  }
  cell.volume_mm3 = total;
}

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

double latticeValue(std::int64_t ix, std::int64_t iy, std::uint64_t seed) {
  const std::uint64_t h =
      splitmix(seed ^ splitmix(static_cast<std::uint64_t>(ix) * 0x632be59bd9b4e019ULL ^
                               splitmix(static_cast<std::uint64_t>(iy))));
  return (h >> 11) * (1.0 / 9007199254740992.0);  // 53 bits -> [0, 1)
}

double valueNoise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = smoothstep(x - fx), ty = smoothstep(y - fy);
  const double a = latticeValue(ix, iy, seed), b = latticeValue(ix + 1, iy, seed);
  const double c = latticeValue(ix, iy + 1, seed), d = latticeValue(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) * (1 - ty) + (c + (d - c) * tx) * ty;
}

// Hair noise at s mm along a row of hairs `span` mm long: two octaves of value
// noise, features kHairStreakMm and half that wide, stretched so that the
// hairs range from nearly bare to fully loaded (value noise of two octaves
// keeps mostly to its middle). `periodic`: the row closes on itself (around a
// cross-section), so its noise wraps with no seam.
double hairRowNoise(double s, double span, bool periodic, std::uint64_t seed) {
  double sum = 0;
  const double weights[2] = {0.6, 0.4};
  for (int octave = 0; octave < 2; ++octave) {
    const double feature = BrushTexelMap::kHairStreakMm / (1 << octave);
    const std::int64_t cells =
        std::max<std::int64_t>(1, std::llround(span / feature));
    const double x = s / span * static_cast<double>(cells);
    const double fx = std::floor(x);
    std::int64_t i0 = static_cast<std::int64_t>(fx), i1 = i0 + 1;
    if (periodic) {
      i0 = ((i0 % cells) + cells) % cells;
      i1 = ((i1 % cells) + cells) % cells;
    }
    const double a = latticeValue(i0, octave, seed), b = latticeValue(i1, octave, seed);
    sum += weights[octave] * (a + (b - a) * smoothstep(x - fx));
  }
  return smoothstep((sum - 0.2) / 0.6);
}

constexpr std::uint64_t kHairSeedAround = 0x68616972'61726fULL;
constexpr std::uint64_t kHairSeedAcross = 0x68616972'616372ULL;
constexpr std::uint64_t kHairSeedStrips = 0x68616972'737472ULL;

}  // namespace

// ---------------------------------------------------------------- BrushTexelMap

BrushTexelMap::BrushTexelMap(const Brush& brush) {
  spines_ = static_cast<int>(brush.spines.size());
  double lo = 1e300, hi = -1e300, length = 0;
  for (const SpineSpec& s : brush.spines) {
    const double half = s.width_mm.empty() ? 0 : 0.5 * s.width_mm.front();
    lo = std::min(lo, s.root_mm.x() - half);
    hi = std::max(hi, s.root_mm.x() + half);
    double l = 0;
    for (double seg : s.segment_lengths_mm) l += seg;
    length = std::max(length, l);
  }
  std::unique_ptr<BrushSurface> surface;
  if (brush.surface.present()) {
    surface = std::make_unique<BrushSurface>(brush);
    for (int i = 0; i < surface->refinedVertexCount(); ++i) {
      const double x = surface->refinedRestPosition(i).x();
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  if (!(hi > lo)) {
    lo = -0.5;
    hi = 0.5;
  }
  x0_ = lo;
  x1_ = hi;
  texel_area_mm2_ = std::max(hi - lo, 1e-3) * std::max(length, 1e-3) / kTexels;

  for (const SpineSpec& s : brush.spines) {
    spine_w_.push_back(lateral(s.root_mm.x()));
    const double width = s.width_mm.empty() ? 0 : s.width_mm.front();
    spine_dw_.push_back(static_cast<float>(width / (x1_ - x0_)));
  }

  if (brush.strips.present()) {
    const StripLayout layout = layoutStrips(brush);
    strips_ = layout.count;
    strip_root_width_mm_ = static_cast<float>(brush.strips.root_width_mm);
    strip_tip_width_mm_ = static_cast<float>(brush.strips.tip_width_mm);
    for (int k = 0; k < layout.count; ++k) {
      strip_w_.push_back(lateral(layout.roots_mm[k].x()));
      strip_hair_.push_back(static_cast<float>(
          smoothstep((latticeValue(k, 0, kHairSeedStrips) - 0.1) / 0.8)));
    }
  }
  const double width = x1_ - x0_;
  if (spines_ > 0) {
    const size_t n = static_cast<size_t>(std::ceil(width / kHairTableStepMm));
    for (size_t i = 0; i <= n; ++i)
      hair_across_.push_back(static_cast<float>(
          hairRowNoise(width * static_cast<double>(i) / n, width, false, kHairSeedAcross)));
  }

  // Surface: mean rest x of the refined vertices in each (u, v) bin; an empty
  // bin takes the mean of its u column, and an empty column a straight brush's
  // cos(2 pi u) across the width.
  surface_w_.assign(kSurfaceBinsU * kSurfaceBinsV, 0.5f);
  if (surface) {
    std::vector<double> sum(surface_w_.size(), 0), col_sum(kSurfaceBinsU, 0);
    std::vector<int> n(surface_w_.size(), 0), col_n(kSurfaceBinsU, 0);
    for (int i = 0; i < surface->refinedVertexCount(); ++i) {
      const Eigen::Vector2f uv = surface->uv(i);
      double u = uv.x() - std::floor(uv.x());
      const int bu = std::min(kSurfaceBinsU - 1, static_cast<int>(u * kSurfaceBinsU));
      const int bv = std::clamp(static_cast<int>(uv.y() * kSurfaceBinsV), 0, kSurfaceBinsV - 1);
      const double w = lateral(surface->refinedRestPosition(i).x());
      sum[bv * kSurfaceBinsU + bu] += w;
      n[bv * kSurfaceBinsU + bu] += 1;
      col_sum[bu] += w;
      col_n[bu] += 1;
    }
    for (int bu = 0; bu < kSurfaceBinsU; ++bu) {
      const double u = (bu + 0.5) / kSurfaceBinsU;
      const double col = col_n[bu] > 0 ? col_sum[bu] / col_n[bu]
                                       : 0.5 + 0.5 * std::cos(2 * M_PI * u);
      for (int bv = 0; bv < kSurfaceBinsV; ++bv) {
        const int b = bv * kSurfaceBinsU + bu;
        surface_w_[b] = static_cast<float>(n[b] > 0 ? sum[b] / n[b] : col);
      }
    }
    buildSurfaceHair(*surface);
  }
}

// The rest cross-section as a closed curve in u: the mean rest (x, y) of the
// refined vertices in each populated u bin, in order of u. Arc length along it
// gives each surface hair its place in the bundle in mm.
void BrushTexelMap::buildSurfaceHair(const BrushSurface& surface) {
  struct Bin {
    double u = 0, x = 0, y = 0;
    int n = 0;
  };
  std::vector<Bin> bins(kSurfaceBinsU);
  for (int i = 0; i < surface.refinedVertexCount(); ++i) {
    const double u = surface.uv(i).x() - std::floor(surface.uv(i).x());
    Bin& b = bins[std::min(kSurfaceBinsU - 1, static_cast<int>(u * kSurfaceBinsU))];
    const Eigen::Vector3d p = surface.refinedRestPosition(i);
    b.u += u;
    b.x += p.x();
    b.y += p.y();
    ++b.n;
  }
  std::vector<Bin> ring;
  for (Bin& b : bins)
    if (b.n > 0) {
      b.u /= b.n;
      b.x /= b.n;
      b.y /= b.n;
      ring.push_back(b);
    }
  if (ring.size() < 3) return;
  // Cumulative arc length at each populated bin, and the closed perimeter.
  const size_t m = ring.size();
  std::vector<double> arc(m, 0.0);
  double run = 0;
  for (size_t k = 1; k < m; ++k) {
    run += std::hypot(ring[k].x - ring[k - 1].x, ring[k].y - ring[k - 1].y);
    arc[k] = run;
  }
  const double perimeter = run + std::hypot(ring[0].x - ring[m - 1].x, ring[0].y - ring[m - 1].y);
  if (!(perimeter > 1e-6)) return;
  // Arc length at each bin edge u = e / kSurfaceBinsU, interpolated between
  // populated bins (wrapping past the last to the first plus the perimeter).
  surface_s_.assign(kSurfaceBinsU + 1, 0);
  for (int e = 0; e <= kSurfaceBinsU; ++e) {
    const double u = static_cast<double>(e) / kSurfaceBinsU;
    size_t hi = 0;
    while (hi < ring.size() && ring[hi].u < u) ++hi;
    double u0, s0, u1, s1;
    if (hi == 0) {
      u0 = ring[m - 1].u - 1;
      s0 = run - perimeter;
      u1 = ring[0].u;
      s1 = 0;
    } else if (hi == m) {
      u0 = ring[m - 1].u;
      s0 = run;
      u1 = ring[0].u + 1;
      s1 = perimeter;
    } else {
      u0 = ring[hi - 1].u;
      s0 = arc[hi - 1];
      u1 = ring[hi].u;
      s1 = arc[hi];
    }
    const double t = u1 > u0 ? (u - u0) / (u1 - u0) : 0;
    double s = s0 + t * (s1 - s0);
    s = std::fmod(s + perimeter, perimeter);  // in [0, perimeter)
    surface_s_[e] = static_cast<float>(s);
  }
  // A bin straddling the seam would interpolate from near the perimeter back
  // to near 0: unwrap so that each bin's edges increase.
  for (int e = 1; e <= kSurfaceBinsU; ++e)
    while (surface_s_[e] < surface_s_[e - 1]) surface_s_[e] += static_cast<float>(perimeter);
  const size_t n = static_cast<size_t>(std::ceil(perimeter / kHairTableStepMm));
  for (size_t i = 0; i < n; ++i)
    hair_around_.push_back(static_cast<float>(hairRowNoise(
        perimeter * static_cast<double>(i) / n, perimeter, true, kHairSeedAround)));
  inv_step_around_ = static_cast<float>(n / perimeter);
}

float BrushTexelMap::lateral(double x_mm) const {
  return static_cast<float>(std::clamp((x_mm - x0_) / (x1_ - x0_), 0.0, 1.0));
}

// ---------------------------------------------------------------- BrushPaint

BrushPaint::BrushPaint(const Brush& brush)
    : map_(brush),
      capacity_(brush.paint_capacity),
      flag_mm_(brush.paint_flag_mm),
      wicking_(brush.paint_wicking),
      cells_(BrushTexelMap::kTexels) {}

void BrushPaint::clean() {
  for (PaintCell& c : cells_) c = PaintCell{};
  capacity_mm3_ = 0;
}

void BrushPaint::load(const PaintLoad& load, MixModel model, const std::string& where) {
  auto fail = [&](const std::string& field, const std::string& rule) {
    return dataError(where, field, rule);
  };
  const std::string mode = std::string("mode \"") + paintModeName(load.mode) + "\"";
  if (const std::optional<PaintLoadProblem> e = checkPaintLoad(load, mode))
    throw fail("/" + e->field, e->rule);
  std::vector<Optics> paints(load.paints.size());
  for (size_t i = 0; i < paints.size(); ++i) {
    std::string why;
    if (!resolvePaint(load.paints[i], model, &paints[i], &why))
      throw fail("/paints/" + std::to_string(i), why);
    const float thin = static_cast<float>(1 - kDilutionThinning * load.dilution);
    if (model == MixModel::kKubelkaMunk)
      for (int c = 0; c < 3; ++c) paints[i].k[c] *= thin, paints[i].s[c] *= thin;
    else
      for (int c = 0; c < 3; ++c) paints[i].s[c] *= thin;
  }
  model_ = model;
  flow_ = 1 + load.dilution;
  full_film_mm_ = kFullLoadFilmMm * capacity_;
  const double film = full_film_mm_ * load.amount;
  const float volume = static_cast<float>(film * map_.texelAreaMm2());
  capacity_mm3_ = full_film_mm_ * map_.texelAreaMm2() * BrushTexelMap::kTexels;

  for (int row = 0; row < BrushTexelMap::kRows; ++row)
    for (int col = 0; col < BrushTexelMap::kColumns; ++col) {
      const double w = BrushTexelMap::columnCentre(col), v = BrushTexelMap::rowCentre(row);
      std::vector<double> weight(paints.size(), 0.0);
      if (paints.size() == 1) {
        weight[0] = 1;
      } else if (load.mode == PaintLoad::Mode::kAcross) {
        // Boundaries at k / n; each a smooth step of half-width kAcrossBlendHalfWidth.
        const int n = static_cast<int>(paints.size());
        double rest = 1;
        for (int k = 0; k + 1 < n; ++k) {
          const double b = double(k + 1) / n;
          const double t = smoothstep((w - (b - kAcrossBlendHalfWidth)) /
                                      (2 * kAcrossBlendHalfWidth));
          weight[k] = rest * (1 - t);
          rest *= t;
        }
        weight[n - 1] = rest;
      } else {  // tip
        const double b = 1 - load.tip_length;
        const double t = smoothstep((v - (b - kTipBlendHalfWidth)) / (2 * kTipBlendHalfWidth));
        weight[0] = 1 - t;
        weight[1] = t;
      }
      PaintCell& cell = cells_[row * BrushTexelMap::kColumns + col];
      cell = PaintCell{};
      cell.volume_mm3 = volume;
      for (size_t p = 0; p < paints.size(); ++p)
        for (int c = 0; c < 3; ++c) {
          cell.optics.k[c] += static_cast<float>(weight[p]) * paints[p].k[c];
          cell.optics.s[c] += static_cast<float>(weight[p]) * paints[p].s[c];
        }
    }
}

double BrushPaint::totalVolumeMm3() const {
  double v = 0;
  for (const PaintCell& c : cells_) v += c.volume_mm3;
  return v;
}

// ---------------------------------------------------------------- PaintCanvas

double paperTooth(const PaperSpec& paper, double x_mm, double y_mm) {
  if (paper.tooth_scale_mm <= 0) return 1;
  const double x = x_mm / paper.tooth_scale_mm, y = y_mm / paper.tooth_scale_mm;
  // Two octaves: the grain and a finer grain at half its size, 0.35 as strong.
  const double n = valueNoise(x, y, paper.seed) + 0.35 * valueNoise(2 * x, 2 * y, paper.seed + 1);
  return n / 1.35;
}

PaintCanvas::PaintCanvas(const CanvasGrid& grid, const PaperSpec& paper, MixModel model)
    : grid_(grid), paper_(paper), model_(model) {
  if (grid.width_px <= 0 || grid.height_px <= 0 || grid.width_px > kMaxCanvasSidePx ||
      grid.height_px > kMaxCanvasSidePx ||
      double(grid.width_px) * grid.height_px > double(kMaxCanvasPixels))
    throw Error(ExitCode::kDataError,
                "canvas of " + std::to_string(grid.width_px) + " x " +
                    std::to_string(grid.height_px) +
                    " px: must be 1 .. 16384 px a side and at most 64 Mpx");
  Rgb colour;
  if (!parseHexColour(paper.colour, &colour))
    throw Error(ExitCode::kDataError,
                "paper colour '" + paper.colour + "': must be a colour like " + kDefaultPaperColour);
  if (!(paper.tooth_depth_mm >= 0) || !(paper.tooth_scale_mm > 0))
    throw Error(ExitCode::kDataError,
                "paper tooth: depth must be >= 0 mm and scale > 0 mm");
  const size_t n = static_cast<size_t>(grid.width_px) * grid.height_px;
  wet_.assign(n, PaintCell{});
  const std::array<float, 3> bg = {static_cast<float>(srgbToLinear(colour.r)),
                                   static_cast<float>(srgbToLinear(colour.g)),
                                   static_cast<float>(srgbToLinear(colour.b))};
  dry_.assign(n, bg);
  dry_height_.assign(n, 0.0f);
  tooth_.assign(n, -1.0f);  // tooth() fills each pixel in on first use
}

float PaintCanvas::toothAt(size_t i) const {
  const int c = static_cast<int>(i % static_cast<size_t>(grid_.width_px));
  const int r = static_cast<int>(i / static_cast<size_t>(grid_.width_px));
  const double x = grid_.x0_mm + (c + 0.5) / grid_.px_per_mm;
  const double y = grid_.y0_mm + (grid_.height_px - r - 0.5) / grid_.px_per_mm;
  return static_cast<float>(paperTooth(paper_, x, y));
}

std::array<double, 3> PaintCanvas::reflectance(size_t i) const {
  const std::array<double, 3> bg = {dry_[i][0], dry_[i][1], dry_[i][2]};
  const PaintCell& w = wet_[i];
  if (w.volume_mm3 <= kVolumeEpsMm3) return bg;
  const double d = w.volume_mm3 / pixelAreaMm2() / kKmUnitFilmMm;
  return filmOver(w.optics, d, bg, model_);
}

double PaintCanvas::heightMm(size_t i) const {
  return dry_height_[i] + wet_[i].volume_mm3 / pixelAreaMm2();
}

void PaintCanvas::dry() {
  for (size_t i = 0; i < wet_.size(); ++i) {
    if (wet_[i].volume_mm3 > kVolumeEpsMm3) {
      const std::array<double, 3> r = reflectance(i);
      for (int c = 0; c < 3; ++c) dry_[i][c] = static_cast<float>(r[c]);
      dry_height_[i] += static_cast<float>(wet_[i].volume_mm3 / pixelAreaMm2());
    }
    wet_[i] = PaintCell{};
  }
}

double PaintCanvas::wetVolumeMm3() const {
  double v = 0;
  for (const PaintCell& c : wet_) v += c.volume_mm3;
  return v;
}

double PaintCanvas::dryVolumeMm3() const {
  double v = 0;
  for (float h : dry_height_) v += h;
  return v * pixelAreaMm2();
}

bool PaintCanvas::blank() const {
  for (size_t i = 0; i < wet_.size(); ++i)
    if (wet_[i].volume_mm3 > kVolumeEpsMm3 || dry_height_[i] > 0) return false;
  return true;
}

namespace {

// The value at canvas point (x, y) of the piece nearest it in (x, y),
// interpolated along the piece between its ends' values `a` and `b`
// (pointers to members of Piece); 0 without pieces.
template <class Piece>
double nearestPieceValue(const std::vector<Piece>& pieces, double x_mm, double y_mm,
                         float Piece::*a, float Piece::*b) {
  double best = std::numeric_limits<double>::infinity(), value = 0;
  for (const Piece& p : pieces) {
    const double dx = p.bx_mm - p.ax_mm, dy = p.by_mm - p.ay_mm;
    const double len2 = dx * dx + dy * dy;
    const double t =
        len2 > 0 ? std::clamp(((x_mm - p.ax_mm) * dx + (y_mm - p.ay_mm) * dy) / len2, 0.0, 1.0)
                 : 0.0;
    const double ex = p.ax_mm + t * dx - x_mm, ey = p.ay_mm + t * dy - y_mm;
    const double d2 = ex * ex + ey * ey;
    if (d2 < best) {
      best = d2;
      value = p.*a + t * (p.*b - p.*a);
    }
  }
  return value;
}

}  // namespace

double HairSlide::at(double x_mm, double y_mm) const {
  return nearestPieceValue(pieces, x_mm, y_mm, &Piece::slide_a_mm, &Piece::slide_b_mm);
}

double HairPress::at(double x_mm, double y_mm) const {
  return nearestPieceValue(pieces, x_mm, y_mm, &Piece::press_a, &Piece::press_b);
}

// ---------------------------------------------------------------- transfer

double compoundFraction(double fraction, double exposure) {
  const double f = std::clamp(fraction, 0.0, 1.0);
  if (!(exposure > 0)) return 0;
  if (f >= 1) return 1;
  return -std::expm1(exposure * std::log1p(-f));  // 1 - (1 - f)^exposure, exact near 0
}

namespace {

constexpr int kTexels = BrushTexelMap::kTexels;

// A pixel a texel of the brush touches in one step, and how hard: contact
// (scaled, on a flagged rim, by how much of the paper the flags wipe:
// FlagScrub) sets the pickup, deposit (contact gated by dryness, scaled by
// the hair's noise) the paint laid down.
struct Touch {
  std::uint32_t pixel;
  std::uint16_t texel;
  float contact, deposit;
};

// Working space of convexFootprint, kept from step to step.
struct FlagHullScratch {
  std::vector<int> label;          // per footprint pixel: its touching piece, -1 untouched
  std::vector<int> stack;          // the flood fill's pixels to visit
  std::vector<int> lo, hi;         // per footprint row: the piece's extreme columns
  std::vector<Eigen::Vector2d> pts;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> hull;  // its edges
};

// Per-step working arrays, reused from step to step (the engine runs on one
// thread per canvas), so a step allocates nothing once warm, save qhull's own
// working memory for a flagged brush's rim (hullEdges): under 2 % of a
// badger render's time under perf.
struct TransferScratch {
  std::vector<Touch> touches;
  std::vector<double> demand;    // per texel: the sum of its touches' deposit weights
  std::vector<double> out_sum;   // per texel: paint given to the canvas (mm^3)
  std::vector<double> in_sum;    // per texel: paint picked up (mm^3)
  std::vector<double> fed;       // per texel: paint its column feeds it this step (planFeed)
  std::vector<double> feeds;     // per texel: paint it gives its column's fed texels
  std::vector<std::array<float, 6>> in_optics;  // per texel: volume-weighted K and S picked up
  std::vector<float> flag;       // per footprint pixel: deposit factor of flagged ends (flagRim)
  std::vector<int> flag_sums;    // per footprint pixel: flagRim's column sums of hull pixels
  std::vector<std::uint8_t> flag_mask;  // flagRim's hull of the footprint (convexFootprint)
  std::vector<int> hull_hair;    // per footprint pixel: whose hair touches it (hullHair), -1 none
  std::vector<int> hull_queue;   // hullHair's working space
  FlagHullScratch flag_hull;     // convexFootprint's working space
  std::vector<float> slide;      // per FlagScrub cell: the hair's slide there (mm), < 0 not yet
  std::vector<float> press;      // per PressShare cell: the transfer's share there, < 0 not yet
  std::vector<float> cover;      // per PressShare cell: the flags' share on the paper, likewise

  void reset(size_t pixels) {
    touches.clear();
    demand.assign(kTexels, 0.0);
    out_sum.assign(kTexels, 0.0);
    in_sum.assign(kTexels, 0.0);
    fed.assign(kTexels, 0.0);
    feeds.assign(kTexels, 0.0);
    in_optics.assign(kTexels, {0, 0, 0, 0, 0, 0});
    touches.reserve(pixels);
  }
};

// Per texel: how far it has run dry (0 at dry_load or more, 1 empty).
std::array<float, kTexels> texelDryness(const BrushPaint& brush, const TransferParams& params) {
  std::array<float, kTexels> dryness;
  const double texel_area = brush.map().texelAreaMm2();
  const double full_film = std::max(brush.fullFilmMm(), 1e-12);
  for (int t = 0; t < kTexels; ++t) {
    const double load = brush.cell(t).volume_mm3 / texel_area / full_film;
    dryness[t] = static_cast<float>(std::clamp(1 - load / params.dry_load, 0.0, 1.0));
  }
  return dryness;
}

// The edges of the convex hull of `pts` (pixel centres, in ascending rows),
// by qhull. Collinear points (one pixel, a row, a one-pixel line) have no
// two-dimensional hull, which qhull reports as an error: their hull is the
// segment between the first and the last, the extremes along their line.
void hullEdges(const std::vector<Eigen::Vector2d>& pts,
               std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>* edges) {
  edges->clear();
  const Eigen::Vector2d d = pts.back() - pts.front();
  bool flat = true;
  for (const Eigen::Vector2d& p : pts) {
    const Eigen::Vector2d e = p - pts.front();
    if (d.x() * e.y() - d.y() * e.x() != 0) flat = false;  // integer centres: exact
  }
  if (flat) {
    edges->emplace_back(pts.front(), pts.back());
    return;
  }
  std::vector<coordT> coords;
  for (const Eigen::Vector2d& p : pts) coords.insert(coords.end(), {p.x(), p.y()});
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, stderr);
  char flags[] = "qhull";
  if (qh_new_qhull(qh, 2, static_cast<int>(pts.size()), coords.data(), False, flags, nullptr,
                   stderr) == 0) {
    facetT* facet;
    FORALLfacets {
      const vertexT* a = static_cast<vertexT*>(SETfirst_(facet->vertices));
      const vertexT* b = static_cast<vertexT*>(SETsecond_(facet->vertices));
      edges->emplace_back(Eigen::Vector2d(a->point[0], a->point[1]),
                          Eigen::Vector2d(b->point[0], b->point[1]));
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong, totlong;
  qh_memfreeshort(qh, &curlong, &totlong);
}

// Marks in `m` (row length mw, offset by `pad`) every pixel whose centre lies
// in the convex hull of `pts` (pixel centres, in ascending rows): each row
// filled between where the hull's edges cross it.
void fillHull(const std::vector<Eigen::Vector2d>& pts, int mw, int pad,
              std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>* hull,
              std::vector<std::uint8_t>* m) {
  hullEdges(pts, hull);
  for (int r = static_cast<int>(pts.front().y()); r <= static_cast<int>(pts.back().y()); ++r) {
    double x0 = std::numeric_limits<double>::max(), x1 = -x0;
    for (const auto& [a, b] : *hull) {
      if ((a.y() - r) * (b.y() - r) > 0) continue;  // the edge does not cross row r
      if (a.y() == b.y()) {
        x0 = std::min({x0, a.x(), b.x()});
        x1 = std::max({x1, a.x(), b.x()});
        continue;
      }
      const double x = a.x() + (r - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      x0 = std::min(x0, x);
      x1 = std::max(x1, x);
    }
    const int c1 = static_cast<int>(std::floor(x1 + 1e-9));
    for (int c = static_cast<int>(std::ceil(x0 - 1e-9)); c <= c1; ++c)
      (*m)[static_cast<size_t>(r + pad) * mw + c + pad] = 1;
  }
}

// The footprint with each touching piece (8-connected touched pixels)
// replaced by its convex hull, as a mask padded by `pad` on every side (row
// length fp.width + 2 pad). Each row's extreme pixels of a piece are its
// hull's only candidates.
void convexFootprint(const FootprintView& fp, int pad, std::vector<std::uint8_t>* mask,
                     FlagHullScratch* s) {
  const int w = fp.width, h = fp.height, mw = w + 2 * pad;
  mask->assign(static_cast<size_t>(mw) * (h + 2 * pad), 0);
  s->label.assign(static_cast<size_t>(w) * h, -1);
  s->lo.assign(static_cast<size_t>(h), w);
  s->hi.assign(static_cast<size_t>(h), -1);
  auto touched = [&](int i) {
    const float* px = fp.texels + static_cast<size_t>(i) * 4;
    return px[3] > 0 && px[2] > 0;
  };
  int pieces = 0;
  for (int seed = 0; seed < w * h; ++seed) {
    if (s->label[static_cast<size_t>(seed)] >= 0 || !touched(seed)) continue;
    s->label[static_cast<size_t>(seed)] = pieces;
    s->stack.assign(1, seed);
    int r0 = h, r1 = -1;
    while (!s->stack.empty()) {
      const int i = s->stack.back(), r = i / w, c = i % w;
      s->stack.pop_back();
      r0 = std::min(r0, r);
      r1 = std::max(r1, r);
      s->lo[static_cast<size_t>(r)] = std::min(s->lo[static_cast<size_t>(r)], c);
      s->hi[static_cast<size_t>(r)] = std::max(s->hi[static_cast<size_t>(r)], c);
      for (int dr = -1; dr <= 1; ++dr)
        for (int dc = -1; dc <= 1; ++dc) {
          const int rr = r + dr, cc = c + dc, j = rr * w + cc;
          if (rr < 0 || rr >= h || cc < 0 || cc >= w || s->label[static_cast<size_t>(j)] >= 0 ||
              !touched(j))
            continue;
          s->label[static_cast<size_t>(j)] = pieces;
          s->stack.push_back(j);
        }
    }
    s->pts.clear();
    for (int r = r0; r <= r1; ++r) {
      int& lo = s->lo[static_cast<size_t>(r)];
      int& hi = s->hi[static_cast<size_t>(r)];
      if (hi < 0) continue;
      s->pts.emplace_back(lo, r);
      if (hi != lo) s->pts.emplace_back(hi, r);
      lo = w;
      hi = -1;
    }
    fillHull(s->pts, mw, pad, &s->hull, mask);
    ++pieces;
  }
}

// flag_mm in whole pixels, at least one: the half-side of flagRim's square
// and the padding of its mask.
int flagPadPx(double flag_mm, double px_per_mm) {
  return std::max(1, static_cast<int>(std::lround(flag_mm * px_per_mm)));
}

// Flagged hair ends (Brush::paint_flag_mm, docs/brush-format.md): a soft
// hair's split ends splay past the body of the hair and are all that reaches
// the paper at the rim of the footprint. Each flag is a few fibres finer than
// the hair, holding and laying a thinner film, while it wicks wet paint up as
// well as the hair does. So near the footprint's outline the deposit falls
// off and pickup does not: there the wet film settles thinner, and the mark's
// edge is a ramp about flag_mm wide, not a step. The rim is the head's
// outline, not its bundles': the spines' tubes stand for a dense mass of
// hair that fills the notches and gaps the model leaves between them, and a
// head's contact with the plane (a dome's cap, swept along the step) is
// convex, so the outline of each touching piece is its convex hull
// (convexFootprint; docs/paint.md, "The rim is the head's outline"). How
// deep a pixel lies is the share f of the hulls in the square of half-side
// flag_mm around it: 1/2 on a straight outline, rising linearly to 1 at
// flag_mm inside it, and g = smoothstep((f - 1/2) / (1/2)). A lone hair or
// one bundle's tip narrower than flag_mm, touching apart from the rest, is
// a piece of its own, never reaches f = 1/2 and lays nothing: it is all
// flags. Returns false, leaving *out alone, for a brush without flags.
// `mask`, `hull` and `sums` are working space.
bool flagRim(const FootprintView& fp, double flag_mm, double px_per_mm, std::vector<float>* out,
             std::vector<std::uint8_t>* mask, FlagHullScratch* hull, std::vector<int>* sums) {
  const int w = fp.width, h = fp.height;
  if (!(flag_mm > 0) || w == 0 || h == 0) return false;
  const int half = flagPadPx(flag_mm, px_per_mm);
  convexFootprint(fp, half, mask, hull);
  const int mw = w + 2 * half;
  std::vector<float>& g = *out;
  g.resize(static_cast<size_t>(w) * h);
  std::vector<int>& cols = *sums;  // per pixel: hull pixels in its column's window
  cols.resize(static_cast<size_t>(w) * h);
  for (int c = 0; c < w; ++c) {
    // Footprint row r is mask row r + half: its window is mask rows r .. r + 2 half.
    const std::uint8_t* col = mask->data() + c + half;
    auto inside = [&](int mr) { return static_cast<int>(col[static_cast<size_t>(mr) * mw]); };
    int sum = 0;
    for (int mr = 0; mr <= 2 * half; ++mr) sum += inside(mr);
    for (int r = 0; r < h; ++r) {
      cols[static_cast<size_t>(r) * w + c] = sum;
      if (r + 1 < h) sum += inside(r + 2 * half + 1) - inside(r);
    }
  }
  const float inv_area = 1.0f / static_cast<float>((2 * half + 1) * (2 * half + 1));
  for (int r = 0; r < h; ++r) {
    const int* row = cols.data() + static_cast<size_t>(r) * w;
    auto at = [&](int c) { return c < 0 || c >= w ? 0 : row[c]; };
    int sum = 0;
    for (int c = -half; c <= half; ++c) sum += at(c);
    for (int c = 0; c < w; ++c) {
      const float x = std::clamp((sum * inv_area - 0.5f) * 2.0f, 0.0f, 1.0f);
      g[static_cast<size_t>(r) * w + c] = x * x * (3 - 2 * x);
      sum += at(c + half + 1) - at(c - half);
    }
  }
  return true;
}

// The hair between the bundles (docs/paint.md, "The gaps are hair too"): the
// notches and gaps the spines' tubes leave inside a touching piece's convex
// hull (flagRim's mask, padded by `pad`) are hair on a real head, the dense
// mass the spines sample, which reaches the paper where the hair around it
// does. Each such pixel is touched by the hair of the nearest touched pixel
// (8-connected steps through the hull, breadth first from every touched
// pixel at once): *who holds, per footprint pixel, the index of the pixel
// whose texel, depth and cover it takes (itself where the geometry touches),
// -1 outside every hull. `queue` is working space.
void hullHair(const FootprintView& fp, const std::vector<std::uint8_t>& mask, int pad,
              std::vector<int>* who, std::vector<int>* queue) {
  const int w = fp.width, h = fp.height, mw = w + 2 * pad;
  who->assign(static_cast<size_t>(w) * h, -1);
  queue->clear();
  for (int i = 0; i < w * h; ++i) {
    const float* px = fp.texels + static_cast<size_t>(i) * 4;
    if (px[3] > 0 && px[2] > 0) {
      (*who)[static_cast<size_t>(i)] = i;
      queue->push_back(i);
    }
  }
  for (size_t k = 0; k < queue->size(); ++k) {
    const int i = (*queue)[k], r = i / w, c = i % w;
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int rr = r + dr, cc = c + dc, j = rr * w + cc;
        if (rr < 0 || rr >= h || cc < 0 || cc >= w || (*who)[static_cast<size_t>(j)] >= 0 ||
            !mask[static_cast<size_t>(rr + pad) * mw + cc + pad])
          continue;
        (*who)[static_cast<size_t>(j)] = (*who)[static_cast<size_t>(i)];
        queue->push_back(j);
      }
  }
}

// The share of the flagged rim's deposit every touched pixel keeps, however
// few flags reach it (flagDeposit). A rim laid only where a grain peak passes
// the gate is a fringe of lone dots, each a speck beside a pressed blot in an
// opaque paint; with half, the film still varies twofold from pixel to pixel
// but grows steadily inwards, so the rim is one piece with a ragged edge.
constexpr float kFlagFloor = 0.5f;

// Whether the flags reach a pixel where a share `share` of them lies on the
// paper: the few that do stand where the paper is high (tooth) or the hair
// is well loaded (hairNoise), so a pixel is reached where their mean lies
// above 1 - share, over the dry brush's soft edge (kInvDryEdge). 1 at
// share 1, whatever the pixel.
float flagsReach(float share, float tooth, float hair) {
  return std::clamp((0.5f * (tooth + hair) - (1 - share)) * kInvDryEdge + 1.0f, 0.0f, 1.0f);
}

// Deposit factor of the flagged rim (flagRim's g in [0, 1]): thinner, and
// uneven. The flags are few and splay unevenly, so the further out, the fewer
// of them reach a pixel: a pixel takes its full share g only where the flags
// reach it (flagsReach with share g); elsewhere kFlagFloor of it.
float flagDeposit(float g, float tooth, float hair) {
  return g * (kFlagFloor + (1 - kFlagFloor) * flagsReach(g, tooth, hair));
}

// A value over the footprint's canvas points that varies over millimetres
// (the spines' slide, their pressure): looked up once per square cell of
// about kSlideCellMm, at the cell's centre, and kept for the step. The
// values looked up are never negative (the cache's "not yet").
constexpr double kSlideCellMm = 0.25;
class CellLookup {
 public:
  using Value = std::function<float(double x_mm, double y_mm)>;
  CellLookup(const FootprintView& fp, const CanvasGrid& grid, std::vector<float>* cache)
      : fp_(fp), grid_(grid), cache_(*cache) {}
  // Starts the step's cache; at() calls value at each cell's first use.
  void start(Value value) {
    value_ = std::move(value);
    cell_ = std::max(1, static_cast<int>(std::lround(kSlideCellMm * grid_.px_per_mm)));
    cells_w_ = (fp_.width + cell_ - 1) / cell_;
    cache_.assign(static_cast<size_t>(cells_w_) * ((fp_.height + cell_ - 1) / cell_), -1.0f);
  }
  // The value at footprint pixel (c, r).
  float at(int c, int r) {
    const int cc = c / cell_, cr = r / cell_;
    float& v = cache_[static_cast<size_t>(cr) * cells_w_ + cc];
    if (v < 0) {
      // The cell's centre in canvas mm (engine/model/canvas.h: row 0 at the top).
      const double col = fp_.col0 + (cc + 0.5) * cell_, row = fp_.row0 + (cr + 0.5) * cell_;
      v = value_(grid_.x0_mm + col / grid_.px_per_mm,
                 grid_.y0_mm + (grid_.height_px - row) / grid_.px_per_mm);
    }
    return v;
  }

 private:
  const FootprintView& fp_;
  const CanvasGrid& grid_;
  std::vector<float>& cache_;
  Value value_;
  int cell_ = 1, cells_w_ = 0;
};

// How the flagged hair's slide over the paper sets its transfer: the share
// min(1, s / flag_scrub_mm) of the paper its flags wipe, s the hair's slide
// per reference step where it touches (TransferParams::flag_scrub_mm). The
// rim picks up g + (1 - g) of it (pickup), and the flagged brush's hair lays
// flag_still_deposit + (1 - flag_still_deposit) of it (lay). Without a slide
// (none known, or no contact time) both are in full.
class FlagScrub {
 public:
  FlagScrub(const FootprintView& fp, const CanvasGrid& grid, const TransferParams& params,
            std::vector<float>* cache)
      : slide_(fp, grid, cache) {
    const double exposure = std::max(params.exposure, 0.0);
    if (fp.slide == nullptr || !(exposure > 0) || !(params.flag_scrub_mm > 0)) return;
    on_ = true;
    still_ = static_cast<float>(std::clamp(params.flag_still_deposit, 0.0, 1.0));
    inv_ref_ = 1.0 / (params.flag_scrub_mm * exposure);
    const HairSlide* slide = fp.slide;
    slide_.start([slide](double x, double y) { return static_cast<float>(slide->at(x, y)); });
  }
  // The pickup's share at footprint pixel (c, r), whose rim deposit factor is g.
  float pickup(int c, int r, float g) {
    if (!on_ || g >= 1) return 1.0f;
    return g + (1 - g) * wiped(c, r);
  }
  // The deposit's share at footprint pixel (c, r): every flag, on the rim as
  // in the body, holds its paint in its splits and gives it as the paper
  // draws it out, a share standing. On the rim the flags' number (how much
  // of the paper they cover, flagDeposit) scales both the deposit and,
  // standing, the pickup; the release scales the deposit alone, so a rim
  // standing on the paper settles no darker than the body does.
  float lay(int c, int r) {
    if (!on_ || still_ >= 1) return 1.0f;
    return still_ + (1 - still_) * wiped(c, r);
  }

 private:
  float wiped(int c, int r) {
    return static_cast<float>(std::min(1.0, slide_.at(c, r) * inv_ref_));
  }
  CellLookup slide_;
  bool on_ = false;
  float still_ = 1;
  double inv_ref_ = 0;
};

// What the hair's pressure does at each pixel of the footprint: the share
// of the transfer rates it gives (TransferParams::press_full_n_per_mm2),
// press_floor plus the rest in proportion to the pressure, up to all of it;
// and the share of a flagged brush's flags it lays on the paper
// (TransferParams::flag_cover_n_per_mm2). Without a pressure known, both in
// full.
class PressShare {
 public:
  PressShare(const FootprintView& fp, const CanvasGrid& grid, const TransferParams& params,
             std::vector<float>* share_cache, std::vector<float>* cover_cache)
      : share_(fp, grid, share_cache), cover_(fp, grid, cover_cache) {
    if (fp.press == nullptr || !(params.press_full_n_per_mm2 > 0)) return;
    on_ = true;
    const float floor = static_cast<float>(std::clamp(params.press_floor, 0.0, 1.0));
    const double inv_full = 1.0 / params.press_full_n_per_mm2;
    const HairPress* press = fp.press;
    share_.start([press, floor, inv_full](double x, double y) {
      const double p = press->at(x, y);
      return floor + (1 - floor) * static_cast<float>(std::clamp(p * inv_full, 0.0, 1.0));
    });
    // No cover pressure: every flag lies on the paper at any load.
    if (!(params.flag_cover_n_per_mm2 > 0)) return;
    cover_on_ = true;
    const float cover_floor = static_cast<float>(std::clamp(params.flag_cover_floor, 0.0, 1.0));
    const double inv_cover = 1.0 / params.flag_cover_n_per_mm2;
    cover_.start([press, cover_floor, inv_cover](double x, double y) {
      const double p = press->at(x, y);
      return cover_floor +
             (1 - cover_floor) * static_cast<float>(std::clamp(p * inv_cover, 0.0, 1.0));
    });
  }
  // The transfer rates' share at footprint pixel (c, r).
  float at(int c, int r) { return on_ ? share_.at(c, r) : 1.0f; }
  // The share of a flagged brush's flags on the paper at footprint pixel (c, r).
  float flagCover(int c, int r) { return cover_on_ ? cover_.at(c, r) : 1.0f; }

 private:
  CellLookup share_, cover_;
  bool on_ = false, cover_on_ = false;
};

// Stage 1 of transfer: who touches what, and how hard. Fills scratch.touches
// and scratch.demand; returns the number of touching pixels.
int gatherTouches(const FootprintView& fp, const BrushPaint& brush, const PaintCanvas& canvas,
                  const TransferParams& params, const std::array<float, kTexels>& dryness,
                  TransferScratch& scratch) {
  std::vector<Touch>& touches = scratch.touches;
  std::vector<double>& demand = scratch.demand;
  const CanvasGrid& g = canvas.grid();
  const BrushTexelMap& map = brush.map();
  const float tooth_depth = static_cast<float>(canvas.paper().tooth_depth_mm);
  const float bridging = static_cast<float>(std::max(params.hair_bridging, 1.0));
  const float valley_reach = tooth_depth * bridging;
  const float inv_scale = static_cast<float>(1.0 / canvas.paper().tooth_scale_mm);
  const float inv_band = static_cast<float>(1.0 / fp.contact_band_mm);
  const float streaks = static_cast<float>(std::clamp(params.hair_streaks, 0.0, 2.0));
  const float dry_threshold = static_cast<float>(params.dry_threshold);
  const bool flagged =
      flagRim(fp, brush.flagMm(), g.px_per_mm, &scratch.flag, &scratch.flag_mask,
              &scratch.flag_hull, &scratch.flag_sums);
  if (flagged)
    hullHair(fp, scratch.flag_mask, flagPadPx(brush.flagMm(), g.px_per_mm), &scratch.hull_hair,
             &scratch.hull_queue);
  FlagScrub scrub(fp, g, params, &scratch.slide);
  PressShare press(fp, g, params, &scratch.press, &scratch.cover);
  int contact_px = 0;
  for (int r = 0; r < fp.height; ++r) {
    const int row = fp.row0 + r;
    if (row < 0 || row >= g.height_px) continue;
    for (int c = 0; c < fp.width; ++c) {
      // A flagged head's hair fills its hull (hullHair).
      const int from = flagged ? scratch.hull_hair[static_cast<size_t>(r) * fp.width + c]
                               : r * fp.width + c;
      if (from < 0) continue;
      const float* px = fp.texels + static_cast<size_t>(from) * 4;
      if (px[3] <= 0) continue;
      const int col = fp.col0 + c;
      if (col < 0 || col >= g.width_px) continue;
      const size_t i = canvas.index(col, row);
      // The brush reaches the paper where it dips below the paper's surface: the
      // peaks (tooth 1) at the top of the contact band, the valleys lower. Hairs
      // bridge the grain rather than follow it: reaching the floor of a valley
      // tooth_depth deep takes hair_bridging times that much pressing (footprint
      // depth), so a light touch catches only the peaks.
      // Contact saturates (x (2 - x)): hairs bend and spread as they press, so a
      // hair half-way into the band already lays down three quarters of its paint.
      // A hair strip narrower than the grain bridges it less (hair_bridging).
      const float strip_w = map.stripWidthMm(px[0], px[1]);
      const float reach =
          strip_w > 0 ? tooth_depth * (1 + (bridging - 1) * std::min(1.0f, strip_w * inv_scale))
                      : valley_reach;
      const float x =
          std::clamp((px[2] - reach * (1 - canvas.tooth(i))) * inv_band, 0.0f, 1.0f);
      // A hair finer than the pixel touches only its share of it (px[3] < 1).
      const float contact = x * (2 - x) * std::min(px[3], 1.0f);
      if (contact <= 0) continue;
      const int t = map.texel(px[0], px[1]);
      // Hairs differ (hairNoise, fixed per hair, so its effects streak along
      // the stroke): a hair holding less lays a thinner film (streaks), and
      // as its texel runs dry it gives paint only where the paper stands
      // higher (tooth) than a threshold that grows with the dryness, sooner
      // for the barer hairs: streaks along travel, broken by the grain's
      // valleys (dry brush). A texel that is not running dry is not gated.
      const float hair = map.hairNoise(px[0], px[1]);
      const float d = dryness[t];
      const float need = d * (dry_threshold - d * kHairVariation * (hair - 0.5f));
      const float gate =
          std::clamp((canvas.tooth(i) - need) * kInvDryEdge + 1.0f, 0.0f, 1.0f);
      float dep = contact * gate * (1 + streaks * (hair - 0.5f));
      float pick = contact;
      // Pressed hair gives and takes paint, resting hair barely (PressShare).
      const float pressed = press.at(c, r);
      dep *= pressed;
      pick *= pressed;
      if (flagged) {
        // Only the flags the load lays on the paper touch it (flagsReach).
        const float reached = flagsReach(press.flagCover(c, r), canvas.tooth(i), hair);
        if (reached <= 0) continue;
        dep *= reached;
        pick *= reached;
        const float rim = scratch.flag[static_cast<size_t>(r) * fp.width + c];
        dep *= flagDeposit(rim, canvas.tooth(i), hair) * scrub.lay(c, r);
        // Over dry paper there is nothing to take up (each pixel is touched
        // once a step). The hair in a gap (hullHair) lies between bundles
        // that no joint of its own presses onto the paper: it wets the share
        // it lays on, as flags standing do, and does not wipe the rest.
        if (canvas.wet(i).volume_mm3 > 0)
          pick *= from == r * fp.width + c ? scrub.pickup(c, r, rim) : rim;
      }
      touches.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint16_t>(t), pick,
                         dep});
      demand[t] += dep;
      ++contact_px;
    }
  }
  return contact_px;
}

// The reservoir within a step (docs/paint.md, "The cap on a texel's
// deposit"): a texel hands over at most max_out of its paint a step, and a
// texel whose touches want more than that is fed the rest by the other
// texels of its column, the hair along which paint runs to the touching
// end, as far as they can spare it (each at most max_out of its own, less
// what it lays itself). Hair that does not wick (BrushPaint::wicking below
// 1) runs paint only down towards its tips: the texels past the tipmost fed
// one spare only that share. Where the column cannot feed all that is
// wanted, the fed texels' deposit is cut to their own cap plus the same
// share of their shortfall. Fills scratch.fed and scratch.feeds and scales
// per_pixel (deposit per unit of contact) of the texels cut.
void planFeed(const BrushPaint& brush, double max_out, std::array<float, kTexels>& per_pixel,
              TransferScratch& scratch) {
  constexpr int C = BrushTexelMap::kColumns, R = BrushTexelMap::kRows;
  std::array<double, R> short_of, spare;
  for (int col = 0; col < C; ++col) {
    double need = 0;
    int tipmost = -1;
    for (int row = 0; row < R; ++row) {
      const int t = row * C + col;
      const double own = max_out * brush.cell(t).volume_mm3;
      const double out = double(per_pixel[t]) * scratch.demand[t];
      short_of[row] = std::max(0.0, out - own);
      spare[row] = short_of[row] > 0 ? 0.0 : own - out;
      need += short_of[row];
      if (short_of[row] > 0) tipmost = row;
    }
    if (!(need > 0)) continue;
    double can = 0;
    for (int row = 0; row < R; ++row) {
      if (row > tipmost) spare[row] *= brush.wicking();
      can += spare[row];
    }
    const double fed_share = std::min(1.0, can / need);
    const double give_share = can > 0 ? std::min(1.0, need / can) : 0.0;
    for (int row = 0; row < R; ++row) {
      const int t = row * C + col;
      scratch.feeds[t] = give_share * spare[row];
      if (!(short_of[row] > 0)) continue;
      scratch.fed[t] = fed_share * short_of[row];
      const double own = max_out * brush.cell(t).volume_mm3;
      per_pixel[t] = static_cast<float>((own + scratch.fed[t]) / scratch.demand[t]);
    }
  }
}

// Moves the paint planFeed planned, within each column: the givers' paint is
// pooled, so a fed texel takes in their mixture.
void feedFromColumns(BrushPaint& brush, const TransferScratch& scratch) {
  constexpr int C = BrushTexelMap::kColumns, R = BrushTexelMap::kRows;
  for (int col = 0; col < C; ++col) {
    double pool = 0, pool_k[3] = {0, 0, 0}, pool_s[3] = {0, 0, 0};
    for (int row = 0; row < R; ++row) {
      const float give = static_cast<float>(scratch.feeds[row * C + col]);
      if (!(give > 0)) continue;
      PaintCell& cell = brush.cell(row * C + col);
      cell.volume_mm3 -= give;
      pool += give;
      for (int k = 0; k < 3; ++k) {
        pool_k[k] += double(give) * cell.optics.k[k];
        pool_s[k] += double(give) * cell.optics.s[k];
      }
    }
    if (!(pool > 0)) continue;
    Optics pooled;
    for (int k = 0; k < 3; ++k) {
      pooled.k[k] = static_cast<float>(pool_k[k] / pool);
      pooled.s[k] = static_cast<float>(pool_s[k] / pool);
    }
    for (int row = 0; row < R; ++row) {
      PaintCell& cell = brush.cell(row * C + col);
      const float take = static_cast<float>(scratch.fed[row * C + col]);
      if (take > 0) mixInto(cell, cell.volume_mm3, pooled, take);
    }
  }
}

// Stage 2: deposit and pickup per pixel, from the texels' paint at the start
// of the step. Rates are per reference step of contact
// (TransferParams::exposure): an amount per step scales with the exposure, a
// fraction taken per step compounds as 1 - (1 - f)^exposure. Sums what each
// texel gave and took up in scratch.out_sum, in_sum and in_optics.
void depositAndPickUp(const BrushPaint& brush, PaintCanvas& canvas, const TransferParams& params,
                      double exposure, TransferScratch& scratch) {
  const double area_px = canvas.pixelAreaMm2();
  const double full_film = std::max(brush.fullFilmMm(), 1e-12);
  const double rate = params.deposit_rate * exposure * brush.flow();
  const double max_out = compoundFraction(params.max_out_fraction, exposure);
  std::array<float, kTexels> per_pixel;  // deposit per unit of `deposit` contact (mm^3)
  for (int t = 0; t < kTexels; ++t) {
    const double v = brush.cell(t).volume_mm3;
    // The paper takes paint at a rate set by the paint, not by how much the hairs
    // hold: a fixed share of a full load's film per step, as long as the texel
    // has it. So a lightly loaded brush runs out sooner, not thinner.
    // Hair that does not wick (BrushPaint::wicking below 1) keeps what it
    // took up on the outside of its ends, and a texel holding more than a
    // full load's film gives in proportion to what it holds: what a softener
    // lifts from wet paint it lays again a little further on (docs/paint.md,
    // "Unabsorbent hair").
    const double film = brush.wicking() < 1 ? std::max(full_film, v / brush.map().texelAreaMm2())
                                            : full_film;
    per_pixel[t] = static_cast<float>(rate * film * area_px);
  }
  planFeed(brush, max_out, per_pixel, scratch);
  const float pickup = static_cast<float>(compoundFraction(params.pickup_rate, exposure));
  for (const Touch& h : scratch.touches) {
    PaintCell& px = canvas.wet(h.pixel);
    const PaintCell& tex = brush.cell(h.texel);
    const float out = per_pixel[h.texel] * h.deposit;
    const float in = pickup * h.contact * px.volume_mm3;
    if (in > 0) {
      scratch.in_sum[h.texel] += in;
      // Optics sums in float: they set a colour, not a volume (1e-7 is invisible).
      std::array<float, 6>& acc = scratch.in_optics[h.texel];
      for (int k = 0; k < 3; ++k) {
        acc[k] += in * px.optics.k[k];
        acc[3 + k] += in * px.optics.s[k];
      }
    }
    scratch.out_sum[h.texel] += out;
    mixInto(px, px.volume_mm3 - in, tex.optics, out);
  }
}

// Stage 3: the brush texture loses what it gave and mixes in what it picked up.
void settleTexels(BrushPaint& brush, const TransferScratch& scratch, TransferStats* stats) {
  for (int t = 0; t < kTexels; ++t) {
    if (scratch.out_sum[t] == 0 && scratch.in_sum[t] == 0) continue;
    PaintCell& cell = brush.cell(t);
    Optics picked;
    if (scratch.in_sum[t] > 0)
      for (int k = 0; k < 3; ++k) {
        picked.k[k] = static_cast<float>(scratch.in_optics[t][k] / scratch.in_sum[t]);
        picked.s[k] = static_cast<float>(scratch.in_optics[t][3 + k] / scratch.in_sum[t]);
      }
    mixInto(cell, static_cast<float>(cell.volume_mm3 - scratch.out_sum[t]), picked,
            static_cast<float>(scratch.in_sum[t]));
    stats->deposited_mm3 += scratch.out_sum[t];
    stats->picked_up_mm3 += scratch.in_sum[t];
  }
}

// Stage 4, the reservoir: within each column (one lateral position of the
// hair bundle) paint flows from texels holding more than the column's mean
// towards those holding less, a fraction `flow` of the difference. The givers'
// paint is pooled, so the receivers get the givers' mixture.
void flowWithinColumns(BrushPaint& brush, double flow) {
  constexpr int C = BrushTexelMap::kColumns, R = BrushTexelMap::kRows;
  const float phi = static_cast<float>(flow);
  for (int col = 0; col < C; ++col) {
    double mean = 0;
    for (int row = 0; row < R; ++row) mean += brush.cell(row * C + col).volume_mm3;
    mean /= R;
    double pool = 0, pool_k[3] = {0, 0, 0}, pool_s[3] = {0, 0, 0}, want = 0;
    for (int row = 0; row < R; ++row) {
      PaintCell& cell = brush.cell(row * C + col);
      const double excess = cell.volume_mm3 - mean;
      if (excess > 0) {
        const float give = static_cast<float>(phi * excess);
        cell.volume_mm3 -= give;
        pool += give;
        for (int k = 0; k < 3; ++k) {
          pool_k[k] += double(give) * cell.optics.k[k];
          pool_s[k] += double(give) * cell.optics.s[k];
        }
      } else {
        want += phi * -excess;
      }
    }
    if (pool <= 0 || want <= 0) continue;
    Optics pooled;
    for (int k = 0; k < 3; ++k) {
      pooled.k[k] = static_cast<float>(pool_k[k] / pool);
      pooled.s[k] = static_cast<float>(pool_s[k] / pool);
    }
    // Receivers share the pool in proportion to their shortfall (pool == want up to
    // rounding; scaling by pool / want keeps the sum exact).
    const double scale = pool / want;
    for (int row = 0; row < R; ++row) {
      PaintCell& cell = brush.cell(row * C + col);
      // Only texels that were below the mean before the givers gave (a giver
      // ends at or above the mean, so "below the mean" still picks them).
      if (cell.volume_mm3 >= mean) continue;
      const float take = static_cast<float>(phi * (mean - cell.volume_mm3) * scale);
      mixInto(cell, cell.volume_mm3, pooled, take);
    }
  }
}

// Stage 4 for hair that does not wick (BrushPaint::wicking below 1): paint
// runs down each column's hairs, from a texel to the next one towards the tip
// where that holds less, a fraction `flow` of half their difference (half: a
// pair at flow 1 ends level), and never back up. So a loaded belly still feeds
// tips that run drier than it, while what the tips lifted from wet paint stays
// there (docs/paint.md, "Unabsorbent hair"). Every junction's share is taken
// from the texels as they were before this step (the order of rows does not
// matter), and a texel gives at most flow / 2 of what it holds.
void flowTowardsTips(BrushPaint& brush, double flow) {
  constexpr int C = BrushTexelMap::kColumns, R = BrushTexelMap::kRows;
  const double half = 0.5 * flow;
  std::array<float, R> give;
  for (int col = 0; col < C; ++col) {
    for (int row = 0; row + 1 < R; ++row) {
      const double drop =
          brush.cell(row * C + col).volume_mm3 - brush.cell((row + 1) * C + col).volume_mm3;
      give[row] = drop > 0 ? static_cast<float>(half * drop) : 0.0f;
    }
    give[R - 1] = 0;
    // From the tip back, so each texel gives its own mixture before it receives.
    for (int row = R - 2; row >= 0; --row) {
      if (give[row] <= 0) continue;
      PaintCell& from = brush.cell(row * C + col);
      PaintCell& to = brush.cell((row + 1) * C + col);
      mixInto(to, to.volume_mm3, from.optics, give[row]);
      from.volume_mm3 -= give[row];
    }
  }
}

}  // namespace

TransferStats transfer(const FootprintView& fp, BrushPaint& brush, PaintCanvas& canvas,
                       const TransferParams& params) {
  thread_local TransferScratch tl_scratch;
  TransferScratch& scratch = tl_scratch;  // no thread-local lookup inside the loops
  scratch.reset(static_cast<size_t>(fp.width) * fp.height);
  const std::array<float, kTexels> dryness = texelDryness(brush, params);
  TransferStats stats;
  stats.contact_px = gatherTouches(fp, brush, canvas, params, dryness, scratch);
  const double exposure = std::max(params.exposure, 0.0);
  depositAndPickUp(brush, canvas, params, exposure, scratch);
  feedFromColumns(brush, scratch);
  settleTexels(brush, scratch, &stats);
  // Unabsorbent hair draws up only its share of the flow (BrushPaint::wicking);
  // the rest runs towards the tips only.
  const double flow = compoundFraction(params.reservoir_flow, exposure);
  if (flow * brush.wicking() > 0) flowWithinColumns(brush, flow * brush.wicking());
  if (flow * (1 - brush.wicking()) > 0) flowTowardsTips(brush, flow * (1 - brush.wicking()));
  return stats;
}

}  // namespace bristle

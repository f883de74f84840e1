#pragma once
// The paint model, after the painting system the paper's brush drives
// (dAb, Baxter et al. SIGGRAPH 2001; IMPaSTo, NPAR 2004): paint is a texture on
// the brush; each step the footprint says which brush texel touches which canvas
// pixel and how deep, and paint moves both ways between them.
//
//  BrushPaint   a grid of texels over the brush's (across, along) coordinates,
//               each a volume of paint and its optics (engine/paint/pigments.h).
//  PaintCanvas  per pixel a wet layer (volume + optics) over a dry layer (the
//               reflectance of everything dried so far over the paper, and its
//               height), and the paper's tooth (a seeded height field).
//  transfer()   one step: deposit, pickup, brush texture update, reservoir flow.
//
// Volumes are in mm^3; a film's thickness is its volume over its area.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/geometry/brush_vertex.h"  // BrushPart in the texture coordinate u
#include "engine/model/canvas.h"
#include "engine/paint/paint_spec.h"
#include "engine/paint/pigments.h"

namespace bristle {

class BrushSurface;

// One cell of paint: a brush texel or a canvas pixel's wet layer.
struct PaintCell {
  float volume_mm3 = 0;
  Optics optics;  // per unit volume; meaningless while volume is 0
};

// Paint film a fully loaded brush (amount 1, capacity 1) holds per mm^2 of its
// texture: the hair bundle soaks up paint well beyond one film, about 0.3 mm
// (a loaded 12 x 16 mm flat then holds ~0.07 ml, a painter's "full load").
inline constexpr double kFullLoadFilmMm = 0.3;

// Where brush geometry texture coordinates (engine/geometry/brush_vertex.h) land on
// the brush's paint texture. The texture is kColumns x kRows texels over
// (w, v) in [0, 1]^2: w across the brush's width axis (the brush frame's x,
// 0 at its -x edge, 1 at its +x edge), v along the hairs (0 at the ferrule,
// 1 at the tip). The geometry's own u is per part: the surface's u is an angle
// around the brush axis, a spine tube's u picks the spine, a strip's u its
// texture row. This map turns each into w from the part's rest position in x.
class BrushTexelMap {
 public:
  static constexpr int kColumns = 32;
  static constexpr int kRows = 32;
  static constexpr int kTexels = kColumns * kRows;

  explicit BrushTexelMap(const Brush& brush);
  // Lateral position w in [0, 1] of a geometry texture coordinate u (any part).
  float across(float u, float v) const;
  // Texel of a geometry texture coordinate (u, v).
  int texel(float u, float v) const;
  // Width (mm) of the hair strip a texture coordinate lies on, at its place v
  // along the hair (the strips taper linearly from root to tip, §4.2); 0 for the
  // surface and the spines' tubes, which are bundles, not single strips. A
  // strip shortened by length_jitter reaches v = f < 1 at its tip, so v
  // over-states how far along it a point is: the width given is at most the
  // true one's taper ahead, i.e. never narrower than the strip.
  float stripWidthMm(float u, float v) const {
    if (partOfTextureU(u) != BrushPart::kStrip || strips_ == 0) return 0;
    return strip_root_width_mm_ +
           (strip_tip_width_mm_ - strip_root_width_mm_) * std::clamp(v, 0.0f, 1.0f);
  }
  // Which hair a texture coordinate lies on, as a value in [0, 1] fixed per
  // hair: hairs differ in how much paint they hold and lay down, and a hair
  // keeps its place in the bundle, so what depends on this value streaks
  // along the direction of travel (docs/paint.md, "Hair streaks"). It is
  // smooth value noise over the hair's place in the bundle, in mm: around the
  // rest surface's cross-section for the surface (so a round streaks whichever
  // way it moves), across the width for the spines' tubes, and one value per
  // hair strip. Features are kHairStreakMm wide and half that.
  float hairNoise(float u, float v) const;
  static constexpr double kHairStreakMm = 0.5;
  static float columnCentre(int col) { return (col + 0.5f) / kColumns; }
  static float rowCentre(int row) { return (row + 0.5f) / kRows; }
  // Area (mm^2) one texel of the brush's paint texture stands for.
  double texelAreaMm2() const { return texel_area_mm2_; }
  double widthMm() const { return x1_ - x0_; }

 private:
  float lateral(double x_mm) const;
  static constexpr int kSurfaceBinsU = 128;
  static constexpr int kSurfaceBinsV = 8;
  double x0_ = 0, x1_ = 1;
  double texel_area_mm2_ = 1;
  int spines_ = 0, strips_ = 0;
  float strip_root_width_mm_ = 0, strip_tip_width_mm_ = 0;
  std::vector<float> spine_w_;    // per spine: w of its root
  std::vector<float> spine_dw_;   // per spine: its width at the root, in w
  std::vector<float> strip_w_;    // per strip texture row: w of its root
  std::vector<float> surface_w_;  // kSurfaceBinsV x kSurfaceBinsU: w of the rest surface
  // Hair noise (hairNoise): tables kHairTableStepMm apart over the rest
  // surface's perimeter (periodic) and over the brush's width, and one value
  // per strip. surface_s_ is the arc length (mm) around the rest cross-section
  // at each surface u bin's edge (kSurfaceBinsU + 1 values, 0 to the perimeter).
  static constexpr double kHairTableStepMm = 0.02;
  std::vector<float> surface_s_;
  std::vector<float> hair_around_, hair_across_, strip_hair_;
  float inv_step_around_ = 0;  // table entries per mm around the surface
  void buildSurfaceHair(const BrushSurface& surface);
};

// Inline: called once per touching pixel per step.
inline float BrushTexelMap::across(float u, float v) const {
  const BrushPart part = partOfTextureU(u);
  if (part == BrushPart::kSpine) {
    if (spines_ == 0) return 0.5f;
    const float su = ownTextureU(part, u) * spines_;
    const int s = std::clamp(static_cast<int>(su), 0, spines_ - 1);
    // Across the tube, from its -x side to its +x side (engine/geometry/spine_bundles.h).
    return std::clamp(spine_w_[s] + (su - s - 0.5f) * spine_dw_[s], 0.0f, 1.0f);
  }
  if (part == BrushPart::kStrip) {
    if (strips_ == 0) return 0.5f;
    const int k = std::clamp(static_cast<int>(ownTextureU(part, u) * strips_), 0, strips_ - 1);
    return strip_w_[k];
  }
  const float uw = u - std::floor(u);
  const int bu = std::min(kSurfaceBinsU - 1, static_cast<int>(uw * kSurfaceBinsU));
  const int bv = std::clamp(static_cast<int>(v * kSurfaceBinsV), 0, kSurfaceBinsV - 1);
  return surface_w_[bv * kSurfaceBinsU + bu];
}

inline float BrushTexelMap::hairNoise(float u, float v) const {
  const BrushPart part = partOfTextureU(u);
  if (part == BrushPart::kSpine) {
    if (hair_across_.empty()) return 0.5f;
    const float w = across(u, v);
    const size_t n = hair_across_.size() - 1;
    return hair_across_[std::min(n, static_cast<size_t>(w * n + 0.5f))];
  }
  if (part == BrushPart::kStrip) {
    if (strip_hair_.empty()) return 0.5f;
    const int k = std::clamp(static_cast<int>(ownTextureU(part, u) * strips_), 0, strips_ - 1);
    return strip_hair_[k];
  }
  if (hair_around_.empty()) return 0.5f;
  const float uw = (u - std::floor(u)) * kSurfaceBinsU;
  const int b = std::min(kSurfaceBinsU - 1, static_cast<int>(uw));
  const float s = surface_s_[b] + (uw - b) * (surface_s_[b + 1] - surface_s_[b]);
  const size_t n = hair_around_.size();
  return hair_around_[static_cast<size_t>(s * inv_step_around_ + 0.5f) % n];
}

inline int BrushTexelMap::texel(float u, float v) const {
  const float w = across(u, v);
  const int col = std::clamp(static_cast<int>(w * kColumns), 0, kColumns - 1);
  const int row = std::clamp(static_cast<int>(v * kRows), 0, kRows - 1);
  return row * kColumns + col;
}

// The paint on a brush.
class BrushPaint {
 public:
  explicit BrushPaint(const Brush& brush);
  const BrushTexelMap& map() const { return map_; }

  // Loads the brush afresh (what was on it is washed out): every texel gets
  // amount * brush.paint_capacity * kFullLoadFilmMm of film. Throws
  // Error(kDataError) "<where>: /<field>: <rule>" for a load that breaks a rule
  // of checkPaintLoad (engine/paint/paint_spec.h). `where` names the source (a scene
  // file and pointer, or "--paint").
  void load(const PaintLoad& load, MixModel model, const std::string& where);
  // A clean, empty brush (it can still pick paint up).
  void clean();

  MixModel model() const { return model_; }
  double capacityMm3() const { return capacity_mm3_; }
  double totalVolumeMm3() const;
  PaintCell& cell(int texel) { return cells_[texel]; }
  const PaintCell& cell(int texel) const { return cells_[texel]; }
  const PaintCell& cellAt(int col, int row) const {
    return cells_[row * BrushTexelMap::kColumns + col];
  }
  // Texel film thickness at full load (mm): the reference "dry" is measured from.
  double fullFilmMm() const { return full_film_mm_; }
  // Flow multiplier from the loaded paint's dilution (thinner paint flows more).
  double flow() const { return flow_; }
  // The brush's flagged hair ends (mm, Brush::paint_flag_mm; 0: none): the
  // rim of the footprint this deep lays a thinner film (transfer()).
  double flagMm() const { return flag_mm_; }
  // The share of the reservoir flow that draws paint up the hair
  // (Brush::paint_wicking, 1: all of it; the rest runs only towards the
  // tips; transfer()).
  double wicking() const { return wicking_; }

 private:
  BrushTexelMap map_;
  double capacity_ = 1;
  double capacity_mm3_ = 0;
  double full_film_mm_ = kFullLoadFilmMm;
  double flow_ = 1;
  double flag_mm_ = 0;
  double wicking_ = 1;
  MixModel model_ = MixModel::kKubelkaMunk;
  std::vector<PaintCell> cells_;
};

// The canvas's paint: wet and dry layers over a toothy paper.
class PaintCanvas {
 public:
  // Throws Error(kDataError) if paper.colour is not "#rrggbb" or the tooth is
  // negative / its scale not positive, Error(kDataError) past the size limits
  // of engine/model/canvas.h (before allocating).
  PaintCanvas(const CanvasGrid& grid, const PaperSpec& paper, MixModel model);

  const CanvasGrid& grid() const { return grid_; }
  const PaperSpec& paper() const { return paper_; }
  MixModel model() const { return model_; }
  double pixelAreaMm2() const { return 1.0 / (grid_.px_per_mm * grid_.px_per_mm); }
  size_t index(int col, int row) const {
    return static_cast<size_t>(row) * grid_.width_px + col;
  }
  size_t pixels() const { return wet_.size(); }

  PaintCell& wet(size_t i) { return wet_[i]; }
  const PaintCell& wet(size_t i) const { return wet_[i]; }
  // Paper tooth at a pixel: 0 in the deepest valley, 1 on the highest peak.
  // Worked out on the pixel's first use (paperTooth at its centre) and kept:
  // a stroke touches a small part of its canvas, and a painting's canvas of
  // tens of megapixels took seconds to fill in advance. Not thread-safe, as
  // nothing else of the canvas is.
  float tooth(size_t i) const {
    if (tooth_[i] < 0) tooth_[i] = toothAt(i);
    return tooth_[i];
  }
  // Linear reflectance of the dry layer (paper and dried paint).
  const std::array<float, 3>& dryReflectance(size_t i) const { return dry_[i]; }

  // The wet layer dries onto the dry layer (a scene's dry_before): composited
  // over it, its thickness added to the dry height; the wet layer is emptied.
  void dry();

  // Linear reflectance of a pixel: wet film over the dry layer.
  std::array<double, 3> reflectance(size_t i) const;
  // Paint height above the paper (mm): dry height plus the wet film.
  double heightMm(size_t i) const;

  double wetVolumeMm3() const;
  double dryVolumeMm3() const;
  bool blank() const;  // no paint at all, wet or dry

 private:
  CanvasGrid grid_;
  PaperSpec paper_;
  MixModel model_;
  std::vector<PaintCell> wet_;
  std::vector<std::array<float, 3>> dry_;
  std::vector<float> dry_height_;
  float toothAt(size_t i) const;
  mutable std::vector<float> tooth_;  // < 0: not worked out yet
};

// Paper tooth (value noise, two octaves, world-anchored so a pixel at the same
// canvas position gets the same tooth whatever the canvas window): in [0, 1].
double paperTooth(const PaperSpec& paper, double x_mm, double y_mm);

// How far the hair slid over the paper in one step, for flagged hair's
// pickup (transfer(); docs/paint.md, "Flags scrub only as they slide"): the
// pieces of the spines pressed onto the paper, each a segment from a to b in
// canvas mm (x, y) with how far each end moved over the paper during the
// step (mm, in x and y only: a joint that rises or sinks does not rub the
// paper). The hair at a point of the footprint moves with the nearest
// piece, the spines carrying the hair around them (Baxter & Lin 2004, §4);
// with no piece nothing is pressed onto the paper, and nothing slides.
struct HairSlide {
  struct Piece {
    float ax_mm, ay_mm, bx_mm, by_mm;
    float slide_a_mm, slide_b_mm;
  };
  std::vector<Piece> pieces;
  // The slide (mm) at canvas point (x, y): that of the piece nearest it in
  // (x, y), interpolated along the piece; 0 without pieces.
  double at(double x_mm, double y_mm) const;
};

// How hard the hair presses the paper in one step, for the transfer rate
// (TransferParams::press_full_n_per_mm2; docs/paint.md, "Pressed hair gives
// and takes, resting hair barely"): the same pieces as HairSlide's (the
// spines' joints that bear the canvas's force, eq. 5, and the segments
// between two that do), each end carrying the contact pressure (N/mm^2) of
// its spine, the load it bears over the hair it lays on the paper. The hair
// at a point of the footprint presses as the nearest piece does; with no
// piece nothing bears a load, and nothing presses.
struct HairPress {
  struct Piece {
    float ax_mm, ay_mm, bx_mm, by_mm;
    float press_a, press_b;  // N/mm^2
  };
  std::vector<Piece> pieces;
  // The pressure (N/mm^2) at canvas point (x, y): that of the piece nearest
  // it in (x, y), interpolated along the piece; 0 without pieces.
  double at(double x_mm, double y_mm) const;
};

// The footprint of one step as the paint model sees it: a window of the
// canvas's pixels (col0, row0 = its top-left pixel in the canvas) with 4 floats
// per pixel, u, v, depth_mm, coverage (render/gl/footprint_renderer.h).
struct FootprintView {
  int col0 = 0, row0 = 0;
  int width = 0, height = 0;
  const float* texels = nullptr;
  // The contact band (mm) the footprint was rendered with: depth_mm runs from
  // 0 at the band's top to contact_band_mm at the canvas, and brush geometry
  // that reaches the canvas presses fully.
  double contact_band_mm = 0.1;
  // How the hair moved over the paper this step (HairSlide), for flagged
  // hair's pickup; null when not known: the flags then pick up in full.
  const HairSlide* slide = nullptr;
  // How hard the hair pressed the paper this step (HairPress), for the
  // transfer rate of every brush; null when not known: it transfers in full.
  const HairPress* press = nullptr;
};

struct TransferParams {
  // Pressing (footprint depth, mm) it takes for hairs to reach the floor of the
  // paper's grain, in units of the grain's depth. A hair spans several grain
  // features (tooth_scale ~ 0.4 mm against hairs ~0.1 mm thick and far longer)
  // and bends into a valley only under load; 8x lets a firm stroke (depth
  // ~1 mm where spines press) fill the grain while a stroke that barely touches
  // (depth ~0.1 - 0.3 mm) marks only its peaks on a 0.05 mm grain.
  // That is a bundle's bridging (the surface, the spines' tubes). A hair strip
  // narrower than the grain's features sinks into a valley wider than itself:
  // its bridging falls from this towards 1 (the grain's own depth) in
  // proportion to its width over the grain's feature size (docs/paint.md,
  // "A single hair follows the grain").
  double hair_bridging = 8.0;
  // Per step, a touching texel hands this fraction of a full load's film to each
  // pixel under it, in proportion to contact, while it has paint (at most
  // max_out_fraction of what it holds) ...
  double deposit_rate = 0.03;
  // ... and each touching pixel gives up this fraction of its wet paint to the texel.
  // Wet film settles where deposit and pickup balance: deposit_rate / pickup_rate
  // of a full load's film (0.15 * 0.3 mm = 0.045 mm, about 2 optical units).
  double pickup_rate = 0.2;
  // A texel hands over at most this fraction of its own paint in one step;
  // what its touches want past that, its column (the hair along which paint
  // runs to the touching end) feeds it within the step, each texel of it
  // sparing at most this fraction of its own (docs/paint.md, "The cap on a
  // texel's deposit").
  double max_out_fraction = 0.5;
  // Below this fraction of a full load a texel begins to run dry: it deposits only
  // where the paper's tooth (0 valley .. 1 peak) exceeds a threshold growing
  // with its dryness to about dry_threshold when empty, higher for the barer
  // hairs and lower for the better loaded (BrushTexelMap::hairNoise), so a
  // spent brush draws its best hairs' lines, broken where the grain dips:
  // dry brush.
  double dry_load = 0.25;
  // How unevenly the hairs lay paint: a hair with hair noise n in [0, 1]
  // deposits 1 + hair_streaks * (n - 1/2) times what an even bundle would
  // (the mean stays 1), so the wet film settles (deposit against pickup)
  // (1 + h/2) / (1 - h/2) = 2.3 times as thick under the best-loaded hairs
  // as under the barest at h = 0.8: streaks along the stroke (docs/paint.md,
  // "Hair streaks").
  double hair_streaks = 0.8;
  double dry_threshold = 0.9;
  // Flagged hair (BrushPaint::flagMm) takes up wet paint by the paper it
  // wipes. Its flags are fine and few: standing on the paper they wet only
  // the share of it they cover, the share g they lay on (the rim's deposit
  // factor); drawn across it, each flag wipes the gap beside it as it slides
  // by the gap's width. So where the footprint tells how the hair slid
  // (FootprintView::slide), the rim's pickup is the full hair's times
  // g + (1 - g) min(1, s / flag_scrub_mm), s the slide per reference step
  // (a speed, so that cutting a step in two changes nothing). 0.2 mm is the
  // gap between its flags: the hairs are 0.1 mm thick, and the dome's tips,
  // few and splayed, stand about two thicknesses apart. A flag drawn at
  // 40 mm/s or faster, a softening stroke, wipes all of the paper under the
  // rim, while one lifting straight off it or creeping to a stop does not
  // scrub it (docs/paint.md, "Flags scrub only as they slide").
  double flag_scrub_mm = 0.2;
  // Flagged hair lays paint as it slides, too: its split ends hold the paint
  // in their splits by capillarity, and the paper draws it out of them as
  // they pass over it (the film drawn from a meniscus grows with the speed,
  // as in dip coating), while a flag standing on the paper gives only what
  // wets its contact. So where the footprint tells how the hair slid, a
  // flagged brush's deposit is the rate's
  // flag_still_deposit + (1 - flag_still_deposit) min(1, s / flag_scrub_mm):
  // in full at 40 mm/s or faster, per mm slid below it, and this share
  // standing. Under a still dome the film then settles at this share of the
  // deposit-pickup balance, not at all of it: a softener landing on the
  // paper leaves no blot, and its mark fades in. It applies on the flagged
  // rim too, where fewer flags reach the paper (the rim's g scales deposit
  // and, standing, pickup alike): each of them holds and gives its paint as
  // the body's do, so a standing rim settles no darker than the body and a
  // pressed dab feathers out at its edge. 1: deposit whatever the slide
  // (docs/paint.md, "Flags lay as they slide").
  double flag_still_deposit = 0.25;
  // Paint moves between hair and paper as the hair presses on it (dAb's and
  // the paper's transfer, §4.2.1, is by contact; this is how hard): a
  // pressed bundle squeezes paint out of its hair onto the paper and wets
  // the paper's film into its hair, while hair resting on the paper under
  // no load only brushes it. Where the footprint tells how hard the hair
  // presses (FootprintView::press), both deposit and pickup run at
  // press_floor + (1 - press_floor) min(1, P / press_full_n_per_mm2) of
  // their rates, P the contact pressure there. The film's balance
  // (deposit_rate / pickup_rate) is the same at any pressure: a light touch
  // that lingers still settles the paper, but hair sweeping past under a
  // vanishing load (a softener's tips springing back as it lifts) leaves the
  // film nearly as it found it. 0.01 N/mm^2 is under what a round or a flat
  // presses with through a stroke's body (their spines along
  // straight-pull.csv: 0.0125 and 0.013 N/mm^2 at the 5th percentile), so
  // their bodies transfer in full, and about a calligraphy brush's median
  // (0.0095); the badger's soft dome presses 0.001 - 0.004 N/mm^2
  // (docs/paint.md, "Pressed hair gives and takes, resting hair barely").
  double press_full_n_per_mm2 = 0.01;
  double press_floor = 0.1;
  // How many of a flagged brush's flags reach the paper (BrushPaint::flagMm).
  // A softener's dome is flags all over: fine split ends, few and splayed,
  // that bridge the paper's grain. Under a light load only the flags its
  // load bends onto the paper touch it, on the grain's peaks, and the more
  // it presses the more of them lie down, into the valleys too, as the
  // contact of a fibre mat grows with its load. So where the footprint
  // tells how hard the hair presses, a flagged brush touches a pixel only
  // where the paper stands high (tooth) or the hair there is well loaded
  // (hairNoise), their mean above 1 - f, with f = flag_cover_floor +
  // (1 - flag_cover_floor) min(1, P / flag_cover_n_per_mm2), over the dry
  // brush's soft edge; where it does not touch, it neither gives nor takes
  // paint. A light touch then leaves a broken, streaked film however dark
  // the paint, where a film of any thickness in an opaque paint reads as a
  // solid bar, and a firm press covers the paper. 0.003 N/mm^2 is the middle
  // of what the badger presses through its pulls (0.001 - 0.004); resting
  // under no load its flags still touch the highest fifth of the grain.
  // Brushes without flags cover what their geometry touches (docs/paint.md,
  // "Light flags touch the grain's peaks").
  double flag_cover_n_per_mm2 = 0.003;
  double flag_cover_floor = 0.2;
  // Paint flows within each column of the brush texture (one lateral position of
  // the bundle) towards texels that lost paint, the belly feeding the tip by
  // capillarity: this fraction of each texel's difference from the column mean
  // per step. Strong enough that the hairs in contact do not run dry while the
  // rest of the bundle is full (a contact row drains ~50% per step without it).
  double reservoir_flow = 0.2;
  // How long this step's contact lasted, in reference steps (the step's time
  // over kTransferReferenceStepS). The rates above are per reference step:
  // deposit (an amount) scales with it, and pickup, max_out_fraction and
  // reservoir_flow (fractions) compound as 1 - (1 - f)^exposure. So paint
  // transfer depends on how long the brush touched, not on how many steps
  // the touch was cut into (rates per step would make the round's straight
  // pull lay 71, 111 and 204 mm^3 at --max-step-mm 0.25, 0.1 and 0.05).
  // 1 = one reference step, what a direct call gets by default.
  double exposure = 1.0;
};

// Contact time of bristle's reference step: the rates of TransferParams are per
// this much contact. It is the step the default planner takes on a trajectory
// sampled at 100 Hz, as the library's are (two steps per 10 ms sample, from
// SimOptions' min_rate_hz of 120), the steps the rates were tuned on; steps cut
// finer by --max-step-mm, or a 1 kHz haptic recording, no longer lay more paint.
inline constexpr double kTransferReferenceStepS = 1.0 / 200;

// A fraction f taken per reference step, over `exposure` reference steps:
// 1 - (1 - f)^exposure (0 for no exposure, 1 for f >= 1). Splitting a step in
// two halves of the exposure takes the same fraction in all.
double compoundFraction(double fraction, double exposure);

struct TransferStats {
  double deposited_mm3 = 0;  // brush -> canvas
  double picked_up_mm3 = 0;  // canvas -> brush
  int contact_px = 0;        // pixels with contact > 0
};

// One step of bidirectional transfer (dAb): volume is conserved exactly up to
// float rounding (brush + canvas wet before == after).
TransferStats transfer(const FootprintView& footprint, BrushPaint& brush, PaintCanvas& canvas,
                       const TransferParams& params);

}  // namespace bristle

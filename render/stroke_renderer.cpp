#include "render/stroke_renderer.h"
#include "render/step_pipeline.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "engine/base/error.h"

namespace bristle::render {

namespace {

// A pixel count for a message; beyond a long (a far-off handle) in e notation.
std::string pixels(double v) {
  if (std::fabs(v) < 1e15) return std::to_string(static_cast<long>(v));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

CanvasGrid canvasForStroke(const Brush& brush, const Trajectory& trajectory,
                           const StrokeOptions& options) {
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const TrajectorySample& s : trajectory.samples) {
    lo = lo.cwiseMin(s.pose.position_mm.head<2>());
    hi = hi.cwiseMax(s.pose.position_mm.head<2>());
  }
  const double pad = brush.reachMm() + options.margin_mm;
  CanvasGrid g;
  g.px_per_mm = options.px_per_mm;
  // Snap the corner to the pixel grid so that world positions map to the same
  // pixel boundaries whatever the trajectory's extent.
  g.x0_mm = std::floor((lo.x() - pad) * g.px_per_mm) / g.px_per_mm;
  g.y0_mm = std::floor((lo.y() - pad) * g.px_per_mm) / g.px_per_mm;
  const double w = std::ceil((hi.x() + pad - g.x0_mm) * g.px_per_mm);
  const double h = std::ceil((hi.y() + pad - g.y0_mm) * g.px_per_mm);
  if (w > kMaxCanvasSidePx || h > kMaxCanvasSidePx || w * h > double(kMaxCanvasPixels))
    throw dataError(trajectory.path, "extent",
                    "the stroke needs a " + pixels(w) + " x " + pixels(h) +
                        " px canvas, above the limit of 16384 px a side and 64 Mpx; lower "
                        "--px-per-mm");
  g.width_px = static_cast<int>(w);
  g.height_px = static_cast<int>(h);
  return g;
}

// The footprint is drawn in tiles of at most this many pixels a side (the GL
// target's size); a larger window is drawn tile by tile into one image, so the
// paint laid depends on --px-per-mm only through the discretisation
// (docs/paint.md, "Which texel touches a pixel").
constexpr int kFootprintTilePx = 2048;

StrokeRenderer::StrokeRenderer() : renderer_(kFootprintTilePx) {
  // The strips are single hairs (paper §4.2); the surface and the spines'
  // bundles stand for many hairs side by side and are sampled as they are.
  renderer_.setHairTextureRange(textureUBegin(BrushPart::kStrip), textureUEnd(BrushPart::kStrip));
}
StrokeRenderer::~StrokeRenderer() = default;

bool StrokeRenderer::footprint(BrushGeometry& geometry, const BrushState& state,
                               const CanvasGrid& grid, double contact_band_mm, FootprintImage* out) {
  triangles_.clear();
  geometry.build(state, &triangles_, contact_band_mm);
  return renderTriangles(grid, contact_band_mm, out);
}

bool StrokeRenderer::renderTriangles(const CanvasGrid& grid, double contact_band_mm,
                                     FootprintImage* out) {
  const std::vector<BrushVertex>& tris = triangles_;
  // The window is the bounding box of the triangles that dip below the clip plane.
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  vertices_.clear();
  for (size_t t = 0; t + 2 < tris.size(); t += 3) {
    // The hair's builders left out what stays above the band already; the
    // surface's triangles are all here.
    if (!reachesDown(tris[t], tris[t + 1], tris[t + 2], contact_band_mm)) continue;
    for (int k = 0; k < 3; ++k) {
      const BrushVertex& v = tris[t + k];
      x0 = std::min(x0, double(v.x_mm));
      x1 = std::max(x1, double(v.x_mm));
      y0 = std::min(y0, double(v.y_mm));
      y1 = std::max(y1, double(v.y_mm));
      vertices_.push_back(FootprintVertex{v.x_mm, v.y_mm, v.z_mm, v.u, v.v});
    }
  }
  if (vertices_.empty()) return false;
  // Whole canvas pixels covering the box, clamped to the canvas.
  const int c0 = std::max(0, static_cast<int>(std::floor(grid.colOf(x0))));
  const int c1 = std::min(grid.width_px, static_cast<int>(std::ceil(grid.colOf(x1))));
  const int r0 = std::max(0, static_cast<int>(std::floor(grid.rowOf(y1))));
  const int r1 = std::min(grid.height_px, static_cast<int>(std::ceil(grid.rowOf(y0))));
  if (c1 <= c0 || r1 <= r0) return false;
  FootprintWindow win;
  win.px_per_mm = grid.px_per_mm;
  win.width_px = c1 - c0;
  win.height_px = r1 - r0;
  win.x0_mm = grid.x0_mm + c0 / grid.px_per_mm;
  win.y0_mm = grid.y0_mm + (grid.height_px - r1) / grid.px_per_mm;
  // A brush held at rest (docs/dynamics.md, "A brush held still") sends the
  // same triangles step after step; the same triangles in the same window
  // draw the same footprint, which `out` still holds if it is this
  // renderer's own image (a caller's may have changed since).
  const bool same = out == &image_ && out == drawn_into_ && contact_band_mm == drawn_band_mm_ &&
                    win == drawn_window_ && vertices_.size() == drawn_vertices_.size() &&
                    std::memcmp(vertices_.data(), drawn_vertices_.data(),
                                vertices_.size() * sizeof(FootprintVertex)) == 0;
  kept_ = same;
  if (!same) {
    drawn_into_ = nullptr;  // until the render below has filled it
    renderTiled(win, contact_band_mm, out);
    drawn_into_ = out;
    drawn_window_ = win;
    drawn_band_mm_ = contact_band_mm;
  }
  // The list just drawn (or kept) becomes the one to compare the next with;
  // the other buffer is refilled then.
  std::swap(vertices_, drawn_vertices_);
  return true;
}

void StrokeRenderer::renderTiled(const FootprintWindow& win, double contact_band_mm,
                                 FootprintImage* out) {
  if (win.width_px <= kFootprintTilePx && win.height_px <= kFootprintTilePx) {
    renderer_.render(vertices_, win, contact_band_mm, out);
    return;
  }
  out->window = win;
  out->texels.assign(static_cast<size_t>(win.width_px) * win.height_px * 4, 0.0f);
  // Tiles on the canvas's pixel grid: column c and row r (from the top) of the
  // window, each tile's bottom-left corner where its pixels begin.
  for (int r = 0; r < win.height_px; r += kFootprintTilePx) {
    for (int c = 0; c < win.width_px; c += kFootprintTilePx) {
      FootprintWindow tile;
      tile.px_per_mm = win.px_per_mm;
      tile.width_px = std::min(kFootprintTilePx, win.width_px - c);
      tile.height_px = std::min(kFootprintTilePx, win.height_px - r);
      tile.x0_mm = win.x0_mm + c / win.px_per_mm;
      tile.y0_mm = win.y0_mm + (win.height_px - r - tile.height_px) / win.px_per_mm;
      renderer_.render(vertices_, tile, contact_band_mm, &tile_);
      const size_t row_floats = static_cast<size_t>(tile.width_px) * 4;
      for (int k = 0; k < tile.height_px; ++k)
        std::memcpy(&out->texels[(static_cast<size_t>(r + k) * win.width_px + c) * 4],
                    &tile_.texels[k * row_floats], row_floats * sizeof(float));
    }
  }
}

namespace {

// A state between a and b (same brush): positions moved along, rotations
// turned along the shorter arc. For drawing only: the blend of two solved
// states is not itself solved, but within a stamp spacing of both it is
// where the hair passed.
void blendStates(const BrushState& a, const BrushState& b, double t, BrushState* out) {
  out->step = b.step;
  out->t_s = a.t_s + t * (b.t_s - a.t_s);
  out->handle.position_mm = a.handle.position_mm + t * (b.handle.position_mm - a.handle.position_mm);
  out->handle.rotation = a.handle.rotation.slerp(t, b.handle.rotation);
  out->spines.resize(b.spines.size());
  for (size_t s = 0; s < b.spines.size(); ++s) {
    const SpineState& sa = a.spines[s];
    const SpineState& sb = b.spines[s];
    SpineState& o = out->spines[s];
    o.joints_mm.resize(sb.joints_mm.size());
    for (size_t j = 0; j < sb.joints_mm.size(); ++j)
      o.joints_mm[j] = sa.joints_mm[j] + t * (sb.joints_mm[j] - sa.joints_mm[j]);
    o.rot.resize(sb.rot.size());
    for (size_t j = 0; j < sb.rot.size(); ++j)
      o.rot[j] = Eigen::Quaterniond(sa.rot[j])
                     .slerp(t, Eigen::Quaterniond(sb.rot[j]))
                     .toRotationMatrix();
    o.contact = sb.contact;
    o.sliding = sb.sliding;
    o.stuck_xy_mm = sb.stuck_xy_mm;
    // The canvas loads too: they set how far each bundle is pressed into the
    // paper (engine/geometry/spine_bundles.h; kBundleFlatLoadN, engine/model/brush.h).
    const std::vector<double>& fa = sa.solution.normal_force_n;
    const std::vector<double>& fb = sb.solution.normal_force_n;
    o.solution.normal_force_n.resize(fb.size());
    for (size_t j = 0; j < fb.size(); ++j)
      o.solution.normal_force_n[j] = (j < fa.size() ? fa[j] : 0.0) * (1 - t) + fb[j] * t;
  }
}

// At most this many stamps sweep one step: the walk (engine/dynamics/stepper.cpp)
// keeps a step's contact jump within max(2 --max-step-mm, 2 px), 4 px at the default
// 8 px/mm and 0.25 mm, so a sweep at one stamp per pixel needs 4-5; 32 covers
// a --max-step-mm of 2 at 8 px/mm.
constexpr int kMaxSweepStamps = 32;

// Which stamps of a sweep draw the half solid at each joint: (*plan)[k] for
// k = 1..stamps - 1 (the last stamp draws everything). A half solid whose
// patch on the paper keeps a curvature radius rho (capPatchRoundness) may
// move d = 2 sqrt(2 rho h - h^2) from one copy to the next and leave notches
// at most h = notch_px deep between them. Each is drawn at a stamp when
// waiting for the next would move it further than d from where it was last
// drawn, `from` counting as drawn: the step before drew it, and the paint
// sees the union of the steps' footprints.
void planCapStamps(const Brush& brush, const BrushState& from, const BrushState& to, int stamps,
                   double px_per_mm, double band_mm, double notch_px,
                   std::vector<JointCaps>* plan) {
  const size_t ns = brush.spines.size();
  plan->resize(stamps);
  for (JointCaps& caps : *plan) {
    caps.resize(ns);
    for (size_t s = 0; s < ns; ++s) caps[s].assign(brush.spines[s].jointCount() + 1, 0);
  }
  thread_local std::vector<double> rho_from, rho_to;
  for (size_t s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush.spines[s];
    capPatchRoundness(spec, from.spines[s], from.handle, band_mm, &rho_from);
    capPatchRoundness(spec, to.spines[s], to.handle, band_mm, &rho_to);
    for (int j = 1; j <= spec.jointCount(); ++j) {
      // How far its outline moves over the step: with the joint, and as its
      // patch grows or shrinks.
      const double motion =
          ((from.spines[s].joints_mm[j] - to.spines[s].joints_mm[j]).head<2>().norm() +
           std::fabs(rho_to[j] - rho_from[j])) * px_per_mm;
      const double rho = std::min(rho_from[j], rho_to[j]) * px_per_mm;
      const double d = 2 * std::sqrt(std::max(0.0, 2 * rho * notch_px - notch_px * notch_px));
      double last = 0;
      for (int k = 1; k < stamps; ++k) {
        if (notch_px > 0 && motion * (double(k + 1) / stamps - last) <= d) continue;
        (*plan)[k][s][j] = 1;
        last = double(k) / stamps;
      }
    }
  }
}

// How the spines slid over the paper from one state to the next, for a
// flagged brush's pickup (engine/paint/paint.h, HairSlide): each joint that
// touches the paper (SpineState::contact: it bears the canvas's force,
// Baxter & Lin 2004, eq. 5) with its move in x and y over the step, joined
// to the joint above it where that one touches too. Hair wipes the paper
// only where it is pressed onto it: the bundle of a joint that bears no load
// lies on the paper without rubbing it, so no joint touching, no slide.
void spineSlide(const BrushState& from, const BrushState& to, HairSlide* out) {
  out->pieces.clear();
  for (size_t s = 0; s < to.spines.size() && s < from.spines.size(); ++s) {
    const std::vector<Eigen::Vector3d>& a = from.spines[s].joints_mm;
    const std::vector<Eigen::Vector3d>& b = to.spines[s].joints_mm;
    const std::vector<bool>& touches = to.spines[s].contact;  // joints 1..n
    for (size_t j = 1; j < b.size() && j < a.size() && j <= touches.size(); ++j) {
      if (!touches[j - 1]) continue;
      const size_t i = j > 1 && touches[j - 2] ? j - 1 : j;
      out->pieces.push_back({static_cast<float>(b[i].x()), static_cast<float>(b[i].y()),
                             static_cast<float>(b[j].x()), static_cast<float>(b[j].y()),
                             static_cast<float>((b[i] - a[i]).head<2>().norm()),
                             static_cast<float>((b[j] - a[j]).head<2>().norm())});
    }
  }
}

// How hard the spines pressed the paper at a state, for the transfer rate
// (engine/paint/paint.h, HairPress): the pieces of spineSlide, each carrying
// its spine's contact pressure, the canvas's force on its joints (eq. 5's
// multipliers) over the hair it lays on the paper. The hair between joints
// lies along the paper and shares their load (as bundlePlacement has it), so
// the load is the spine's; its hair on the paper is, for each joint that
// touches, the segment leading to it, as wide as its bundle there.
void spinePress(const Brush& brush, const BrushState& state, HairPress* out) {
  out->pieces.clear();
  for (size_t s = 0; s < state.spines.size() && s < brush.spines.size(); ++s) {
    const SpineSpec& spec = brush.spines[s];
    const SpineState& spine = state.spines[s];
    const std::vector<Eigen::Vector3d>& x = spine.joints_mm;
    double load_n = 0, area_mm2 = 0;
    for (double f : spine.solution.normal_force_n) load_n += f;
    for (size_t j = 1; j < x.size() && j <= spine.contact.size(); ++j)
      if (spine.contact[j - 1] && j < spec.width_mm.size() && j <= spec.segment_lengths_mm.size())
        area_mm2 += spec.width_mm[j] * spec.segment_lengths_mm[j - 1];
    const float press = area_mm2 > 0 ? static_cast<float>(load_n / area_mm2) : 0.0f;
    for (size_t j = 1; j < x.size() && j <= spine.contact.size(); ++j) {
      if (!spine.contact[j - 1]) continue;
      const size_t i = j > 1 && spine.contact[j - 2] ? j - 1 : j;
      out->pieces.push_back({static_cast<float>(x[i].x()), static_cast<float>(x[i].y()),
                             static_cast<float>(x[j].x()), static_cast<float>(x[j].y()), press,
                             press});
    }
  }
}

}  // namespace

bool StrokeRenderer::sweptFootprint(BrushGeometry& geometry, const BrushState& from,
                                    const BrushState& to, const CanvasGrid& grid,
                                    double contact_band_mm, double spacing_mm, FootprintImage* out,
                                    double notch_px) {
  const double jump = contactJumpMm(geometry.brush(), from, to, contact_band_mm);
  const int stamps =
      std::clamp(static_cast<int>(std::ceil(jump / spacing_mm)), 1, kMaxSweepStamps);
  triangles_.clear();
  if (stamps > 1)
    planCapStamps(geometry.brush(), from, to, stamps, grid.px_per_mm, contact_band_mm, notch_px,
                  &stamp_plan_);
  // The blends stamp the hair only: the subdivision surface is the belly, many
  // pixels across, whose stamps a step apart overlap anyway; refining it again
  // for each blend would nearly double a step's footprint time
  // (docs/PERFORMANCE.md, "Footprints").
  // Of the half solids at the spines' joints, each stamp draws those planned
  // for it.
  for (int k = 1; k < stamps; ++k) {
    blendStates(from, to, double(k) / stamps, &blended_);
    geometry.buildHair(blended_, &triangles_, contact_band_mm, &stamp_plan_[k]);
  }
  geometry.build(to, &triangles_, contact_band_mm);
  return renderTriangles(grid, contact_band_mm, out);
}

void StrokeRenderer::paintStep(BrushGeometry& geometry, const BrushState* from,
                               const BrushState& state, const StrokeOptions& options,
                               PaintCanvas* canvas, BrushPaint* paint, StrokeResult* result) {
  const CanvasGrid& grid = canvas->grid();
  // The solver's contact counts as touching too, so that a brush that reached
  // the paper but marked no pixel is told apart from one that never reached it.
  for (const SpineState& spine : state.spines)
    if (std::find(spine.contact.begin(), spine.contact.end(), true) != spine.contact.end())
      result->touched = true;
  // One stamp per pixel of motion: a hair finer than a pixel, its tip dragged
  // several pixels a step, otherwise leaves a dotted line where a real one
  // draws a line.
  const double spacing_mm = 1.0 / grid.px_per_mm;
  const bool touched =
      from ? sweptFootprint(geometry, *from, state, grid, options.contact_band_mm, spacing_mm,
                            &image_, options.sweep_notch_px)
           : footprint(geometry, state, grid, options.contact_band_mm, &image_);
  if (!touched) return;
  if (kept_) ++result->footprints_kept;
  FootprintView view;
  // Pixel offset of the window in the canvas.
  view.col0 = static_cast<int>(std::lround(grid.colOf(image_.window.x0_mm)));
  view.row0 = static_cast<int>(
      std::lround(grid.rowOf(image_.window.y0_mm + image_.window.height_px / grid.px_per_mm)));
  view.width = image_.window.width_px;
  view.height = image_.window.height_px;
  view.texels = image_.texels.data();
  view.contact_band_mm = options.contact_band_mm;
  // Flagged hair picks up by how far it slid (TransferParams::flag_scrub_mm).
  if (from && paint->flagMm() > 0) {
    spineSlide(*from, state, &slide_);
    view.slide = &slide_;
  }
  // Every brush transfers as hard as it presses (TransferParams::press_full_n_per_mm2).
  spinePress(geometry.brush(), state, &press_);
  view.press = &press_;
  TransferParams params = options.transfer;
  // The step's contact time: the first stamp (no step before it) has none.
  params.exposure = from ? std::max(state.t_s - from->t_s, 0.0) / kTransferReferenceStepS : 0.0;
  const TransferStats st = transfer(view, *paint, *canvas, params);
  if (st.contact_px > 0) result->touched = true;
  result->deposited_mm3 += st.deposited_mm3;
  result->picked_up_mm3 += st.picked_up_mm3;
}

WalkOptions walkOptions(const StrokeOptions& options, double px_per_mm) {
  WalkOptions walk;
  walk.sim = options.sim;
  walk.px_per_mm = px_per_mm;
  walk.contact_band_mm = options.contact_band_mm;
  walk.stop_on_jump = options.stop_on_jump;
  return walk;
}

StrokeResult StrokeRenderer::render(const Brush& brush, const Trajectory& trajectory,
                                    std::unique_ptr<SpineSolver> solver,
                                    const StrokeOptions& options, PaintCanvas* canvas,
                                    BrushPaint* paint, const StepCallback& on_step,
                                    std::unique_ptr<SpineSolver> fallback) {
  BrushGeometry geometry(brush);
  Simulation sim(brush, options.sim, std::move(solver), std::move(fallback));
  StrokeResult result;
  // A stroke's first footprint is drawn, whatever the last stroke's was
  // (its renderer's options may have changed since).
  drawn_into_ = nullptr;
  bool first = true;
  BrushState painted;  // the state the last stamp showed
  const StepCallback draw = [&](const BrushState& state, int step, int steps) {
    // The first state has no step before it: a stamp, not a sweep.
    paintStep(geometry, first ? nullptr : &painted, state, options, canvas, paint, &result);
    first = false;
    painted = state;
    if (on_step) on_step(state, step, steps);
  };
  Stepper stepper(sim, walkOptions(options, canvas->grid().px_per_mm));
  const int threads = options.threads > 0 ? options.threads : defaultRenderThreads();
  if (threads >= 2)
    walkAhead(stepper, trajectory, draw);
  else
    stepper.walk(trajectory, draw);
  result.stats = sim.stats();
  return result;
}

}  // namespace bristle::render

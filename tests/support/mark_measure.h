#pragma once
// Image measures of a painted mark (the "Brush body" checks, bench/measure_marks):
// width along the stroke and its variation, blots (connected components, the
// largest one's convex-hull fill), and how far ink reaches past a given x.
//
// Everything works on a single-channel coverage image: v in [0, 1] per pixel,
// 1 = fully inked, row 0 at the top (as in the PNGs bristle writes). A pixel is
// "inked" when v > threshold. Pixel (c, r) covers canvas x in
// [x0 + c / ppm, x0 + (c + 1) / ppm] and y in [y0 + (h - r - 1) / ppm, y0 + (h - r) / ppm]
// (engine/model/canvas.h: x0, y0 is the bottom-left corner). coverageFromRgba8 and the
// PNG loader (mark_png.h) make one from a bristle image.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace bristle::testsupport {

struct Coverage {
  int w = 0, h = 0;
  double px_per_mm = 8;
  double x0_mm = 0, y0_mm = 0;  // canvas position of the bottom-left corner
  std::vector<float> v;         // w * h, row-major, row 0 at the top

  Coverage() = default;
  Coverage(int width, int height, double ppm = 8)
      : w(width), h(height), px_per_mm(ppm), v(static_cast<std::size_t>(width) * height, 0.0f) {}
  float& at(int c, int r) { return v[static_cast<std::size_t>(r) * w + c]; }
  float at(int c, int r) const { return v[static_cast<std::size_t>(r) * w + c]; }
};

// Ink of an 8-bit RGBA image (row 0 at the top). When any pixel is not opaque
// the ink is the alpha (paint on a transparent background). Otherwise it is the
// drop in luminance (Rec. 709 weights on the 8-bit values) below the paper,
// whose colour is the top-left pixel's: ink = clamp((L_paper - L) / L_paper, 0, 1),
// i.e. 1 - L / 255 on white paper. Light paint on light paper barely registers.
Coverage coverageFromRgba8(int w, int h, const std::uint8_t* rgba, double px_per_mm = 8);

enum class Axis { kX, kY };

// Width of the mark across the stroke, per position along it. With Axis::kX the
// stroke runs along x: for each column, the extent (mm) from the first to the
// last inked pixel of the column (both included; 0 when the column has none).
// With Axis::kY the same per row, across x. The centre is the canvas
// coordinate across the stroke (y for kX, x for kY, mm) of the middle of that
// extent: where the ink of a column sits against the stroke's line.
struct WidthProfile {
  Axis axis = Axis::kX;
  double px_per_mm = 8;
  std::vector<double> width_mm;   // per column (kX) or row (kY)
  std::vector<double> centre_mm;  // likewise; 0 where there is no ink
  int first = -1, last = -1;     // the inked span (indices into width_mm); -1: no ink
  bool empty() const { return first < 0; }
};
WidthProfile widthProfile(const Coverage& img, double threshold = 0.1, Axis axis = Axis::kX);

// Indices [lo, hi) of the part of the inked span from from_frac to to_frac of its
// length (n = last - first + 1: lo = first + round(from n), hi = first + round(to n)).
// Uninked positions inside the span count, with width 0 (a gap is a variation).
struct SpanRange {
  int lo = 0, hi = 0;
};
SpanRange middleRange(const WidthProfile& p, double from_frac = 0.2, double to_frac = 0.8);

// Mean width (mm) over the middle of the span; 0 without ink.
double meanWidthMm(const WidthProfile& p, double from_frac = 0.2, double to_frac = 0.8);
// Coefficient of variation (population std / mean) of the width over the middle
// of the span; 0 without ink.
double widthCv(const WidthProfile& p, double from_frac = 0.2, double to_frac = 0.8);

// Blots: 8-connected components of inked pixels, ignoring specks smaller than
// min_component_px. The convex hull of the largest is that of its pixels as unit
// squares (Andrew's monotone chain over the pixel corners, exact in integers),
// so a filled axis-aligned rectangle has fill 1 and fill <= 1 always.
struct BlotStats {
  int components = 0;          // of at least min_component_px pixels
  int specks = 0;              // smaller components, ignored
  long largest_area_px = 0;
  double largest_hull_area_px = 0;
  double fill = 0;             // largest_area_px / largest_hull_area_px (0 without ink)
  double largest_area_mm2 = 0;
  double largest_hull_area_mm2 = 0;
  // How evenly the largest blot is inked: the median ink of its pixels, and
  // the share of the pixels whose centres lie in its hull that have less
  // than half that ink (pale rings and gaps inside a blot; 0 for an even one).
  double median_ink = 0;
  double pale_share = 0;
  // The other components, specks included, that lie wholly outside the
  // largest one's hull (no pixel centre in it): marks beside the blot, where
  // a crumb of its own ragged edge lies in a notch of its outline.
  int satellites = 0;
};
BlotStats blotStats(const Coverage& img, double threshold = 0.1, int min_component_px = 4);

// How far ink reaches beyond x_mm (canvas mm) on one side: side = -1 behind
// (x < x_mm), +1 ahead (x > x_mm). It is the distance from x_mm to the far edge
// of the farthest inked column on that side, 0 when there is none. For a pull
// along +x, inkBeyondMm(img, x, -1) is the extent of ink behind x (tip drag: pass
// the handle's x where the contact ends and compare with the mark's own reach).
double inkBeyondMm(const Coverage& img, double x_mm, int side = -1, double threshold = 0.1);

// Lines across a stroke that runs along x: the runs of inked pixels down one
// column, where runs apart by at most merge_gap_px uninked pixels are one line
// (the paper's grain breaks a line without making it two). 0 outside the image.
int lineCount(const Coverage& img, int column, double threshold = 0.1, int merge_gap_px = 1);

// Streaks along the direction of travel, from the structure tensor of the ink
// over a window (columns [c0, c1), rows [r0, r1), clipped to the image so that
// central differences stay inside it): J_x = sum of (dv/dx)^2, J_y = sum of
// (dv/dy)^2. Returns (J_across - J_along) / (J_across + J_along) for a stroke
// travelling along `travel`: +1 when the ink changes only across the stroke
// (streaks exactly along it), -1 when only along it (bands across it), 0 for
// texture with no direction (a grain's dots) and for a window of even ink.
double streakAnisotropy(const Coverage& img, int c0, int c1, int r0, int r1, Axis travel);

// How square a stroke's ends are. The stroke runs along `travel` (Axis::kX:
// along the columns, its ends left and right). Its width is the lanes across
// it (rows for kX, columns for kY) inked over at least 5 % of their length;
// `trim` of that width is dropped from each side (a bundle's edge). For each
// remaining lane, where the ink starts and stops along the stroke; the spread
// (max - min, mm) of those starts is the start end's raggedness, of the stops
// the stop end's. A square-ended rectangle gives 0 at both.
struct EndSpread {
  double start_mm = 0, stop_mm = 0;
  int lanes = 0;  // lanes measured (0 without ink)
};
EndSpread endSpread(const Coverage& img, Axis travel, double trim = 0.0,
                    double threshold = 0.1);

// The cross-profile of a stroke running along `travel`: the mean ink of each
// lane across it (rows for Axis::kX, top row first; columns for kY), over the
// positions [from, to) along it (columns for kX, rows for kY), clipped to the image.
std::vector<double> crossProfile(const Coverage& img, Axis travel, int from, int to);

// Edge softness of a cross-profile. The ink's span is the lanes above 10 % of
// the profile's maximum, the plateau the mean over the middle half of that
// span (a stroke's body, streaks and all). On each side, the 10-90 % ramp is
// the distance (mm) from where the profile, walked inwards from outside the
// span, first reaches 10 % of the plateau to where it first reaches 90 % of
// it (crossings interpolated linearly between lanes). A step edge gives at
// most a pixel; 0 for an empty profile.
struct EdgeRamp {
  double low_side_mm = 0, high_side_mm = 0;  // the lane-0 side and the far side
  double plateau = 0;
  double meanMm() const { return 0.5 * (low_side_mm + high_side_mm); }
};
EdgeRamp edgeRamp(const std::vector<double>& profile, double px_per_mm);

// How far (mm) a stroke lays its paint before running dry, from its profile
// along the travel (the mean ink across it per position: crossProfile with
// the other axis). The stroke starts where the profile first reaches 10 % of
// its maximum; its start level is the profile's mean from start_mm to
// start_mm + window_mm past that (after the landing, over the body). The run
// ends where the profile's running mean over smooth_mm first falls under
// share x the start level; the run is the distance from the start to there,
// or to the stroke's last position (10 % of the maximum) if it never does.
// 0 for an empty profile.
double inkRunMm(const std::vector<double>& along, double px_per_mm, double share,
                double start_mm = 2, double window_mm = 8, double smooth_mm = 2);

// Inked pixels of the whole image.
long inkedPixels(const Coverage& img, double threshold = 0.1);

// Canvas x (mm) of the rear-most and front-most inked column edges; false without ink.
bool inkXRangeMm(const Coverage& img, double threshold, double* min_x_mm, double* max_x_mm);

// Principal axes of the inked pixels (each counted once, whatever its ink):
// the ratio of the long one to the short one, the square root of the ratio of
// their covariance's eigenvalues. 1 for a disc, 2 for an ellipse twice as long
// as it is wide; 0 with fewer than two inked pixels or all in a line.
double principalAxisRatio(const Coverage& img, double threshold = 0.1);

// The centroid of the inked pixels' ink (canvas mm, each pixel weighted by its
// ink): where a blot sits, to set against where the handle pressed it.
// False without ink.
bool inkCentroidMm(const Coverage& img, double threshold, double* x_mm, double* y_mm);

// The outline of a blot pressed straight down, seen from its ink centroid
// (inkCentroidMm's, in pixels). Along each of `directions` rays the blot's
// radius is the farthest point whose ink (bilinear between pixel centres)
// exceeds the threshold; the radii, smoothed over +-3 degrees (half a
// millimetre of arc at 10 mm, over the pixel staircase), go round the blot.
//  - lobes: the maxima of the radius that stand out by at least
//    prominence_mm (topographic prominence on the circle: how far the radius
//    falls on the lower of its two sides before it rises above the maximum
//    again; the largest radius always counts): a round blot has one, a cloud
//    of discs one per disc on its outline.
//  - the edge's softness: along each ray, walked inwards from outside, the
//    distance from where the ink first reaches 10 % of the blot's level to
//    where it first reaches 90 % of it (the level: the median ink of the
//    pixels above the threshold); the median over the rays. A hard edge gives
//    about a pixel.
//  - how the ink lies from the middle out: the mean ink within 0.3 of the
//    mean radius and over 0.6-0.9 of it, along the rays.
struct BlotOutline {
  int lobes = 0;
  double mean_radius_mm = 0, radius_cv = 0;
  double edge_ramp_mm = 0;
  double level = 0;
  double centre_ink = 0, outer_ink = 0;
};
BlotOutline blotOutline(const Coverage& img, double threshold = 0.1, double prominence_mm = 0.5,
                        int directions = 360);

}  // namespace bristle::testsupport

#include "tests/support/mark_measure.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>

namespace bristle::testsupport {

namespace {

double luminance(const std::uint8_t* px) {
  return 0.2126 * px[0] + 0.7152 * px[1] + 0.0722 * px[2];
}

struct Point {
  long long x = 0, y = 0;
  bool operator<(const Point& o) const { return x != o.x ? x < o.x : y < o.y; }
  bool operator==(const Point& o) const { return x == o.x && y == o.y; }
};

long long cross(const Point& o, const Point& a, const Point& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

// Andrew's monotone chain: the hull counter-clockwise, collinear points dropped.
std::vector<Point> convexHull(std::vector<Point> pts) {
  std::sort(pts.begin(), pts.end());
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<Point> hull(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  hull.resize(k - 1);
  return hull;
}

// Twice the area of a polygon (shoelace), exact.
long long twiceArea(const std::vector<Point>& poly) {
  long long a = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Point& p = poly[i];
    const Point& q = poly[(i + 1) % poly.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return a < 0 ? -a : a;
}

// Whether the centre of pixel (c, r) lies in `hull` (pixel corners,
// counter-clockwise, at least 3): tested in doubled coordinates, so exactly.
bool centreInHull(const std::vector<Point>& hull, int c, int r) {
  const Point p{2LL * c + 1, 2LL * r + 1};
  for (size_t k = 0; k < hull.size(); ++k) {
    const Point a{2 * hull[k].x, 2 * hull[k].y};
    const Point b{2 * hull[(k + 1) % hull.size()].x, 2 * hull[(k + 1) % hull.size()].y};
    if (cross(a, b, p) < 0) return false;
  }
  return true;
}

// BlotStats' median_ink and pale_share of a blot's pixels and hull (in
// pixel corners, counter-clockwise): pixel centres are tested in doubled
// coordinates, so exactly.
void paleShare(const Coverage& img, const std::vector<std::pair<int, int>>& blot,
               const std::vector<Point>& hull, BlotStats* out) {
  std::vector<float> ink;
  ink.reserve(blot.size());
  for (const auto& [c, r] : blot) ink.push_back(img.at(c, r));
  std::nth_element(ink.begin(), ink.begin() + ink.size() / 2, ink.end());
  out->median_ink = ink[ink.size() / 2];
  if (hull.size() < 3) return;
  long inside = 0, pale = 0;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      if (!centreInHull(hull, c, r)) continue;
      ++inside;
      if (img.at(c, r) < 0.5 * out->median_ink) ++pale;
    }
  if (inside > 0) out->pale_share = double(pale) / double(inside);
}

}  // namespace

Coverage coverageFromRgba8(int w, int h, const std::uint8_t* rgba, double px_per_mm) {
  Coverage img(w, h, px_per_mm);
  const size_t n = static_cast<size_t>(w) * h;
  bool transparent = false;
  for (size_t i = 0; i < n && !transparent; ++i) transparent = rgba[4 * i + 3] != 255;
  if (transparent) {
    for (size_t i = 0; i < n; ++i) img.v[i] = float(rgba[4 * i + 3] / 255.0);
    return img;
  }
  const double paper = n > 0 ? luminance(rgba) : 255.0;
  for (size_t i = 0; i < n; ++i) {
    const double ink = paper > 0 ? (paper - luminance(rgba + 4 * i)) / paper : 0.0;
    img.v[i] = float(std::clamp(ink, 0.0, 1.0));
  }
  return img;
}

WidthProfile widthProfile(const Coverage& img, double threshold, Axis axis) {
  WidthProfile p;
  p.axis = axis;
  p.px_per_mm = img.px_per_mm;
  const int along = axis == Axis::kX ? img.w : img.h;
  const int across = axis == Axis::kX ? img.h : img.w;
  p.width_mm.assign(static_cast<size_t>(along), 0.0);
  p.centre_mm.assign(static_cast<size_t>(along), 0.0);
  for (int i = 0; i < along; ++i) {
    int lo = -1, hi = -1;
    for (int j = 0; j < across; ++j) {
      const float v = axis == Axis::kX ? img.at(i, j) : img.at(j, i);
      if (v > threshold) {
        if (lo < 0) lo = j;
        hi = j;
      }
    }
    if (lo < 0) continue;
    p.width_mm[size_t(i)] = (hi - lo + 1) / img.px_per_mm;
    // Pixel edges: rows count down from the top, columns right from x0.
    p.centre_mm[size_t(i)] = axis == Axis::kX
                                 ? img.y0_mm + (2.0 * img.h - lo - hi - 1) / (2 * img.px_per_mm)
                                 : img.x0_mm + (lo + hi + 1) / (2 * img.px_per_mm);
    if (p.first < 0) p.first = i;
    p.last = i;
  }
  return p;
}

SpanRange middleRange(const WidthProfile& p, double from_frac, double to_frac) {
  if (p.empty()) return {};
  const int n = p.last - p.first + 1;
  SpanRange r;
  r.lo = p.first + static_cast<int>(std::lround(from_frac * n));
  r.hi = p.first + static_cast<int>(std::lround(to_frac * n));
  r.lo = std::clamp(r.lo, p.first, p.last);
  r.hi = std::clamp(r.hi, r.lo + 1, p.last + 1);
  return r;
}

double meanWidthMm(const WidthProfile& p, double from_frac, double to_frac) {
  if (p.empty()) return 0;
  const SpanRange r = middleRange(p, from_frac, to_frac);
  double sum = 0;
  for (int i = r.lo; i < r.hi; ++i) sum += p.width_mm[size_t(i)];
  return sum / (r.hi - r.lo);
}

double widthCv(const WidthProfile& p, double from_frac, double to_frac) {
  if (p.empty()) return 0;
  const SpanRange r = middleRange(p, from_frac, to_frac);
  const double mean = meanWidthMm(p, from_frac, to_frac);
  if (mean <= 0) return 0;
  double ss = 0;
  for (int i = r.lo; i < r.hi; ++i) {
    const double d = p.width_mm[size_t(i)] - mean;
    ss += d * d;
  }
  return std::sqrt(ss / (r.hi - r.lo)) / mean;
}

BlotStats blotStats(const Coverage& img, double threshold, int min_component_px) {
  BlotStats out;
  const int w = img.w, h = img.h;
  std::vector<int> label(static_cast<size_t>(w) * h, -1);
  std::vector<std::pair<int, int>> stack, largest;
  std::vector<std::pair<int, int>> pixels;
  for (int r0 = 0; r0 < h; ++r0) {
    for (int c0 = 0; c0 < w; ++c0) {
      const size_t i0 = size_t(r0) * w + c0;
      if (label[i0] >= 0 || !(img.v[i0] > threshold)) continue;
      const int id = out.components + out.specks;
      pixels.clear();
      stack.assign(1, {c0, r0});
      label[i0] = id;
      while (!stack.empty()) {
        const auto [c, r] = stack.back();
        stack.pop_back();
        pixels.push_back({c, r});
        for (int dr = -1; dr <= 1; ++dr)
          for (int dc = -1; dc <= 1; ++dc) {
            const int cc = c + dc, rr = r + dr;
            if (cc < 0 || rr < 0 || cc >= w || rr >= h) continue;
            const size_t j = size_t(rr) * w + cc;
            if (label[j] >= 0 || !(img.v[j] > threshold)) continue;
            label[j] = id;
            stack.push_back({cc, rr});
          }
      }
      if (static_cast<int>(pixels.size()) < min_component_px) {
        ++out.specks;
        continue;
      }
      ++out.components;
      if (static_cast<long>(pixels.size()) > out.largest_area_px) {
        out.largest_area_px = static_cast<long>(pixels.size());
        largest = pixels;
      }
    }
  }
  if (largest.empty()) return out;

  // The hull of the pixel squares is the hull of the outer corners of each row's
  // leftmost and rightmost pixels.
  std::vector<int> row_lo(size_t(h), w), row_hi(size_t(h), -1);
  for (const auto& [c, r] : largest) {
    row_lo[size_t(r)] = std::min(row_lo[size_t(r)], c);
    row_hi[size_t(r)] = std::max(row_hi[size_t(r)], c);
  }
  std::vector<Point> corners;
  for (int r = 0; r < h; ++r) {
    if (row_hi[size_t(r)] < 0) continue;
    for (long long y : {r, r + 1}) {
      corners.push_back({row_lo[size_t(r)], y});
      corners.push_back({row_hi[size_t(r)] + 1LL, y});
    }
  }
  const std::vector<Point> hull = convexHull(corners);
  out.largest_hull_area_px = 0.5 * double(twiceArea(hull));
  paleShare(img, largest, hull, &out);
  // Satellites: the other components, specks too, none of whose pixels lies
  // in the largest one's hull.
  const int largest_id = label[size_t(largest.front().second) * w + largest.front().first];
  std::vector<char> inside(size_t(out.components + out.specks), 0);
  if (hull.size() >= 3)
    for (int r = 0; r < h; ++r)
      for (int c = 0; c < w; ++c) {
        const int id = label[size_t(r) * w + c];
        if (id >= 0 && id != largest_id && !inside[size_t(id)] && centreInHull(hull, c, r))
          inside[size_t(id)] = 1;
      }
  for (size_t id = 0; id < inside.size(); ++id)
    if (int(id) != largest_id && !inside[id]) ++out.satellites;
  if (out.largest_hull_area_px > 0)
    out.fill = double(out.largest_area_px) / out.largest_hull_area_px;
  const double px2 = img.px_per_mm * img.px_per_mm;
  out.largest_area_mm2 = double(out.largest_area_px) / px2;
  out.largest_hull_area_mm2 = out.largest_hull_area_px / px2;
  return out;
}

bool inkXRangeMm(const Coverage& img, double threshold, double* min_x_mm, double* max_x_mm) {
  int lo = -1, hi = -1;
  for (int c = 0; c < img.w; ++c) {
    bool inked = false;
    for (int r = 0; r < img.h && !inked; ++r) inked = img.at(c, r) > threshold;
    if (!inked) continue;
    if (lo < 0) lo = c;
    hi = c;
  }
  if (lo < 0) return false;
  if (min_x_mm) *min_x_mm = img.x0_mm + lo / img.px_per_mm;
  if (max_x_mm) *max_x_mm = img.x0_mm + (hi + 1) / img.px_per_mm;
  return true;
}

int lineCount(const Coverage& img, int column, double threshold, int merge_gap_px) {
  if (column < 0 || column >= img.w) return 0;
  int lines = 0, gap = -1;  // gap < 0: no line yet
  for (int r = 0; r < img.h; ++r) {
    if (img.at(column, r) > threshold) {
      if (gap < 0 || gap > merge_gap_px) ++lines;
      gap = 0;
    } else if (gap >= 0) {
      ++gap;
    }
  }
  return lines;
}

double streakAnisotropy(const Coverage& img, int c0, int c1, int r0, int r1, Axis travel) {
  c0 = std::max(c0, 1);
  r0 = std::max(r0, 1);
  c1 = std::min(c1, img.w - 1);
  r1 = std::min(r1, img.h - 1);
  double jx = 0, jy = 0;
  for (int r = r0; r < r1; ++r)
    for (int c = c0; c < c1; ++c) {
      const double gx = 0.5 * (img.at(c + 1, r) - img.at(c - 1, r));
      const double gy = 0.5 * (img.at(c, r + 1) - img.at(c, r - 1));
      jx += gx * gx;
      jy += gy * gy;
    }
  if (!(jx + jy > 0)) return 0;
  const double across = travel == Axis::kX ? jy : jx, along = travel == Axis::kX ? jx : jy;
  return (across - along) / (across + along);
}

EndSpread endSpread(const Coverage& img, Axis travel, double trim, double threshold) {
  // Lane k across the stroke, position i along it.
  const bool along_x = travel == Axis::kX;
  const int lanes = along_x ? img.h : img.w, length = along_x ? img.w : img.h;
  auto inked = [&](int k, int i) {
    return (along_x ? img.at(i, k) : img.at(k, i)) > threshold;
  };
  std::vector<int> count(lanes, 0);
  for (int k = 0; k < lanes; ++k)
    for (int i = 0; i < length; ++i) count[k] += inked(k, i);
  int first = -1, last = -1;
  for (int k = 0; k < lanes; ++k)
    if (count[k] >= 0.05 * length) {
      if (first < 0) first = k;
      last = k;
    }
  EndSpread e;
  if (first < 0) return e;
  const int drop = static_cast<int>(std::floor(trim * (last - first + 1)));
  int start_lo = length, start_hi = -1, stop_lo = length, stop_hi = -1;
  for (int k = first + drop; k <= last - drop; ++k) {
    int a = -1, b = -1;
    for (int i = 0; i < length; ++i)
      if (inked(k, i)) {
        if (a < 0) a = i;
        b = i;
      }
    if (a < 0) continue;  // a gap across the stroke: no end to measure
    start_lo = std::min(start_lo, a);
    start_hi = std::max(start_hi, a);
    stop_lo = std::min(stop_lo, b);
    stop_hi = std::max(stop_hi, b);
    ++e.lanes;
  }
  if (e.lanes == 0) return e;
  e.start_mm = (start_hi - start_lo) / img.px_per_mm;
  e.stop_mm = (stop_hi - stop_lo) / img.px_per_mm;
  return e;
}

long inkedPixels(const Coverage& img, double threshold) {
  long n = 0;
  for (float v : img.v) n += v > threshold;
  return n;
}

double inkBeyondMm(const Coverage& img, double x_mm, int side, double threshold) {
  double lo = 0, hi = 0;
  if (!inkXRangeMm(img, threshold, &lo, &hi)) return 0;
  return side < 0 ? std::max(0.0, x_mm - lo) : std::max(0.0, hi - x_mm);
}

std::vector<double> crossProfile(const Coverage& img, Axis travel, int from, int to) {
  const bool along_x = travel == Axis::kX;
  const int lanes = along_x ? img.h : img.w, length = along_x ? img.w : img.h;
  from = std::clamp(from, 0, length);
  to = std::clamp(to, from, length);
  std::vector<double> p(static_cast<size_t>(lanes), 0.0);
  if (to == from) return p;
  for (int lane = 0; lane < lanes; ++lane) {
    double sum = 0;
    for (int k = from; k < to; ++k) sum += along_x ? img.at(k, lane) : img.at(lane, k);
    p[static_cast<size_t>(lane)] = sum / (to - from);
  }
  return p;
}

namespace {

// Where, walking from lane `start` by `step` (+1 or -1), the profile first
// reaches `level`: a fractional lane, interpolated between the lanes it falls between.
double rampCrossing(const std::vector<double>& p, int start, int step, double level) {
  for (int i = start; i >= 0 && i < static_cast<int>(p.size()); i += step) {
    if (p[static_cast<size_t>(i)] < level) continue;
    if (i == start) return i;
    const double a = p[static_cast<size_t>(i - step)], b = p[static_cast<size_t>(i)];
    return (i - step) + step * (level - a) / (b - a);
  }
  return start;
}

}  // namespace

EdgeRamp edgeRamp(const std::vector<double>& profile, double px_per_mm) {
  EdgeRamp e;
  if (profile.empty()) return e;
  const double peak = *std::max_element(profile.begin(), profile.end());
  if (!(peak > 0)) return e;
  const int n = static_cast<int>(profile.size());
  int first = 0, last = n - 1;
  while (profile[static_cast<size_t>(first)] <= 0.1 * peak) ++first;
  while (profile[static_cast<size_t>(last)] <= 0.1 * peak) --last;
  const int span = last - first + 1, m0 = first + span / 4, m1 = last - span / 4;
  for (int i = m0; i <= m1; ++i) e.plateau += profile[static_cast<size_t>(i)];
  e.plateau /= m1 - m0 + 1;
  const double lo = 0.1 * e.plateau, hi = 0.9 * e.plateau;
  // Start one lane outside the ink so the 10 % crossing is interpolated too.
  const int a = std::max(first - 1, 0), b = std::min(last + 1, n - 1);
  e.low_side_mm =
      (rampCrossing(profile, a, +1, hi) - rampCrossing(profile, a, +1, lo)) / px_per_mm;
  e.high_side_mm =
      (rampCrossing(profile, b, -1, lo) - rampCrossing(profile, b, -1, hi)) / px_per_mm;
  return e;
}

double inkRunMm(const std::vector<double>& along, double px_per_mm, double share,
                double start_mm, double window_mm, double smooth_mm) {
  if (along.empty()) return 0;
  const double peak = *std::max_element(along.begin(), along.end());
  if (!(peak > 0)) return 0;
  const int n = static_cast<int>(along.size());
  int first = 0, last = n - 1;
  while (along[static_cast<size_t>(first)] < 0.1 * peak) ++first;
  while (along[static_cast<size_t>(last)] < 0.1 * peak) --last;
  auto px = [&](double mm) { return static_cast<int>(std::lround(mm * px_per_mm)); };
  // The mean over positions [a, b), clipped to the stroke.
  auto mean = [&](int a, int b) {
    a = std::clamp(a, first, last + 1);
    b = std::clamp(b, a, last + 1);
    double sum = 0;
    for (int i = a; i < b; ++i) sum += along[static_cast<size_t>(i)];
    return b > a ? sum / (b - a) : 0.0;
  };
  const int w0 = first + px(start_mm), w1 = w0 + std::max(1, px(window_mm));
  const double level = share * mean(w0, w1);
  const int k = std::max(1, px(smooth_mm));
  for (int i = w1; i + k <= last + 1; ++i)
    if (mean(i, i + k) < level) return (i - first) / px_per_mm;
  return (last + 1 - first) / px_per_mm;
}

double principalAxisRatio(const Coverage& img, double threshold) {
  double n = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      if (img.at(c, r) <= threshold) continue;
      n += 1;
      sx += c;
      sy += r;
      sxx += double(c) * c;
      syy += double(r) * r;
      sxy += double(c) * r;
    }
  if (n < 2) return 0;
  const double a = sxx / n - sx * sx / n / n, b = syy / n - sy * sy / n / n,
               cxy = sxy / n - sx * sy / n / n;
  const double mid = (a + b) / 2, half = std::sqrt((a - b) * (a - b) / 4 + cxy * cxy);
  return mid - half > 0 ? std::sqrt((mid + half) / (mid - half)) : 0;
}

bool inkCentroidMm(const Coverage& img, double threshold, double* x_mm, double* y_mm) {
  double m = 0, mx = 0, my = 0;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      const double v = img.at(c, r);
      if (v <= threshold) continue;
      m += v;
      mx += v * (img.x0_mm + (c + 0.5) / img.px_per_mm);
      my += v * (img.y0_mm + (img.h - r - 0.5) / img.px_per_mm);
    }
  if (!(m > 0)) return false;
  *x_mm = mx / m;
  *y_mm = my / m;
  return true;
}

}  // namespace bristle::testsupport

namespace bristle::testsupport {

namespace {

// Ink at pixel coordinates (x, y) (pixel centres at half-integers),
// bilinear between the four nearest centres; 0 outside the image.
double inkAt(const Coverage& img, double x, double y) {
  const double fx = x - 0.5, fy = y - 0.5;
  const int c = static_cast<int>(std::floor(fx)), r = static_cast<int>(std::floor(fy));
  const double ax = fx - c, ay = fy - r;
  auto v = [&](int cc, int rr) {
    return cc < 0 || rr < 0 || cc >= img.w || rr >= img.h ? 0.0 : double(img.at(cc, rr));
  };
  return (1 - ay) * ((1 - ax) * v(c, r) + ax * v(c + 1, r)) +
         ay * ((1 - ax) * v(c, r + 1) + ax * v(c + 1, r + 1));
}

// Maxima of a circular sequence that stand out by at least `prominence`: on
// each side the sequence falls to some low before it rises above the maximum
// (or comes round to it), and the higher of the two lows lies at least that
// far below it. The highest maximum always counts. Equal values are ordered
// by index, so that a plateau is one maximum and the highest is one sample.
int prominentMaxima(const std::vector<double>& r, double prominence) {
  const int n = static_cast<int>(r.size());
  auto wrap = [&](int i) { return ((i % n) + n) % n; };
  auto at = [&](int i) { return r[static_cast<size_t>(wrap(i))]; };
  auto higher = [&](int j, int i) {  // sample j above sample i
    return at(j) > at(i) || (at(j) == at(i) && wrap(j) > wrap(i));
  };
  int count = 0;
  for (int i = 0; i < n; ++i) {
    if (!higher(i, i - 1) || !higher(i, i + 1)) continue;
    double low_left = at(i), low_right = at(i);
    int k = 1;
    for (; k < n && !higher(i - k, i); ++k) low_left = std::min(low_left, at(i - k));
    if (k == n) {  // nothing above it: the highest
      ++count;
      continue;
    }
    for (k = 1; k < n && !higher(i + k, i); ++k) low_right = std::min(low_right, at(i + k));
    if (at(i) - std::max(low_left, low_right) >= prominence) ++count;
  }
  return count;
}

}  // namespace

BlotOutline blotOutline(const Coverage& img, double threshold, double prominence_mm,
                        int directions) {
  BlotOutline out;
  double cx = 0, cy = 0, m = 0;
  std::vector<float> inked;
  for (int r = 0; r < img.h; ++r)
    for (int c = 0; c < img.w; ++c) {
      const float v = img.at(c, r);
      if (!(v > threshold)) continue;
      m += v;
      cx += v * (c + 0.5);
      cy += v * (r + 0.5);
      inked.push_back(v);
    }
  if (!(m > 0) || directions < 8) return out;
  cx /= m;
  cy /= m;
  std::nth_element(inked.begin(), inked.begin() + inked.size() / 2, inked.end());
  out.level = inked[inked.size() / 2];
  const double step = 0.25, reach = std::hypot(img.w, img.h);
  std::vector<double> radius(static_cast<size_t>(directions)), ramp;
  std::vector<std::vector<double>> rays(static_cast<size_t>(directions));
  for (int d = 0; d < directions; ++d) {
    const double a = 2 * std::numbers::pi * d / directions, dx = std::cos(a), dy = std::sin(a);
    std::vector<double>& ray = rays[static_cast<size_t>(d)];
    for (double s = 0; s < reach; s += step) ray.push_back(inkAt(img, cx + s * dx, cy + s * dy));
    int last = 0;
    for (int i = 0; i < static_cast<int>(ray.size()); ++i)
      if (ray[static_cast<size_t>(i)] > threshold) last = i;
    radius[static_cast<size_t>(d)] = last * step;
    int i10 = -1, i90 = -1;
    for (int i = static_cast<int>(ray.size()) - 1; i >= 0 && i90 < 0; --i) {
      const double v = ray[static_cast<size_t>(i)];
      if (i10 < 0 && v >= 0.1 * out.level) i10 = i;
      if (i10 >= 0 && v >= 0.9 * out.level) i90 = i;
    }
    if (i10 >= 0) ramp.push_back((i10 - std::max(i90, 0)) * step / img.px_per_mm);
  }
  // Smoothed over +-3 degrees.
  const int half = std::max(1, directions / 120);
  std::vector<double> smooth(radius.size());
  double sum = 0, sum2 = 0;
  for (int d = 0; d < directions; ++d) {
    double s = 0;
    for (int k = -half; k <= half; ++k)
      s += radius[static_cast<size_t>(((d + k) % directions + directions) % directions)];
    smooth[static_cast<size_t>(d)] = s / (2 * half + 1) / img.px_per_mm;
    sum += smooth[static_cast<size_t>(d)];
    sum2 += smooth[static_cast<size_t>(d)] * smooth[static_cast<size_t>(d)];
  }
  out.mean_radius_mm = sum / directions;
  const double var = std::max(0.0, sum2 / directions - out.mean_radius_mm * out.mean_radius_mm);
  out.radius_cv = out.mean_radius_mm > 0 ? std::sqrt(var) / out.mean_radius_mm : 0;
  out.lobes = prominentMaxima(smooth, prominence_mm);
  if (!ramp.empty()) {
    std::nth_element(ramp.begin(), ramp.begin() + ramp.size() / 2, ramp.end());
    out.edge_ramp_mm = ramp[ramp.size() / 2];
  }
  // Mean ink along the rays within 0.3 of the mean radius, and over 0.6-0.9.
  const double rpx = out.mean_radius_mm * img.px_per_mm;
  double c_sum = 0, o_sum = 0;
  long c_n = 0, o_n = 0;
  for (const std::vector<double>& ray : rays)
    for (size_t i = 0; i < ray.size(); ++i) {
      const double s = i * step / rpx;
      if (s < 0.3) c_sum += ray[i], ++c_n;
      else if (s >= 0.6 && s < 0.9) o_sum += ray[i], ++o_n;
    }
  out.centre_ink = c_n ? c_sum / c_n : 0;
  out.outer_ink = o_n ? o_sum / o_n : 0;
  return out;
}

}  // namespace bristle::testsupport

#include "input/pen_mapping.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/base/error.h"
#include "input/pen_axis.h"
#include "input/svg_geometry.h"

namespace bristle::input {

namespace {

constexpr double kRadPerDeg = M_PI / 180;

double scaleOf(const Recording& rec, const MappingOptions& o) {
  return o.mm_per_unit > 0 ? o.mm_per_unit : rec.mm_per_unit;
}

// One pen sample as a trajectory sample at time t_s.
TrajectorySample mapSample(const PenSample& p, double t_s, const Placement& place,
                           const MappingOptions& o, const std::string& path) {
  TrajectorySample s;
  s.t_s = t_s;
  s.line = p.line;
  const Eigen::Vector2d xy = place.toMm(p.x, p.y);
  if (!(xy.cwiseAbs().maxCoeff() <= kMaxPositionMm))
    throw dataError(path, "line " + std::to_string(p.line),
                    "the position (" + formatNumber(p.x) + ", " + formatNumber(p.y) +
                        ") lands at (" + formatNumber(xy.x()) + ", " + formatNumber(xy.y()) +
                        ") mm, beyond the limit of +-100000 mm (check --dpi / --px-per-mm)");
  s.pose.position_mm = Eigen::Vector3d(xy.x(), xy.y(), 0);
  Eigen::Vector3d axis = p.has_tilt ? p.axis : penAxisFromTilt(o.tilt_x_deg, o.tilt_y_deg);
  if (place.flip_y) axis.y() = -axis.y();
  s.pose.rotation = handleRotation(axis, p.has_twist ? p.twist_deg : o.twist_deg);
  s.depth_mm = pressureToDepthMm(p.pressure, p.down, o);
  s.buttons = p.down ? 1 : 0;
  return s;
}

// A pen-up copy of p at (x, y): the hover before a first or after a last touch.
PenSample hoverAt(const PenSample& p, double x, double y) {
  PenSample h = p;
  h.x = x;
  h.y = y;
  h.down = false;
  h.pressure = 0;
  return h;
}

Trajectory emptyTrajectory(const Recording& rec) {
  Trajectory t;
  t.path = rec.path;
  t.t_column = 1;
  t.depth_column = 4;  // t_s,x_mm,y_mm,depth_mm,... as trajectoryCsv writes it
  return t;
}

}  // namespace

double pressureToDepthMm(double pressure, bool down, const MappingOptions& o) {
  if (!down) return -o.hover_mm;
  return o.max_depth_mm * std::pow(std::clamp(pressure, 0.0, 1.0), o.pressure_gamma);
}

Eigen::Quaterniond handleRotation(const Eigen::Vector3d& axis_canvas, double twist_deg) {
  const Eigen::Vector3d a = axis_canvas.normalized();
  const Eigen::Quaterniond tilt = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), a);
  // Clockwise seen from above is a negative turn about an axis pointing up.
  const Eigen::Quaterniond twist(Eigen::AngleAxisd(-twist_deg * kRadPerDeg, a));
  return (twist * tilt).normalized();
}

Eigen::Vector2d Placement::toMm(double x, double y) const {
  return Eigen::Vector2d((x - x_min) * mm_per_unit + margin_mm,
                         (flip_y ? (y_max - y) : (y - y_min)) * mm_per_unit + margin_mm);
}

Placement placementOf(const Recording& rec, const MappingOptions& o) {
  Placement p;
  p.mm_per_unit = scaleOf(rec, o);
  p.flip_y = o.flip_y;
  p.margin_mm = o.margin_mm;
  double x_max = -std::numeric_limits<double>::infinity();
  p.x_min = p.y_min = std::numeric_limits<double>::infinity();
  p.y_max = -std::numeric_limits<double>::infinity();
  for (const PenSample& s : rec.samples) {
    p.x_min = std::min(p.x_min, s.x);
    x_max = std::max(x_max, s.x);
    p.y_min = std::min(p.y_min, s.y);
    p.y_max = std::max(p.y_max, s.y);
  }
  p.width_mm = (x_max - p.x_min) * p.mm_per_unit + 2 * o.margin_mm;
  p.height_mm = (p.y_max - p.y_min) * p.mm_per_unit + 2 * o.margin_mm;
  return p;
}

std::vector<PenSample> smoothed(const std::vector<PenSample>& in, double smooth_ms) {
  if (!(smooth_ms > 0) || in.size() < 3) return in;
  const double half = smooth_ms / 2000;
  std::vector<PenSample> out = in;
  // Prefix sums over each run, so that a window of any width costs the same
  // (a 10 s window over samples microseconds apart would otherwise cost n^2).
  // Positions are summed relative to the run's first sample, which keeps the
  // sums' rounding at the size of a stroke, not of the tablet's coordinates.
  struct Sums {
    double x = 0, y = 0, p = 0, tc = 0, ts = 0;
    Eigen::Vector3d axis = Eigen::Vector3d::Zero();
  };
  std::vector<Sums> prefix;
  std::size_t run_start = 0;
  while (run_start < in.size()) {
    std::size_t run_end = run_start;  // one past the run's last sample
    while (run_end < in.size() && in[run_end].down == in[run_start].down) ++run_end;
    const double x0 = in[run_start].x, y0 = in[run_start].y;
    prefix.assign(run_end - run_start + 1, Sums{});
    for (std::size_t k = run_start; k < run_end; ++k) {
      const Sums& a = prefix[k - run_start];
      Sums& b = prefix[k - run_start + 1];
      b.x = a.x + (in[k].x - x0);
      b.y = a.y + (in[k].y - y0);
      b.p = a.p + in[k].pressure;
      b.axis = a.axis + in[k].axis;
      b.tc = a.tc + std::cos(in[k].twist_deg * kRadPerDeg);
      b.ts = a.ts + std::sin(in[k].twist_deg * kRadPerDeg);
    }
    std::size_t lo = run_start, hi = run_start;  // window [lo, hi)
    for (std::size_t i = run_start; i < run_end; ++i) {
      while (in[lo].t_s < in[i].t_s - half) ++lo;
      while (hi < run_end && in[hi].t_s <= in[i].t_s + half) ++hi;
      const Sums& a = prefix[lo - run_start];
      const Sums& b = prefix[hi - run_start];
      const double n = static_cast<double>(hi - lo);
      out[i].x = x0 + (b.x - a.x) / n;
      out[i].y = y0 + (b.y - a.y) / n;
      out[i].pressure = std::clamp((b.p - a.p) / n, 0.0, 1.0);
      const Eigen::Vector3d axis = b.axis - a.axis;
      if (axis.norm() > 1e-9) out[i].axis = axis.normalized();
      const double twist = std::atan2(b.ts - a.ts, b.tc - a.tc) / kRadPerDeg;
      out[i].twist_deg = twist < 0 ? twist + 360 : twist;
    }
    run_start = run_end;
  }
  return out;
}

Trajectory toTrajectory(const Recording& rec, const MappingOptions& o) {
  const Placement place = placementOf(rec, o);
  const std::vector<PenSample> pen = smoothed(rec.samples, o.smooth_ms);
  Trajectory traj = emptyTrajectory(rec);
  const double lead_in = pen.front().down ? o.lead_s : 0;
  const double t0 = pen.front().t_s - lead_in;
  if (lead_in > 0)
    traj.samples.push_back(mapSample(hoverAt(pen.front(), pen.front().x, pen.front().y), 0,
                                     place, o, rec.path));
  for (const PenSample& p : pen) traj.samples.push_back(mapSample(p, p.t_s - t0, place, o, rec.path));
  if (pen.back().down)
    traj.samples.push_back(mapSample(hoverAt(pen.back(), pen.back().x, pen.back().y),
                                     pen.back().t_s - t0 + o.lead_s, place, o, rec.path));
  return traj;
}

std::vector<Trajectory> toStrokeTrajectories(const Recording& rec, const MappingOptions& o) {
  const Placement place = placementOf(rec, o);
  const std::vector<PenSample> pen = smoothed(rec.samples, o.smooth_ms);
  std::vector<Trajectory> out;
  std::size_t i = 0;
  while (i < pen.size()) {
    if (!pen[i].down) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j + 1 < pen.size() && pen[j + 1].down) ++j;
    // The hover before: the pen-up sample before the touch, or where the pen
    // was lead_s before it (on the way from that sample) when that is longer ago.
    PenSample before = hoverAt(pen[i], pen[i].x, pen[i].y);
    before.t_s = pen[i].t_s - o.lead_s;
    if (i > 0) {
      const PenSample& a = pen[i - 1];
      const double u = std::clamp((before.t_s - a.t_s) / (pen[i].t_s - a.t_s), 0.0, 1.0);
      before = hoverAt(a, a.x + u * (pen[i].x - a.x), a.y + u * (pen[i].y - a.y));
      before.t_s = a.t_s + u * (pen[i].t_s - a.t_s);
    }
    PenSample after = hoverAt(pen[j], pen[j].x, pen[j].y);
    after.t_s = pen[j].t_s + o.lead_s;
    if (j + 1 < pen.size()) {
      const PenSample& b = pen[j + 1];
      const double u = std::clamp((after.t_s - pen[j].t_s) / (b.t_s - pen[j].t_s), 0.0, 1.0);
      after = hoverAt(b, pen[j].x + u * (b.x - pen[j].x), pen[j].y + u * (b.y - pen[j].y));
      after.t_s = pen[j].t_s + u * (b.t_s - pen[j].t_s);
    }
    Trajectory traj = emptyTrajectory(rec);
    const double t0 = before.t_s;
    traj.samples.push_back(mapSample(before, 0, place, o, rec.path));
    for (std::size_t k = i; k <= j; ++k)
      traj.samples.push_back(mapSample(pen[k], pen[k].t_s - t0, place, o, rec.path));
    traj.samples.push_back(mapSample(after, after.t_s - t0, place, o, rec.path));
    out.push_back(std::move(traj));
    i = j + 1;
  }
  return out;
}

std::vector<std::string> mappingNotes(const Recording& rec, const MappingOptions& o,
                                      const std::string& depth_rule) {
  const Placement p = placementOf(rec, o);
  std::size_t strokes = 0;
  for (std::size_t k = 0; k < rec.samples.size(); ++k)
    if (rec.samples[k].down && (k == 0 || !rec.samples[k - 1].down)) ++strokes;
  const std::string s = formatNumber(p.mm_per_unit), m = formatNumber(p.margin_mm);
  std::vector<std::string> notes = {
      "bristle import of " + rec.path + " (" + formatName(rec.format) + "): " +
          std::to_string(rec.samples.size()) + " samples, " + std::to_string(strokes) +
          " pen-down stroke(s)",
      "units: " + rec.units_note + "; " + s + " mm per source unit",
      "placement: x_mm = (x - " + formatNumber(p.x_min) + ") * " + s + " + " + m + "; " +
          (p.flip_y ? "y_mm = (" + formatNumber(p.y_max) + " - y) * " + s + " + " + m +
                          " (y flipped: the source's y points down)"
                    : "y_mm = (y - " + formatNumber(p.y_min) + ") * " + s + " + " + m +
                          " (y not flipped)"),
      "depth_mm: " + formatNumber(o.max_depth_mm) + " * pressure^" +
          formatNumber(o.pressure_gamma) + " past first contact while the pen is down (" +
          depth_rule + "); pen up: -" + formatNumber(o.hover_mm) + " (hovering)",
  };
  const bool any_tilt = std::any_of(rec.samples.begin(), rec.samples.end(),
                                    [](const PenSample& q) { return q.has_tilt; });
  notes.push_back(std::string("handle: ") +
                  (any_tilt ? "tilt and twist from the recording"
                            : "tiltX " + formatNumber(o.tilt_x_deg) + ", tiltY " +
                                  formatNumber(o.tilt_y_deg) + ", twist " +
                                  formatNumber(o.twist_deg) + " degrees (the recording has none)") +
                  "; buttons: 1 pen down, 0 pen up");
  if (o.smooth_ms > 0)
    notes.push_back("smoothed: centred moving average over " + formatNumber(o.smooth_ms) + " ms");
  return notes;
}

std::string trajectoryCsv(const Trajectory& t, const std::vector<std::string>& notes) {
  std::string out = "# bristle-trajectory/1\n";
  for (const std::string& n : notes) out += "# " + n + "\n";
  out += "t_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz,buttons\n";
  char buf[256];
  for (const TrajectorySample& s : t.samples) {
    const Eigen::Quaterniond& q = s.pose.rotation;
    // + 0.0 turns a -0 into 0 (printed as "-0.000000000" otherwise).
    std::snprintf(buf, sizeof buf, "%.9f,%.6f,%.6f,%.6f,%.9f,%.9f,%.9f,%.9f,%d\n", s.t_s,
                  s.pose.position_mm.x() + 0.0, s.pose.position_mm.y() + 0.0, s.depth_mm + 0.0,
                  q.w() + 0.0, q.x() + 0.0, q.y() + 0.0, q.z() + 0.0, s.buttons);
    out += buf;
  }
  return out;
}

}  // namespace bristle::input

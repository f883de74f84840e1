#include "engine/formats/input_warnings.h"
#include "engine/dynamics/stepper.h"

#include <algorithm>
#include <cstdio>

namespace bristle {
namespace {

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// The largest side of the box around `points` (mm).
double extentMm(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d lo = points.front(), hi = points.front();
  for (const Eigen::Vector3d& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).maxCoeff();
}

// "89 min" or "27 h": a duration people read at a glance.
std::string minutesOrHours(double s) {
  return s < 2 * 3600 ? fmt("%.0f min", s / 60) : fmt("%.0f h", s / 3600);
}

std::string durationWarning(const Trajectory& t, double span, double planned_steps) {
  // The unit that brings the span under the limit.
  const char* unit = span / 1e3 <= kLongTrajectoryS   ? "milliseconds"
                     : span / 1e6 <= kLongTrajectoryS ? "microseconds"
                                                      : "nanoseconds";
  return t.path + ": t_s spans " + fmt("%.0f", span) + " s (" + minutesOrHours(span) +
         (planned_steps > 0 ? ", " + fmt("%.0f", planned_steps) + " simulation steps" : "") +
         "); were the times in " + unit + "?";
}

std::string stepsWarning(const Trajectory& t, double span, double planned_steps,
                         const Brush& brush, const SimOptions& options) {
  double travel_mm = 0;
  for (size_t k = 0; k + 1 < t.samples.size(); ++k)
    travel_mm += rootMotionBoundMm(brush, t.samples[k].pose, t.samples[k + 1].pose);
  const std::string head = t.path + ": the trajectory plans " + fmt("%.0f", planned_steps) +
                           " simulation steps, over " + fmt("%.0f", kManyPlannedSteps) +
                           " (an hour or more of solving): ";
  if (travel_mm / options.max_step_mm >= span * options.min_rate_hz)
    return head + "the spine roots travel " + fmt("%.0f", travel_mm) + " mm at most " +
           fmt("%g", options.max_step_mm) +
           " mm a step; were x_mm, y_mm and z_mm in micrometres?";
  return head + fmt("%.0f", span) + " s of t_s at " + fmt("%g", options.min_rate_hz) +
         " steps a second";
}

}  // namespace

std::string trajectoryWarning(const Trajectory& t, double planned_steps, const Brush* brush,
                              const SimOptions& options) {
  const double span = t.endTime() - t.startTime();
  if (span > kLongTrajectoryS) return durationWarning(t, span, planned_steps);
  if (brush && planned_steps > kManyPlannedSteps)
    return stepsWarning(t, span, planned_steps, *brush, options);
  return "";
}

std::string brushScaleWarning(const Brush& brush) {
  if (!brush.surface.present() || brush.spines.empty()) return "";
  std::vector<Eigen::Vector3d> spine_points;
  for (const SpineSpec& s : brush.spines) {
    spine_points.push_back(s.root_mm);
    spine_points.push_back(s.root_mm - Eigen::Vector3d(0, 0, s.lengthMm()));
  }
  const double spines = extentMm(spine_points);
  const double cage = extentMm(brush.surface.cage_mm);
  const double ratio = std::max(spines, cage) / std::max(std::min(spines, cage), 1e-300);
  if (!(ratio > kBrushPartsMaxRatio)) return "";
  return brush.path + ": /spines span " + fmt("%.3g", spines) +
         " mm but /surface/cage_vertices_mm spans " + fmt("%.3g", cage) + " mm (" +
         fmt("%.0f", ratio) + " times " + (cage > spines ? "larger" : "smaller") +
         "); both are in mm: were they written in different units?";
}

}  // namespace bristle

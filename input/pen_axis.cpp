#include "input/pen_axis.h"

#include <cmath>

namespace bristle::input {

Eigen::Vector3d penAxisFromTilt(double tilt_x_deg, double tilt_y_deg) {
  constexpr double kRad = M_PI / 180;
  const bool flat_x = std::fabs(tilt_x_deg) >= 90, flat_y = std::fabs(tilt_y_deg) >= 90;
  // tan(tilt) is the axis's lean per unit of height along each axis.
  if (flat_x || flat_y) {
    const Eigen::Vector3d flat(flat_x ? std::copysign(1.0, tilt_x_deg) : 0,
                               flat_y ? std::copysign(1.0, tilt_y_deg) : 0, 0);
    return flat.normalized();
  }
  return Eigen::Vector3d(std::tan(tilt_x_deg * kRad), std::tan(tilt_y_deg * kRad), 1).normalized();
}

Eigen::Vector3d penAxisFromAltitudeAzimuth(double altitude_rad, double azimuth_rad) {
  const double c = std::cos(altitude_rad);
  return Eigen::Vector3d(c * std::cos(azimuth_rad), c * std::sin(azimuth_rad),
                         std::sin(altitude_rad))
      .normalized();
}

}  // namespace bristle::input

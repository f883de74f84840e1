#pragma once
// The pen's axis from what tablets and browsers report (W3C Pointer Events,
// "tiltX", "tiltY", "altitudeAngle", "azimuthAngle"), in the source's axes:
// x right, y down the screen, z out of the surface towards the user. The axis
// points from the tip to the top of the pen; (0, 0, 1) is upright.

#include <Eigen/Core>

namespace bristle::input {

// tiltX: the angle (degrees, [-90, 90]) between the y-z plane and the plane
// holding the pen and the y axis, positive when the top leans towards +x;
// tiltY likewise towards +y. At +-90 the pen lies on the surface.
Eigen::Vector3d penAxisFromTilt(double tilt_x_deg, double tilt_y_deg);

// altitudeAngle: radians above the surface ([0, pi/2], pi/2 upright);
// azimuthAngle: radians from +x towards +y ([0, 2 pi], clockwise on a screen)
// of the pen's top.
Eigen::Vector3d penAxisFromAltitudeAzimuth(double altitude_rad, double azimuth_rad);

}  // namespace bristle::input

#pragma once
// Device frame <-> canvas frame. A Phantom reports its stylus in its own frame
// (mm, origin at the workspace centre, x right, y up, z towards the user) and
// takes forces in it (N). The canvas frame (docs/design.md, "Frames and units") has the paper on
// the table: x right, y away from the user, z up. So
//   canvas = M device + origin,   M = [1 0 0; 0 0 -1; 0 1 0]
// and the brush frame is the stylus frame: the hairs (-z of the brush) point
// where the pen's tip points (-z of the stylus). Header-only so the tests'
// stand-in libHD can script its path from a canvas-frame trajectory.

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "engine/model/pose.h"

namespace bristle::haptics {

struct DeviceMapping {
  // Where the workspace centre sits in the canvas frame: over the middle of a
  // 200 x 200 mm sheet, 40 mm above it (a Touch reaches ~60 mm below centre).
  Eigen::Vector3d origin_mm{100, 100, 40};

  static Eigen::Matrix3d m() {
    Eigen::Matrix3d r;
    r << 1, 0, 0, 0, 0, -1, 0, 1, 0;
    return r;
  }
  // transform: 16 doubles, column-major, translation in 12-14 (HD_CURRENT_TRANSFORM).
  Pose toCanvas(const double* transform) const {
    Eigen::Matrix3d r;
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) r(row, c) = transform[4 * c + row];
    Pose p;
    p.position_mm = m() * Eigen::Vector3d(transform[12], transform[13], transform[14]) + origin_mm;
    p.rotation = Eigen::Quaterniond(m() * r).normalized();
    return p;
  }
  void toDevice(const Pose& canvas, double* transform) const {
    const Eigen::Matrix3d r = m().transpose() * canvas.rotation.toRotationMatrix();
    const Eigen::Vector3d t = m().transpose() * (canvas.position_mm - origin_mm);
    for (int c = 0; c < 4; ++c)
      for (int row = 0; row < 4; ++row) transform[4 * c + row] = 0;
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) transform[4 * c + row] = r(row, c);
    for (int i = 0; i < 3; ++i) transform[12 + i] = t[i];
    transform[15] = 1;
  }
  Eigen::Vector3d forceToDevice(const Eigen::Vector3d& f_canvas) const {
    return m().transpose() * f_canvas;
  }
  Eigen::Vector3d forceToCanvas(const Eigen::Vector3d& f_device) const { return m() * f_device; }
};

}  // namespace bristle::haptics

#pragma once
// Where a brush first touches the paper, and trajectories whose heights are
// given relative to that (docs/formats.md, "Heights relative to the paper").
//
// A brush's first-contact height, for a handle orientation, is the height of
// the ferrule (the brush frame's origin) at which the brush at rest, held at
// that orientation, just touches the paper z = 0: the most its rest geometry
// reaches below the ferrule. That geometry is what the renderer draws (engine/
// brush_geometry.h): the spines with their hair bundles (bundleReachBelowPoints:
// a round bundle's radius, a slab's rounded rectangle) and, where the brush has
// one, the refined subdivision surface at rest, whichever reaches lower. The
// bristle strips are left out: they lie between the spines, and no library
// brush's reach below its bundles (tests/engine/geometry/test_first_contact.cpp).

#include <vector>

#include <Eigen/Geometry>

#include "engine/model/brush.h"
#include "engine/model/trajectory.h"

namespace bristle {

class FirstContact {
 public:
  // Keeps a reference to `brush`, which must outlive this. Builds the brush's
  // surface once (throws Error(kDataError) naming /surface for an unusable cage,
  // as BrushGeometry does).
  explicit FirstContact(const Brush& brush);

  // The ferrule's height (mm) at which the brush at rest, held at `rotation`
  // (brush frame to canvas frame), first touches the paper.
  double heightMm(const Eigen::Quaterniond& rotation) const;

 private:
  const Brush* brush_;
  std::vector<std::vector<double>> rest_q_;    // per spine: rest (theta, phi) per joint
  std::vector<Eigen::Vector3d> surface_rest_mm_;  // refined surface at rest, brush frame
};

// FirstContact(brush).heightMm(rotation); identity = held upright.
double firstContactHeightMm(const Brush& brush,
                            const Eigen::Quaterniond& rotation = Eigen::Quaterniond::Identity());

// The trajectory as `brush` is held along it. A trajectory that gives its
// heights as depth_mm (press depth past first contact) gets each sample's
// ferrule height, first contact at that sample's orientation minus its depth;
// one with z_mm comes back as it is. Every place a trajectory meets its brush
// (render, preview, record, replay, scene strokes, sheet cells, validate)
// calls this before validateTrajectoryForBrush. Throws Error(kDataError) naming
// the sample's line and depth_mm column when a ferrule height would pass the
// position limit (kMaxPositionMm).
Trajectory resolveDepths(const Trajectory& trajectory, const Brush& brush);

}  // namespace bristle

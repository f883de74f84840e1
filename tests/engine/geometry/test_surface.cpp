// The subdivision surface (paper §4.1): skinning reproduces the cage at rest,
// Catmull-Clark stays in the cage's convex hull, the surface follows pressed
// spines, and bad cages are rejected by name.

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "engine/geometry/brush_surface.h"
#include "engine/base/error.h"
#include "engine/geometry/spine_bundles.h"
#include "engine/mechanics/spine_kinematics.h"
#include "test_helpers.h"
#include "tests/support/tube_cage.h"

using namespace bristle;
using namespace bristle::testing;

namespace {

// Rigid motion and a convex combination are exact up to rounding: 1e-9 mm is
// ~1e6 ulps of a 10 mm coordinate, far below anything that matters.
constexpr double kExactMm = 1e-9;

// Spines hanging side by side along x, slightly bent at rest, tapering.
Brush tubeBrush(int spines, int level, int ring = 8) {
  std::vector<SpineSpec> specs;
  for (int s = 0; s < spines; ++s) {
    const double x = (s - 0.5 * (spines - 1)) * 1.5;
    SpineSpec sp = makeSpine({4, 4, 4}, {10, 8, 6}, 0, Eigen::Vector3d(x, 0, 0));
    sp.rest_angles_rad = {{0.04, 0.1 * x}, {0.03, 0}, {0.02, -0.01}};
    sp.width_mm = {2.0, 1.8, 1.4, 0.8};
    specs.push_back(sp);
  }
  Brush b = makeBrush(specs, 0.5, 0.4);
  b.surface = makeTubeCage(b, ring, level);
  return b;
}

// The brush state for given joint angles (rest angles if q is empty).
BrushState stateAt(const Brush& b, const Pose& handle, std::vector<std::vector<double>> q = {}) {
  BrushState st;
  st.handle = handle;
  st.spines.resize(b.spines.size());
  for (size_t s = 0; s < b.spines.size(); ++s) {
    std::vector<double>& qs = st.spines[s].solution.q;
    if (q.empty())
      for (const Eigen::Vector2d& a : b.spines[s].rest_angles_rad)
        qs.insert(qs.end(), {a[0], a[1]});
    else
      qs = q[s];
    SpineFk fk;
    spineForwardKinematics(b.spines[s], handle, qs.data(), 0, &fk);
    st.spines[s].joints_mm = fk.x;
    for (size_t k = 0; k < qs.size() / 2; ++k)
      st.spines[s].rot.push_back(jointRotation(qs[2 * k], qs[2 * k + 1]));
  }
  return st;
}

Pose tiltedPose() {
  Pose p = poseAt(3, -2, 15);
  p.rotation = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 0.5).normalized());
  return p;
}

ExitCode codeOf(const Brush& b, std::string* message) {
  try {
    BrushSurface surface(b);
  } catch (const Error& e) {
    *message = e.what();
    return e.code();
  }
  return ExitCode::kOk;
}

// One spine; the cage is given, every vertex follows the root.
Brush cageBrush(std::vector<Eigen::Vector3d> cage, std::vector<std::vector<int>> faces) {
  Brush b = makeBrush({makeSpine({4}, {10})}, 0.5, 0.4);
  b.surface.skin.assign(cage.size(), {SkinInfluence{0, 0, 1.0}});
  b.surface.cage_mm = std::move(cage);
  b.surface.faces = std::move(faces);
  return b;
}

// The brush lowered straight down from 14 mm to 7 mm over 70 steps: its
// 12 mm spines pressed about 5 mm past touching, well bent.
BrushState pressedStraightDown(const Brush& b) {
  Simulation sim(b, SimOptions{}, makeIpoptSolver());
  double t = 0;
  sim.reset(poseAt(0, 0, 14), t);
  for (int i = 1; i <= 70; ++i) sim.step(poseAt(0, 0, 14 - 0.1 * i), t += 0.01);
  return sim.state();
}

}  // namespace

TEST_CASE("skinning reproduces the cage at rest under any handle pose", "[surface]") {
  const Brush b = tubeBrush(3, 0);
  BrushSurface surface(b);
  REQUIRE(surface.refinedVertexCount() == int(b.surface.cage_mm.size()));
  int expected_triangles = 0;
  for (const auto& f : b.surface.faces) expected_triangles += int(f.size()) - 2;
  REQUIRE(surface.triangleCount() == expected_triangles);

  Simulation sim(b, SimOptions{}, makeIpoptSolver());
  for (Pose pose : {Pose{}, tiltedPose()}) {
    // Held well above the paper: below it, a surface is pressed no deeper
    // than its spines' bundles ("a pressed brush carries its surface").
    pose.position_mm.z() += 100;
    // Both a hand-made state and the simulation's own state at rest.
    sim.reset(pose, 0);
    for (const BrushState& st : {stateAt(b, pose), sim.state()}) {
      std::vector<BrushVertex> tris;
      surface.update(st, &tris);
      REQUIRE(tris.size() == size_t(3 * expected_triangles));
      for (size_t i = 0; i < b.surface.cage_mm.size(); ++i)
        CHECK((surface.refinedPosition(int(i)) - pose.apply(b.surface.cage_mm[i])).norm() <
              kExactMm);
      // The emitted triangles are the cage's own faces, in float.
      const auto& f0 = b.surface.faces[0];
      const Eigen::Vector3d want = pose.apply(b.surface.cage_mm[f0[0]]);
      CHECK(tris[0].x_mm == Approx(want.x()).margin(1e-5));
      CHECK(tris[0].z_mm == Approx(want.z()).margin(1e-5));
    }
  }
}

TEST_CASE("the refined surface stays inside the cage's convex hull", "[surface]") {
  // Catmull-Clark vertices are convex combinations of cage vertices: compare
  // support functions in many directions (a Fibonacci sphere), which bounds
  // the hull from outside, and the axis-aligned box.
  std::vector<Eigen::Vector3d> dirs;
  for (int i = 0; i < 400; ++i) {
    const double z = 1 - (i + 0.5) / 200.0, r = std::sqrt(1 - z * z);
    const double a = i * std::numbers::pi * (3 - std::sqrt(5.0));
    dirs.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  for (int level = 1; level <= 3; ++level) {
    const Brush b = tubeBrush(2, level);
    BrushSurface surface(b);
    const std::vector<std::vector<double>> bent = {{0.5, 0.2, 0.4, -0.1, 0.3, 0.2},
                                                   {0.3, -0.2, 0.5, 0.1, -0.2, 0.4}};
    for (const BrushState& st : {stateAt(b, Pose{}), stateAt(b, tiltedPose(), bent)}) {
      std::vector<BrushVertex> tris;
      surface.update(st, &tris);
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
      for (int i = 0; i < surface.cageVertexCount(); ++i) {
        lo = lo.cwiseMin(surface.cagePosition(i));
        hi = hi.cwiseMax(surface.cagePosition(i));
      }
      for (const Eigen::Vector3d& d : dirs) {
        double cage_max = -1e300, surf_max = -1e300;
        for (int i = 0; i < surface.cageVertexCount(); ++i)
          cage_max = std::max(cage_max, d.dot(surface.cagePosition(i)));
        for (int i = 0; i < surface.refinedVertexCount(); ++i)
          surf_max = std::max(surf_max, d.dot(surface.refinedPosition(i)));
        CHECK(surf_max <= cage_max + kExactMm);
      }
      for (int i = 0; i < surface.refinedVertexCount(); ++i) {
        const Eigen::Vector3d p = surface.refinedPosition(i);
        CHECK((p.array() >= lo.array() - kExactMm).all());
        CHECK((p.array() <= hi.array() + kExactMm).all());
      }
    }
  }
}

TEST_CASE("the surface rises with the bundles a light load lifts off the paper", "[surface]") {
  // The same spine, pressed 5 mm, with its full canvas load and with none:
  // unloaded, its bundles are raised off the joints on the paper until they
  // only touch it (bundlePlacement), and the surface wrapping them rises with
  // them, straight up, by the weighted raise of the bundles it follows.
  const Brush b = tubeBrush(1, 2);
  BrushSurface surface(b);
  const BrushState loaded = pressedStraightDown(b);
  REQUIRE(loaded.anyContact());
  BrushState light = loaded;
  for (SpineState& s : light.spines) std::fill(s.solution.normal_force_n.begin(),
                                                s.solution.normal_force_n.end(), 0.0);
  const BundlePlacement p_loaded = bundlePlacement(b.spines[0], loaded.spines[0], loaded.handle);
  const BundlePlacement p_light = bundlePlacement(b.spines[0], light.spines[0], light.handle);
  std::vector<BrushVertex> tris;
  std::vector<Eigen::Vector3d> cage_loaded, cage_light;
  surface.update(loaded, &tris);
  for (int i = 0; i < surface.cageVertexCount(); ++i) cage_loaded.push_back(surface.cagePosition(i));
  surface.update(light, &tris);
  for (int i = 0; i < surface.cageVertexCount(); ++i) cage_light.push_back(surface.cagePosition(i));
  // A raise that shows: a tenth of the tube's 1 mm radius, far above the
  // float noise (kExactMm).
  constexpr double kRaisedMm = 0.1;
  int raised = 0;
  for (int i = 0; i < surface.cageVertexCount(); ++i) {
    CHECK((cage_light[i] - cage_loaded[i]).head<2>().norm() < kExactMm);  // straight up
    CHECK(cage_light[i].z() >= cage_loaded[i].z() - kExactMm);            // never down
    if (b.surface.skin[i].size() != 1) continue;
    const int j = b.surface.skin[i][0].point;
    // Where neither is held at its bundle's depth, the rise is the raise's.
    if (cage_loaded[i].z() <= -p_loaded.depth_mm[j] + kExactMm) continue;
    if (cage_light[i].z() <= -p_light.depth_mm[j] + kExactMm) continue;
    const double rise = p_light.raise_mm[j] - p_loaded.raise_mm[j];
    CHECK(cage_light[i].z() - cage_loaded[i].z() == Approx(rise).margin(kExactMm));
    raised += rise > kRaisedMm;
  }
  CHECK(raised > 0);
}

TEST_CASE("a pressed brush carries its surface with the spine", "[surface]") {
  const Brush b = tubeBrush(1, 2);
  BrushSurface surface(b);
  const BrushState st = pressedStraightDown(b);
  const std::vector<Eigen::Vector3d>& x = st.spines[0].joints_mm;
  REQUIRE(st.anyContact());
  std::vector<BrushVertex> tris;
  surface.update(st, &tris);

  // Each ring vertex is rigidly attached to its spine point's bundle, whose
  // centre is the point raised by bundlePlacement's raise_mm: distances to
  // that centre keep their rest values -- except where that would take it
  // deeper below the canvas than the bundle is pressed (depth_mm): there it
  // lies at that depth.
  const BrushState rest = stateAt(b, Pose{});
  const BundlePlacement bundle = bundlePlacement(b.spines[0], st.spines[0], st.handle);
  const std::vector<double>& depth = bundle.depth_mm;
  int rigid = 0, held = 0;
  for (int i = 0; i < surface.cageVertexCount(); ++i) {
    const SkinInfluence& in = b.surface.skin[i][0];
    if (b.surface.skin[i].size() != 1) continue;
    const Eigen::Vector3d c = surface.cagePosition(i);
    CHECK(c.z() >= -depth[in.point] - kExactMm);
    if (c.z() <= -depth[in.point] + kExactMm) {
      ++held;
      continue;
    }
    ++rigid;
    const double rest_dist = (b.surface.cage_mm[i] - rest.spines[0].joints_mm[in.point]).norm();
    const Eigen::Vector3d centre = x[in.point] + bundle.raise_mm[in.point] * Eigen::Vector3d::UnitZ();
    CHECK((c - centre).norm() == Approx(rest_dist).margin(kExactMm));
  }
  // Pressed 5 mm, most of the ring rides above the paper, and the rings at
  // the contact joints reach the depth their bundles are pressed to.
  CHECK(rigid > held);
  CHECK(held > 0);
  // The surface reaches below the canvas (that is the footprint) next to the
  // spine's contact joints, no deeper than the thickest ring, and leans with
  // the bent spine.
  int low = 0;
  for (int i = 0; i < surface.refinedVertexCount(); ++i)
    if (surface.refinedPosition(i).z() < surface.refinedPosition(low).z()) low = i;
  const Eigen::Vector3d p = surface.refinedPosition(low);
  constexpr double kThickestRadiusMm = 1.1;  // width 2 / 2, grown ~8% for the ring
  CHECK(p.z() < 0);
  CHECK(p.z() > -kThickestRadiusMm);
  double to_contact = 1e300;
  for (size_t j = 1; j < x.size(); ++j)
    if (st.spines[0].contact[j - 1]) to_contact = std::min(to_contact, (p - x[j]).norm());
  CHECK(to_contact < kThickestRadiusMm);
  const Eigen::Vector2d lean = x.back().head<2>() - st.handle.position_mm.head<2>();
  REQUIRE(lean.norm() > 2);  // pressed 5 mm: the spine is well bent
  CHECK(lean.dot(p.head<2>() - st.handle.position_mm.head<2>()) > 0);
  REQUIRE(tris.size() == size_t(3 * surface.triangleCount()));
  float lowest_emitted = 1e30f;
  for (const BrushVertex& v : tris) lowest_emitted = std::min(lowest_emitted, v.z_mm);
  CHECK(lowest_emitted == Approx(p.z()).margin(1e-5));
}

TEST_CASE("a cage that is not a manifold is rejected naming /surface", "[surface]") {
  const std::vector<Eigen::Vector3d> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, -1}, {0, -1, -1},
                                          {0, 0, -2}, {5, 5, 5}};
  std::string msg;
  // Three triangles on the edge (0, 1).
  CHECK(codeOf(cageBrush(v, {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}), &msg) == ExitCode::kDataError);
  CHECK_THAT(msg, Catch::StartsWith("test-brush: /surface/faces/2: non-manifold edge (0, 1)"));
  // Two faces crossing (0, 1) the same way: inconsistent orientation.
  CHECK(codeOf(cageBrush(v, {{0, 1, 2}, {0, 1, 3}}), &msg) == ExitCode::kDataError);
  CHECK_THAT(msg, Catch::Contains("/surface/faces/1") && Catch::Contains("orientation"));
  // Two fans touching at one vertex (a bow tie).
  CHECK(codeOf(cageBrush(v, {{0, 1, 2}, {0, 3, 4}}), &msg) == ExitCode::kDataError);
  CHECK_THAT(msg, Catch::Contains("/surface/cage_vertices_mm/0: non-manifold vertex"));
  // Vertices 3, 4 and 5 belong to no face.
  CHECK(codeOf(cageBrush(v, {{0, 1, 2}}), &msg) == ExitCode::kDataError);
  CHECK_THAT(msg, Catch::Contains("/surface/cage_vertices_mm/3: is used by no face"));
}

TEST_CASE("surface texture coordinates: angle around the axis and depth", "[surface]") {
  // Straight spine: the axis is the vertical through the root, so u is the
  // plain angle in the brush's xy plane.
  Brush straight = makeBrush({makeSpine({4, 4, 4}, {10, 8, 6})}, 0.5, 0.4);
  straight.surface = makeTubeCage(straight, 8, 2);
  BrushSurface surface(straight);
  float vmin = 1, vmax = 0;
  for (int i = 0; i < surface.refinedVertexCount(); ++i) {
    const Eigen::Vector2f uv = surface.uv(i);
    const Eigen::Vector3d p = surface.refinedRestPosition(i);
    CHECK(uv.x() >= 0);
    CHECK(uv.x() < 1);
    vmin = std::min(vmin, uv.y());
    vmax = std::max(vmax, uv.y());
    if (p.head<2>().norm() > 1e-3) {  // off the axis
      const double a = 2 * std::numbers::pi * uv.x();
      CHECK(std::cos(a) * p.y() - std::sin(a) * p.x() == Approx(0).margin(1e-5));
      CHECK(std::cos(a) * p.x() + std::sin(a) * p.y() > 0);
    }
  }
  CHECK(vmin == 0);
  CHECK(vmax == 1);
  // No triangle smears across the seam or around the tip pole, straight or
  // bent at rest, with one spine or several: corners stay within 1/8 turn
  // (the 8-vertex rings make the tip fan's triangles 1/8 turn wide, 1/32 at
  // level 2; seam triangles carry u just above 1).
  for (const Brush& b : {straight, tubeBrush(1, 2), tubeBrush(3, 3)}) {
    BrushSurface sb(b);
    std::vector<BrushVertex> tris;
    sb.update(stateAt(b, Pose{}), &tris);
    for (size_t t = 0; t < tris.size(); t += 3) {
      const float lo = std::min({tris[t].u, tris[t + 1].u, tris[t + 2].u});
      const float hi = std::max({tris[t].u, tris[t + 1].u, tris[t + 2].u});
      CHECK(lo >= 0);
      CHECK(hi < 1.125f);
      CHECK(hi - lo < 0.125f);
    }
  }
}

TEST_CASE("makeTubeCage builds an outward tube whose limit has the spine's width",
          "[surface]") {
  Brush b = makeBrush({makeSpine({5, 5}, {10, 10})}, 0.5, 0.4);
  b.spines[0].width_mm = {2, 2, 2};
  b.surface = makeTubeCage(b, 8, 4);
  const SurfaceSpec& sf = b.surface;
  REQUIRE(sf.cage_mm.size() == 3 * 8 + 1);
  REQUIRE(sf.faces.size() == 2 * 8 + 8);
  // Outward: each face's normal points away from the spine axis (or down, at the tip).
  for (const auto& f : sf.faces) {
    const Eigen::Vector3d n = (sf.cage_mm[f[1]] - sf.cage_mm[f[0]])
                                  .cross(sf.cage_mm[f[f.size() - 1]] - sf.cage_mm[f[0]]);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int i : f) c += sf.cage_mm[i] / double(f.size());
    CHECK(n.dot(Eigen::Vector3d(c.x(), c.y(), std::min(0.0, c.z() + 10))) > 0);
  }
  // Between the ends the limit is a near-circle of radius width / 2: the cubic
  // B-spline of an octagon ripples by ~0.5% around its mean radius.
  BrushSurface surface(b);
  for (int i = 0; i < surface.refinedVertexCount(); ++i) {
    const Eigen::Vector3d p = surface.refinedRestPosition(i);
    if (p.z() < -3 && p.z() > -7) CHECK(p.head<2>().norm() == Approx(1.0).epsilon(0.01));
  }
  CHECK_THROWS_AS(makeTubeCage(b, 2), Error);
  // A flat brush of several spines makes a valid cage too.
  CHECK_NOTHROW(BrushSurface(tubeBrush(4, 2, 12)));
}

// A brush's first-contact height (engine/geometry/first_contact.h) against closed forms,
// against the geometry the renderer draws, and trajectories whose heights are
// press depths past it (resolveDepths).

#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/geometry/first_contact.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/solvers/spine_solver.h"
#include "test_helpers.h"

using namespace bristle;
using Catch::Matchers::Contains;

namespace {

// Closed forms are evaluated in doubles along the same few operations: they
// agree to rounding, far below a micrometre.
constexpr double kExactMm = 1e-9;

Eigen::Quaterniond tiltAbout(const Eigen::Vector3d& axis, double angle_rad) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, axis));
}

// One spine hanging from the ferrule's centre: segments `lengths_mm`, a round
// bundle `width_mm` wide all along (or, with thickness_mm, a slab), and the
// given rest angles of each joint.
nlohmann::json oneSpine(const std::vector<double>& lengths_mm, double width_mm,
                        double thickness_mm = 0,
                        const std::vector<std::vector<double>>& rest = {}) {
  const size_t n = lengths_mm.size();
  nlohmann::json spine = {{"root_mm", {0, 0, 0}},
                          {"segment_lengths_mm", lengths_mm},
                          {"stiffness_nmm_per_rad", std::vector<double>(n, 5.0)},
                          {"width_mm", std::vector<double>(n + 1, width_mm)}};
  if (thickness_mm > 0) spine["thickness_mm"] = std::vector<double>(n + 1, thickness_mm);
  if (!rest.empty()) spine["rest_angles_rad"] = rest;
  return {{"format", "bristle-brush/1"}, {"name", "one"}, {"spines", {spine}}};
}

Brush brushOf(const nlohmann::json& doc) { return parseBrush(doc.dump(), "one.json"); }

Brush library(const std::string& name) {
  return loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json");
}

const std::vector<std::string> kLibrary = {"round",  "flat", "bright",     "filbert",
                                           "badger", "fan",  "calligraphy"};

}  // namespace

TEST_CASE("a straight round spine first touches at L cos(tilt) + r", "[first-contact]") {
  // L = 12 mm in three segments, a bundle 1.6 mm wide: r = 0.8 mm. The half
  // solid at the tip reaches r below it whichever way a round bundle points;
  // the spine's tip is L cos(tilt) below the ferrule.
  const double length = 12, r = 0.8;
  const Brush b = brushOf(oneSpine({5, 4, 3}, 2 * r));
  CHECK(firstContactHeightMm(b) == Approx(length + r).margin(kExactMm));
  for (double tilt : {0.2, 0.6, 1.2}) {
    INFO("tilt " << tilt);
    for (const Eigen::Vector3d& axis : std::vector<Eigen::Vector3d>{
             Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d(1, 1, 0).normalized()})
      CHECK(firstContactHeightMm(b, tiltAbout(axis, tilt)) ==
            Approx(length * std::cos(tilt) + r).margin(kExactMm));
  }
  // Lying flat, the whole bundle rests on the paper: r.
  CHECK(firstContactHeightMm(b, tiltAbout(Eigen::Vector3d::UnitX(), std::numbers::pi / 2)) ==
        Approx(r).margin(kExactMm));
}

TEST_CASE("a bent spine first touches where its rest shape reaches lowest", "[first-contact]") {
  // Two segments of 6 mm, the second bent 0.5 rad at rest (theta of joint 1):
  // the tip is 6 + 6 cos(0.5) below the ferrule, held upright.
  const double r = 0.5;
  const Brush b = brushOf(oneSpine({6, 6}, 2 * r, 0, {{0, 0}, {0.5, 0}}));
  CHECK(firstContactHeightMm(b) == Approx(6 + 6 * std::cos(0.5) + r).margin(kExactMm));
  // Theta bends a segment towards +y of its parent (eq. 10): tilted by -0.5
  // rad about x the bent segment hangs straight down and the first leans,
  // 6 cos(0.5) + 6; tilted by +0.5 both lean the same way, the second twice
  // as far, 6 cos(0.5) + 6 cos(1).
  CHECK(firstContactHeightMm(b, tiltAbout(Eigen::Vector3d::UnitX(), -0.5)) ==
        Approx(6 * std::cos(0.5) + 6 + r).margin(kExactMm));
  CHECK(firstContactHeightMm(b, tiltAbout(Eigen::Vector3d::UnitX(), 0.5)) ==
        Approx(6 * std::cos(0.5) + 6 * std::cos(1.0) + r).margin(kExactMm));
}

TEST_CASE("a slab's first contact follows its width or thickness, as it tilts",
          "[first-contact]") {
  // A slab a = 2 mm across (brush x) and b = 0.5 mm thick (brush y): its
  // section at the tip reaches sqrt(b^2 sin^2 + a b cos^2) below the tip
  // tilted about x (the thickness turns down), sqrt(a^2 sin^2 + a b cos^2)
  // tilted about y (the width turns down). Upright, sqrt(a b) (the half
  // solid's depth along the hair, spine_bundles.cpp, BundleSection).
  const double length = 10, a = 2, b = 0.5;
  const Brush slab = brushOf(oneSpine({5, 5}, 2 * a, 2 * b));
  CHECK(firstContactHeightMm(slab) == Approx(length + std::sqrt(a * b)).margin(kExactMm));
  for (double tilt : {0.3, 0.9}) {
    INFO("tilt " << tilt);
    const double s = std::sin(tilt), c = std::cos(tilt);
    CHECK(firstContactHeightMm(slab, tiltAbout(Eigen::Vector3d::UnitX(), tilt)) ==
          Approx(length * c + std::sqrt(b * b * s * s + a * b * c * c)).margin(kExactMm));
    CHECK(firstContactHeightMm(slab, tiltAbout(Eigen::Vector3d::UnitY(), tilt)) ==
          Approx(length * c + std::sqrt(a * a * s * s + a * b * c * c)).margin(kExactMm));
  }
}

TEST_CASE("a surface that reaches lower than the spines touches first", "[first-contact]") {
  // A 10 mm spine 1 mm wide inside a pyramid cage whose apex hangs 14 mm
  // below the ferrule; at refinement level 0 the surface is the cage itself.
  nlohmann::json doc = oneSpine({5, 5}, 1);
  doc["surface"] = {
      {"cage_vertices_mm", {{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {0, 0, -14}}},
      {"faces", {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}},
      {"skin", {{{0, 0, 1}}, {{0, 0, 1}}, {{0, 0, 1}}, {{0, 0, 1}}, {{0, 2, 1}}}},
      {"refinement_level", 0}};
  const Brush b = brushOf(doc);
  CHECK(firstContactHeightMm(b) == Approx(14).margin(kExactMm));
  const double tilt = 0.5;
  CHECK(firstContactHeightMm(b, tiltAbout(Eigen::Vector3d::UnitX(), tilt)) ==
        Approx(14 * std::cos(tilt)).margin(kExactMm));
  // Lying flat, the cage's base corners reach 1 mm down, the spine's bundle
  // 0.5 mm, the apex none.
  CHECK(firstContactHeightMm(b, tiltAbout(Eigen::Vector3d::UnitX(), std::numbers::pi / 2)) ==
        Approx(1).margin(kExactMm));
}

TEST_CASE("every library brush held at its first contact plus a gap draws nothing below it",
          "[first-contact][library]") {
  // The renderer's own geometry (surface, strips and spine tubes) of the brush
  // at rest, its ferrule at first contact + 1 mm: its lowest vertex is 1 mm
  // above the paper. Below: nothing may reach lower, the strips included
  // (left out of first contact, engine/geometry/first_contact.h), but for the float
  // vertices' rounding (1e-4 mm). Above: the drawn half solids are sampled at
  // their pole, which for a slab tilted sideways lies above the solid's lowest
  // point (the flats' slabs: 0.034 mm, measured): allowed 0.05 mm, a third of
  // a pixel at the library sheet's 6 px/mm.
  constexpr double kGapMm = 1, kBelowMm = 1e-4, kAboveMm = 0.05;
  for (const std::string& name : kLibrary) {
    const Brush brush = library(name);
    BrushGeometry geometry(brush);
    Simulation sim(brush, SimOptions{}, makeIpoptSolver());
    for (const Eigen::Quaterniond& q : std::vector<Eigen::Quaterniond>{
             Eigen::Quaterniond::Identity(), tiltAbout(Eigen::Vector3d::UnitX(), 0.35),
             tiltAbout(Eigen::Vector3d::UnitY(), 0.8)}) {
      Pose pose;
      pose.rotation = q;
      pose.position_mm.z() = firstContactHeightMm(brush, q) + kGapMm;
      sim.reset(pose, 0);
      std::vector<BrushVertex> triangles;
      geometry.build(sim.state(), &triangles);
      double lowest = 1e9;
      for (const BrushVertex& v : triangles) lowest = std::min(lowest, double(v.z_mm));
      INFO(name << " held at " << q.coeffs().transpose() << ": lowest vertex z = " << lowest);
      CHECK(lowest >= kGapMm - kBelowMm);
      CHECK(lowest <= kGapMm + kAboveMm);
    }
  }
}

TEST_CASE("resolveDepths turns depths into ferrule heights per sample's orientation",
          "[first-contact]") {
  const Brush b = brushOf(oneSpine({5, 4, 3}, 1.6));  // touches at 12 cos(tilt) + 0.8
  const std::string text =
      "# bristle-trajectory/1\n"
      "t_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz\n"
      "0,0,0,-2,1,0,0,0\n"
      "0.5,3,0,1.5,1,0,0,0\n"
      "1,6,0,3,0.98006658,0.19866933,0,0\n";  // tilted 0.4 rad about x
  const Trajectory given = parseTrajectory(text, "d.csv");
  const Trajectory held = resolveDepths(given, b);
  CHECK_FALSE(held.needsBrush());
  CHECK(given.needsBrush());  // the file's own trajectory is left as read
  REQUIRE(held.samples.size() == 3);
  // Quaternions in the file carry 8 decimals: the angle is 0.4 rad to ~1e-8,
  // the height exact to ~1e-7 mm.
  CHECK(held.samples[0].pose.position_mm.z() == Approx(12.8 + 2).margin(kExactMm));
  CHECK(held.samples[1].pose.position_mm.z() == Approx(12.8 - 1.5).margin(kExactMm));
  CHECK(held.samples[2].pose.position_mm.z() ==
        Approx(12 * std::cos(0.4) + 0.8 - 3).margin(1e-6));
  CHECK(held.samples[1].pose.position_mm.x() == 3);
  // Resolved once, it stays: a second brush does not move it again.
  const Trajectory again = resolveDepths(held, library("round"));
  CHECK(again.samples[1].pose.position_mm.z() == held.samples[1].pose.position_mm.z());
  // A trajectory with z_mm is every brush's as it is.
  const Trajectory absolute = parseTrajectory(
      "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n0,0,0,20,1,0,0,0\n1,0,0,19,1,0,0,0\n",
      "a.csv");
  CHECK(resolveDepths(absolute, b).samples[1].pose.position_mm.z() == 19);
}

TEST_CASE("a depth trajectory unresolved, or pressed through the ferrule, is refused",
          "[first-contact]") {
  const Brush b = brushOf(oneSpine({5, 4, 3}, 1.6));
  const Trajectory deep = parseTrajectory(
      "# bristle-trajectory/1\nt_s,x_mm,y_mm,depth_mm,qw,qx,qy,qz\n"
      "0,0,0,-1,1,0,0,0\n1,0,0,14,1,0,0,0\n",
      "deep.csv");
  // Forgetting resolveDepths is a programming error, caught where poses are used.
  CHECK_THROWS_AS(validateTrajectoryForBrush(deep, b), std::logic_error);
  CHECK_THROWS_AS(planStepTimes(deep, b, SimOptions{}), std::logic_error);
  // 14 mm past a first contact at 12.8 mm puts the ferrule 1.2 mm into the paper.
  const testing::Caught caught =
      testing::catchError([&] { validateTrajectoryForBrush(resolveDepths(deep, b), b); });
  REQUIRE(caught.thrown);
  CHECK(caught.code == static_cast<int>(ExitCode::kDataError));
  CHECK_THAT(caught.message, Contains("deep.csv: line 4") && Contains("below the canvas") &&
                                 Contains("depth_mm = 14"));
}

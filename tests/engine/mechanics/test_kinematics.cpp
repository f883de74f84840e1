// Spine forward kinematics (paper eqs. 10-11) and its derivatives.

#include <catch2/catch.hpp>
#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "engine/dynamics/simulation.h"
#include "engine/mechanics/spine_kinematics.h"
#include "test_helpers.h"

using namespace bristle;
using bristle::testing::makeSpine;

namespace {
// Positions are O(10 mm); double round-off in a few 3x3 products is ~1e-14 mm.
constexpr double kExactTolMm = 1e-12;
// Central differences with h = 1e-6 rad: truncation ~h^2 * |x'''| ~ 1e-11 mm,
// round-off ~1e-16 * 20 mm / 1e-6 = 2e-9 mm. 1e-6 leaves a wide margin while
// still catching any wrong term (those are O(1 mm/rad)).
constexpr double kFdStep = 1e-6;
constexpr double kFdTol = 1e-6;
}  // namespace

TEST_CASE("eq. 10 rotation is Ry(phi) Rx(theta) and orthonormal", "[kinematics]") {
  const Eigen::Matrix3d r = jointRotation(0.3, -0.7);
  const double ct = std::cos(0.3), st = std::sin(0.3), cp = std::cos(-0.7), sp = std::sin(-0.7);
  Eigen::Matrix3d expected;
  expected << cp, sp * st, sp * ct, 0, ct, -st, -sp, cp * st, cp * ct;  // eq. 10 as printed
  CHECK((r - expected).norm() < kExactTolMm);
  CHECK((r * r.transpose() - Eigen::Matrix3d::Identity()).norm() < kExactTolMm);
}

TEST_CASE("forward kinematics matches hand-computed poses", "[kinematics]") {
  const SpineSpec one = makeSpine({5.0}, {1.0});
  SpineFk fk;
  Pose up;  // identity rotation: hairs hang along -z
  up.position_mm = Eigen::Vector3d(1, 2, 10);

  SECTION("at rest the spine hangs straight down") {
    double q[2] = {0, 0};
    spineForwardKinematics(one, up, q, 0, &fk);
    CHECK((fk.x[1] - Eigen::Vector3d(1, 2, 5)).norm() < kExactTolMm);
  }
  SECTION("theta bends in the y-z plane towards +y") {
    double q[2] = {0.3, 0};
    spineForwardKinematics(one, up, q, 0, &fk);
    CHECK((fk.x[1] - Eigen::Vector3d(1, 2 + 5 * std::sin(0.3), 10 - 5 * std::cos(0.3))).norm() <
          kExactTolMm);
  }
  SECTION("phi bends in the x-z plane towards -x") {
    double q[2] = {0, 0.4};
    spineForwardKinematics(one, up, q, 0, &fk);
    CHECK((fk.x[1] - Eigen::Vector3d(1 - 5 * std::sin(0.4), 2, 10 - 5 * std::cos(0.4))).norm() <
          kExactTolMm);
  }
  SECTION("joint angles accumulate along the chain") {
    const SpineSpec two = makeSpine({5.0, 3.0}, {1.0, 1.0});
    double q[4] = {0.3, 0, 0.2, 0};
    spineForwardKinematics(two, up, q, 0, &fk);
    const Eigen::Vector3d tip(1, 2 + 5 * std::sin(0.3) + 3 * std::sin(0.5),
                              10 - 5 * std::cos(0.3) - 3 * std::cos(0.5));
    CHECK((fk.x[2] - tip).norm() < kExactTolMm);
  }
  SECTION("the handle rotation carries the spine") {
    Pose turned = up;
    // Tilt the handle 90 degrees about +x: the hairs now point along +y.
    turned.rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX());
    const SpineSpec rooted = makeSpine({5.0}, {1.0}, 0, Eigen::Vector3d(0.5, 0, 0));
    double q[2] = {0, 0};
    spineForwardKinematics(rooted, turned, q, 0, &fk);
    CHECK((fk.x[0] - Eigen::Vector3d(1.5, 2, 10)).norm() < kExactTolMm);
    CHECK((fk.x[1] - Eigen::Vector3d(1.5, 7, 10)).norm() < kExactTolMm);
  }
}

TEST_CASE("first and second derivatives match central differences", "[kinematics]") {
  const SpineSpec spine = makeSpine({4.0, 3.5, 3.0, 2.5}, {10, 8, 6, 5}, 0,
                                    Eigen::Vector3d(0.7, -0.4, -0.2));
  Pose handle;
  handle.position_mm = Eigen::Vector3d(3, 4, 12);
  handle.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 0.5).normalized()));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.0, 1.0);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<double> q(8);
    for (double& a : q) a = angle(rng);
    SpineFk fk, fp, fm;
    spineForwardKinematics(spine, handle, q.data(), 2, &fk);
    for (int v = 0; v < 8; ++v) {
      std::vector<double> qp = q, qm = q;
      qp[v] += kFdStep;
      qm[v] -= kFdStep;
      spineForwardKinematics(spine, handle, qp.data(), 1, &fp);
      spineForwardKinematics(spine, handle, qm.data(), 1, &fm);
      for (int j = 0; j <= 4; ++j) {
        const Eigen::Vector3d fd = (fp.x[j] - fm.x[j]) / (2 * kFdStep);
        INFO("joint " << j << " var " << v);
        CHECK((fk.d(j, v) - fd).norm() < kFdTol);
        for (int w = 0; w < 8; ++w) {
          const Eigen::Vector3d fd2 = (fp.d(j, w) - fm.d(j, w)) / (2 * kFdStep);
          INFO("second derivative w " << w);
          CHECK((fk.dd(j, v, w) - fd2).norm() < kFdTol);
        }
      }
    }
  }
}

TEST_CASE("re-based kinematics: derivatives with base rotations match central differences",
          "[kinematics][rebase]") {
  // Base rotations turned 100-170 degrees: where eq. 10's own angles are singular.
  const SpineSpec spine = makeSpine({4.0, 3.5, 3.0}, {10, 8, 6});
  const std::vector<Eigen::Matrix3d> base = {
      Eigen::Matrix3d(Eigen::AngleAxisd(1.75, Eigen::Vector3d::UnitX())),
      Eigen::Matrix3d(Eigen::AngleAxisd(2.9, Eigen::Vector3d(0.3, 1, 0).normalized())),
      Eigen::Matrix3d(Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -1, 0.2).normalized()))};
  Pose handle;
  handle.position_mm = Eigen::Vector3d(1, 2, 9);
  std::vector<double> q = {0.05, -0.02, 0.01, 0.03, -0.04, 0.02};
  SpineFk fk, fp, fm;
  spineForwardKinematics(spine, handle, base.data(), q.data(), 2, &fk);
  for (int v = 0; v < 6; ++v) {
    std::vector<double> qp = q, qm = q;
    qp[v] += kFdStep;
    qm[v] -= kFdStep;
    spineForwardKinematics(spine, handle, base.data(), qp.data(), 1, &fp);
    spineForwardKinematics(spine, handle, base.data(), qm.data(), 1, &fm);
    for (int j = 0; j <= 3; ++j) {
      INFO("joint " << j << " var " << v);
      CHECK((fk.d(j, v) - (fp.x[j] - fm.x[j]) / (2 * kFdStep)).norm() < kFdTol);
      for (int w = 0; w < 6; ++w)
        CHECK((fk.dd(j, v, w) - (fp.d(j, w) - fm.d(j, w)) / (2 * kFdStep)).norm() < kFdTol);
    }
  }
  // At q = 0 the derivatives are those of turning each joint about its own
  // frame's x and y axes: never zero, whatever the base (no singularity).
  std::vector<double> zero(6, 0.0);
  spineForwardKinematics(spine, handle, base.data(), zero.data(), 1, &fk);
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 2; ++a) CHECK(fk.d(k + 1, 2 * k + a).norm() == Approx(spine.segment_lengths_mm[k]));
}

TEST_CASE("the smallest turn between two axes stays a rotation near a half turn",
          "[kinematics]") {
  // Re-basing (canonicalRotations) turns each joint's rest axis onto its
  // current one every step. Axes that come out of many steps' products are
  // unit only to rounding; a soft tip bent back towards a half turn makes a
  // naive Rodrigues' 1 / (1 + a.b) blow that rounding up into a matrix that is
  // no rotation, and the tip segment of a graded round, pressed and lifted
  // with coarse steps, would grow from 3.5 to 43 mm. Whatever the axes' rounding, the
  // result must be a rotation (to 1e-12, a few ulps of products of order 1)
  // taking the one direction onto the other (to 1e-9: the inputs themselves
  // are off unit by up to 1e-9 here).
  constexpr double kOrthoTol = 1e-12, kDirTol = 1e-9;
  const Eigen::Vector3d a = Eigen::Vector3d(0.3, -0.2, 0.93).normalized();
  for (double gap : {1.0, 1e-2, 1e-4, 1e-6}) {  // 1 + a.b of the exact directions
    // b at angle acos(gap - 1) from a, about an axis across a.
    const Eigen::Vector3d across = a.cross(Eigen::Vector3d::UnitX()).normalized();
    const double angle = std::acos(gap - 1);
    const Eigen::Vector3d b = Eigen::AngleAxisd(angle, across) * a;
    for (double scale : {1.0, 1 + 1e-9, 1 - 1e-9}) {
      INFO("1 + a.b = " << gap << ", |b| = " << scale);
      const Eigen::Matrix3d r = minimalRotation(a * (2 - scale), b * scale);
      CHECK((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() < kOrthoTol);
      CHECK(r.determinant() == Approx(1.0).margin(kOrthoTol));
      CHECK((r * a - b).norm() < kDirTol);
    }
  }
}

TEST_CASE("re-basing keeps every joint where it is and the twist as at rest",
          "[kinematics][rebase]") {
  SpineSpec spine = makeSpine({4.0, 3.5, 3.0}, {10, 8, 6});
  spine.rest_angles_rad = {{0.05, -0.1}, {0.0, 0.2}, {-0.1, 0.1}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  Pose handle;
  handle.rotation = Eigen::AngleAxisd(0.5, Eigen::Vector3d(1, 1, 0).normalized());
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Eigen::Matrix3d> rot;
    for (int k = 0; k < 3; ++k)
      rot.push_back(Eigen::Matrix3d(Eigen::AngleAxisd(
          2.5 * std::fabs(u(rng)), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized())));
    const std::vector<Eigen::Matrix3d> canon = canonicalRotations(spine, rot);
    const std::vector<double> zero(6, 0.0);
    SpineFk a, b;
    spineForwardKinematics(spine, handle, rot.data(), zero.data(), 0, &a);
    spineForwardKinematics(spine, handle, canon.data(), zero.data(), 0, &b);
    // Positions of O(10 mm) through a few 3x3 products: round-off ~1e-14.
    for (int j = 0; j <= 3; ++j) CHECK((a.x[j] - b.x[j]).norm() < 1e-12);
    const std::vector<Eigen::Matrix3d> rest = restRotations(spine);
    for (int k = 0; k < 3; ++k) {
      // Canonical: the smallest turn from the rest rotation, so its axis of
      // rotation rest^T... lies in the plane normal to the rest axis: no twist.
      const Eigen::AngleAxisd turn(canon[k] * rest[k].transpose());
      CHECK(std::fabs(turn.axis().dot(rest[k].col(2))) * std::sin(turn.angle()) < 1e-12);
      CHECK(canon[k].isUnitary(1e-12));
      // A second re-base changes nothing.
      const std::vector<Eigen::Matrix3d> again = canonicalRotations(spine, canon);
      CHECK((again[k] - canon[k]).norm() < 1e-12);
    }
  }
}

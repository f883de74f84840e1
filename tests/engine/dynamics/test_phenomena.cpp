// The brush phenomena of paper §3 and §5, each with a physical assertion:
// stiction and its hysteresis (§3.4.1), anisotropic friction (§3.4.2),
// plasticity from joint friction (§3.5), the unit calibration of §5, and the
// optimality (KKT) of every accepted solve.

#include <catch2/catch.hpp>
#include <cmath>

#include "engine/dynamics/simulation.h"
#include "engine/formats/brush_reader.h"
#include "engine/mechanics/spine_kinematics.h"
#include "test_helpers.h"

using namespace bristle;
using namespace bristle::testing;

namespace {

Pose tilted(double x, double y, double z, double tilt_about_y_rad) {
  Pose p = poseAt(x, y, z);
  p.rotation = Eigen::AngleAxisd(tilt_about_y_rad, Eigen::Vector3d::UnitY());
  return p;
}

double tangentialRatio(const BrushState& st) {
  return st.force_n.head<2>().norm() / st.force_n.z();
}

}  // namespace

TEST_CASE("stiction holds below mu_s Fn, slips above, slides at mu_k and re-sticks",
          "[phenomena][friction]") {
  SpineSpec spine = makeSpine({6, 6}, {8, 5});
  spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
  const double mu_s = 0.6, mu_k = 0.3;  // far apart, so the stick-slip is unmistakable
  const Brush brush = makeBrush({spine}, mu_s, mu_k);
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  sim.reset(poseAt(0, 0, 14), t);
  moveHandle(sim, poseAt(0, 0, 14), poseAt(0, 0, 8.5), &t);
  for (int i = 0; i < 10; ++i) sim.step(poseAt(0, 0, 8.5), t += 0.01);
  REQUIRE(sim.state().spines[0].contact[1]);
  REQUIRE_FALSE(sim.state().spines[0].contact[0]);  // the tip is the only contact
  REQUIRE_FALSE(sim.state().spines[0].sliding[1]);

  // Creep the handle sideways in 0.02 mm steps: the load on the tip grows until
  // it reaches mu_s Fn, then the tip breaks free.
  // Fn of the step before is what friction uses (eq. 3); it changes by well
  // under 2% per 0.02 mm step here.
  constexpr double kRatioTol = 0.02;
  double x = 0, ratio_before_slip = 0;
  bool slipped = false;
  while (x < 12 && !slipped) {
    x += 0.02;
    const BrushState& st = sim.step(poseAt(x, 0, 8.5), t += 0.01);
    if (st.spines[0].sliding[1]) {
      slipped = true;
    } else {
      ratio_before_slip = tangentialRatio(st);
      REQUIRE(ratio_before_slip <= mu_s * (1 + kRatioTol));
    }
  }
  REQUIRE(slipped);
  // It held right up to the static limit...
  CHECK(ratio_before_slip >= 0.9 * mu_s);
  // ...and once sliding, the friction is the kinetic one.
  moveHandle(sim, poseAt(x, 0, 8.5), poseAt(x + 3, 0, 8.5), &t, 0.05);
  CHECK(sim.state().spines[0].sliding[1]);
  CHECK(tangentialRatio(sim.state()) == Approx(mu_k).epsilon(0.05));
  // Stop the handle: the tip stops and sticks again (hysteresis: it is held
  // from now on by mu_s, not mu_k).
  for (int i = 0; i < 5; ++i) sim.step(poseAt(x + 3, 0, 8.5), t += 0.01);
  CHECK_FALSE(sim.state().spines[0].sliding[1]);
  CHECK(sim.state().spines[0].contact[1]);
}

// The stiction test's spine, pressed so that its tip is the only contact.
struct StuckTip {
  Brush brush;
  Simulation sim;
  double t = 0;
  explicit StuckTip(double mu_s, double mu_k)
      : brush(makeBrush({stiffSpine()}, mu_s, mu_k)),
        sim(brush, SimOptions{}, makeIpoptSolver()) {
    sim.reset(poseAt(0, 0, 14), t);
    moveHandle(sim, poseAt(0, 0, 14), poseAt(0, 0, 8.5), &t);
    for (int i = 0; i < 10; ++i) sim.step(poseAt(0, 0, 8.5), t += 0.01);
  }
  static SpineSpec stiffSpine() {
    SpineSpec spine = makeSpine({6, 6}, {8, 5});
    spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
    return spine;
  }
  // Moves the handle sideways in steps of step_mm until the tip slips; returns
  // how far the handle went (12 mm if it never slipped).
  double slipOnsetMm(double step_mm) {
    double x = 0;
    while (x < 12) {
      x += step_mm;
      if (sim.step(poseAt(x, 0, 8.5), t += 0.01).spines[0].sliding[1]) break;
    }
    return x;
  }
};

TEST_CASE("stiction does not depend on the step: a stuck tip creeps no further in fine steps",
          "[phenomena][friction]") {
  // A sticking joint is held where it stuck (§3.4.1). Smoothed friction lets
  // it creep a little under load, of order the smoothing width; measured from
  // where the last step left it, that creep came back every step, so a drag
  // in fine steps crept along at mu_s and never slipped, and a loaded brush
  // held still crept back towards rest.
  const double mu_s = 0.6, mu_k = 0.3;
  SECTION("the tip breaks free after the same handle travel in coarse and fine steps") {
    StuckTip coarse(mu_s, mu_k), fine(mu_s, mu_k);
    REQUIRE(coarse.sim.state().spines[0].contact[1]);
    REQUIRE_FALSE(coarse.sim.state().spines[0].sliding[1]);
    const double x_coarse = coarse.slipOnsetMm(0.02);
    const double x_fine = fine.slipOnsetMm(0.0025);
    INFO("slip after " << x_coarse << " mm in 0.02 mm steps, " << x_fine << " mm in 0.0025 mm");
    REQUIRE(x_coarse < 12);
    REQUIRE(x_fine < 12);
    // The coarse steps find the onset to within one step (0.02 mm, 0.7% of
    // the travel), and their previous-step Fn (eq. 3) lags the fine steps' by
    // at most 2% of the load (the stiction test above), about 1% of the
    // travel here. 2% covers both. (Held from where the last step left it,
    // the fine steps never slipped in 12 mm.)
    constexpr double kOnsetTol = 0.02;
    CHECK(std::abs(x_fine - x_coarse) < kOnsetTol * x_coarse);
    // Once sliding, both slide at mu_k.
    for (StuckTip* run : {&coarse, &fine}) {
      const double x0 = run == &coarse ? x_coarse : x_fine;
      moveHandle(run->sim, poseAt(x0, 0, 8.5), poseAt(x0 + 3, 0, 8.5), &run->t, 0.05);
      CHECK(run->sim.state().spines[0].sliding[1]);
      CHECK(tangentialRatio(run->sim.state()) == Approx(mu_k).epsilon(0.05));
    }
  }
  SECTION("a loaded tip held still stays where it stuck") {
    StuckTip run(mu_s, mu_k);
    // Load the tip to about two thirds of the static limit, then hold.
    StuckTip probe(mu_s, mu_k);
    const double onset = probe.slipOnsetMm(0.02);
    moveHandle(run.sim, poseAt(0, 0, 8.5), poseAt(0.66 * onset, 0, 8.5), &run.t, 0.02);
    const BrushState& loaded = run.sim.state();
    REQUIRE_FALSE(loaded.spines[0].sliding[1]);
    const double ratio = tangentialRatio(loaded);
    INFO("load " << ratio / mu_s << " of mu_s Fn");
    REQUIRE(ratio > 0.4 * mu_s);
    const Eigen::Vector2d tip0 = loaded.spines[0].joints_mm[2].head<2>();
    for (int i = 0; i < 400; ++i) run.sim.step(poseAt(0.66 * onset, 0, 8.5), run.t += 0.01);
    const BrushState& held = run.sim.state();
    const double crept = (held.spines[0].joints_mm[2].head<2>() - tip0).norm();
    INFO("crept " << crept << " mm in 400 steps");
    CHECK_FALSE(held.spines[0].sliding[1]);
    // Smoothed friction holds a joint within a few widths (1e-3 mm) of where
    // it stuck; a creep every step would add up to a tenth of a millimetre.
    constexpr double kHeldMm = 5e-3;
    CHECK(crept < kHeldMm);
    CHECK(tangentialRatio(held) == Approx(ratio).epsilon(0.02));
  }
}

TEST_CASE("anisotropy: pushing a tilted brush costs more friction than pulling it",
          "[phenomena][friction]") {
  // The handle leans 30 degrees so that the hairs trail towards -x. Pulling
  // (+x) drags the tip towards its parent joint, along d_p of eq. 14; pushing
  // (-x) drives it the other way.
  auto effectiveMu = [](double c_eta, double direction) {
    SpineSpec spine = makeSpine({6, 6}, {8, 5});
    spine.rest_angles_rad[0] = Eigen::Vector2d(0, 0.05);
    Brush brush = makeBrush({spine}, 0.4, 0.4);
    brush.friction.anisotropy_strength = c_eta;
    brush.friction.anisotropy_exponent = 2;
    Simulation sim(brush, SimOptions{}, makeIpoptSolver());
    double t = 0;
    const double tilt = 0.52;
    sim.reset(tilted(0, 0, 14, tilt), t);
    moveHandle(sim, tilted(0, 0, 14, tilt), tilted(0, 0, 9.5, tilt), &t);
    // Drag 6 mm; average the tangential/normal ratio over the last 3 mm, where
    // the tip slides steadily.
    double sum = 0;
    int count = 0;
    for (int i = 1; i <= 60; ++i) {
      const BrushState& st = sim.step(tilted(direction * 0.1 * i, 0, 9.5, tilt), t += 0.01);
      if (i > 30) {
        REQUIRE(st.spines[0].sliding[1]);
        sum += tangentialRatio(st);
        ++count;
      }
    }
    return sum / count;
  };
  const double pull0 = effectiveMu(0.0, +1), push0 = effectiveMu(0.0, -1);
  const double pull8 = effectiveMu(0.8, +1), push8 = effectiveMu(0.8, -1);
  // Isotropic (C_eta = 0, eq. 3): the same mu both ways. 3% covers the
  // previous-step Fn that eq. 3 uses.
  CHECK(pull0 == Approx(0.4).epsilon(0.03));
  CHECK(push0 == Approx(0.4).epsilon(0.03));
  // C_eta = 0.8: pulling along d_p loses most of its friction (eq. 13 with
  // eta = 0.8 cos^2 of the angle between the motion and d_p); pushing keeps it all.
  CHECK(push8 == Approx(0.4).epsilon(0.03));
  CHECK(pull8 < 0.6 * push8);
}

TEST_CASE("plasticity: a brush lifted off stays bent by D/K with damping, not without",
          "[phenomena][damping]") {
  // Joint friction (eqs. 4, 15) holds a joint once its spring torque K (a - a_rest)
  // falls to D: in the air the residual bend of each joint is exactly D_i / K_i.
  auto residual = [](double d_scale) {
    SpineSpec spine = makeSpine({6, 6}, {8, 5});
    spine.damping_nmm = {0.01 * d_scale, 0.006 * d_scale};
    spine.rest_angles_rad[0] = Eigen::Vector2d(0.05, 0);
    const Brush brush = makeBrush({spine}, 0.45, 0.35);
    Simulation sim(brush, SimOptions{}, makeIpoptSolver());
    double t = 0;
    sim.reset(poseAt(0, 0, 14), t);
    moveHandle(sim, poseAt(0, 0, 14), poseAt(0, 0, 7), &t);
    moveHandle(sim, poseAt(0, 0, 7), poseAt(4, 0, 7), &t);
    REQUIRE(sim.state().anyContact());
    moveHandle(sim, poseAt(4, 0, 7), poseAt(4, 0, 16), &t);  // lift off
    REQUIRE_FALSE(sim.state().anyContact());
    const std::vector<Eigen::Vector3d> lifted = sim.state().spines[0].joints_mm;
    const Eigen::Vector3d lift_handle = sim.state().handle.position_mm;
    // A long hold in the air, moving about: nothing may creep (joint positions
    // relative to the handle stay within round-off of re-basing every step).
    moveHandle(sim, poseAt(4, 0, 16), poseAt(30, 10, 18), &t);
    const Eigen::Vector3d moved = sim.state().handle.position_mm - lift_handle;
    for (size_t j = 0; j < lifted.size(); ++j)
      CHECK((sim.state().spines[0].joints_mm[j] - lifted[j] - moved).norm() < 1e-9);
    Eigen::Vector2d out;
    for (int k = 0; k < 2; ++k) out[k] = bendFromRest(spine, sim.state().spines[0], k);
    return out;
  };
  // The damping term is smoothed over 1e-5 rad: the residual is D/K to ~1%;
  // 5% of D/K (6e-5 rad) is the margin.
  const Eigen::Vector2d with = residual(1.0);
  CHECK(with[0] == Approx(0.01 / 8).epsilon(0.05));
  CHECK(with[1] == Approx(0.006 / 5).epsilon(0.05));
  // Without damping the spring takes it all the way back (solver accuracy ~1e-6).
  const Eigen::Vector2d without = residual(0.0);
  CHECK(without[0] < 1e-5);
  CHECK(without[1] < 1e-5);
}

TEST_CASE("the round preset is calibrated as paper §5 says: 1-2 N bends it nearly 90 degrees",
          "[phenomena][calibration]") {
  // §5: K of the order of 5-10 N mm/rad, so that a brush under 1-2 N of normal
  // force bends nearly 90 degrees; the paper's haptic force is the average over spines, so
  // the force here is the mean normal force per spine.
  const Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  // The joints' K is graded along the hair (see the library test below); what
  // §5 fixes is the brush's response, measured here.
  for (const SpineSpec& s : brush.spines)
    for (size_t k = 0; k < s.stiffness_nmm_per_rad.size(); ++k) {
      if (k > 0) CHECK(s.stiffness_nmm_per_rad[k] <= s.stiffness_nmm_per_rad[k - 1]);
      CHECK(s.damping_nmm[k] <= 0.01);
    }
  CHECK(brush.friction.mu_static >= 0.3);
  CHECK(brush.friction.mu_static <= 0.5);
  CHECK(brush.friction.mu_kinetic >= 0.3);

  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  sim.reset(poseAt(0, 0, 24), t);
  double bend_at_1n = -1, bend_at_2n = -1;
  for (double z = 24; z > 8 && bend_at_2n < 0; z -= 0.05) {
    const BrushState& st = sim.step(poseAt(0, 0, z), t += 0.01);
    double force = 0, bend = 0;
    for (const SpineState& s : st.spines) {
      for (double f : s.solution.normal_force_n) force += f;
      const Eigen::Vector3d tip = s.joints_mm.back() - s.joints_mm[s.joints_mm.size() - 2];
      bend += std::acos(std::clamp(-tip.normalized().z(), -1.0, 1.0));
    }
    force /= st.spines.size();
    bend = bend / st.spines.size() * 180 / M_PI;
    if (bend_at_1n < 0 && force >= 1.0) bend_at_1n = bend;
    if (force >= 2.0) bend_at_2n = bend;
  }
  INFO("tip bend at 1 N: " << bend_at_1n << " deg, at 2 N: " << bend_at_2n << " deg");
  REQUIRE(bend_at_1n > 0);
  REQUIRE(bend_at_2n > 0);
  // "Nearly 90 degrees" somewhere in 1-2 N, and not folded back past it at 1 N.
  CHECK(bend_at_2n >= 75);
  CHECK(bend_at_1n <= 100);
  // The library meets it at the low end, 1 N (docs/haptics.md, "How hard the
  // brush pushes back"): within 5 degrees of 90 there (measured 89.2). A
  // round made stiffer without its marks changing would still be on its
  // bending plateau at 1 N, tens of degrees short.
  CHECK(bend_at_1n >= 85);
}

TEST_CASE("every accepted solve is a KKT point of its problem", "[phenomena][solver]") {
  // grad E + sum_j lambda_j grad z_j - z_L + z_U = 0 (Ipopt's sign convention).
  // Ipopt stops at tol 1e-8 on its (scaled) optimality error; measured worst
  // residuals are ~1e-8 N mm/rad against gradients of O(1-10): 1e-6 leaves a
  // factor of 100 and still catches any wrong derivative or multiplier sign.
  constexpr double kKktTol = 1e-6;
  // Each spine's own problem, as the paper poses it: without hair volume, whose
  // links couple the spines' conditions (tested in test_solvers.cpp, "hair
  // volume solved as one NLP").
  Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  brush.volume = VolumeSpec{};
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  const double tilt = 0.4;
  sim.reset(tilted(0, 0, 24, tilt), t);
  std::vector<Pose> path = {tilted(0, 0, 24, tilt), tilted(0, 0, 13, tilt), tilted(10, 4, 12, tilt),
                            tilted(14, -3, 15, tilt), tilted(14, -3, 24, tilt)};
  double worst = 0;
  int checked = 0;
  for (size_t leg = 0; leg + 1 < path.size(); ++leg) {
    const double dist = (path[leg + 1].position_mm - path[leg].position_mm).norm();
    const int n = static_cast<int>(std::ceil(dist / 0.2));
    for (int i = 1; i <= n; ++i) {
      const BrushState& st = sim.step(interpolatePose(path[leg], path[leg + 1], double(i) / n),
                                      t += 0.01);
      for (size_t s = 0; s < st.spines.size(); ++s) {
        const SpineState& sp = st.spines[s];
        if (sp.summary.status != SolveStatus::kOk) continue;
        const SpineProblem& p = sim.lastProblems()[s];
        const int nv = p.vars();
        std::vector<double> g(nv);
        SpineFk fk;
        spineEnergy(p, sp.solution.q.data(), &fk, nullptr, g.data(), nullptr);
        for (int v = 0; v < nv; ++v) {
          double r = g[v] - sp.solution.z_lower[v] + sp.solution.z_upper[v];
          for (int j = 1; j <= fk.n; ++j) r += sp.solution.lambda[j - 1] * fk.d(j, v).z();
          worst = std::max(worst, std::fabs(r));
        }
        ++checked;
      }
    }
  }
  INFO("worst KKT residual " << worst << " over " << checked << " spine solves");
  CHECK(checked > 100);
  CHECK(worst < kKktTol);
}

TEST_CASE("a straight spine pressed straight down buckles the same way every time",
          "[phenomena][buckling]") {
  // No rest curvature at all: the canvas constraint has no gradient at the
  // straight pose (a buckling point). The solve starts from a 1e-3 rad bend
  // towards +y of the brush, so the spine bends that way, reproducibly.
  auto press = [](const Pose& start) {
    const SpineSpec spine = makeSpine({5, 5, 5}, {9, 7, 5});
    const Brush brush = makeBrush({spine}, 0.4, 0.3);
    Simulation sim(brush, SimOptions{}, makeIpoptSolver());
    double t = 0;
    sim.reset(start, t);
    Pose down = start;
    down.position_mm.z() -= 7;
    moveHandle(sim, start, down, &t);
    REQUIRE(sim.state().spines[0].summary.usable());
    REQUIRE(sim.state().anyContact());
    return sim.state().spines[0];
  };
  const SpineState a = press(poseAt(0, 0, 16));
  const SpineState b = press(poseAt(0, 0, 16));
  CHECK(a.joints_mm == b.joints_mm);
  // The tip went towards +y (theta > 0 bends towards +y, eq. 10) and did not twist sideways.
  CHECK(a.joints_mm.back().y() > 3.0);
  CHECK(std::fabs(a.joints_mm.back().x()) < 1e-6);
  // With the handle turned 90 degrees about z, the bend turns with the brush.
  Pose turned = poseAt(0, 0, 16);
  turned.rotation = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ());
  const SpineState c = press(turned);
  CHECK(c.joints_mm.back().x() < -3.0);
}

TEST_CASE("every brush of the library has the paper's §5 parameters", "[phenomena][calibration]") {
  for (const char* name : {"round", "flat", "bright", "filbert", "badger", "fan", "calligraphy"}) {
    const Brush brush =
        loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json");
    INFO(name);
    for (const SpineSpec& s : brush.spines)
      for (size_t k = 0; k < s.stiffness_nmm_per_rad.size(); ++k) {
        // §5: K "on the order of" 5-10 N mm/rad. A hair is a tapered rod whose
        // bending stiffness falls with the fourth power of its diameter, so the
        // library grades K from the ferrule to the tip (docs/dynamics.md,
        // "Graded stiffness"); every joint stays within one order of magnitude
        // of the paper's range, and the whole brush's response is the
        // calibration test above.
        CHECK(s.stiffness_nmm_per_rad[k] >= 0.5);
        CHECK(s.stiffness_nmm_per_rad[k] <= 100);
        if (k > 0) CHECK(s.stiffness_nmm_per_rad[k] <= s.stiffness_nmm_per_rad[k - 1]);
        CHECK(s.damping_nmm[k] <= 0.01);          // D up to about 0.01
      }
    CHECK(brush.friction.mu_static >= 0.3);       // mu 0.3-0.5
    CHECK(brush.friction.mu_static <= 0.5);
    CHECK(brush.friction.mu_kinetic >= 0.3);
  }
}

namespace {
// The library round pressed straight down from above its first contact to
// 8 mm past it (its hair is 19.9 mm long; the golden's press-lift.csv), with
// `spread_n_per_mm` for its squashed hair; its state at the bottom.
BrushState pressRound(double spread_n_per_mm) {
  Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  brush.volume.spread_n_per_mm = spread_n_per_mm;
  Simulation sim(brush, SimOptions{}, makeIpoptSolver());
  double t = 0;
  const Pose top = poseAt(30, 30, 22), bottom = poseAt(30, 30, 12);
  sim.reset(top, t);
  moveHandle(sim, top, bottom, &t);
  return sim.state();
}
}  // namespace

TEST_CASE("a squashed round spreads round its handle: no spine's belly crosses the axis",
          "[phenomena][volume]") {
  // Pressed straight down, the round's buckle has two branches: the whole
  // bundle laid over to one side (the near spines' bellies carried across the
  // handle's axis) or spread round it. The volume rule holds each joint out
  // along its own rest direction from the axis (docs/dynamics.md, "A squashed
  // bundle spreads"), so the laid-over branch costs it energy and the press
  // takes the spread one. Without the rule (0 N/mm) the bundle lays over.
  auto crossed = [](const BrushState& st, const Brush& brush, double* contact_off_mm) {
    int n = 0, in_contact = 0;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (size_t s = 0; s < st.spines.size(); ++s) {
      const Eigen::Vector2d root = brush.spines[s].root_mm.head<2>();
      const std::vector<Eigen::Vector3d>& x = st.spines[s].joints_mm;
      for (size_t j = 1; j < x.size(); ++j) {
        const Eigen::Vector2d from_axis = x[j].head<2>() - Eigen::Vector2d(30, 30);
        if (x[j].z() < 0.05) {
          sum += from_axis;
          ++in_contact;
        }
        // The centre spine (rooted on the axis) has no outward of its own.
        if (root.norm() > 0 && j + 1 < x.size() && from_axis.dot(root) < 0) ++n;
      }
    }
    *contact_off_mm = in_contact > 0 ? (sum / in_contact).norm() : HUGE_VAL;
    return n;
  };
  const Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  REQUIRE(brush.volume.spread_n_per_mm > 0);
  double off = 0, off_without = 0;
  const BrushState spread = pressRound(brush.volume.spread_n_per_mm);
  const BrushState without = pressRound(0);
  for (const SpineState& s : spread.spines) REQUIRE(s.summary.usable());
  const int n_spread = crossed(spread, brush, &off), n_without = crossed(without, brush, &off_without);
  INFO("belly joints across the axis: " << n_spread << " spread, " << n_without
       << " without; contact centroid " << off << " mm off the axis, " << off_without
       << " without");
  CHECK(n_spread == 0);
  CHECK(n_without > 0);
  // The joints on the paper centred on the handle: within 1 mm, a ninth of
  // the 9 mm blot, where laid over they sit several mm to the side.
  constexpr double kMaxContactOffMm = 1.0;
  CHECK(off <= kMaxContactOffMm);
  CHECK(off_without > kMaxContactOffMm);
}

TEST_CASE("a pull gives the squashed hair room: the squash fades with the handle's travel",
          "[phenomena][volume]") {
  // bundleSquash (docs/dynamics.md, "A squashed bundle spreads"): the room
  // is H + kTrailRoomPerMm * travel; 9 mm of hair under a ferrule 4 mm up.
  const Pose p = poseAt(0, 0, 4);
  CHECK(bundleSquash(9.0, p, 0) == Approx(9.0 / 4));
  CHECK(bundleSquash(9.0, p, 1) == Approx(9.0 / (4 + kTrailRoomPerMm)));
  CHECK(bundleSquash(9.0, p, 5.0 / kTrailRoomPerMm) == 1);
  CHECK(bundleSquash(9.0, p, 10) == 1);
  // Where the axis meets the paper: under an upright handle, and 2 mm along
  // the lean of one tilted 45 degrees about y whose ferrule is 2 mm up.
  CHECK((axisOnPaper(poseAt(3, 4, 7)) - Eigen::Vector2d(3, 4)).norm() < 1e-12);
  Pose tilt = poseAt(0, 0, 2);
  tilt.rotation = Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY());
  const Eigen::Vector2d on_paper = axisOnPaper(tilt);
  CHECK(std::fabs(std::fabs(on_paper.x()) - 2.0) < 1e-9);
  CHECK(std::fabs(on_paper.y()) < 1e-12);
}

#pragma once
// bristle/simulation.h -- a brush head simulated step by step as its handle
// moves (Baxter & Lin 2004, §3: each spine's joints solved for the least
// energy, eq. 3-11, with friction, eq. 10, against the paper at z = 0).
//
//   bristle::api::Simulation sim(bristle::api::Brush::load("round"));
//   sim.reset({{0, 0, 20}}, 0.0);                     // at rest in the air
//   const auto& s = sim.step({{0, 0, 15}}, 0.02);     // pressed 5 mm lower
//   s.contact_joints; s.force_n;
//
// The caller chooses the steps: a step moves the ferrule from its last pose
// to the new one, and is solved well when no hair root moves more than about
// max_step_mm (0.25 mm); `bristle render` plans its steps so.
//
// Ipopt's linear solver: MUMPS, unless the program installed bristle's dense
// KKT solver (process-wide; docs/api.md, "Process-wide set-up"). Both reach
// the same optima; the dense one is faster and is what `bristle` uses.

#include <array>
#include <memory>
#include <vector>

#include "bristle/brush.h"

namespace bristle::api {

enum class Solver {
  kIpopt,  // interior point (Ipopt); SLSQP retries a spine it fails on
  kSlsqp,  // sequential quadratic programming (NLopt); Ipopt retries
};

// A ferrule pose: position in canvas mm, rotation as a quaternion w, x, y, z
// (normalised; the identity points the hair straight down).
struct Pose {
  std::array<double, 3> xyz_mm{0, 0, 0};
  std::array<double, 4> quaternion_wxyz{1, 0, 0, 0};
};

struct SpineState {
  std::vector<std::array<double, 3>> joints_mm;  // root first, then joint 1..n (mm)
  std::vector<bool> contact;                     // joint 1..n on the paper
  std::array<double, 3> force_n{0, 0, 0};        // the paper's force on this spine (N)
  bool solved = true;                            // false: its solve failed, the shape is kept
};

struct StepResult {
  double t_s = 0;
  std::vector<SpineState> spines;
  std::array<double, 3> force_n{0, 0, 0};  // the paper's force on the brush (N)
  int contact_joints = 0;                  // joints on the paper, over all spines
  bool contact() const { return contact_joints > 0; }
};

class Simulation {
 public:
  // Throws Error (kUsage) for a solver_max_iterations outside [1, 100000].
  explicit Simulation(const Brush& brush, Solver solver = Solver::kIpopt,
                      int solver_max_iterations = 200);
  ~Simulation();
  Simulation(Simulation&&) noexcept;
  Simulation& operator=(Simulation&&) noexcept;
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // The brush at rest at this pose at time t_s (no contact is solved).
  void reset(const Pose& ferrule, double t_s);
  // One step to this pose at t_s, after the last one's time; the first step
  // without a reset starts from rest at this pose. Throws Error (kUsage)
  // naming the argument for a non-finite or out-of-range pose, a zero
  // quaternion or a time that does not increase.
  const StepResult& step(const Pose& ferrule, double t_s);
  const StepResult& state() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bristle::api

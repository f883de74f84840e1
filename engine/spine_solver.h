#pragma once
// Solvers for the per-step spine problems (paper §3.1 step 3). A solver returns
// a summary, never throws per step (STYLE.md item 5): a failed step is counted,
// reported, and the caller continues from the last good state.

#include <memory>
#include <span>
#include <string>
#include <vector>

#include "engine/spine_energy.h"

namespace bristle {

enum class SolveStatus {
  kOk,          // converged to tol
  kAcceptable,  // converged to acceptable_tol
  kFree,        // no contact, nothing to solve: the previous angles are the optimum
  kFailed,      // no usable solution; the caller keeps the previous state
};
const char* toString(SolveStatus s);

struct SolveSummary {
  SolveStatus status = SolveStatus::kOk;
  int iterations = 0;
  std::string message;  // the backend's own status name (e.g. Ipopt's)
  bool usable() const { return status != SolveStatus::kFailed; }
};

// One spine's unknowns and the multipliers that warm-start the next solve.
struct SpineSolution {
  std::vector<double> q;               // 2n joint angles (rad)
  std::vector<double> normal_force_n;  // n canvas forces on joints 1..n (N, >= 0)
  // Backend warm-start data (empty until the first solve).
  std::vector<double> lambda, z_lower, z_upper;
};

// Bounds on every joint angle: theta stays off the Euler-XYZ singularity at
// +-90 degrees (paper §3.2); phi has no singularity but is kept sane.
inline constexpr double kThetaLimitRad = 1.45;
inline constexpr double kPhiLimitRad = 2.8;

class SpineSolver {
 public:
  virtual ~SpineSolver() = default;
  // Solves all problems as one step. solutions[i] holds the start (warm start)
  // on entry and the result on exit (unchanged if the summary is not usable).
  virtual SolveSummary solve(std::span<const SpineProblem* const> problems,
                             std::span<SpineSolution* const> solutions) = 0;
  virtual const char* name() const = 0;
};

struct IpoptSettings {
  double tol = 1e-8;             // ~3e-5 mm joint accuracy (SOLVER-NOTES.md)
  double acceptable_tol = 1e-5;
  int max_iterations = 200;
};
std::unique_ptr<SpineSolver> makeIpoptSolver(const IpoptSettings& settings = {});

}  // namespace bristle

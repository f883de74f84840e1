#pragma once
// Solvers for the per-step spine problems (paper §3.1 step 3). A solver returns
// a summary, never throws per step (docs/design.md, "Style habits", item 5): a
// failed step is counted, reported, and the caller continues from the last good
// state.

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "engine/mechanics/spine_energy.h"

namespace bristle {

enum class SolveStatus {
  kOk,          // converged to tol
  kAcceptable,  // converged to acceptable_tol
  kFree,        // no contact, nothing to solve: the previous angles are the optimum
  kSettled,     // held still at rest (SimOptions::settled_mm): the last optimum stands
  kFailed,      // no usable solution; the caller keeps the previous state
};
const char* toString(SolveStatus s);

struct SolveSummary {
  SolveStatus status = SolveStatus::kOk;
  int iterations = 0;
  std::string message;  // the backend's own status name (e.g. Ipopt's)
  // 1 when a failed warm start was solved again from a re-centred start
  // (Ipopt; the iterations count both tries).
  int recentred = 0;
  int recentred_iterations = 0;  // of `iterations`, the re-centred try's
  // The watch (SpineSolver::setWatch) stopped the solve: status is kFailed,
  // and the caller drops the step rather than rescue the solve.
  bool stopped = false;
  bool usable() const { return status != SolveStatus::kFailed; }
};

// One spine's unknowns and the multipliers that warm-start the next solve.
struct SpineSolution {
  std::vector<double> q;               // 2n joint angles (rad)
  std::vector<double> normal_force_n;  // n canvas forces on joints 1..n (N, >= 0)
  // Backend warm-start data (empty until the first solve).
  std::vector<double> lambda, z_lower, z_upper;
  // Per joint (0 where it had none): the multiplier of the bound t >= 0 on its
  // friction's epigraph variable (engine/solvers/ipopt/ipopt_solver.cpp).
  std::vector<double> friction_z;
};

// Bounds on every joint angle: theta stays off the Euler-XYZ singularity at
// +-90 degrees (paper §3.2); phi has no singularity but is kept sane.
inline constexpr double kThetaLimitRad = 1.45;
inline constexpr double kPhiLimitRad = 2.8;

// Looks at a solve while it runs (SpineSolver::setWatch). A solver that can
// see its iterates (Ipopt, after each iteration) asks stop() and, when it says
// so, ends the solve at once and reports it `stopped`. A solver that cannot
// (SLSQP) never asks: the caller still judges the result.
class SolveWatch {
 public:
  virtual ~SolveWatch() = default;
  // q[i]: the joint angles of problems[i] at the current iterate.
  virtual bool stop(std::span<const SpineProblem* const> problems,
                    std::span<const double* const> q) = 0;
};

class SpineSolver {
 public:
  virtual ~SpineSolver() = default;
  // Until set to nullptr again, solves show their iterates to `watch`. A
  // solver that wraps another passes it on.
  virtual void setWatch(SolveWatch* watch) { watch_ = watch; }
  // Solves all problems as one step. solutions[i] holds the start (warm start)
  // on entry and the result on exit (unchanged if the summary is not usable).
  // `links` couple the problems' energies (hair volume); only a solver whose
  // couplesSpines() is true takes them, any other fails the solve when given some.
  // Without links the problems are independent.
  virtual SolveSummary solve(std::span<const SpineProblem* const> problems,
                             std::span<SpineSolution* const> solutions,
                             std::span<const VolumeLink> links) = 0;
  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions) {
    return solve(problems, solutions, {});
  }
  // True when solve() minimises the problems' energies and the links' as one
  // NLP for a brush of `spines` spines (Ipopt at any size; SLSQP as one dense
  // block up to SlsqpSettings::max_block_spines). Otherwise hair volume is
  // solved one spine at a time (Gauss-Seidel), which does not converge in one
  // sweep where the spines press on each other (docs/dynamics.md).
  virtual bool couplesSpines(int /*spines*/) const { return false; }
  // True when the solver gains from a start that puts stuck joints back on
  // their anchors (Simulation's predicted start, docs/dynamics.md "Where a
  // solve starts"): an interior-point method does; SLSQP, whose quasi-Newton
  // steps do not overshoot the friction cone's point in the same way, took
  // more evaluations from it (docs/PERFORMANCE.md, "Where a solve starts").
  virtual bool wantsPredictedStart() const { return false; }
  virtual const char* name() const = 0;

 protected:
  SolveWatch* watch_ = nullptr;
};

struct IpoptSettings {
  double tol = 1e-8;             // ~3e-5 mm joint accuracy (docs/design.md, "Solver notes")
  double acceptable_tol = 1e-5;
  int max_iterations = 200;
  // Further Ipopt options as name/value text, applied last (e.g. for tuning
  // experiments: {"mu_strategy", "monotone"}), each one of the allow-list of
  // engine/solvers/ipopt/ipopt_options.h.
  std::vector<std::pair<std::string, std::string>> extra_options;
};
// Throws bristle::Error(kUsage) naming an extra option the allow-list
// (engine/solvers/ipopt/ipopt_options.h) refuses; such a value never reaches Ipopt.
std::unique_ptr<SpineSolver> makeIpoptSolver(const IpoptSettings& settings = {});

}  // namespace bristle

namespace bristle {

// NLopt SLSQP backend (docs/design.md, "Solver notes"): one dense SQP per spine, or
// one for all the spines when hair volume links them (docs/dynamics.md, "SLSQP
// solves the coupled spines as one block"), with the energy's gradient only
// (no Hessian). NLopt returns no multipliers:
// normal forces come from the KKT conditions over the joints on the canvas.
// Its SolveSummary::iterations counts energy evaluations; its status is
// kAcceptable for NLopt's ROUNDOFF_LIMITED at a point on the canvas.
struct SlsqpSettings {
  int max_evaluations = 200;          // objective evaluations per spine (~9 dragging);
                                      // a block of k spines may take k times as many
  // Stop when a line search changes E by less (N mm). SLSQP's quasi-Newton
  // Hessian starts at identity every solve and can take a step of tiny progress
  // well before the optimum: at 1e-10 it stopped up to 1.4e-3 mm short of
  // Ipopt's optimum (4e-7 N mm above it) in a steady drag; 1e-13 stays within
  // ~6e-5 mm for ~10% more evaluations, 100x above the energy's round-off.
  double ftol_abs_nmm = 1e-13;
  double constraint_tol_mm = 1e-10;   // NLopt's feasibility tolerance on z_j >= 0
  double feasibility_tol_mm = 1e-6;   // a result deeper below the canvas fails
  double active_mm = 1e-6;            // joints this close to the canvas may carry force
  // Brushes of up to this many spines solve their hair volume as one block;
  // larger ones one spine at a time. The block's dense QP costs about the cube
  // of its angles: the round (7 spines) takes 8-13 times the CPU of its sweep
  // (docs/PERFORMANCE.md, "SLSQP's block solve"); the badger's 15 would take
  // about 8 times that again.
  int max_block_spines = 8;
};
// Throws bristle::Error(kUsage) naming a setting that is out of range.
std::unique_ptr<SpineSolver> makeSlsqpSolver(const SlsqpSettings& settings = {});

}  // namespace bristle

// NLopt SLSQP backend: one optimisation per spine (the spines of a brush are
// independent problems, and SLSQP's QP is dense, so small problems suit it),
// using the energy's value and gradient, on Hessian-scaled angles (see
// Callbacks). About 9 energy evaluations per 4-joint spine while dragging;
// per step it is the faster solver for brushes of few spines
// (docs/PERFORMANCE.md, "Per step: Ipopt and SLSQP").
// Ipopt stays the reference; tests/engine/solvers/test_solvers.cpp checks that the two agree.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <nlopt.hpp>
#include <string>

#include "engine/base/error.h"
#include "engine/solvers/spine_solver.h"

namespace bristle {
namespace {

// Everything the NLopt callbacks see: the problem of the current solve, the
// variable scaling and the kinematics of the last point evaluated. SLSQP
// evaluates the constraints at the point where it has just evaluated the
// energy, so they reuse its kinematics.
//
// Preconditioning: NLopt works on y = w * q (per variable), w_v = sqrt(H_vv) of
// the energy's Hessian at the start point. SLSQP's quasi-Newton matrix starts
// at the identity every solve; in y the true Hessian's diagonal is ~1, so its
// first steps are close to Newton steps instead of gradient steps on a problem
// whose curvature spans the stiffness profile, friction and damping: about a
// third of the evaluations while dragging (docs/PERFORMANCE.md, "SLSQP and
// Ipopt").
struct Callbacks {
  const SpineProblem* problem = nullptr;
  std::vector<double> inv_w;  // 1 / w_v: q_v = y_v * inv_w[v]
  std::vector<double> q;      // q of the last y the callbacks were given
  SpineFk fk;
  std::vector<double> fk_y;  // the point fk holds
  int fk_order = -1;         // and its derivative order (-1: none)

  bool have(const double* y, int order) const {
    return fk_order >= order &&
           std::memcmp(y, fk_y.data(), fk_y.size() * sizeof(double)) == 0;
  }
  void remember(const double* y, int order) {
    fk_y.assign(y, y + problem->vars());
    fk_order = order;
  }
  const double* toAngles(const double* y) {
    q.resize(inv_w.size());
    for (size_t v = 0; v < q.size(); ++v) q[v] = y[v] * inv_w[v];
    return q.data();
  }
};

// Objective: the spine energy (eq. 1) and its gradient, with respect to y.
double energyCallback(unsigned, const double* y, double* grad, void* data) {
  Callbacks& c = *static_cast<Callbacks*>(data);
  const double e = spineEnergy(*c.problem, c.toAngles(y), &c.fk, nullptr, grad, nullptr);
  if (grad)
    for (size_t v = 0; v < c.inv_w.size(); ++v) grad[v] *= c.inv_w[v];
  c.remember(y, grad ? 1 : 0);
  // A non-finite energy is a bug, not a point to step back from: stop (the
  // C++ wrapper turns this into an exception, caught below as a failure).
  if (!std::isfinite(e)) throw nlopt::forced_stop();
  return e;
}

// eq. 5 for joints 1..n in NLopt's form c(y) <= 0: c_j = -z(x_j). grad is
// m x 2n row-major; joint j depends only on the 2j angles of the joints before it.
void canvasCallback(unsigned m, double* c, unsigned nv, const double* y, double* grad,
                    void* data) {
  Callbacks& cb = *static_cast<Callbacks*>(data);
  const int order = grad ? 1 : 0;
  if (!cb.have(y, order)) {
    spineForwardKinematics(*cb.problem->spine, cb.problem->handle, cb.problem->baseData(),
                           cb.toAngles(y), order,
                           &cb.fk);
    cb.remember(y, order);
  }
  for (unsigned j = 1; j <= m; ++j) {
    c[j - 1] = -cb.fk.x[j].z();
    if (!grad) continue;
    double* row = grad + (j - 1) * nv;
    for (unsigned v = 0; v < nv; ++v)
      row[v] = v < 2 * j ? -cb.fk.d(j, v).z() * cb.inv_w[v] : 0.0;
  }
}

double limitRad(int v) { return v % 2 == 0 ? kThetaLimitRad : kPhiLimitRad; }

const char* resultName(nlopt::result r) {
  switch (r) {
    case nlopt::FAILURE: return "FAILURE";
    case nlopt::INVALID_ARGS: return "INVALID_ARGS";
    case nlopt::OUT_OF_MEMORY: return "OUT_OF_MEMORY";
    case nlopt::ROUNDOFF_LIMITED: return "ROUNDOFF_LIMITED";
    case nlopt::FORCED_STOP: return "FORCED_STOP";
    case nlopt::SUCCESS: return "SUCCESS";
    case nlopt::STOPVAL_REACHED: return "STOPVAL_REACHED";
    case nlopt::FTOL_REACHED: return "FTOL_REACHED";
    case nlopt::XTOL_REACHED: return "XTOL_REACHED";
    case nlopt::MAXEVAL_REACHED: return "MAXEVAL_REACHED";
    case nlopt::MAXTIME_REACHED: return "MAXTIME_REACHED";
    default: return "UNKNOWN";
  }
}

// Canvas forces from the KKT conditions at q (NLopt gives no multipliers):
//   grad E = sum_j nu_j grad z_j,  nu_j >= 0, over the joints on the canvas,
// solved by least squares; rows of angles held at their bounds are left out
// (their bound multipliers absorb them). A negative nu means that joint is not
// pushing: drop the most negative and solve again (a small NNLS; at most n
// rounds). Minimum-norm solution: a straight spine pressed straight down has
// a zero constraint gradient, and then gets no force from it.
std::vector<double> canvasForces(const SpineProblem& p, const std::vector<double>& q,
                                 double active_mm, SpineFk* fk) {
  const int nv = p.vars(), n = nv / 2;
  std::vector<double> grad(nv);
  spineEnergy(p, q.data(), fk, nullptr, grad.data(), nullptr);
  std::vector<double> nu(n, 0.0);
  std::vector<int> rows, cols;
  for (int v = 0; v < nv; ++v)
    if (std::fabs(q[v]) < limitRad(v) - 1e-9) rows.push_back(v);
  for (int j = 1; j <= n; ++j)
    if (fk->x[j].z() < active_mm) cols.push_back(j);
  while (!cols.empty() && !rows.empty()) {
    Eigen::MatrixXd a(rows.size(), cols.size());
    Eigen::VectorXd b(rows.size());
    for (size_t r = 0; r < rows.size(); ++r) {
      b[r] = grad[rows[r]];
      for (size_t k = 0; k < cols.size(); ++k) a(r, k) = fk->d(cols[k], rows[r]).z();
    }
    const Eigen::VectorXd x = a.completeOrthogonalDecomposition().solve(b);
    Eigen::Index worst = 0;
    if (x.minCoeff(&worst) >= 0) {
      for (size_t k = 0; k < cols.size(); ++k) nu[cols[k] - 1] = x[k];
      break;
    }
    cols.erase(cols.begin() + worst);
  }
  return nu;
}

class SlsqpSolver : public SpineSolver {
 public:
  explicit SlsqpSolver(const SlsqpSettings& settings) : settings_(settings) {}

  const char* name() const override { return "slsqp"; }

  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions,
                     std::span<const VolumeLink> links) override {
    if (!links.empty()) {  // one spine at a time: the caller couples them (couplesSpines)
      SolveSummary failed;
      failed.status = SolveStatus::kFailed;
      failed.message = "slsqp solves spines one at a time and takes no volume links";
      return failed;
    }
    try {
      return solveAll(problems, solutions);
    } catch (...) {  // e.g. bad_alloc: a summary, never an exception
      // (docs/design.md, "Style habits", item 5)
      SolveSummary failed;
      failed.status = SolveStatus::kFailed;
      failed.message = "exception outside NLopt";
      return failed;
    }
  }

 private:
  // Spines one after another. All or nothing (SpineSolver's contract): on the
  // first failure the remaining spines are not solved and no solution changes;
  // the caller retries spine by spine. `iterations` counts energy evaluations.
  SolveSummary solveAll(std::span<const SpineProblem* const> problems,
                        std::span<SpineSolution* const> solutions) {
    SolveSummary summary;
    if (problems.size() != solutions.size()) {
      summary.status = SolveStatus::kFailed;
      summary.message = "problem and solution counts differ";
      return summary;
    }
    results_.resize(problems.size());
    for (size_t s = 0; s < problems.size(); ++s) {
      const Outcome o = solveSpine(*problems[s], *solutions[s], &results_[s]);
      summary.iterations += o.evaluations;
      if (o.status == SolveStatus::kFailed) {
        summary.status = SolveStatus::kFailed;
        summary.message = o.message;
        if (problems.size() > 1) summary.message += " (spine " + std::to_string(s) + ")";
        return summary;
      }
      if (o.status == SolveStatus::kAcceptable) summary.status = SolveStatus::kAcceptable;
      // The distinct result names, in order of first appearance.
      if (summary.message.find(o.message) == std::string::npos)
        summary.message += (summary.message.empty() ? "" : ",") + o.message;
    }
    for (size_t s = 0; s < problems.size(); ++s) std::swap(*solutions[s], results_[s]);
    return summary;
  }

  struct Outcome {
    SolveStatus status = SolveStatus::kFailed;
    int evaluations = 0;
    std::string message;
  };
  // One NLopt object per variable count, with its bounds and callbacks set once.
  struct Optimizer {
    explicit Optimizer(int nv) : opt(nlopt::LD_SLSQP, unsigned(nv)) {}
    nlopt::opt opt;
    Callbacks callbacks;
  };

  Optimizer& optimizer(int nv) {
    if (optimizers_.size() <= size_t(nv)) optimizers_.resize(nv + 1);
    std::unique_ptr<Optimizer>& o = optimizers_[nv];
    if (o) return *o;
    auto made = std::make_unique<Optimizer>(nv);
    made->opt.set_min_objective(energyCallback, &made->callbacks);
    made->opt.add_inequality_mconstraint(canvasCallback, &made->callbacks,
                                         std::vector<double>(nv / 2, settings_.constraint_tol_mm));
    // No xtol_rel: it is relative to |q|, so it never triggers at q = 0 (a straight
    // spine) and every no-contact step would run to maxeval (docs/design.md, "Solver notes").
    made->opt.set_ftol_abs(settings_.ftol_abs_nmm);
    made->opt.set_maxeval(settings_.max_evaluations);
    o = std::move(made);
    return *o;
  }

  // w_v = sqrt(|H_vv|) of the energy's Hessian at the start q, floored at
  // kMinCurvatureRatio of the largest so that a flat direction (a joint whose
  // friction and spring nearly cancel) does not get a huge step; the bounds
  // scale with it.
  void setScaling(const SpineProblem& p, const std::vector<double>& q, Optimizer* opt) {
    // A variable's curvature may be this small relative to the stiffest one
    // before it is floored: 1e-4 bounds the scale spread at 100x, the range of
    // the stiffness profiles and friction terms of the brush library.
    constexpr double kMinCurvatureRatio = 1e-4;
    // The curvature of the smoothed kinks holds only within their smoothing width
    // of the last step: joint damping's |dq| over 1e-5 rad (D / eps ~ 500 N mm/rad
    // against K ~ 10) and friction's |dx| over 1e-3 mm (mu Fn / eps). Scaling by
    // it would make every step start far too short, so the scale is taken with
    // both smoothed wide enough to span a step's motion, and reflects springs,
    // contact and the average friction drag. Widening damping alone lets a cold
    // press fail; widening both, friction to 1 mm, takes the fewest evaluations
    // on bench_solver's probes (about 9 a dragging step, against 40 unscaled).
    constexpr double kScaleDampRad = 0.05;
    constexpr double kScaleFrictionMm = 1.0;
    const int nv = p.vars();
    hess_.resize(size_t(nv) * nv);
    scale_problem_ = p;
    scale_problem_.eps_damp_rad = std::max(p.eps_damp_rad, kScaleDampRad);
    scale_problem_.eps_mm = std::max(p.eps_mm, kScaleFrictionMm);
    spineEnergy(scale_problem_, q.data(), &fk_, nullptr, nullptr, hess_.data());
    auto curvature = [&](int v) {
      const double c = std::fabs(hess_[v * nv + v]);
      return std::isfinite(c) ? c : 0.0;
    };
    double largest = 0;
    for (int v = 0; v < nv; ++v) largest = std::max(largest, curvature(v));
    Callbacks& cb = opt->callbacks;
    cb.inv_w.resize(nv);
    lo_.resize(nv);
    hi_.resize(nv);
    for (int v = 0; v < nv; ++v) {
      const double w =
          largest > 0 ? std::sqrt(std::max(curvature(v), kMinCurvatureRatio * largest)) : 1.0;
      cb.inv_w[v] = 1.0 / w;
      lo_[v] = -limitRad(v) * w;
      hi_[v] = limitRad(v) * w;
    }
    opt->opt.set_lower_bounds(lo_);
    opt->opt.set_upper_bounds(hi_);
  }

  Outcome solveSpine(const SpineProblem& p, const SpineSolution& start, SpineSolution* out) {
    Outcome o;
    const int nv = p.vars(), n = nv / 2;
    if (start.q.size() != size_t(nv)) {
      o.message = "start has the wrong number of angles";
      return o;
    }
    std::vector<double>& q = out->q;
    q.resize(nv);
    for (int v = 0; v < nv; ++v) q[v] = std::clamp(start.q[v], -limitRad(v), limitRad(v));
    nlopt::result r = nlopt::FAILURE;
    try {
      Optimizer& opt = optimizer(nv);
      Callbacks& cb = opt.callbacks;
      cb.problem = &p;
      cb.fk_order = -1;
      setScaling(p, q, &opt);
      std::vector<double>& y = y_;
      y.resize(nv);
      // Clamped again in y: q / inv_w and limit * w can differ in the last bit,
      // and NLopt refuses a start outside its bounds.
      for (int v = 0; v < nv; ++v) y[v] = std::clamp(q[v] / cb.inv_w[v], lo_[v], hi_[v]);
      double e = 0;
      try {
        r = opt.opt.optimize(y, e);
      } catch (const nlopt::roundoff_limited&) {
        // The wrapper throws on ROUNDOFF_LIMITED after writing the best point to y.
        r = nlopt::ROUNDOFF_LIMITED;
      }
      for (int v = 0; v < nv; ++v) q[v] = std::clamp(y[v] * cb.inv_w[v], -limitRad(v), limitRad(v));
      o.evaluations = opt.opt.get_numevals();
      o.message = resultName(r);
      // NLopt returns its best point: the lowest energy among the points within
      // constraint_tol_mm of feasibility, or the least infeasible one if none was.
      double lowest = HUGE_VAL;
      bool finite = true;
      for (double a : q) finite = finite && std::isfinite(a);
      if (finite) {
        spineForwardKinematics(*p.spine, p.handle, p.baseData(), q.data(), 0, &fk_);
        for (int j = 1; j <= n; ++j) lowest = std::min(lowest, fk_.x[j].z());
      }
      const bool feasible = finite && lowest >= -settings_.feasibility_tol_mm;
      switch (r) {
        case nlopt::SUCCESS:
        case nlopt::STOPVAL_REACHED:
        case nlopt::FTOL_REACHED:
        case nlopt::XTOL_REACHED:
          o.status = SolveStatus::kOk;
          break;
        case nlopt::ROUNDOFF_LIMITED:
          // SLSQP stops so when its line search finds no descent (mode 8) or its
          // LSQ subproblem turns singular. On this problem that happens at the
          // optimum, where E no longer changes in double precision: run with
          // ftol_abs 0, every solve ends so, within 1e-7 mm of Ipopt's optimum.
          // (NLopt itself turns mode 8 at a feasible point into FTOL_REACHED when
          // E changed by < 10 ftol_abs.) So it is accepted, as kAcceptable, only
          // if the point is on or above the canvas within feasibility_tol_mm.
          o.status = SolveStatus::kAcceptable;
          break;
        default:  // MAXEVAL_REACHED, MAXTIME_REACHED
          return o;
      }
      if (!feasible) {
        o.status = SolveStatus::kFailed;
        if (finite) {
          char depth[64];
          std::snprintf(depth, sizeof depth, ": %.3g mm below the canvas", -lowest);
          o.message += depth;
        } else {
          o.message += ": not finite";
        }
        return o;
      }
      out->normal_force_n = canvasForces(p, q, settings_.active_mm, &fk_);
    } catch (const std::exception& ex) {  // NLopt's FAILURE, INVALID_ARGS, FORCED_STOP...
      o.status = SolveStatus::kFailed;
      o.message = std::string("exception: ") + ex.what();
      return o;
    } catch (...) {
      o.status = SolveStatus::kFailed;
      o.message = "exception";
      return o;
    }
    // Ipopt's sign convention (Lagrangian E + lambda^T z: lambda <= 0 on an active
    // joint), so either backend can warm-start Ipopt; no bound multipliers, but
    // sized as Ipopt reads them whenever lambda has n entries.
    out->lambda.resize(n);
    for (int j = 0; j < n; ++j) out->lambda[j] = -out->normal_force_n[j];
    out->z_lower.assign(nv, 0.0);
    out->z_upper.assign(nv, 0.0);
    return o;
  }

  SlsqpSettings settings_;
  std::vector<std::unique_ptr<Optimizer>> optimizers_;
  std::vector<SpineSolution> results_;
  SpineFk fk_;
  std::vector<double> hess_, lo_, hi_, y_;
  SpineProblem scale_problem_;
};

}  // namespace

std::unique_ptr<SpineSolver> makeSlsqpSolver(const SlsqpSettings& settings) {
  auto check = [](bool ok, const char* field, double value, const char* rule) {
    if (!ok)
      throw Error(ExitCode::kUsage, std::string("SlsqpSettings::") + field + " = " +
                                        std::to_string(value) + ": " + rule);
  };
  // NLopt reads maxeval <= 0 as "no limit".
  check(settings.max_evaluations >= 1, "max_evaluations", settings.max_evaluations, "must be >= 1");
  check(settings.ftol_abs_nmm >= 0, "ftol_abs_nmm", settings.ftol_abs_nmm, "must be >= 0");
  check(settings.constraint_tol_mm >= 0, "constraint_tol_mm", settings.constraint_tol_mm,
        "must be >= 0");
  check(settings.feasibility_tol_mm >= 0, "feasibility_tol_mm", settings.feasibility_tol_mm,
        "must be >= 0");
  check(settings.active_mm >= 0, "active_mm", settings.active_mm, "must be >= 0");
  return std::make_unique<SlsqpSolver>(settings);
}

}  // namespace bristle

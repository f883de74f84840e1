// NLopt SLSQP backend: one optimisation per spine where the spines are
// independent problems, and one for all of them where hair volume couples
// them (their links, docs/dynamics.md; SLSQP's QP is dense, which a brush's
// few dozen angles suit), using the energy's value and gradient, on
// Hessian-scaled angles (see Callbacks). About 9 energy evaluations per 4-joint spine while dragging;
// per step it is the faster solver for brushes of few spines
// (docs/PERFORMANCE.md, "Per step: Ipopt and SLSQP").
// Ipopt stays the reference; tests/engine/solvers/test_solvers.cpp checks that the two agree.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <nlopt.hpp>
#include <span>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "engine/solvers/spine_solver.h"

namespace bristle {
namespace {

// Everything the NLopt callbacks see: the block of spines of the current solve
// (one spine, or the spines coupled by hair volume and their links), the
// variable scaling and the kinematics of the last point evaluated. SLSQP
// evaluates the constraints at the point where it has just evaluated the
// energy, so they reuse its kinematics.
//
// A block's variables are its spines' angles one spine after another
// (offset[s] .. offset[s + 1]); its constraints are their joints' eq. 5, in the
// same order (spine s's joint j is row offset[s] / 2 + j - 1).
//
// Preconditioning: NLopt works on y = w * q (per variable), w_v = sqrt(H_vv) of
// the energy's Hessian at the start point. SLSQP's quasi-Newton matrix starts
// at the identity every solve; in y the true Hessian's diagonal is ~1, so its
// first steps are close to Newton steps instead of gradient steps on a problem
// whose curvature spans the stiffness profile, friction and damping: about a
// third of the evaluations while dragging (docs/PERFORMANCE.md, "SLSQP and
// Ipopt").
struct Callbacks {
  std::vector<const SpineProblem*> problems;
  std::vector<int> offset;            // problems.size() + 1 entries
  std::span<const VolumeLink> links;  // between problems (indices into them)
  std::vector<double> inv_w;  // 1 / w_v: q_v = y_v * inv_w[v]
  std::vector<double> q;      // q of the last y the callbacks were given
  std::vector<SpineFk> fk;    // per spine
  std::vector<double> fk_y;  // the point fk holds
  int fk_order = -1;         // and its derivative order (-1: none)

  bool have(const double* y, int order) const {
    return fk_order >= order &&
           std::memcmp(y, fk_y.data(), fk_y.size() * sizeof(double)) == 0;
  }
  void remember(const double* y, int order) {
    fk_y.assign(y, y + offset.back());
    fk_order = order;
  }
  const double* toAngles(const double* y) {
    q.resize(inv_w.size());
    for (size_t v = 0; v < q.size(); ++v) q[v] = y[v] * inv_w[v];
    return q.data();
  }
};

// The block's energy at angles q: every spine's (eq. 1, with its volume
// contacts against neighbours outside the block) and every link's, with
// the gradient in q if grad is given. Leaves each spine's kinematics at q in
// c.fk (order 1 with a gradient).
double blockEnergy(Callbacks& c, const double* q, double* grad) {
  double e = 0;
  c.fk.resize(c.problems.size());
  for (size_t s = 0; s < c.problems.size(); ++s)
    e += spineEnergy(*c.problems[s], q + c.offset[s], &c.fk[s], nullptr,
                     grad ? grad + c.offset[s] : nullptr, nullptr);
  for (const VolumeLink& l : c.links)
    e += volumeLinkEnergy(l, c.fk[l.a], c.fk[l.b], grad ? grad + c.offset[l.a] : nullptr,
                          grad ? grad + c.offset[l.b] : nullptr, nullptr, nullptr, nullptr);
  return e;
}

// Objective: the block's energy and its gradient, with respect to y.
double energyCallback(unsigned, const double* y, double* grad, void* data) {
  Callbacks& c = *static_cast<Callbacks*>(data);
  const double e = blockEnergy(c, c.toAngles(y), grad);
  if (grad)
    for (size_t v = 0; v < c.inv_w.size(); ++v) grad[v] *= c.inv_w[v];
  c.remember(y, grad ? 1 : 0);
  // A non-finite energy is a bug, not a point to step back from: stop (the
  // C++ wrapper turns this into an exception, caught below as a failure).
  if (!std::isfinite(e)) throw nlopt::forced_stop();
  return e;
}

// eq. 5 for joints 1..n of every spine in NLopt's form c(y) <= 0: c_j = -z(x_j).
// grad is m x nv row-major; joint j depends only on the 2j angles of its own
// spine's joints before it.
void canvasCallback(unsigned m, double* c, unsigned nv, const double* y, double* grad,
                    void* data) {
  Callbacks& cb = *static_cast<Callbacks*>(data);
  const int order = grad ? 1 : 0;
  cb.fk.resize(cb.problems.size());
  if (!cb.have(y, order)) {
    const double* q = cb.toAngles(y);
    for (size_t s = 0; s < cb.problems.size(); ++s) {
      const SpineProblem& p = *cb.problems[s];
      spineForwardKinematics(*p.spine, p.handle, p.baseData(), q + cb.offset[s], order,
                             &cb.fk[s]);
    }
    cb.remember(y, order);
  }
  if (grad) std::fill(grad, grad + size_t(m) * nv, 0.0);
  for (size_t s = 0; s < cb.problems.size(); ++s) {
    const int off = cb.offset[s], n = (cb.offset[s + 1] - off) / 2;
    for (int j = 1; j <= n; ++j) {
      const int r = off / 2 + j - 1;
      c[r] = -cb.fk[s].x[j].z();
      if (!grad) continue;
      double* row = grad + size_t(r) * nv;
      for (int v = 0; v < 2 * j; ++v) row[off + v] = -cb.fk[s].d(j, v).z() * cb.inv_w[off + v];
    }
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
// a zero constraint gradient, and then gets no force from it. In a block,
// grad is the block energy's gradient in this spine's angles (its links'
// pushes included) and fk its kinematics at q, of order 1.
std::vector<double> canvasForces(int nv, const double* q, const double* grad, double active_mm,
                                 const SpineFk* fk) {
  const int n = nv / 2;
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
  // Spines coupled by hair volume are one dense NLP, as Ipopt's, up to
  // max_block_spines (docs/dynamics.md, "SLSQP solves the coupled spines as
  // one block").
  bool couplesSpines(int spines) const override { return spines <= settings_.max_block_spines; }

  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions,
                     std::span<const VolumeLink> links) override {
    try {
      return solveAll(problems, solutions, links);
    } catch (...) {  // e.g. bad_alloc: a summary, never an exception
      // (docs/design.md, "Style habits", item 5)
      SolveSummary failed;
      failed.status = SolveStatus::kFailed;
      failed.message = "exception outside NLopt";
      return failed;
    }
  }

 private:
  // Blocks of spines, each solved as one NLP: the spines joined by links that
  // act or nearly act where the solve starts (docs/dynamics.md, "SLSQP solves
  // the coupled spines as one block"); without links, every spine alone. All
  // or nothing (SpineSolver's contract): on the first failure the remaining
  // blocks are not solved and no solution changes; the caller retries spine
  // by spine. `iterations` counts energy evaluations.
  SolveSummary solveAll(std::span<const SpineProblem* const> problems,
                        std::span<SpineSolution* const> solutions,
                        std::span<const VolumeLink> links) {
    SolveSummary summary;
    if (problems.size() != solutions.size()) {
      summary.status = SolveStatus::kFailed;
      summary.message = "problem and solution counts differ";
      return summary;
    }
    for (const VolumeLink& l : links)
      if (l.a < 0 || l.b < 0 || size_t(l.a) >= problems.size() ||
          size_t(l.b) >= problems.size() || l.a == l.b) {
        summary.status = SolveStatus::kFailed;
        summary.message = "a volume link names a spine outside the solve";
        return summary;
      }
    // A link held apart may come to act during the solve (a large step): then
    // it joins its spines' block and the solve is redone, at most twice.
    joined_.assign(links.size(), 0);
    results_.resize(problems.size());
    for (int round = 0;; ++round) {
      const std::vector<std::vector<int>> blocks = splitBlocks(problems, solutions, links);
      if (!solveBlocks(problems, solutions, blocks, links.empty(), &summary)) return summary;
      if (links.empty() || round == 2 || !joinActed(problems, links)) break;
      summary.message.clear();
      summary.status = SolveStatus::kOk;
    }
    for (size_t s = 0; s < problems.size(); ++s) std::swap(*solutions[s], results_[s]);
    return summary;
  }

  // Solves each block from the starts into results_; false (with the summary
  // failed) on the first block that fails.
  bool solveBlocks(std::span<const SpineProblem* const> problems,
                   std::span<SpineSolution* const> solutions,
                   const std::vector<std::vector<int>>& blocks, bool unlinked,
                   SolveSummary* summary) {
    for (size_t b = 0; b < blocks.size(); ++b) {
      const std::vector<int>& members = blocks[b];
      std::vector<const SpineProblem*> bp;
      std::vector<SpineSolution*> bs;
      for (int s : members) {
        bp.push_back(unlinked ? problems[s] : &held_[s]);
        bs.push_back(solutions[s]);
      }
      block_outs_.resize(members.size());
      const Outcome o = solveBlock(bp, bs, block_links_[b], block_outs_);
      summary->iterations += o.evaluations;
      if (o.status == SolveStatus::kFailed) {
        summary->status = SolveStatus::kFailed;
        summary->message = o.message;
        if (problems.size() > 1) summary->message += " (spine " + std::to_string(members[0]) + ")";
        return false;
      }
      for (size_t k = 0; k < members.size(); ++k) std::swap(results_[members[k]], block_outs_[k]);
      if (o.status == SolveStatus::kAcceptable) summary->status = SolveStatus::kAcceptable;
      // The distinct result names, in order of first appearance.
      if (summary->message.find(o.message) == std::string::npos)
        summary->message += (summary->message.empty() ? "" : ",") + o.message;
    }
    return true;
  }

  // Wider than a pair of joints closes in a step: the round's straight pull
  // converges as the steps shrink with 0.25 mm (SSIM 0.997 between 0.1 and
  // 0.05 mm steps), not with 0.05 mm (0.988, under the 0.99 asked by
  // "marks: paint laid down converges as the steps shrink").
  static constexpr double kBlockNearMm = 0.25;
  // Whether link l's push or cohesion acts within near_mm at joints x.
  static bool linkNear(const VolumeLink& l, const std::vector<std::vector<Eigen::Vector3d>>& x,
                       double near_mm) {
    const Eigen::Vector3d d = x[l.a][l.joint] - x[l.b][l.joint];
    const double push_r = l.push_dir.isZero() ? d.norm() : l.push_dir.dot(d);
    return push_r < l.min_mm + near_mm || (l.max_mm > 0 && d.norm() > l.max_mm - near_mm);
  }

  // Every spine's joints at the given angles.
  template <class Angles>
  std::vector<std::vector<Eigen::Vector3d>> blockJoints(
      std::span<const SpineProblem* const> problems, Angles angles) {
    std::vector<std::vector<Eigen::Vector3d>> x(problems.size());
    for (size_t s = 0; s < problems.size(); ++s) {
      const SpineProblem& p = *problems[s];
      spineForwardKinematics(*p.spine, p.handle, p.baseData(), angles(s), 0, &fk_);
      x[s].assign(fk_.x.begin(), fk_.x.end());
    }
    return x;
  }

  // Marks in joined_ the links held apart that act at the results (where the
  // held contact and the link part ways); true if any.
  bool joinActed(std::span<const SpineProblem* const> problems, std::span<const VolumeLink> links) {
    const auto x = blockJoints(problems, [&](size_t s) { return results_[s].q.data(); });
    bool any = false;
    for (size_t i = 0; i < links.size(); ++i)
      if (!joined_[i] && linkNear(links[i], x, 0.0)) joined_[i] = any = true;
    return any;
  }

  // The blocks of the solve, each a list of spines, with their links (indices
  // into the block) in block_links_. A link joins two spines' blocks when its
  // push or cohesion acts within kBlockNearMm of where the solve starts, or
  // of where an earlier round of it ended (joined_); a
  // link that does not is held as the problem's own VolumeContact against the
  // other spine where it starts (held_), as the caller holds a neighbour
  // outside the solve, so that it still pushes if the step closes the gap.
  std::vector<std::vector<int>> splitBlocks(std::span<const SpineProblem* const> problems,
                                            std::span<SpineSolution* const> starts,
                                            std::span<const VolumeLink> links) {
    const int ns = int(problems.size());
    std::vector<int> root(ns);
    for (int s = 0; s < ns; ++s) root[s] = s;
    auto find = [&](int s) {
      while (root[s] != s) s = root[s] = root[root[s]];
      return s;
    };
    std::vector<std::vector<Eigen::Vector3d>> x;
    if (!links.empty()) x = blockJoints(problems, [&](size_t s) { return starts[s]->q.data(); });
    for (size_t i = 0; i < links.size(); ++i) {
      if (!joined_[i]) joined_[i] = linkNear(links[i], x, kBlockNearMm);
      if (joined_[i]) root[find(links[i].a)] = find(links[i].b);
    }
    std::vector<std::vector<int>> blocks;
    std::vector<int> block_of(ns, -1), local(ns, -1);
    for (int s = 0; s < ns; ++s) {
      int& b = block_of[find(s)];
      if (b < 0) {
        b = int(blocks.size());
        blocks.emplace_back();
      }
      local[s] = int(blocks[b].size());
      blocks[b].push_back(s);
    }
    block_links_.assign(blocks.size(), {});
    if (links.empty()) return blocks;
    held_.resize(ns);
    for (int s = 0; s < ns; ++s) held_[s] = *problems[s];
    for (size_t i = 0; i < links.size(); ++i) {
      VolumeLink l = links[i];
      if (joined_[i]) {
        const int b = block_of[find(l.a)];
        l.a = local[l.a];
        l.b = local[l.b];
        block_links_[b].push_back(l);
        continue;
      }
      held_[l.a].volume.push_back({l.joint, x[l.b][l.joint], l.min_mm, l.max_mm, l.push_dir});
      held_[l.b].volume.push_back(
          {l.joint, x[l.a][l.joint], l.min_mm, l.max_mm, Eigen::Vector3d(-l.push_dir)});
    }
    return blocks;
  }

  struct Outcome {
    SolveStatus status = SolveStatus::kFailed;
    int evaluations = 0;
    std::string message;
  };
  // One NLopt object per variable count (a block of nv angles has nv / 2
  // joints on the canvas to keep above it), with its callbacks set once.
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
    o = std::move(made);
    return *o;
  }

  // w_v = sqrt(|H_vv|) of each spine's own energy's Hessian at the start q,
  // floored at kMinCurvatureRatio of the spine's largest so that a flat
  // direction (a joint whose friction and spring nearly cancel) does not get a
  // huge step; the bounds scale with it. The links' curvature is left out: the
  // block's figures (docs/dynamics.md) were measured so.
  void setScaling(std::span<const SpineProblem* const> problems, const std::vector<int>& offset,
                  const double* q, double* inv_w, double* lo, double* hi) {
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
    const size_t ns = problems.size();
    hess_.resize(ns);
    scale_fk_.resize(ns);
    for (size_t s = 0; s < ns; ++s) {
      const SpineProblem& p = *problems[s];
      const int nv = p.vars();
      hess_[s].assign(size_t(nv) * nv, 0.0);
      scale_problem_ = p;
      scale_problem_.eps_damp_rad = std::max(p.eps_damp_rad, kScaleDampRad);
      scale_problem_.eps_mm = std::max(p.eps_mm, kScaleFrictionMm);
      spineEnergy(scale_problem_, q + offset[s], &scale_fk_[s], nullptr, nullptr, hess_[s].data());
    }
    for (size_t s = 0; s < ns; ++s) {
      const int nv = problems[s]->vars(), off = offset[s];
      auto curvature = [&](int v) {
        const double c = std::fabs(hess_[s][v * nv + v]);
        return std::isfinite(c) ? c : 0.0;
      };
      double largest = 0;
      for (int v = 0; v < nv; ++v) largest = std::max(largest, curvature(v));
      for (int v = 0; v < nv; ++v) {
        const double w =
            largest > 0 ? std::sqrt(std::max(curvature(v), kMinCurvatureRatio * largest)) : 1.0;
        inv_w[off + v] = 1.0 / w;
        lo[off + v] = -limitRad(v) * w;
        hi[off + v] = limitRad(v) * w;
      }
    }
  }

  // Runs NLopt on the block from the starts; q gets its (clamped) result.
  nlopt::result optimizeBlock(std::span<const SpineProblem* const> problems,
                              std::span<SpineSolution* const> starts,
                              std::span<const VolumeLink> links, std::vector<double>* q,
                              Optimizer** used) {
    std::vector<int> offset = {0};
    for (const SpineProblem* p : problems) offset.push_back(offset.back() + p->vars());
    const int nv = offset.back();
    q->resize(nv);
    for (size_t s = 0; s < problems.size(); ++s)
      for (int v = 0; v < problems[s]->vars(); ++v)
        (*q)[offset[s] + v] = std::clamp(starts[s]->q[v], -limitRad(v), limitRad(v));
    Optimizer& opt = optimizer(nv);
    *used = &opt;
    Callbacks& cb = opt.callbacks;
    cb.problems.assign(problems.begin(), problems.end());
    cb.offset = offset;
    cb.links = links;
    cb.fk_order = -1;
    cb.inv_w.resize(nv);
    lo_.resize(nv);
    hi_.resize(nv);
    setScaling(problems, offset, q->data(), cb.inv_w.data(), lo_.data(), hi_.data());
    opt.opt.set_lower_bounds(lo_);
    opt.opt.set_upper_bounds(hi_);
    // The evaluation budget is per spine: a block of k spines may take k times
    // one spine's.
    opt.opt.set_maxeval(settings_.max_evaluations * int(problems.size()));
    std::vector<double>& y = y_;
    y.resize(nv);
    // Clamped again in y: q / inv_w and limit * w can differ in the last bit,
    // and NLopt refuses a start outside its bounds.
    for (int v = 0; v < nv; ++v) y[v] = std::clamp((*q)[v] / cb.inv_w[v], lo_[v], hi_[v]);
    nlopt::result r = nlopt::FAILURE;
    double e = 0;
    try {
      r = opt.opt.optimize(y, e);
    } catch (const nlopt::roundoff_limited&) {
      // The wrapper throws on ROUNDOFF_LIMITED after writing the best point to y.
      r = nlopt::ROUNDOFF_LIMITED;
    }
    for (size_t s = 0; s < problems.size(); ++s)
      for (int v = 0; v < problems[s]->vars(); ++v) {
        const int k = offset[s] + v;
        (*q)[k] = std::clamp(y[k] * cb.inv_w[k], -limitRad(v), limitRad(v));
      }
    return r;
  }

  // The status NLopt's result earns, before the feasibility check.
  static SolveStatus statusOf(nlopt::result r) {
    switch (r) {
      case nlopt::SUCCESS:
      case nlopt::STOPVAL_REACHED:
      case nlopt::FTOL_REACHED:
      case nlopt::XTOL_REACHED:
        return SolveStatus::kOk;
      case nlopt::ROUNDOFF_LIMITED:
        // SLSQP stops so when its line search finds no descent (mode 8) or its
        // LSQ subproblem turns singular. On this problem that happens at the
        // optimum, where E no longer changes in double precision: run with
        // ftol_abs 0, every solve ends so, within 1e-7 mm of Ipopt's optimum.
        // (NLopt itself turns mode 8 at a feasible point into FTOL_REACHED when
        // E changed by < 10 ftol_abs.) So it is accepted, as kAcceptable, only
        // if the point is on or above the canvas within feasibility_tol_mm.
        return SolveStatus::kAcceptable;
      default:  // MAXEVAL_REACHED, MAXTIME_REACHED
        return SolveStatus::kFailed;
    }
  }

  // Solves a block of spines (one, or all of them with their links) into outs.
  Outcome solveBlock(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> starts, std::span<const VolumeLink> links,
                     std::span<SpineSolution> outs) {
    Outcome o;
    for (size_t s = 0; s < problems.size(); ++s)
      if (starts[s]->q.size() != size_t(problems[s]->vars())) {
        o.message = "start has the wrong number of angles";
        return o;
      }
    try {
      Optimizer* opt = nullptr;
      const nlopt::result r = optimizeBlock(problems, starts, links, &q_, &opt);
      o.evaluations = opt->opt.get_numevals();
      o.message = resultName(r);
      o.status = statusOf(r);
      if (o.status == SolveStatus::kFailed) return o;
      // NLopt returns its best point: the lowest energy among the points within
      // constraint_tol_mm of feasibility, or the least infeasible one if none was.
      // Its kinematics and gradient, for the check and the canvas forces.
      Callbacks& cb = opt->callbacks;
      bool finite = true;
      for (double a : q_) finite = finite && std::isfinite(a);
      double lowest = HUGE_VAL;
      grad_.assign(q_.size(), 0.0);
      if (finite) {
        blockEnergy(cb, q_.data(), grad_.data());
        cb.fk_order = -1;  // cb.fk no longer holds the point of fk_y
        for (const SpineFk& f : cb.fk)
          for (int j = 1; j <= f.vars() / 2; ++j) lowest = std::min(lowest, f.x[j].z());
      }
      if (!(finite && lowest >= -settings_.feasibility_tol_mm)) {
        o.status = SolveStatus::kFailed;
        char depth[64];
        std::snprintf(depth, sizeof depth, ": %.3g mm below the canvas", -lowest);
        o.message += finite ? depth : ": not finite";
        return o;
      }
      for (size_t s = 0; s < problems.size(); ++s)
        finishSpine(*problems[s], q_.data() + cb.offset[s], grad_.data() + cb.offset[s],
                    cb.fk[s], &outs[s]);
    } catch (const std::exception& ex) {  // NLopt's FAILURE, INVALID_ARGS, FORCED_STOP...
      o.status = SolveStatus::kFailed;
      o.message = std::string("exception: ") + ex.what();
    } catch (...) {
      o.status = SolveStatus::kFailed;
      o.message = "exception";
    }
    return o;
  }

  // One spine's result: its angles, canvas forces and warm-start data.
  void finishSpine(const SpineProblem& p, const double* q, const double* grad, const SpineFk& fk,
                   SpineSolution* out) const {
    const int nv = p.vars(), n = nv / 2;
    out->q.assign(q, q + nv);
    out->normal_force_n = canvasForces(nv, q, grad, settings_.active_mm, &fk);
    // Ipopt's sign convention (Lagrangian E + lambda^T z: lambda <= 0 on an active
    // joint), so either backend can warm-start Ipopt; no bound multipliers, but
    // sized as Ipopt reads them whenever lambda has n entries.
    out->lambda.resize(n);
    for (int j = 0; j < n; ++j) out->lambda[j] = -out->normal_force_n[j];
    out->z_lower.assign(nv, 0.0);
    out->z_upper.assign(nv, 0.0);
  }

  SlsqpSettings settings_;
  std::vector<std::unique_ptr<Optimizer>> optimizers_;
  std::vector<SpineSolution> results_, block_outs_;
  std::vector<SpineProblem> held_;  // the problems with their far links held
  std::vector<char> joined_;        // per link: it joins its spines' block
  std::vector<std::vector<VolumeLink>> block_links_;
  SpineFk fk_;
  std::vector<std::vector<double>> hess_;  // per spine of the block, for setScaling
  std::vector<SpineFk> scale_fk_;
  std::vector<double> lo_, hi_, y_, q_, grad_;
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
  check(settings.max_block_spines >= 0, "max_block_spines", settings.max_block_spines,
        "must be >= 0");
  return std::make_unique<SlsqpSolver>(settings);
}

}  // namespace bristle

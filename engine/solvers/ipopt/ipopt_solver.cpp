// Ipopt backend: all spines of a brush are solved as one sparse NLP per step
// (block-diagonal Jacobian; block-diagonal Hessian plus one off-diagonal block
// per pair of spines that hair volume couples), so Ipopt's and MUMPS's set-up
// is paid once per step rather than once per spine.

#include <IpIpoptApplication.hpp>
#include <IpIpoptCalculatedQuantities.hpp>
#include <IpIpoptData.hpp>
#include <IpOrigIpoptNLP.hpp>
#include <IpTNLPAdapter.hpp>
#include <IpRegOptions.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

#include "engine/solvers/ipopt/dense_kkt.h"
#include "engine/base/error.h"
#include "engine/solvers/ipopt/ipopt_options.h"
#include "engine/solvers/ipopt/ipopt_timers.h"
#include "engine/solvers/spine_solver.h"

namespace bristle {
namespace {

using Ipopt::Index;
using Ipopt::Number;

// Friction (eq. 3) is a norm of the joint's displacement, smoothed only over
// 1e-3 mm. As an objective term, a joint that sticks or creeps puts the optimum
// on a near-kink: Newton's model of |dx| has no curvature along dx, so its step
// crosses the kink by the spring's whole reach and the line search cuts it back
// to 1e-3 of its length, step after step (docs/dynamics.md, "Friction in
// epigraph form"). In the epigraph form each joint's friction w G(q) becomes a
// variable t >= 0 with w t in the objective and the constraint t - G(q) >= 0:
// the same minimum (t = G there, as w > 0), but the bound t >= 0 is in
// Newton's model, and the barrier handles the kink as it handles the canvas.
// Damping (eq. 4) stays in the objective: in this form it took more iterations.
// The form is chosen with --ipopt-option friction_form=auto|epigraph|objective;
// auto (the default) takes the epigraph form for NLPs with hair volume and the
// objective form otherwise (IpoptSolver::friction_form_ below says why).
// How far above its norm each t starts. On the constraint itself (0), the
// slack starts at Ipopt's 1e-9 push, so the first Newton step, which also has
// to lift joints that the carried warm start put into the paper, is cut to a
// sliver and solves go into restoration. 1e-4 mm took the fewest iterations
// of 0 to 1e-2 mm (docs/PERFORMANCE.md, "Friction in epigraph form").
constexpr double kEpigraphSlackMm = 1e-4;

// How far above the paper a joint must stay, whatever the angles, for its
// canvas constraint to be left out (BrushNlp::reachingJoints). Only rounding
// needs a margin: the bound is exact geometry, so a micrometre is plenty.
constexpr double kCanvasClearanceMm = 1e-3;

// Every eval_* below answers false on a NaN or infinity, which Ipopt takes as
// a failed evaluation (it cuts the step, or stops with a failed solve). Left to
// itself, Ipopt 3.11 passes a non-finite derivative into the linear solver
// (it checks only when check_derivatives_for_naninf is on), where MUMPS has
// crashed the process on a NaN Hessian.
bool allFinite(const Number* v, Index n) {
  for (Index i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}

class BrushNlp : public Ipopt::TNLP {
  // The Hessian block coupling two spines through hair volume.
  struct CrossBlock {
    int hi, lo;             // spine indices, hi > lo
    std::vector<double> h;  // vars(hi) x vars(lo), row-major
  };

 public:
  BrushNlp(std::span<const SpineProblem* const> problems, std::span<SpineSolution* const> sols,
           std::span<const VolumeLink> links, bool warm, bool epigraph)
      : problems_(problems), sols_(sols), links_(links), warm_(warm), epigraph_(epigraph) {
    terms_.resize(problems_.size());
    for (size_t s = 0; s < problems_.size(); ++s) {
      const SpineProblem& p = *problems_[s];
      const int n = p.spine->jointCount();
      if (epigraph_)
        for (int j = 1; j <= n; ++j)
          if (p.friction_n[j - 1] > 0) terms_[s].push_back(j);
      canvas_.push_back(reachingJoints(p));
      const int m = static_cast<int>(terms_[s].size());
      var_offset_.push_back(nvars_);
      con_offset_.push_back(ncons_);
      nvars_ += 2 * n + m;
      ncons_ += canvasCount(s) + m;
      for (int j : canvas_[s]) nnz_jac_ += 2 * j;  // canvas constraint j: the 2j angles before it
      for (int j : terms_[s]) nnz_jac_ += 2 * j + 1;  // the angles before x_j, and t
      nnz_hess_ += (2 * n) * (2 * n + 1) / 2;
    }
    largest_coupled_rows_ = largestCoupledRows();
    fk_.resize(problems_.size());
    grad_.resize(nvars_);
    hess_.resize(problems_.size());
    friction_.resize(problems_.size());
    for (size_t s = 0; s < problems_.size(); ++s) friction_[s].resize(terms_[s].size());
    // One dense off-diagonal Hessian block per coupled pair of spines, in the
    // lower triangle: rows of the later spine (larger variable offset), columns
    // of the earlier one.
    for (const VolumeLink& l : links_) {
      const int hi = std::max(l.a, l.b), lo = std::min(l.a, l.b);
      int k = 0;
      while (k < static_cast<int>(blocks_.size()) && (blocks_[k].hi != hi || blocks_[k].lo != lo))
        ++k;
      if (k == static_cast<int>(blocks_.size())) {
        blocks_.push_back({hi, lo, {}});
        nnz_hess_ += problems_[hi]->vars() * problems_[lo]->vars();
      }
      link_block_.push_back(k);
    }
  }

  Ipopt::ApplicationReturnStatus status = Ipopt::Internal_Error;
  bool finalized = false;

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag,
                    IndexStyleEnum& index_style) override {
    n = nvars_;
    m = ncons_;
    nnz_jac_g = nnz_jac_;
    nnz_h_lag = nnz_hess_;
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Index, Number* x_l, Number* x_u, Index, Number* g_l,
                       Number* g_u) override {
    for (size_t s = 0; s < problems_.size(); ++s) {
      const int nq = problems_[s]->vars(), nc = canvasCount(s), m = termCount(s);
      for (int i = 0; i < nq; ++i) {
        const double lim = (i % 2 == 0) ? kThetaLimitRad : kPhiLimitRad;
        x_l[var_offset_[s] + i] = -lim;
        x_u[var_offset_[s] + i] = lim;
      }
      for (int i = 0; i < m; ++i) {  // t >= 0
        x_l[var_offset_[s] + nq + i] = 0.0;
        x_u[var_offset_[s] + nq + i] = 2e19;
      }
      // eq. 5: every joint on or above the canvas; and t - G >= 0.
      for (int j = 0; j < nc + m; ++j) {
        g_l[con_offset_[s] + j] = 0.0;
        g_u[con_offset_[s] + j] = 2e19;  // > nlp_upper_bound_inf: no upper bound
      }
    }
    return true;
  }

  bool get_starting_point(Index, bool init_x, Number* x, bool init_z, Number* z_L, Number* z_U,
                          Index, bool init_lambda, Number* lambda) override {
    for (size_t s = 0; s < problems_.size(); ++s) {
      const SpineProblem& p = *problems_[s];
      const SpineSolution& sol = *sols_[s];
      const int nv = p.vars(), nc = nv / 2, m = termCount(s);
      const bool have = warm_ && sol.lambda.size() == size_t(nc);
      const int vo = var_offset_[s], co = con_offset_[s];
      for (int i = 0; i < nv; ++i) {
        const double lim = (i % 2 == 0) ? kThetaLimitRad : kPhiLimitRad;
        if (init_x) x[vo + i] = std::clamp(sol.q[i], -lim, lim);
        if (init_z) {
          z_L[vo + i] = have ? sol.z_lower[i] : 0.0;
          z_U[vo + i] = have ? sol.z_upper[i] : 0.0;
        }
      }
      if (init_lambda)
        for (int c = 0; c < canvasCount(s); ++c)
          lambda[co + c] = have ? sol.lambda[canvas_[s][c] - 1] : 0.0;
      if (m == 0) continue;
      if (init_x) {
        SpineFk fk;
        spineForwardKinematics(*p.spine, p.handle, p.baseData(), x + vo, 0, &fk);
        FrictionJointTerm term;
        for (int i = 0; i < m; ++i) {
          frictionJointTerm(p, fk, terms_[s][i], 0, &term);
          x[vo + nv + i] = term.g + kEpigraphSlackMm;
        }
      }
      for (int i = 0; i < m; ++i) {
        // t > 0 at the optimum unless the joint stays put, where its bound's
        // multiplier is small; dL/dt = w + lambda - z = 0 gives lambda = -w.
        if (init_z) {
          const int j = terms_[s][i];
          const bool kept = have && sol.friction_z.size() == size_t(nc);
          z_L[vo + nv + i] = kept ? sol.friction_z[j - 1] : 0.0;
          z_U[vo + nv + i] = 0.0;
        }
        if (init_lambda) lambda[co + canvasCount(s) + i] = -p.friction_n[terms_[s][i] - 1];
      }
    }
    return true;
  }

  bool eval_f(Index, const Number* x, bool new_x, Number& obj) override {
    update(x, new_x);
    obj = energy_;
    return std::isfinite(energy_);
  }

  bool eval_grad_f(Index n, const Number* x, bool new_x, Number* g) override {
    update(x, new_x);
    std::copy(grad_.begin(), grad_.begin() + n, g);
    return allFinite(g, n);
  }

  bool eval_g(Index, const Number* x, bool new_x, Index m, Number* g) override {
    update(x, new_x);
    for (size_t s = 0; s < problems_.size(); ++s) {
      const int nq = fk_[s].vars(), nc = canvasCount(s);
      for (int c = 0; c < nc; ++c) g[con_offset_[s] + c] = fk_[s].x[canvas_[s][c]].z();
      for (int i = 0; i < termCount(s); ++i)
        g[con_offset_[s] + nc + i] = x[var_offset_[s] + nq + i] - friction_[s][i].g;
    }
    return allFinite(g, m);
  }

  bool eval_jac_g(Index, const Number* x, bool new_x, Index, Index nele_jac, Index* rows,
                  Index* cols, Number* values) override {
    Index k = 0;
    if (values == nullptr) {
      for (size_t s = 0; s < problems_.size(); ++s) {
        const int nq = problems_[s]->vars(), nc = canvasCount(s);
        const int vo = var_offset_[s], co = con_offset_[s];
        for (int c = 0; c < nc; ++c)
          for (int v = 0; v < 2 * canvas_[s][c]; ++v) {
            rows[k] = co + c;
            cols[k] = vo + v;
            ++k;
          }
        for (int i = 0; i < termCount(s); ++i) {
          // Joint j's friction depends on the 2j angles before it, and on t.
          for (int v = 0; v < 2 * terms_[s][i]; ++v) {
            rows[k] = co + nc + i;
            cols[k] = vo + v;
            ++k;
          }
          rows[k] = co + nc + i;
          cols[k] = vo + nq + i;
          ++k;
        }
      }
      return true;
    }
    update(x, new_x);
    for (size_t s = 0; s < problems_.size(); ++s) {
      for (int j : canvas_[s])
        for (int v = 0; v < 2 * j; ++v) values[k++] = fk_[s].d(j, v).z();
      for (const FrictionJointTerm& t : friction_[s]) {
        for (int v = 0; v < t.var_count; ++v) values[k++] = -t.grad[v];
        values[k++] = 1.0;
      }
    }
    return allFinite(values, nele_jac);
  }

  bool eval_h(Index, const Number* x, bool new_x, Number obj_factor, Index, const Number* lambda,
              bool, Index nele_hess, Index* rows, Index* cols, Number* values) override {
    Index k = 0;
    if (values == nullptr) {
      for (size_t s = 0; s < problems_.size(); ++s) {
        const int nv = problems_[s]->vars();
        for (int r = 0; r < nv; ++r)
          for (int c = 0; c <= r; ++c) {
            rows[k] = var_offset_[s] + r;
            cols[k] = var_offset_[s] + c;
            ++k;
          }
      }
      for (const CrossBlock& b : blocks_)
        for (int r = 0; r < problems_[b.hi]->vars(); ++r)
          for (int c = 0; c < problems_[b.lo]->vars(); ++c) {
            rows[k] = var_offset_[b.hi] + r;
            cols[k] = var_offset_[b.lo] + c;
            ++k;
          }
      return true;
    }
    update(x, new_x);
    for (size_t s = 0; s < problems_.size(); ++s) {
      const SpineFk& fk = fk_[s];
      const int nv = fk.vars();
      // The objective's Hessian, then each friction constraint's: the
      // Lagrangian has lambda (t - G), so G's Hessian enters with -lambda.
      lagrangian_.resize(static_cast<size_t>(nv) * nv);
      for (int i = 0; i < nv * nv; ++i) lagrangian_[i] = obj_factor * hess_[s][i];
      for (int i = 0; i < termCount(s); ++i) {
        const FrictionJointTerm& t = friction_[s][i];
        const double l = -lambda[con_offset_[s] + canvasCount(s) + i];
        for (int c = 0; c < t.var_count; ++c)
          for (int r = 0; r < t.var_count; ++r)
            lagrangian_[c * nv + r] += l * t.hess[c * t.var_count + r];
      }
      for (int r = 0; r < nv; ++r)
        for (int c = 0; c <= r; ++c) {
          double v = lagrangian_[c * nv + r];
          // Constraint j involves angles of joints < j only.
          for (int i = 0; i < canvasCount(s); ++i) {
            const int j = canvas_[s][i];
            if (j > std::max(r, c) / 2) v += lambda[con_offset_[s] + i] * fk.dd(j, r, c).z();
          }
          values[k++] = v;
        }
    }
    for (const CrossBlock& b : blocks_)
      for (double h : b.h) values[k++] = obj_factor * h;
    return allFinite(values, nele_hess);
  }

  // Rows of the largest block of the KKT matrix Ipopt factors: spines that
  // hair volume links solve as one block. A spine of n joints with m friction
  // variables and c canvas constraints has 2n + m variables and c + m
  // constraints, and each constraint brings a slack and a multiplier:
  // 2n + 2c + 3m rows.
  int largestCoupledRows() const {
    const int ns = static_cast<int>(problems_.size());
    std::vector<int> group(ns);
    for (int s = 0; s < ns; ++s) group[s] = s;
    auto root = [&](int s) {
      while (group[s] != s) s = group[s] = group[group[s]];
      return s;
    };
    for (const VolumeLink& l : links_) group[std::max(root(l.a), root(l.b))] = std::min(root(l.a), root(l.b));
    std::vector<int> rows(ns, 0);
    int largest = 0;
    for (int s = 0; s < ns; ++s) {
      const int n = problems_[s]->spine->jointCount(), m = termCount(s);
      largest = std::max(largest, rows[root(s)] += 2 * n + 2 * canvasCount(s) + 3 * m);
    }
    return largest;
  }
  int largest_coupled_rows_ = 0;

  // Shows each accepted iterate of the regular phase to the watch, if any,
  // and stops the solve when it says so. Ipopt 3.11 passes no iterate here
  // (get_curr_iterate is 3.14's), so it is read from Ipopt's data and put
  // back in this NLP's variable order by the adapter, as Ipopt does before
  // every evaluation.
  bool intermediate_callback(Ipopt::AlgorithmMode mode, Index, Number, Number, Number, Number,
                             Number, Number, Number, Number, Index,
                             const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override {
    if (!watch_ || mode != Ipopt::RegularMode || !ip_data || !ip_cq) return true;
    auto* orig = dynamic_cast<Ipopt::OrigIpoptNLP*>(Ipopt::GetRawPtr(ip_cq->GetIpoptNLP()));
    auto* adapter = orig ? dynamic_cast<Ipopt::TNLPAdapter*>(Ipopt::GetRawPtr(orig->nlp())) : nullptr;
    if (!adapter || !Ipopt::IsValid(ip_data->curr())) return true;
    watched_x_.resize(nvars_);
    adapter->ResortX(*ip_data->curr()->x(), watched_x_.data());
    watched_q_.resize(problems_.size());
    for (size_t s = 0; s < problems_.size(); ++s) watched_q_[s] = watched_x_.data() + var_offset_[s];
    stopped = watch_->stop(problems_, watched_q_);
    return !stopped;
  }
  SolveWatch* watch_ = nullptr;
  bool stopped = false;  // the watch stopped the solve

  void finalize_solution(Ipopt::SolverReturn, Index, const Number* x, const Number* z_L,
                         const Number* z_U, Index, const Number*, const Number* lambda, Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    finalized = true;
    for (size_t s = 0; s < problems_.size(); ++s) {
      SpineSolution& sol = result_.emplace_back();
      const int nv = problems_[s]->vars(), nc = nv / 2;
      const int vo = var_offset_[s], co = con_offset_[s];
      sol.q.assign(x + vo, x + vo + nv);
      sol.z_lower.assign(z_L + vo, z_L + vo + nv);
      sol.z_upper.assign(z_U + vo, z_U + vo + nv);
      // A joint without a canvas constraint cannot reach the paper: no force.
      sol.lambda.assign(nc, 0.0);
      for (int c = 0; c < canvasCount(s); ++c) sol.lambda[canvas_[s][c] - 1] = lambda[co + c];
      sol.normal_force_n.resize(nc);
      // Ipopt's Lagrangian is f + lambda^T g: an active g >= 0 has lambda <= 0,
      // and -lambda is the canvas's force on the joint in newtons (E in N mm, g in mm).
      for (int j = 0; j < nc; ++j) sol.normal_force_n[j] = std::max(0.0, -sol.lambda[j]);
      sol.friction_z.assign(nc, 0.0);
      for (int i = 0; i < termCount(s); ++i) sol.friction_z[terms_[s][i] - 1] = z_L[vo + nv + i];
    }
  }

  std::vector<SpineSolution> result_;

 private:
  int termCount(size_t s) const { return static_cast<int>(terms_[s].size()); }
  int canvasCount(size_t s) const { return static_cast<int>(canvas_[s].size()); }

  // The joints (1..n) that eq. 5's canvas constraint must hold: those that
  // some angles could put on the paper. Joint j is never nearer the root than
  // the segments before it are long, so a root higher above the paper than
  // that keeps the joint off it whatever the angles, and its constraint could
  // never be active. Leaving it out takes two rows out of the KKT matrix
  // (its slack and its multiplier) and only the far barrier term
  // -mu log(z_j) out of the problem.
  static std::vector<int> reachingJoints(const SpineProblem& p) {
    const SpineSpec& spine = *p.spine;
    const double root_z = p.handle.apply(spine.root_mm).z();
    std::vector<int> joints;
    double reach = 0;
    for (int j = 1; j <= spine.jointCount(); ++j) {
      reach += spine.segment_lengths_mm[j - 1];
      if (root_z - reach <= kCanvasClearanceMm) joints.push_back(j);
    }
    return joints;
  }

  void update(const Number* x, bool new_x) {
    if (!new_x && have_) return;
    have_ = true;
    energy_ = 0;
    const EnergyParts parts = epigraph_ ? EnergyParts::kWithoutFriction : EnergyParts::kAll;
    for (size_t s = 0; s < problems_.size(); ++s) {
      const SpineProblem& p = *problems_[s];
      const int nv = p.vars(), vo = var_offset_[s];
      hess_[s].resize(nv * nv);
      energy_ +=
          spineEnergy(p, x + vo, &fk_[s], nullptr, grad_.data() + vo, hess_[s].data(), parts);
      for (int i = 0; i < termCount(s); ++i) {
        frictionJointTerm(p, fk_[s], terms_[s][i], 2, &friction_[s][i]);
        energy_ += friction_[s][i].weight * x[vo + nv + i];
        grad_[vo + nv + i] = friction_[s][i].weight;
      }
    }
    for (CrossBlock& b : blocks_)
      b.h.assign(static_cast<size_t>(problems_[b.hi]->vars()) * problems_[b.lo]->vars(), 0.0);
    for (size_t i = 0; i < links_.size(); ++i) addLink(links_[i], &blocks_[link_block_[i]]);
  }

  // Hair volume between joint j of spines a and b, both free (volumeLinkEnergy):
  // the diagonal blocks go to each spine's Hessian, the cross terms to the
  // pair's block, whose rows belong to the later spine.
  void addLink(const VolumeLink& l, CrossBlock* block) {
    const int nva = problems_[l.a]->vars(), nvb = problems_[l.b]->vars();
    cross_.assign(static_cast<size_t>(nva) * nvb, 0.0);
    int parts = 0;
    energy_ += volumeLinkEnergy(l, fk_[l.a], fk_[l.b], grad_.data() + var_offset_[l.a],
                                grad_.data() + var_offset_[l.b], hess_[l.a].data(),
                                hess_[l.b].data(), cross_.data(), &parts);
    // A pair between its limits adds nothing: its cross block would add zeros
    // to a block that starts at +0 and so never holds -0, which changes no bit.
    if (parts == 0) return;
    for (int w = 0; w < nva; ++w)    // variable of a
      for (int v = 0; v < nvb; ++v) {  // variable of b
        const double h = cross_[static_cast<size_t>(w) * nvb + v];
        if (l.a > l.b)
          block->h[static_cast<size_t>(w) * nvb + v] += h;
        else
          block->h[static_cast<size_t>(v) * nva + w] += h;
      }
  }

  std::span<const SpineProblem* const> problems_;
  std::span<SpineSolution* const> sols_;
  std::span<const VolumeLink> links_;
  bool warm_;
  bool epigraph_;
  std::vector<std::vector<int>> terms_;  // per spine, the joints (1..n) whose friction has a t
  std::vector<std::vector<int>> canvas_;  // per spine, the joints (1..n) with a canvas constraint
  std::vector<CrossBlock> blocks_;
  std::vector<int> link_block_;  // per link, its block
  std::vector<double> cross_;    // one link's cross terms (workspace)
  std::vector<int> var_offset_, con_offset_;  // per spine: angles, then t; canvas, then t - G
  int nvars_ = 0, ncons_ = 0, nnz_jac_ = 0, nnz_hess_ = 0;
  std::vector<SpineFk> fk_;
  std::vector<double> grad_;
  std::vector<std::vector<double>> hess_;
  std::vector<std::vector<FrictionJointTerm>> friction_;  // per spine, per term: G and derivatives
  std::vector<double> lagrangian_;           // one spine's Hessian block (workspace)
  double energy_ = 0;
  bool have_ = false;
  std::vector<double> watched_x_;         // the iterate shown to the watch
  std::vector<const double*> watched_q_;  // per spine, its angles in watched_x_
};

const char* ipoptStatusName(Ipopt::ApplicationReturnStatus s) {
  switch (s) {
    case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates: return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop: return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found: return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed: return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom: return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition: return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option: return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected: return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception: return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown: return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory: return "Insufficient_Memory";
    default: return "Internal_Error";
  }
}

// The barrier parameter a warm start begins from. With tol 1e-8 Ipopt ends at
// mu ~1e-9 anyway, so a warm start begins at its final barrier and only
// Newton's steps remain. From 1e-6 the round, badger and calligraphy brushes'
// S-curves took 18-28% more iterations; from 1e-11 the round took 27% more
// (too small a mu for the steps in which the contact set changes;
// docs/PERFORMANCE.md, "Ipopt's warm starts and its timers").
constexpr double kWarmMuInit = 1e-9;

// How far a warm start's iterate and multipliers are pushed into the interior:
// the first try (the previous step's solution is nearly optimal), and the
// re-centred retry of a failed one. On the round, calligraphy and badger on a
// tablet recording (docs/PERFORMANCE.md, "Ipopt's warm starts and its
// timers"), 1e-3 and 1e-5 took the same iterations within 1%, 1e-2 2% more;
// the retry's adaptive barrier picks its own mu whatever mu_init says.
constexpr double kWarmPush = 1e-9;
constexpr double kRetryWarmPush = 1e-3;

// The largest KKT block bristle's solver takes; an NLP with a larger one goes
// to MUMPS. Ipopt's MA27 interface sizes the real work array from the
// solver's advice, s^2 reals per block, times its own margin of 5: 40 MB at
// 1,000 rows (about 35 spines of 4 joints linked by hair volume; the
// library's largest, the badger, makes about 420).
constexpr int kOwnKktMaxRows = 1000;

// Ipopt's own default for max_resto_iter, restored for cold starts.
constexpr int kIpoptDefaultMaxRestoIter = 3000000;

class IpoptSolver : public SpineSolver {
 public:
  // No console journal: Ipopt prints nothing, whatever its print_level says,
  // so standard output stays the PNG's (-o -) and messages stay bristle's.
  explicit IpoptSolver(const IpoptSettings& settings)
      : app_(new Ipopt::IpoptApplication(/*create_console_out=*/false)) {
    Ipopt::OptionsList& o = *app_->Options();
    o.SetStringValue("sb", "yes");  // no banner
    o.SetIntegerValue("print_level", 0);
    o.SetStringValue("hessian_approximation", "exact");
    o.SetStringValue("mu_strategy", "adaptive");
    // ~8% fewer instructions (docs/design.md, "Solver notes").
    o.SetIntegerValue("mumps_scaling", 0);
    o.SetNumericValue("tol", settings.tol);
    o.SetNumericValue("acceptable_tol", settings.acceptable_tol);
    o.SetIntegerValue("max_iter", settings.max_iterations);
    o.SetIntegerValue("min_refinement_steps", 0);
    o.SetIntegerValue("max_soc", 0);
    // Small warm-start pushes: the previous step's solution is nearly optimal.
    setWarmStartPush(o, kWarmPush);
    bool timers_needed = false;
    // Each extra option meets bristle's allow-list first (engine/solvers/ipopt/ipopt_options.h),
    // wherever it came from: the brush's hint, the command line, a manifest.
    for (const auto& [name, value] : settings.extra_options) {
      if (const std::optional<std::string> problem = ipoptOptionProblem(name, value))
        throw Error(ExitCode::kUsage, "Ipopt option " + name + "=" + value + ": " + *problem);
      applyOption(o, name, value, &timers_needed);
    }
    timers_off_ = timers_off_ && !timers_needed;
    // Only if the program installed it (process/process_hooks.h); MUMPS otherwise.
    dense_kkt_ = dense_kkt_ && denseKktSolverInstalled();
    if (dense_kkt_) {
      // MA27's default scaling is HSL's MC19, which Debian does not have; the
      // MUMPS solves took none either (Ipopt's default for it).
      if (!o.SetStringValue("linear_system_scaling", "none")) bad_option_ = "linear_system_scaling";
    }
    if (!bad_option_.empty())
      throw Error(ExitCode::kUsage, "Ipopt option " + bad_option_ + ": Ipopt refuses it");
    // From an empty stream, never from a file: Initialize() would read
    // option_file_name, ./ipopt.opt by default, in whatever folder bristle runs.
    std::istringstream no_option_file;
    initialized_ = app_->Initialize(no_option_file) == Ipopt::Solve_Succeeded;
  }

  const char* name() const override { return "ipopt"; }

  bool couplesSpines(int) const override { return true; }
  bool wantsPredictedStart() const override { return true; }

  // Solvers never throw (engine/solvers/spine_solver.h): what throws in a solve (an
  // allocation of the NLP, its results or a message) fails that step alone.
  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions,
                     std::span<const VolumeLink> links) override {
    try {
      return solveOnce(problems, solutions, links);
    } catch (...) {
      SolveSummary failed;  // its message fits the string's own buffer: no allocation
      failed.status = SolveStatus::kFailed;
      failed.message = "exception";
      return failed;
    }
  }

 private:
  SolveSummary solveOnce(std::span<const SpineProblem* const> problems,
                         std::span<SpineSolution* const> solutions,
                         std::span<const VolumeLink> links) {
    SolveSummary summary;
    if (!initialized_) {
      summary.status = SolveStatus::kFailed;
      summary.message = "Ipopt initialisation failed";
      return summary;
    }
    bool warm = true;
    for (SpineSolution* s : solutions)
      warm = warm && s->lambda.size() == s->q.size() / 2;
    Ipopt::OptionsList& o = *app_->Options();
    o.SetStringValue("warm_start_init_point", warm ? "yes" : "no");
    // Warm starts begin next to the optimum: a monotone barrier from a tiny mu
    // finishes them with about a fifth less work than the adaptive update, in
    // the same iterations (docs/PERFORMANCE.md, "Ipopt's warm starts and its
    // timers").
    // Cold starts keep the adaptive strategy, which is the robust one there.
    if (!user_mu_strategy_) {
      o.SetStringValue("mu_strategy", warm ? "monotone" : "adaptive");
      o.SetNumericValue("mu_init", warm ? kWarmMuInit : 0.1);
    }
    bool volume = !links.empty();
    for (const SpineProblem* p : problems)
      volume = volume || !p->volume.empty() || p->volume_stiffness_n_per_mm > 0 ||
               p->cohesion_n_per_mm > 0;
    // Cold starts keep friction in the objective: from cold starts the
    // epigraph form sent solves into Ipopt's restoration phase.
    const bool epigraph =
        warm && (friction_form_ == FrictionForm::kEpigraph ||
                 (friction_form_ == FrictionForm::kAuto && volume));
    Ipopt::SmartPtr<BrushNlp> nlp = new BrushNlp(problems, solutions, links, warm, epigraph);
    nlp->watch_ = watch_;
    // bristle's own KKT solver, in MA27's place (engine/solvers/ipopt/dense_kkt.h): each
    // spine's block densely, the blocks that hair volume couples sparsely.
    if (dense_kkt_)
      o.SetStringValue("linear_solver",
                       nlp->largest_coupled_rows_ <= kOwnKktMaxRows ? "ma27" : "mumps");
    // A warm start that falls into Ipopt's restoration phase has lost its
    // footing: on the round brush's tablet strokes none came back from it in
    // 200 iterations. It stops there, and is solved again re-centred below.
    const bool retry = warm && warm_retry_;
    o.SetIntegerValue("max_resto_iter", retry ? 0 : kIpoptDefaultMaxRestoIter);
    Ipopt::ApplicationReturnStatus st = optimize(nlp, &summary.iterations);
    if (nlp->stopped) return stoppedSummary(summary);  // the caller drops the step
    if (retry && !solvedOk(st)) {
      // The same warm start once more, pushed 1e-3 into the interior with the
      // adaptive barrier, which can raise mu to re-centre the iterate: where
      // the step's solution lies far from the last one (a tip breaking free,
      // a bundle buckling), the warm start's mu = 1e-9 pins the iterate to
      // the bounds it holds. Cheaper than the caller's spine-by-spine cold
      // redo, and it keeps the spines coupled (docs/dynamics.md, "A warm
      // start that fails").
      if (!user_mu_strategy_) o.SetStringValue("mu_strategy", "adaptive");
      o.SetIntegerValue("max_resto_iter", kIpoptDefaultMaxRestoIter);
      if (!user_warm_push_) setWarmStartPush(o, kRetryWarmPush);
      nlp = new BrushNlp(problems, solutions, links, warm, epigraph);
      nlp->watch_ = watch_;
      int more = 0;
      st = optimize(nlp, &more);
      if (!user_warm_push_) setWarmStartPush(o, kWarmPush);
      summary.iterations += more;
      summary.recentred = 1;
      summary.recentred_iterations = more;
      if (nlp->stopped) return stoppedSummary(summary);
    }
    summary.message = ipoptStatusName(st);
    const bool ok = solvedOk(st);
    if (!ok || !nlp->finalized || nlp->result_.size() != solutions.size()) {
      summary.status = SolveStatus::kFailed;
      return summary;
    }
    summary.status = st == Ipopt::Solve_Succeeded ? SolveStatus::kOk : SolveStatus::kAcceptable;
    for (size_t s = 0; s < solutions.size(); ++s) *solutions[s] = std::move(nlp->result_[s]);
    return summary;
  }

  // Sets one option that ipoptOptionProblem allowed: bristle's own are taken
  // here, every other goes to Ipopt by its registered type (setting a wrong
  // type makes Ipopt complain on its journal).
  void applyOption(Ipopt::OptionsList& o, const std::string& name, const std::string& value,
                   bool* timers_needed) {
    // Ipopt 3.14's switch for its timers, which 3.11 does not know: bristle
    // takes it here (engine/solvers/ipopt/ipopt_timers.h).
    if (name == "timing_statistics") {
      timers_off_ = value == "no";
      return;
    }
    // Friction as objective terms or in epigraph form (BrushNlp above).
    if (name == "friction_form") {
      friction_form_ = parseFrictionForm(value).value_or(FrictionForm::kAuto);
      return;
    }
    // A failed warm start solved once more from a re-centred start before
    // the caller gives up on it (IpoptSolver::solve).
    if (name == "warm_retry") {
      warm_retry_ = value == "yes";
      return;
    }
    // bristle's own linear solver (the default), in MA27's place: each block
    // of the KKT matrix densely (Bunch-Kaufman) where it is small, as a sparse
    // LDL^T where hair volume makes it large (engine/solvers/ipopt/dense_kkt.h). mumps is
    // Ipopt's, for every solve.
    if (name == "linear_solver") {
      dense_kkt_ = value == "dense";
      if (dense_kkt_) return;
    }
    // A CPU-time limit needs the timers, whatever the order.
    if (name == "max_cpu_time") *timers_needed = true;
    if (name == "mu_strategy" || name == "mu_init") user_mu_strategy_ = true;
    if (name.rfind("warm_start_", 0) == 0) user_warm_push_ = true;
    Ipopt::SmartPtr<const Ipopt::RegisteredOption> opt = app_->RegOptions()->GetOption(name);
    bool ok = Ipopt::IsValid(opt);
    if (ok && opt->Type() == Ipopt::OT_Integer)
      ok = o.SetIntegerValue(name, static_cast<int>(std::strtol(value.c_str(), nullptr, 10)));
    else if (ok && opt->Type() == Ipopt::OT_Number)
      ok = o.SetNumericValue(name, std::strtod(value.c_str(), nullptr));
    else if (ok)
      ok = o.SetStringValue(name, value);
    if (!ok && bad_option_.empty()) bad_option_ = name + "=" + value;
  }

  // A solve the watch stopped: nothing to rescue, the caller drops the step.
  static SolveSummary stoppedSummary(SolveSummary summary) {
    summary.status = SolveStatus::kFailed;
    summary.stopped = true;
    summary.message = "stopped by the watch";
    return summary;
  }

  static bool solvedOk(Ipopt::ApplicationReturnStatus st) {
    return st == Ipopt::Solve_Succeeded || st == Ipopt::Solved_To_Acceptable_Level;
  }

  static void setWarmStartPush(Ipopt::OptionsList& o, double push) {
    for (const char* opt : {"warm_start_bound_push", "warm_start_bound_frac",
                            "warm_start_slack_bound_frac", "warm_start_slack_bound_push",
                            "warm_start_mult_bound_push"})
      o.SetNumericValue(opt, push);
  }

  // One OptimizeTNLP call; *iterations gets Ipopt's count.
  Ipopt::ApplicationReturnStatus optimize(const Ipopt::SmartPtr<BrushNlp>& nlp, int* iterations) {
    Ipopt::ApplicationReturnStatus st = Ipopt::Internal_Error;
    try {
      const IpoptTimersOff timers_off(timers_off_);
      st = app_->OptimizeTNLP(Ipopt::GetRawPtr(nlp));
    } catch (...) {
      st = Ipopt::NonIpopt_Exception_Thrown;
    }
    if (Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app_->Statistics(); Ipopt::IsValid(stats))
      *iterations = stats->IterationCount();
    return st;
  }

  Ipopt::SmartPtr<Ipopt::IpoptApplication> app_;
  bool initialized_ = false;
  std::string bad_option_;  // the first extra option Ipopt refused
  bool user_mu_strategy_ = false;  // the user chose the barrier strategy
  bool user_warm_push_ = false;    // the user set a warm_start_*_push or _frac
  // A failed warm start solved once more from a re-centred start
  // (--ipopt-option warm_retry=yes, the default).
  bool warm_retry_ = true;
  bool timers_off_ = true;  // Ipopt's getrusage timers (engine/solvers/ipopt/ipopt_timers.h)
  // Friction in epigraph form on warm starts (BrushNlp). auto, the default,
  // takes it where hair volume couples the NLP: with the push held for a step
  // it takes the volume brushes 0.65-0.91 of the objective form's iterations
  // on a tablet recording, and is even on the S-curve. Without hair volume the
  // objective form stays: the epigraph form takes the flat a quarter more
  // iterations on the tablet, and only the fan would gain (docs/dynamics.md,
  // "Friction in epigraph form").
  FrictionForm friction_form_ = FrictionForm::kAuto;
  // bristle's KKT solver for every solve whose blocks are within
  // kOwnKktMaxRows (--ipopt-option linear_solver=dense, the default; any
  // other value is Ipopt's own choice for every solve).
  bool dense_kkt_ = true;
};

}  // namespace

const char* toString(SolveStatus s) {
  switch (s) {
    case SolveStatus::kOk: return "ok";
    case SolveStatus::kAcceptable: return "acceptable";
    case SolveStatus::kFree: return "free";
    case SolveStatus::kSettled: return "settled";
    case SolveStatus::kFailed: return "failed";
  }
  return "unknown";
}

std::unique_ptr<SpineSolver> makeIpoptSolver(const IpoptSettings& settings) {
  return std::make_unique<IpoptSolver>(settings);
}

}  // namespace bristle

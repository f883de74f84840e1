#pragma once
// The spine solvers a run uses, chosen once: a primary backend and the other one
// as its fallback (docs/design.md, "Solver notes"). A solver's name is text only
// where it comes in (the command line, a scene's or sheet's "solver", a live
// session's options) and is parsed there into a SolverKind; everything after
// that builds its solvers through makeSolverPair.

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "engine/model/brush.h"
#include "engine/solvers/spine_solver.h"

namespace bristle {

enum class SolverKind { kIpopt, kSlsqp };

// "ipopt" or "slsqp"; nothing for any other text.
std::optional<SolverKind> parseSolverKind(std::string_view name);
// The name parseSolverKind reads ("ipopt", "slsqp").
const char* solverKindName(SolverKind kind);

// The iteration limit per solve unless a run says otherwise (--solver-max-iterations).
inline constexpr int kDefaultSolverMaxIterations = 200;

struct SolverSettings {
  SolverKind kind = SolverKind::kIpopt;  // the primary; the other one is its fallback
  // Limits both backends per solve: Ipopt's iterations, SLSQP's energy evaluations.
  int max_iterations = kDefaultSolverMaxIterations;
  // Further Ipopt options (IpoptSettings::extra_options), whichever is primary.
  std::vector<std::pair<std::string, std::string>> ipopt_options;
  // SlsqpSettings::max_block_spines: the largest brush whose coupled spines
  // SLSQP solves as one block. 0 sweeps one spine at a time, for a run that
  // must keep a real-time rate rather than converge the hair volume
  // (haptics/live_session.cpp).
  int slsqp_max_block_spines = SlsqpSettings{}.max_block_spines;
};

struct SolverPair {
  std::unique_ptr<SpineSolver> primary, fallback;
};

// The chosen backend as primary and the other as fallback, both limited to
// settings.max_iterations. Throws bristle::Error(kUsage) when the allow-list
// refuses an extra option or the limit is out of range (as makeIpoptSolver, makeSlsqpSolver).
SolverPair makeSolverPair(const SolverSettings& settings = {});
// The same for one brush: its solver hints (Brush::solver) go before the run's
// own Ipopt options, so that a run that names an option itself overrides the
// brush's (docs/brush-format.md, "solver").
SolverPair makeSolverPair(const SolverSettings& settings, const Brush& brush);

}  // namespace bristle

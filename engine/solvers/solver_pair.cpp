#include "engine/solvers/solver_pair.h"

namespace bristle {

std::optional<SolverKind> parseSolverKind(std::string_view name) {
  if (name == "ipopt") return SolverKind::kIpopt;
  if (name == "slsqp") return SolverKind::kSlsqp;
  return std::nullopt;
}

const char* solverKindName(SolverKind kind) {
  return kind == SolverKind::kSlsqp ? "slsqp" : "ipopt";
}

SolverPair makeSolverPair(const SolverSettings& settings) {
  IpoptSettings ipopt;
  ipopt.max_iterations = settings.max_iterations;
  ipopt.extra_options = settings.ipopt_options;
  SlsqpSettings slsqp;
  slsqp.max_evaluations = settings.max_iterations;
  slsqp.max_block_spines = settings.slsqp_max_block_spines;
  SolverPair pair{makeIpoptSolver(ipopt), makeSlsqpSolver(slsqp)};
  if (settings.kind == SolverKind::kSlsqp) std::swap(pair.primary, pair.fallback);
  return pair;
}

SolverPair makeSolverPair(const SolverSettings& settings, const Brush& brush) {
  if (brush.solver.friction_form.empty()) return makeSolverPair(settings);
  SolverSettings with_hints = settings;
  with_hints.ipopt_options.clear();
  with_hints.ipopt_options.emplace_back("friction_form", brush.solver.friction_form);
  for (const auto& option : settings.ipopt_options) with_hints.ipopt_options.push_back(option);
  return makeSolverPair(with_hints);
}

}  // namespace bristle

#include "engine/solvers/ipopt/ipopt_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <vector>

#include "engine/base/spelling.h"

namespace bristle {
namespace {

using T = IpoptOptionType;

// Each range lies within what Ipopt 3.11 registers for the option (its
// reference, "Ipopt Options"), narrowed to values a brush's solve can use:
// tolerances no finer than 1e-12 (the energy's round-off in N mm is near
// 1e-13, docs/design.md "Solver notes"), iterations no more than
// --solver-max-iterations allows, pushes no larger than their fractions allow.
// Choices are those this build has: MUMPS and bristle's dense solver
// (engine/solvers/ipopt/dense_kkt.h) but no HSL, so no ma27/ma57 by name and no
// equilibration-based scaling (MC19). The quasi-Newton Hessian
// (hessian_approximation=limited-memory) is left out: no solve of the round
// brush's S-curve converged with it in 200 iterations, so every step would go
// through the whole rescue, a render hundreds of times longer.
constexpr IpoptOptionRule kRules[] = {
    {"acceptable_compl_inf_tol", T::kNumber, 1e-12, 1e3, nullptr,
     "complementarity a solve may end at as acceptable"},
    {"acceptable_constr_viol_tol", T::kNumber, 1e-12, 1e3, nullptr,
     "constraint violation a solve may end at as acceptable"},
    {"acceptable_dual_inf_tol", T::kNumber, 1e-12, 1e10, nullptr,
     "dual infeasibility a solve may end at as acceptable"},
    {"acceptable_iter", T::kInteger, 0, 1000, nullptr,
     "acceptable iterations in a row that end a solve (0: never)"},
    {"acceptable_obj_change_tol", T::kNumber, 0, 1e20, nullptr,
     "relative energy change a solve may end at as acceptable"},
    {"acceptable_tol", T::kNumber, 1e-12, 1e6, nullptr,
     "the acceptable level's overall tolerance (default 1e-5)"},
    {"bound_frac", T::kNumber, 1e-12, 0.5, nullptr,
     "cold start: how far inside its bounds, as a fraction of their gap"},
    {"bound_push", T::kNumber, 1e-12, 1, nullptr, "cold start: how far inside its bounds"},
    {"bound_relax_factor", T::kNumber, 0, 1e-2, nullptr, "how much the bounds are relaxed"},
    {"compl_inf_tol", T::kNumber, 1e-12, 1e3, nullptr, "complementarity at convergence"},
    {"constr_viol_tol", T::kNumber, 1e-12, 1e3, nullptr, "constraint violation at convergence"},
    {"dual_inf_tol", T::kNumber, 1e-12, 1e10, nullptr, "dual infeasibility at convergence"},
    {"friction_form", T::kChoice, 0, 0, "auto|objective|epigraph",
     "bristle's: friction as objective terms or in epigraph form (docs/dynamics.md)"},
    {"linear_solver", T::kChoice, 0, 0, "dense|mumps",
     "KKT solver: bristle's dense one (default) or MUMPS for every solve"},
    {"max_cpu_time", T::kNumber, 1e-3, 1e6, nullptr, "CPU seconds per solve"},
    {"max_iter", T::kInteger, 1, 100000, nullptr,
     "iterations per solve (as --solver-max-iterations)"},
    {"max_refinement_steps", T::kInteger, 0, 100, nullptr,
     "iterative refinement steps per linear solve, at most"},
    {"max_soc", T::kInteger, 0, 20, nullptr, "second-order corrections per step (default 0)"},
    {"min_refinement_steps", T::kInteger, 0, 100, nullptr,
     "iterative refinement steps per linear solve, at least (default 0)"},
    {"mu_init", T::kNumber, 1e-12, 1, nullptr,
     "the barrier parameter a solve starts from (turns off bristle's choice)"},
    {"mu_oracle", T::kChoice, 0, 0, "probing|loqo|quality-function",
     "how the adaptive barrier picks mu"},
    {"mu_strategy", T::kChoice, 0, 0, "monotone|adaptive",
     "the barrier's update (turns off bristle's choice)"},
    {"mumps_pivtol", T::kNumber, 0, 1, nullptr, "MUMPS's pivot tolerance"},
    {"nlp_scaling_max_gradient", T::kNumber, 1e-3, 1e6, nullptr,
     "gradient-based scaling: the largest gradient"},
    {"nlp_scaling_method", T::kChoice, 0, 0, "gradient-based|none",
     "the NLP's scaling"},
    {"slack_bound_frac", T::kNumber, 1e-12, 0.5, nullptr,
     "cold start: slacks inside their bounds, as a fraction"},
    {"slack_bound_push", T::kNumber, 1e-12, 1, nullptr,
     "cold start: how far slacks start inside their bounds"},
    {"timing_statistics", T::kChoice, 0, 0, "no|yes",
     "bristle's: Ipopt's own timers on (yes) or off (no, the default)"},
    {"tol", T::kNumber, 1e-12, 1e-1, nullptr, "overall tolerance at convergence (default 1e-8)"},
    {"warm_retry", T::kChoice, 0, 0, "yes|no",
     "bristle's: a failed warm start solved again re-centred (default yes)"},
    {"warm_start_bound_frac", T::kNumber, 1e-12, 0.5, nullptr,
     "warm start: how far inside its bounds, as a fraction"},
    {"warm_start_bound_push", T::kNumber, 1e-12, 1, nullptr, "warm start: how far inside its bounds"},
    {"warm_start_mult_bound_push", T::kNumber, 1e-12, 1, nullptr,
     "warm start: how far multipliers start inside their bounds"},
    {"warm_start_slack_bound_frac", T::kNumber, 1e-12, 0.5, nullptr,
     "warm start: slacks inside their bounds, as a fraction"},
    {"warm_start_slack_bound_push", T::kNumber, 1e-12, 1, nullptr,
     "warm start: how far slacks start inside their bounds"},
};

const IpoptOptionRule* findRule(std::string_view name) {
  for (const IpoptOptionRule& r : kRules)
    if (name == r.name) return &r;
  return nullptr;
}

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::vector<std::string> choicesOf(const IpoptOptionRule& r) {
  std::vector<std::string> out;
  std::string_view rest = r.choices;
  while (true) {
    const size_t bar = rest.find('|');
    out.emplace_back(rest.substr(0, bar));
    if (bar == std::string_view::npos) return out;
    rest.remove_prefix(bar + 1);
  }
}

std::string ruleText(const IpoptOptionRule& r) {
  const std::string range = "in [" + number(r.min) + ", " + number(r.max) + "]";
  switch (r.type) {
    case T::kInteger: return "an integer " + range;
    case T::kNumber: return "a finite number " + range;
    case T::kChoice: break;
  }
  std::string list;
  for (const std::string& c : choicesOf(r)) list += (list.empty() ? "" : ", ") + c;
  return "one of " + list;
}

// The whole text as a value of the rule's type, within its range.
bool allowed(const IpoptOptionRule& r, std::string_view value) {
  const char* begin = value.data();
  const char* end = begin + value.size();
  if (r.type == T::kInteger) {
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, v);
    return ec == std::errc() && ptr == end && v >= r.min && v <= r.max;
  }
  if (r.type == T::kNumber) {
    double v = 0;
    const auto [ptr, ec] = std::from_chars(begin, end, v);
    return ec == std::errc() && ptr == end && std::isfinite(v) && v >= r.min && v <= r.max;
  }
  for (const std::string& c : choicesOf(r))
    if (value == c) return true;
  return false;
}

}  // namespace

std::span<const IpoptOptionRule> ipoptOptionRules() { return kRules; }

std::optional<std::string> ipoptOptionProblem(std::string_view name, std::string_view value) {
  const IpoptOptionRule* rule = findRule(name);
  if (rule == nullptr) {
    std::vector<std::string> names;
    for (const IpoptOptionRule& r : kRules) names.emplace_back(r.name);
    std::string text = std::string(name) +
                       " is not an Ipopt option bristle allows (bristle help ipopt-option lists them)";
    if (const std::optional<std::string> near = closestSpelling(name, names))
      text += "; did you mean " + *near + "?";
    return text;
  }
  if (allowed(*rule, value)) return std::nullopt;
  return std::string(name) + " must be " + ruleText(*rule);
}

std::optional<std::pair<std::string, std::string>> splitIpoptOption(std::string_view text) {
  const size_t eq = text.find('=');
  if (eq == std::string_view::npos || eq == 0) return std::nullopt;
  return std::make_pair(std::string(text.substr(0, eq)), std::string(text.substr(eq + 1)));
}

std::optional<std::string> ipoptOptionTextProblem(std::string_view text) {
  const auto kv = splitIpoptOption(text);
  if (!kv) return std::string(text) + ": expected NAME=VALUE";
  if (auto problem = ipoptOptionProblem(kv->first, kv->second))
    return std::string(text) + ": " + *problem;
  return std::nullopt;
}

std::string ipoptOptionsHelp() {
  std::string out;
  for (const IpoptOptionRule& r : kRules) {
    std::string line = std::string("  ") + r.name;
    line.resize(std::max<size_t>(line.size() + 1, 31), ' ');
    out += line + ruleText(r) + ": " + r.purpose + "\n";
  }
  return out;
}

}  // namespace bristle

#pragma once
// The Ipopt options a run may set (--ipopt-option NAME=VALUE, a batch job's
// "ipopt-option", a session header's "# --ipopt-option:" lines), and the one
// check each value meets before it reaches Ipopt, wherever it comes from.
//
// Only options that change the solve are allowed: tolerances, limits, the
// barrier, the initial point's pushes, the Hessian, scaling and the linear
// solver, plus bristle's own (friction_form, warm_retry, timing_statistics).
// No option that names a file (output_file, option_file_name), prints
// (print_level, print_*), or can stall a solve is allowed, so a run writes
// nothing but its outputs and its stdout stays its own (docs/errors.md,
// "Ipopt options"). Every number must be finite and within the inclusive
// range of its rule; every integer is read whole, without wrapping.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace bristle {

enum class IpoptOptionType { kInteger, kNumber, kChoice };

struct IpoptOptionRule {
  const char* name;
  IpoptOptionType type;
  double min, max;      // kInteger, kNumber: the inclusive range
  const char* choices;  // kChoice: the allowed values, separated by '|'
  const char* purpose;  // one line, for --help and docs/dynamics.md
};

// The allowed options, sorted by name.
std::span<const IpoptOptionRule> ipoptOptionRules();

// The rule `name`=`value` breaks, as a message's tail ("tol must be a finite
// number in [1e-12, 0.1]", "output_file is not an Ipopt option bristle
// passes on (...); did you mean ...?"); nothing when it is allowed.
std::optional<std::string> ipoptOptionProblem(std::string_view name, std::string_view value);

// "NAME=VALUE" split at its first '='; nothing when there is no '=' or no name.
std::optional<std::pair<std::string, std::string>> splitIpoptOption(std::string_view text);

// The rule of one NAME=VALUE text, "NAME=VALUE" included ("tol=nan: tol must
// be ..."; "x: expected NAME=VALUE"); nothing when it is allowed.
std::optional<std::string> ipoptOptionTextProblem(std::string_view text);

// The allowed options as lines "  NAME  RULE: PURPOSE" (bristle help ipopt-option).
std::string ipoptOptionsHelp();

}  // namespace bristle

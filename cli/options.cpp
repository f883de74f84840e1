#include "cli/options.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace bristle::cli {

namespace {

// The whole text as an unsigned 64-bit integer: CLI11 reads "-1" as 2^64 - 1
// and a number past 2^64 as 2^64 - 1, each silently another seed.
CLI::Validator unsignedInteger() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::uint64_t v = 0;
        const char* end = text.data() + text.size();
        const auto [ptr, ec] = std::from_chars(text.data(), end, v);
        if (ec == std::errc() && ptr == end) return "";
        return "'" + text + "' must be a whole number in [0, 18446744073709551615]";
      },
      "");
}

}  // namespace

void addPaintOptions(CLI::App* app, PaintOptions& p) {
  app->add_option("--paint,--colour,--color", p.paint,
                  "Paint(s) on the brush: NAME[,NAME..], pigment names or #rrggbb")
      ->capture_default_str();
  app->add_option("--load", p.load,
                  "Loading: solid (one paint), across (2-3 paints side by side across the "
                  "brush's width), tip (body paint, tip paint)")
      ->capture_default_str()
      ->check(CLI::IsMember({"solid", "across", "tip"}));
  app->add_option("--amount", p.amount, "Paint on the brush, a fraction of its capacity (0, 1]")
      ->capture_default_str();
  app->add_option("--tip-length", p.tip_length,
                  "--load tip: share of the hair length the tip paint covers")
      ->capture_default_str();
  app->add_option("--mix", p.mix, "Pigment mixing: km (Kubelka-Munk) or rgb (linear RGB)")
      ->capture_default_str()
      ->check(CLI::IsMember({"km", "rgb"}));
  app->add_option("--paper-tooth", p.paper_tooth_mm,
                  "Depth of the paper's grain (mm); light strokes catch only its peaks")
      ->capture_default_str();
  app->add_option("--paper-scale", p.paper_scale_mm, "Feature size of the paper's grain (mm)")
      ->capture_default_str();
  app->add_option("--paper-seed", p.paper_seed, "Seed of the paper's grain")
      ->capture_default_str()
      ->check(unsignedInteger());
  app->add_flag("--impasto", p.impasto, "Light the paint's thickness from the upper left");
  app->add_option("--bits", p.bits, "Bits per PNG channel")
      ->capture_default_str()
      ->check(CLI::IsMember({8, 16}));
  app->add_option("--background", p.background, "Paper colour (#rrggbb)")
      ->capture_default_str();
}

CLI::Option* addSolverOption(CLI::App* app, const std::string& name,
                             std::function<void(SolverKind)> set, const std::string& help,
                             const std::string& shown) {
  CLI::Option* o = app->add_option_function<std::string>(
      name, [set](const std::string& text) { set(*parseSolverKind(text)); }, help);
  if (!shown.empty()) o->default_str(shown);
  return o->check(CLI::IsMember({"ipopt", "slsqp"}));
}

CLI::Option* addSolver(CLI::App* app, SolverKind& kind, const std::string& help) {
  return addSolverOption(
      app, "--solver", [&kind](SolverKind k) { kind = k; }, help, solverKindName(kind));
}

void addSolverMaxIterations(CLI::App* app, int& max_iterations) {
  app->add_option("--solver-max-iterations", max_iterations,
                  "Iteration limit per solve (Ipopt iterations, SLSQP energy evaluations); a "
                  "spine that hits it with both solvers keeps its last state")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
}

void addIpoptOption(CLI::App* app, std::vector<std::string>& options) {
  app->add_option("--ipopt-option", options,
                  "Ipopt option NAME=VALUE (repeatable), e.g. tol=1e-7; only those "
                  "that change the solve, each range-checked (bristle help ipopt-option lists "
                  "them); bristle's own: friction_form, warm_retry, timing_statistics, "
                  "linear_solver=dense (the default; =mumps for Ipopt's own)");
}

void addSessionRenderOptions(CLI::App* app, SessionRender& r, const std::string& px_per_mm_help,
                             const std::string& solver_help) {
  addPxPerMm(app, r.px_per_mm, px_per_mm_help);
  addSolver(app, r.solver, solver_help);
  addSolverMaxIterations(app, r.solver_max_iterations);
  addIpoptOption(app, r.ipopt_options);
  addPaintOptions(app, r);
}

void addRenderThreads(CLI::App* app, int& threads) {
  app->add_option("--threads", threads,
                  "1: simulate and draw in turns; 2: simulate the next steps while this one is "
                  "drawn. The same pixels either way (default: 2 where the process may use 2 "
                  "or more CPUs)")
      ->check(CLI::Range(1, 2));
}

CLI::Option* addPxPerMm(CLI::App* app, double& px_per_mm, const std::string& help,
                        bool show_default) {
  CLI::Option* o = app->add_option("--px-per-mm", px_per_mm, help);
  if (show_default) o->capture_default_str();
  return o->check(CLI::Range(0.5, 100.0));
}

void addPngOutput(CLI::App* app, std::string& output) {
  app->add_option("-o,--output", output,
                  "Output PNG (PNG only: .jpg, .tif ... are refused); - writes it to stdout")
      ->required();
}

void addBatchKey(CLI::App* app, std::string& key) {
  app->add_option("--batch-key", key)->group("");
}

std::string optionName(const CLI::Option& option) {
  if (!option.get_lnames().empty()) return "--" + option.get_lnames().front();
  if (!option.get_snames().empty()) return "-" + option.get_snames().front();
  return option.get_single_name();
}

namespace {

class HelpFormatter : public CLI::Formatter {
 public:
  std::string make_help(const CLI::App* app, std::string name,
                        CLI::AppFormatMode mode) const override {
    std::string out = CLI::Formatter::make_help(app, name, mode);
    const std::vector<std::string> groups = app->get_groups();
    if (groups.empty() || !groups.back().empty()) return out;
    // The options end "\n", then CLI11's extra "\n", then the "\n" before the footer.
    const std::size_t footer = out.size() - make_footer(app).size();
    if (footer >= 3 && out.compare(footer - 3, 3, "\n\n\n") == 0) out.erase(footer - 1, 1);
    return out;
  }
};

}  // namespace

void useHelpFormatter(CLI::App& app) { app.formatter(std::make_shared<HelpFormatter>()); }

void requireFiniteNumbers(CLI::App& app) {
  // No description: the help stays as it is.
  const CLI::Validator finite(
      [](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end != text.c_str() && *end == '\0' && !std::isfinite(v))
          return "'" + text + "' is not a finite number";
        return "";  // a finite number, or not a number at all (CLI11 says so)
      },
      "");
  for (CLI::Option* opt : app.get_options())
    if (opt->get_type_name().rfind("FLOAT", 0) == 0) opt->check(finite);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    requireFiniteNumbers(*sub);
}

void requireNamedOutputs(CLI::App& app) {
  // "" is how an output option reads when it is not given: given as '', it
  // would be taken for no output at all, or for a file without a name.
  static const char* const kOutputs[] = {"--output", "--trace", "--forces", "--stats",
                                         "--png",    "--diff",  "--log",    "--out"};
  const CLI::Validator named(
      [](std::string& text) -> std::string {
        return text.empty() ? "an empty name: give a file name (or - where standard output is "
                              "allowed)"
                            : "";
      },
      "");
  for (CLI::Option* opt : app.get_options())
    for (const char* name : kOutputs)
      if (optionName(*opt) == name) opt->check(named);
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
    requireNamedOutputs(*sub);
}

}  // namespace bristle::cli

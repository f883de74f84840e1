#pragma once
// The options several subcommands share, each registered by one function so
// that its name, help, default and check are the same wherever it appears.
// Only the files that register subcommands (cli/*_command.cpp, cli/main.cpp)
// include CLI11.

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

#include "cli/paint_options.h"
#include "engine/solvers/solver_pair.h"

namespace bristle::cli {

// Paint and paper options of a single-stroke render (render, record --png, replay).
void addPaintOptions(CLI::App* app, PaintOptions& p);

// --solver and its like: a name on the command line, a SolverKind from there on.
// `set` receives the parsed kind; `shown` is the default --help shows (none if empty).
CLI::Option* addSolverOption(CLI::App* app, const std::string& name,
                             std::function<void(SolverKind)> set, const std::string& help,
                             const std::string& shown);

// --solver with its default shown, into `kind`.
CLI::Option* addSolver(CLI::App* app, SolverKind& kind, const std::string& help);

// The iteration limit of the spine solvers, the same for every command that simulates.
void addSolverMaxIterations(CLI::App* app, int& max_iterations);

// --ipopt-option NAME=VALUE (repeatable), into `options`.
void addIpoptOption(CLI::App* app, std::vector<std::string>& options);

// The options of a session's render (SessionRender): --px-per-mm and --solver
// (with the help given), --solver-max-iterations, --ipopt-option and the paint
// options. One registration for record, replay and the reader of a session's
// header (cli/session_render.h), so that the three hold a value to the same rules.
void addSessionRenderOptions(CLI::App* app, SessionRender& r, const std::string& px_per_mm_help,
                             const std::string& solver_help);

// --threads 1|2 of render and sheet (render::StrokeOptions::threads); `threads`
// stays 0, the machine's choice, unless given.
void addRenderThreads(CLI::App* app, int& threads);

// --px-per-mm, in the range every command accepts (0.5 to 100); the default is
// shown unless `show_default` is false (a value that means "the file's own").
CLI::Option* addPxPerMm(CLI::App* app, double& px_per_mm, const std::string& help,
                        bool show_default = true);

// -o/--output of a PNG ("-": standard output).
void addPngOutput(CLI::App* app, std::string& output);

// The hidden --batch-key KEY of render, sheet and preview: `bristle batch`
// passes each job its key, which the PNG then carries with the job's warnings
// (batch/job_key.h). Not in --help: it is for the batch, not for people.
void addBatchKey(CLI::App* app, std::string& key);

// The name an option is known by on the command line: "--long" when it has a
// long name, else "-s". Never empty: CLI11 2.1's Option::get_name() returns ""
// for an option in the hidden group (--batch-key), so that name cannot tell
// options apart.
std::string optionName(const CLI::Option& option);

// CLI11's help layout, less the blank line CLI11 2.1 adds after the options
// when the last option group is the hidden one (--batch-key). Set on the
// program before its subcommands are added: they take their parent's.
void useHelpFormatter(CLI::App& app);

// Every floating-point option of `app` and its subcommands refuses a value
// that is not a finite number ("nan", "inf"): CLI11's ranges let NaN through,
// since every comparison with it is false. Call once all options exist.
void requireFiniteNumbers(CLI::App& app);

// Every output option (-o, --trace, --forces, --stats, --png, --diff, --log,
// --out) of app and its subcommands refuses an empty name, naming the option
// (exit 64).
void requireNamedOutputs(CLI::App& app);

}  // namespace bristle::cli

// bristle: the command line. Each subcommand registers its own options from
// its file (cli/commands.h); this file holds the program's help, parses, and
// maps errors to the exit codes of docs/design.md, "Exit codes".

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bristle/version.h"
#include "cli/commands.h"
#include "cli/inputs.h"
#include "cli/options.h"
#include "engine/base/error.h"
#include "engine/base/heap_policy.h"
#include "engine/solvers/ipopt/ipopt_options.h"
#include "engine/base/temp_files.h"
#include "process/process_hooks.h"

namespace {

using bristle::cli::Subcommand;

constexpr const char* kDescription =
    "bristle renders brush strokes from recorded 6-DOF stylus motion with the\n"
    "physically based 3D brush of Baxter & Lin (2004).\n";

constexpr const char* kFooter =
    "Examples:\n"
    "  bristle render --brush round \\\n"
    "                 --trajectory scenes/trajectories/s-curve.csv -o s.png --trace s.jsonl\n"
    "  bristle render --solver slsqp --brush flat \\\n"
    "                 --trajectory scenes/trajectories/straight-pull.csv -o flat.png\n"
    "  bristle render --brush round --trajectory - -o - < T.csv > out.png\n"
    "  bristle preview fan -o fan.png\n"
    "  bristle brushes\n"
    "  bristle pigments\n"
    "  bristle validate round scenes/trajectories/s-curve.csv\n"
    "  bristle record --brush round -o session.csv --png live.png\n"
    "  bristle replay session.csv -o replay.png\n"
    "  bristle compare golden/round-s-curve.png new.png --tolerance strict --diff d.png\n"
    "  bristle sheet scenes/sheets/library.json -o library-sheet.png\n"
    "  bristle batch scenes/batch/standard.json --out renders/ --jobs 2\n"
    "  bristle import scenes/recordings/painting30sec-excerpt.dat -o painting.csv\n"
    "A brush is a library name (bristle brushes lists them) or a file; - is stdin for\n"
    "a trajectory and stdout for a PNG.\n"
    "\n"
    "Exit codes: 0 ok, 1 images differ (compare), 64 usage, 65 bad input\n"
    "data, 66 input missing, 69 haptic device unavailable (or failed), 70 internal\n"
    "error, 73 cannot create output, 74 I/O error.\n";

constexpr const char* kIpoptOptionHelp =
    "--ipopt-option NAME=VALUE (render, record, replay; a batch job's \"ipopt-option\")\n"
    "sets one of these options of the spine solver, checked before the run; no\n"
    "other is passed to Ipopt (none that writes a file or prints), and Ipopt\n"
    "reads no option file (docs/dynamics.md, \"Ipopt options\"):\n";

// `bristle help [COMMAND]`: the program's help, one command's, or the Ipopt options.
Subcommand registerHelp(CLI::App& app, const std::vector<Subcommand>& commands) {
  auto topic = std::make_shared<std::string>();
  CLI::App* help = app.add_subcommand("help", "Show help for bristle or one command");
  help->footer(
      "Examples:\n"
      "  bristle help\n"
      "  bristle help validate\n"
      "Each command's help (also COMMAND --help) shows its options and its own examples.");
  help->add_option("command", *topic, "Command to explain, or ipopt-option");
  return {help, [&app, &commands, topic] {
            if (topic->empty()) {
              std::cout << app.help();
              return 0;
            }
            if (*topic == "ipopt-option") {
              std::cout << kIpoptOptionHelp << bristle::ipoptOptionsHelp();
              return 0;
            }
            for (const Subcommand& c : commands) {
              if (c.app->get_name() == *topic) {
                std::cout << c.app->help("bristle");
                return 0;
              }
            }
            bristle::cli::printError("help: unknown command '" + *topic +
                                     "' (commands: render, preview, validate, brushes, "
                                     "pigments, record, replay, sheet, batch, compare, import; "
                                     "or ipopt-option)");
            return static_cast<int>(bristle::ExitCode::kUsage);
          }};
}

// The exit code when parsing ends the run (help, version, a usage error).
std::optional<int> parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    bristle::cli::printError(e.what() + std::string(" (see bristle --help)"));
    return static_cast<int>(bristle::ExitCode::kUsage);
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace bristle::cli;
  // Ipopt's MA27 is bristle's dense KKT solver (process/process_hooks.h): the
  // libraries leave process-wide choices to the program.
  bristle::installProcessHooks();
  // Freed heap stays mapped between solves (engine/base/heap_policy.h): a tenth of
  // a hair-volume brush's render went to growing and trimming the heap.
  bristle::keepFreedHeap();
  // Brush names, on the command line and in the scenes, sheets and manifests it reads.
  bristle::setBrushLibraryDirs(cliBrushLibraryDirs());
  // One variable names the library for listing and lookup alike; the older
  // name is refused aloud rather than silently ignored.
  if (std::getenv("BRISTLE_BRUSHES") != nullptr)
    printError("warning: BRISTLE_BRUSHES is no longer read; put the folder in BRISTLE_BRUSH_PATH "
               "(colon-separated), which `bristle brushes` and every brush name use");
  CLI::App app(kDescription, "bristle");
  useHelpFormatter(app);
  app.footer(kFooter);
  app.set_version_flag("--version", std::string("bristle ") + bristle::kVersion);
  app.require_subcommand(0, 1);
  const std::vector<Subcommand> commands = registerCommands(app);
  const Subcommand help = registerHelp(app, commands);
  if (const std::optional<int> code = parse(app, argc, argv)) return *code;

  // SIGINT, SIGTERM and every other signal that ends the process remove the
  // temporary files of unfinished outputs, then end it as they would have
  // (`batch` and `record` stop more gently on SIGINT and SIGTERM).
  bristle::installTempFileCleanup();
  try {
    // A command's outputs appear together when it returns, or none when it
    // throws (engine/base/atomic_output.h; docs/errors.md, "Outputs").
    bristle::CommitGroup outputs;
    for (const Subcommand& c : commands) {
      if (!c.app->parsed()) continue;
      const int code = c.run();
      outputs.commit();
      return code;
    }
    if (help.app->parsed()) return help.run();
    std::cout << app.help();
    return static_cast<int>(bristle::ExitCode::kUsage);
  } catch (const bristle::Error& e) {
    printError(e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    printError(std::string("internal error: ") + e.what());
    return static_cast<int>(bristle::ExitCode::kSoftware);
  }
}

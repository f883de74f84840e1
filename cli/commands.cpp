// The program's subcommands as one list (main.cpp parses and runs them), and
// a command line checked against them without running it.

#include <CLI/CLI.hpp>
#include <algorithm>

#include "cli/commands.h"
#include "cli/options.h"
#include "engine/base/error.h"

namespace bristle::cli {

std::vector<Subcommand> registerCommands(CLI::App& app) {
  // In this order in `bristle --help`.
  std::vector<Subcommand> commands = {
      registerRender(app),  registerValidate(app), registerBrushes(app), registerPigments(app),
      registerPreview(app), registerRecord(app),   registerReplay(app),  registerSheet(app),
      registerBatch(app),   registerCompare(app),  registerImport(app), registerMeasure(app),
      registerFit(app)};
  requireFiniteNumbers(app);
  requireNamedOutputs(app);
  return commands;
}

std::vector<std::string> givenOptions(const CLI::App* app) {
  std::vector<std::string> given;
  for (const CLI::Option* o : app->get_options())
    if (o->count() > 0 && !o->get_positional()) given.push_back(optionName(*o));
  return given;
}

void checkCommandLine(const std::vector<std::string>& args) {
  // A program of its own: the options it parses into are thrown away with it.
  CLI::App app;
  app.require_subcommand(1);
  const std::vector<Subcommand> commands = registerCommands(app);
  std::vector<std::string> words(args.rbegin(), args.rend());  // CLI11 takes them last first
  try {
    app.parse(words);
  } catch (const CLI::ParseError& e) {
    throw Error(ExitCode::kUsage, e.what());
  }
  for (const Subcommand& c : commands)
    if (c.app->parsed() && c.check) c.check();
}

}  // namespace bristle::cli

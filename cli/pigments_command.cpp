// `bristle pigments`: the pigment table (engine/paint/pigments.h), one line each:
// the name, the colour a film of it shows, its Kubelka-Munk K and S per
// channel and where they come from. On a terminal each line starts with a
// swatch of that colour (24-bit ANSI background); in a pipe the text is plain
// (--swatches always|never overrides).

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>

#include <memory>

#include "cli/commands.h"
#include "cli/options.h"
#include "engine/base/error.h"
#include "engine/paint/pigments.h"

namespace bristle::cli {
namespace {

// Film thickness and paper of the colour shown: what --mix rgb takes as a
// paint's colour (docs/paint.md): a film of 2 units over white paper (0.9).
constexpr double kShownFilmUnits = 2.0;
constexpr double kShownPaper = 0.9;

int srgbByte(double linear) {
  const double v = std::round(255.0 * linearToSrgb(std::clamp(linear, 0.0, 1.0)));
  return static_cast<int>(v);
}

}  // namespace

int runPigments(const std::string& swatches) {
  const bool colour_swatches =
      swatches == "always" || (swatches == "auto" && ::isatty(STDOUT_FILENO));
  for (const Pigment& p : pigmentTable()) {
    Optics optics;
    std::string why;
    resolvePaint(p.name, MixModel::kKubelkaMunk, &optics, &why);
    const std::array<double, 3> rgb =
        filmOver(optics, kShownFilmUnits, {kShownPaper, kShownPaper, kShownPaper},
                 MixModel::kKubelkaMunk);
    const int r = srgbByte(rgb[0]), g = srgbByte(rgb[1]), b = srgbByte(rgb[2]);
    if (colour_swatches) std::printf("\x1b[48;2;%d;%d;%dm    \x1b[0m ", r, g, b);
    std::printf("%-18s #%02x%02x%02x  K %6.3g %6.3g %6.3g  S %6.3g %6.3g %6.3g  %s\n",
                p.name.c_str(), r, g, b, p.k[0], p.k[1], p.k[2], p.s[0], p.s[1], p.s[2],
                p.source.c_str());
  }
  std::fflush(stdout);
  return std::cout.good() && !std::ferror(stdout) ? 0 : static_cast<int>(ExitCode::kIoError);
}

Subcommand registerPigments(CLI::App& app) {
  auto swatches = std::make_shared<std::string>("auto");
  CLI::App* pigments = app.add_subcommand(
      "pigments", "List the pigment table: names, colours, Kubelka-Munk K and S");
  pigments->footer(
      "Examples:\n"
      "  bristle pigments\n"
      "  bristle pigments --swatches never\n"
      "The colour is what a film of the paint (2 units thick) shows over white paper.\n"
      "Any name listed, or a colour #rrggbb, works as --paint. See docs/paint.md.");
  pigments->add_option("--swatches", *swatches,
                       "Colour swatches (24-bit ANSI): auto (when stdout is a terminal), "
                       "always, never")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "always", "never"}));
  return {pigments, [swatches] { return runPigments(*swatches); }};
}

}  // namespace bristle::cli

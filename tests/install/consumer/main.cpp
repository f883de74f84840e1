// An outside project using the installed bristle through its public API only
// (include/bristle/, docs/api.md): the library brush "round", a short pull
// built from arrays, rendered in memory and checked for paint, written as a
// PNG, and the brush pressed onto the paper step by step.
//
//   consumer OUT.png
#include <cstdio>
#include <exception>

#include "bristle/brush.h"
#include "bristle/error.h"
#include "bristle/png.h"
#include "bristle/render.h"
#include "bristle/simulation.h"
#include "bristle/trajectory.h"
#include "bristle/version.h"

namespace api = bristle::api;

namespace {

// Press 2 mm past first contact, pull 10 mm along +x, lift.
api::Trajectory shortPull() {
  const api::Trajectory::Quaternions upright(4, {1, 0, 0, 0});
  return api::Trajectory::fromArraysWithDepth({0.0, 0.1, 0.4, 0.5},
                                              {{10, 10}, {11, 10}, {19, 10}, {20, 10}},
                                              {-1.0, 2.0, 2.0, -1.0}, upright);
}

// Pixels clearly darker than the image's corner, which is bare paper (the
// canvas has a 5 mm margin round all the brush can reach).
long darkerThanPaper(const api::Image& image) {
  const int c = image.channels;
  const int paper = image.pixels[0] + image.pixels[1] + image.pixels[2];
  long n = 0;
  for (size_t i = 0; i + 2 < image.pixels.size(); i += c)
    if (image.pixels[i] + image.pixels[i + 1] + image.pixels[i + 2] < paper - 30) ++n;
  return n;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) return 64;
  try {
    api::setBrushLibraryDirs({BRUSH_LIBRARY_DIR});
    const api::Brush brush = api::Brush::load("round");
    std::printf("bristle %s: brush '%s', %d spines, hair %.1f mm\n", bristle::kVersion,
                brush.name().c_str(), brush.spineCount(), brush.hairLengthMm());

    api::RenderOptions options;
    options.px_per_mm = 4;
    const api::RenderResult stroke = api::renderStroke(brush, shortPull(), options);
    const long dark = darkerThanPaper(stroke.image);
    std::printf("stroke: %d x %d px, %ld px darker than the paper\n", stroke.image.width_px,
                stroke.image.height_px, dark);
    if (dark == 0) return 1;
    api::writePng(argv[1], stroke.image);

    // Lowered 0.25 mm a step from 1 mm above the paper: the hair touches down.
    api::Simulation sim(brush);
    const double top_z = brush.hairLengthMm() + 1;
    sim.reset({{10, 10, top_z}}, 0);
    int first_contact = 0;
    for (int k = 1; k <= 16; ++k) {
      const api::StepResult& s = sim.step({{10, 10, top_z - 0.25 * k}}, 0.01 * k);
      if (s.contact() && first_contact == 0) first_contact = k;
      std::printf("step %d: %d joints on the paper, force z %.3f N\n", k, s.contact_joints,
                  s.force_n[2]);
    }
    if (first_contact == 0) return 1;
    std::printf("simulation: contact from step %d\n", first_contact);
    return 0;
  } catch (const api::Error& e) {
    std::fprintf(stderr, "consumer: %s (exit category %d)\n", e.what(), e.exitCode());
    return e.exitCode();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 70;
  }
}

// Reads a brush with the installed engine and writes a PNG with the installed
// render library: what an outside project linking bristle would do.
#include <cstdio>

#include "bristle/version.h"
#include "engine/model/brush.h"
#include "render/png_io.h"

int main(int argc, char** argv) {
  if (argc != 3) return 64;
  const bristle::Brush brush = bristle::loadBrush(argv[1]);
  bristle::render::Image8 image{2, 1, 4, {0, 0, 0, 255, 255, 255, 255, 255}};
  bristle::render::writePng(argv[2], image);
  std::printf("bristle %s: brush '%s', %zu spines, reach %.1f mm\n", bristle::kVersion,
              brush.name.c_str(), brush.spines.size(), brush.reachMm());
  return 0;
}

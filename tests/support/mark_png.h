#pragma once
// Coverage of a PNG written by bristle (target bristle_testsupport_render, which
// links bristle::render for render/image/png_io.h).

#include <string>

#include "tests/support/mark_measure.h"

namespace bristle::testsupport {

// Reads the PNG (render::readPngRgba8) and makes its coverage with
// coverageFromRgba8. The placement (x0_mm, y0_mm, px_per_mm) comes from the
// PNG's "bristle:canvas" text chunk when present; px_per_mm > 0 overrides the
// resolution (8 px/mm when neither gives one). Throws bristle::Error as
// readPngRgba8 does (66 missing, 65 not a PNG).
Coverage loadCoveragePng(const std::string& path, double px_per_mm = 0);

// The value of the PNG's text chunk `key` ("" when it has none).
std::string pngText(const std::string& png, const std::string& key);

}  // namespace bristle::testsupport

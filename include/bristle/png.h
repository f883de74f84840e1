#pragma once
// bristle/png.h -- an Image (bristle/render.h) written as a PNG file, with
// bristle's provenance text (its version). Written to a temporary file and
// renamed into place, so a failed write leaves no partial file.

#include <string>

#include "bristle/render.h"

namespace bristle::api {

// Throws Error: kCantCreate when the file cannot be created, kIoError when
// writing fails midway, kUsage for an image whose size does not match its pixels.
void writePng(const std::string& path, const Image& image);

}  // namespace bristle::api

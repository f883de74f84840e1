#pragma once
// The canvas's paint to an image (docs/paint.md, "Compose"): per pixel the wet film
// over the dry layer (engine/paint/paint.h, Kubelka-Munk or linear RGB), encoded as
// sRGB; optionally "impasto": the paint's thickness lit from one light, normals
// from the gradient of the paint height (as IMPaSTo renders relief, NPAR 2004).

#include <array>
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include "engine/paint/paint.h"
#include "render/image/png_io.h"

namespace bristle::render {

struct ComposeOptions {
  bool impasto = false;
  // Direction towards the light in the canvas frame (x right, y up, z out of the
  // canvas): from the upper left, 45 degrees above the canvas, as a painting hung
  // under a window is lit. Need not be unit length.
  double light[3] = {-0.55, 0.55, 0.78};
  // Height exaggeration of the relief: 1 is the physical paint thickness. The
  // films a brush lays (~0.05 mm) are far thinner than oil impasto (0.5 mm and
  // more); 4x makes their ridges read at a normal viewing size.
  double relief = 4.0;
  // Share of light that arrives from everywhere (unshaded).
  double ambient = 0.45;
  // Gloss of wet-looking oil paint: highlight strength and Phong exponent.
  double specular = 0.25;
  double shininess = 24;
};

// Linear-light RGB per pixel (3 floats, row 0 at the top), shading applied.
std::vector<float> composeLinear(const PaintCanvas& canvas, const ComposeOptions& options);
// Linear values to sRGB codes, lround(255 or 65535 * linearToSrgb(v)) each.
std::vector<std::uint8_t> encodeSrgb8(std::span<const float> linear);
std::vector<std::uint16_t> encodeSrgb16(std::span<const float> linear);
// 8-bit / 16-bit sRGB-encoded RGB images of the canvas.
Image8 composeRgb8(const PaintCanvas& canvas, const ComposeOptions& options);
Image16 composeRgb16(const PaintCanvas& canvas, const ComposeOptions& options);
// Writes a canvas as a PNG (atomically, writePng): with bits 8 the 8-bit
// composition the caller already made of it (image8, composeRgb8 of the same
// canvas and options), with bits 16 the 16-bit one.
void writeCanvasPng(const std::string& path, const PaintCanvas& canvas, const Image8& image8,
                    const ComposeOptions& options, int bits, const PngText& text);

// A pixel is ink when its colour differs from the bare paper's by more than
// this (sum of |difference| over R, G, B, 8-bit levels): a visible mark, not a
// rounding difference. 6 levels is about 2 per channel, under what the eye
// sees on a light paper but above the one-level steps of sRGB rounding.
inline constexpr int kInkLevels = 6;

// The 8-bit colour bare paper composes to (a blank canvas of one pixel).
std::array<std::uint8_t, 3> paperColour8(const PaperSpec& paper, MixModel model, double px_per_mm,
                                         const ComposeOptions& options);
// Whether an 8-bit RGB(A) pixel is ink on that paper (kInkLevels).
inline bool isInk(const std::uint8_t* px, const std::array<std::uint8_t, 3>& paper) {
  const int d = std::abs(px[0] - paper[0]) + std::abs(px[1] - paper[1]) + std::abs(px[2] - paper[2]);
  return d > kInkLevels;
}
// How many pixels of an 8-bit image are ink: the visible paint of a render.
long inkPixels(const Image8& image, const std::array<std::uint8_t, 3>& paper);

// The PNG text chunks every painting carries: "Software" (bristle and its
// version), "bristle:version" and "bristle:inputs-fnv1a64" (16 hex digits of
// FNV-1a 64 over the bytes of `inputs`, in order; engine/base/fnv1a64.h).
PngText provenanceText(const std::vector<std::string>& inputs);
// The same with the hash already computed (e.g. engine/formats/sheet.h's sheetInputsHash),
// so that writer and checker use one function.
PngText provenanceText(std::uint64_t inputs_fnv1a64);

}  // namespace bristle::render

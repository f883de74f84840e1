#pragma once
// Text labels for rendered images (brush previews, stroke sheets), rasterised
// with FreeType from a Debian font. The output is a coverage mask that callers
// blend onto their own Image8, so the same label code serves every picture.
// FreeType is deterministic for a given font file and version: the same string
// gives the same mask bytes every run.

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

#include "render/image/png_io.h"

namespace bristle::render {

// fonts-dejavu-core (docs/design.md, "Debian dependencies").
inline constexpr const char* kDefaultFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
};

// A font face opened once and reused for many strings. Not thread-safe (one
// FreeType library per Font); create one per thread if needed.
class Font {
 public:
  // Throws std::runtime_error naming the path when the font cannot be opened.
  explicit Font(const std::string& path = kDefaultFontPath);
  ~Font();
  Font(const Font&) = delete;
  Font& operator=(const Font&) = delete;

  // Rasterises UTF-8 text at a pixel size (the em height, as in CSS): a
  // 1-channel coverage mask (0 = none, 255 = full) exactly as wide as the text's
  // ink and advances, and as tall as the font's line (ascender - descender), so
  // masks of one size line up on a common baseline at ascent(size_px) from the
  // top. Invalid UTF-8 bytes render as U+FFFD. Throws std::invalid_argument when
  // size_px is outside [4, 512].
  Image8 rasterize(std::string_view utf8, int size_px);

  // Distance in pixels from the top of a mask to the baseline.
  int ascent(int size_px);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Blends colour through a coverage mask onto target (3 or 4 channels) with the
// mask's top-left corner at (x, y); the parts outside the target are clipped.
// alpha scales the mask (0..1), e.g. for muted labels.
void blendMask(const Image8& mask, int x, int y, Rgb8 colour, Image8* target, double alpha = 1.0);

// Convenience: rasterise and blend in one call, (x, y) = top-left of the line.
// Returns the width in pixels of the drawn text.
int drawText(Font& font, std::string_view utf8, int size_px, int x, int y, Rgb8 colour,
             Image8* target);

}  // namespace bristle::render

// FreeType text rasterisation behind render/image/text.h. Glyphs are placed on whole
// pixels (no sub-pixel positioning) with light hinting: labels stay crisp at
// small sizes and the bytes do not depend on where the string starts.

#include "render/image/text.h"

#include <ft2build.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace bristle::render {

namespace {

constexpr int kMinSizePx = 4, kMaxSizePx = 512;
constexpr char32_t kReplacement = 0xFFFD;

// Decodes one UTF-8 sequence at s[*i], advancing *i. Malformed input (stray
// continuation bytes, truncated or overlong sequences) yields U+FFFD and skips
// one byte, so a bad label degrades visibly instead of failing.
char32_t nextCodepoint(std::string_view s, std::size_t* i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(s[k]); };
  const unsigned char lead = byte(*i);
  int extra = 0;
  char32_t cp = 0;
  if (lead < 0x80) {
    ++*i;
    return lead;
  } else if ((lead & 0xE0) == 0xC0) {
    extra = 1, cp = lead & 0x1F;
  } else if ((lead & 0xF0) == 0xE0) {
    extra = 2, cp = lead & 0x0F;
  } else if ((lead & 0xF8) == 0xF0) {
    extra = 3, cp = lead & 0x07;
  } else {
    ++*i;
    return kReplacement;
  }
  if (*i + extra >= s.size()) {  // truncated sequence
    ++*i;
    return kReplacement;
  }
  for (int k = 1; k <= extra; ++k) {
    if ((byte(*i + k) & 0xC0) != 0x80) {
      ++*i;
      return kReplacement;
    }
    cp = (cp << 6) | (byte(*i + k) & 0x3F);
  }
  static constexpr char32_t kMinForLength[4] = {0, 0x80, 0x800, 0x10000};
  if (cp < kMinForLength[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) {
    ++*i;
    return kReplacement;
  }
  *i += static_cast<std::size_t>(extra) + 1;
  return cp;
}

// A rendered glyph bitmap and where its top-left pixel lands on the line.
struct PlacedGlyph {
  int x = 0, y = 0, width = 0, height = 0;
  std::vector<std::uint8_t> coverage;
};

}  // namespace

struct Font::Impl {
  FT_Library library = nullptr;
  FT_Face face = nullptr;
  std::string path;
  int size_px = 0;  // size currently set on the face

  void setSize(int size_px_in) {
    if (size_px_in < kMinSizePx || size_px_in > kMaxSizePx) {
      throw std::invalid_argument("text size " + std::to_string(size_px_in) +
                                  " px: must be in [4, 512]");
    }
    if (size_px_in == size_px) return;
    if (FT_Set_Pixel_Sizes(face, 0, static_cast<FT_UInt>(size_px_in)) != 0) {
      throw std::runtime_error(path + ": cannot set a " + std::to_string(size_px_in) + " px size");
    }
    size_px = size_px_in;
  }
  // Line metrics in whole pixels, rounded outwards so no ink is cut off.
  int ascent() const { return static_cast<int>((face->size->metrics.ascender + 63) >> 6); }
  int descent() const { return static_cast<int>((-face->size->metrics.descender + 63) >> 6); }
};

Font::Font(const std::string& path) : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  if (FT_Init_FreeType(&impl_->library) != 0) {
    throw std::runtime_error("cannot initialise FreeType");
  }
  if (FT_New_Face(impl_->library, path.c_str(), 0, &impl_->face) != 0) {
    FT_Done_FreeType(impl_->library);
    throw std::runtime_error(path + ": cannot open the font (is fonts-dejavu-core installed?)");
  }
}

Font::~Font() {
  FT_Done_Face(impl_->face);
  FT_Done_FreeType(impl_->library);
}

int Font::ascent(int size_px) {
  impl_->setSize(size_px);
  return impl_->ascent();
}

Image8 Font::rasterize(std::string_view utf8, int size_px) {
  Impl& s = *impl_;
  s.setSize(size_px);
  const int ascent = s.ascent();
  const bool kerning = FT_HAS_KERNING(s.face);

  // Pass 1: lay the glyphs out along the baseline (26.6 fixed point pen).
  std::vector<PlacedGlyph> glyphs;
  FT_Pos pen = 0;
  FT_UInt previous = 0;
  int min_x = 0, max_x = 0;
  for (std::size_t i = 0; i < utf8.size();) {
    const FT_UInt index = FT_Get_Char_Index(s.face, nextCodepoint(utf8, &i));
    if (kerning && previous != 0 && index != 0) {
      FT_Vector delta{};
      FT_Get_Kerning(s.face, previous, index, FT_KERNING_DEFAULT, &delta);
      pen += delta.x;
    }
    previous = index;
    if (FT_Load_Glyph(s.face, index, FT_LOAD_RENDER | FT_LOAD_TARGET_LIGHT) != 0) continue;
    const FT_GlyphSlot slot = s.face->glyph;
    const FT_Bitmap& bitmap = slot->bitmap;
    PlacedGlyph g;
    g.x = static_cast<int>((pen + 32) >> 6) + slot->bitmap_left;
    g.y = ascent - slot->bitmap_top;
    g.width = static_cast<int>(bitmap.width);
    g.height = static_cast<int>(bitmap.rows);
    if (bitmap.pixel_mode == FT_PIXEL_MODE_GRAY && g.width > 0 && g.height > 0) {
      g.coverage.resize(static_cast<std::size_t>(g.width) * g.height);
      for (int row = 0; row < g.height; ++row) {
        const unsigned char* src = bitmap.buffer + static_cast<std::ptrdiff_t>(row) * bitmap.pitch;
        std::copy(src, src + g.width,
                  g.coverage.begin() + static_cast<std::ptrdiff_t>(row) * g.width);
      }
      min_x = std::min(min_x, g.x);
      max_x = std::max(max_x, g.x + g.width);
      glyphs.push_back(std::move(g));
    }
    pen += slot->advance.x;
  }
  max_x = std::max(max_x, static_cast<int>((pen + 32) >> 6));

  // Pass 2: combine (max, so touching glyphs do not darken their overlap).
  Image8 mask;
  mask.channels = 1;
  mask.width = max_x - min_x;
  mask.height = ascent + s.descent();
  mask.pixels.assign(static_cast<std::size_t>(mask.width) * mask.height, 0);
  for (const PlacedGlyph& g : glyphs) {
    for (int row = 0; row < g.height; ++row) {
      const int y = g.y + row;
      if (y < 0 || y >= mask.height) continue;  // ink beyond the line box
      for (int col = 0; col < g.width; ++col) {
        std::uint8_t& dst =
            mask.pixels[static_cast<std::size_t>(y) * mask.width + (g.x - min_x + col)];
        dst = std::max(dst, g.coverage[static_cast<std::size_t>(row) * g.width + col]);
      }
    }
  }
  return mask;
}

void blendMask(const Image8& mask, int x, int y, Rgb8 colour, Image8* target, double alpha) {
  if (target->channels < 3) throw std::invalid_argument("blendMask: target must be RGB(A)");
  const int a_scale = static_cast<int>(std::lround(std::clamp(alpha, 0.0, 1.0) * 255.0));
  const std::uint8_t rgb[3] = {colour.r, colour.g, colour.b};
  for (int row = std::max(0, -y); row < mask.height && y + row < target->height; ++row) {
    for (int col = std::max(0, -x); col < mask.width && x + col < target->width; ++col) {
      // Integer blend (rounded): exact and identical on every machine.
      const int a = mask.pixels[static_cast<std::size_t>(row) * mask.width + col] * a_scale;
      if (a == 0) continue;
      std::uint8_t* px =
          &target->pixels[(static_cast<std::size_t>(y + row) * target->width + (x + col)) *
                          target->channels];
      for (int c = 0; c < 3; ++c) {
        px[c] = static_cast<std::uint8_t>((px[c] * (65025 - a) + rgb[c] * a + 32512) / 65025);
      }
    }
  }
}

int drawText(Font& font, std::string_view utf8, int size_px, int x, int y, Rgb8 colour,
             Image8* target) {
  const Image8 mask = font.rasterize(utf8, size_px);
  blendMask(mask, x, y, colour, target);
  return mask.width;
}

}  // namespace bristle::render

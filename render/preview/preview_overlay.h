#pragma once
// The 2D parts of the brush preview, drawn on the final (box-filtered) image so
// text and hairlines stay crisp: the title, a colour key with the grid spacing,
// and the footprint inset. Internal to render/.

#include "render/preview/preview_geometry.h"
#include "render/image/text.h"

namespace bristle::render::preview {

// Colours shared by the 3D passes and the key (sRGB bytes).
inline constexpr Rgb8 kSpineKey{179, 10, 15};
inline constexpr Rgb8 kSurfaceKey{160, 100, 52};
inline constexpr Rgb8 kStripKey{107, 64, 31};
inline constexpr Rgb8 kInkText{42, 42, 48};
inline constexpr Rgb8 kMutedText{110, 108, 104};

void drawOverlays(const PreviewScene& scene, const PreviewOptions& options, const Layout& layout,
                  Font& font, Image8* image);

// The footprint as ink on paper, cropped to the contact area plus a margin,
// depth-shaded (darker = pressed deeper), with the 5 mm grid, a thin border and
// the label "footprint".
void drawFootprintInset(const FootprintImage& footprint, const PixelRect& rect, int label_size_px,
                        Font& font, Image8* image);

}  // namespace bristle::render::preview

#include "bristle/png.h"

#include <string>

#include "api/model.h"
#include "render/image/compose.h"
#include "render/image/png_io.h"

namespace bristle::api {

void writePng(const std::string& path, const Image& image) {
  const bool channels_ok = image.channels >= 1 && image.channels <= 4;
  if (!channels_ok || image.width_px <= 0 || image.height_px <= 0 ||
      image.pixels.size() !=
          static_cast<size_t>(image.width_px) * image.height_px * image.channels)
    throw api::Error(ErrorCategory::kUsage,
                     "writePng " + path + ": image: " + std::to_string(image.pixels.size()) +
                         " bytes for " + std::to_string(image.width_px) + " x " +
                         std::to_string(image.height_px) + " px of " +
                         std::to_string(image.channels) +
                         " channels (1 to 4): the size must match the pixels");
  translateErrors([&] {
    render::Image8 out{image.width_px, image.height_px, image.channels, image.pixels};
    // The provenance every bristle PNG carries (render/image/compose.h); no inputs hashed.
    render::writePng(path, out, render::provenanceText(std::vector<std::string>{}));
  });
}

}  // namespace bristle::api

// Fuzz target: a PNG as `compare` decodes it (any PNG into 16-bit RGBA, with
// its own layout), and its text chunks as `batch` reads its up-to-date key. The
// input is a memory file: the PNG reader takes a path.

#include "fuzz/fuzz_input.h"
#include "render/image/png_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const bristle::fuzz::MemoryFile file(data, size);
  try {
    bristle::render::PngFormat format;
    const bristle::render::Image16 image = bristle::render::readPngRgba16(file.path(), &format);
    if (image.pixels.size() != static_cast<std::size_t>(image.width) * image.height * 4)
      std::abort();
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  try {
    (void)bristle::render::readPngText(file.path());
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}

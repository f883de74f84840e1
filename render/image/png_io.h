#pragma once
// PNG reading and writing (libpng). Writes go to a temporary file beside the
// target that is renamed into place, so a failed write never leaves a partial file.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace bristle::render {

// 8-bit image, row 0 at the top, channels interleaved (1 = grey, 3 = RGB, 4 = RGBA).
struct Image8 {
  int width = 0, height = 0, channels = 4;
  std::vector<std::uint8_t> pixels;
};

// 16-bit image (values 0..65535), same layout as Image8.
struct Image16 {
  int width = 0, height = 0, channels = 4;
  std::vector<std::uint16_t> pixels;
};

using PngText = std::vector<std::pair<std::string, std::string>>;

// The path writePng takes for standard output: the PNG is encoded in memory
// whole and only then written to it, so an error before that leaves nothing
// on it (the CLI's `-o -`).
inline constexpr const char* kStdoutPath = "-";

// Throws bristle::Error: kCantCreate (73) when the file cannot be created (missing
// directory, no permission), kIoError (74) when writing fails midway. The temp
// file is removed on every failure path.
void writePng(const std::string& path, const Image8& image, const PngText& text = {});
void writePng(const std::string& path, const Image16& image, const PngText& text = {});

// Reads any PNG into 8-bit RGBA (grey and palette are expanded, 16-bit scaled
// down). Throws bristle::Error: kNoInput (66) missing/unreadable, kDataError (65)
// not a PNG or corrupt.
Image8 readPngRgba8(const std::string& path);

// The pixel layout of a PNG file as stored (a palette image has 1 channel).
struct PngFormat {
  int bit_depth = 8;  // 1, 2, 4, 8 or 16
  int channels = 4;   // 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
};

// Reads any PNG into 16-bit RGBA, samples in host order: 8-bit samples v become
// v * 257 (0..255 onto 0..65535 exactly), grey and palette are expanded, a file
// without alpha is opaque (65535). `format`, when given, receives the file's own
// layout; `text`, when given, its text chunks (one read: standard input can be
// read only once). Throws as readPngRgba8.
Image16 readPngRgba16(const std::string& path, PngFormat* format = nullptr,
                      PngText* text = nullptr);

// The text chunks of a PNG (for tests and `bristle compare`).
PngText readPngText(const std::string& path);

}  // namespace bristle::render

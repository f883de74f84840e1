// PNG files: pixels and text round-trip; failures carry the documented exit
// code and never leave a file (or a temporary) behind.

#include <catch2/catch.hpp>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "engine/base/error.h"
#include "render/image/png_io.h"
#include "temp_dir.h"

namespace fs = std::filesystem;
using bristle::Error;
using bristle::ExitCode;
using bristle::render::Image16;
using bristle::render::Image8;
using bristle::render::PngText;
using bristle::render::readPngRgba8;
using bristle::render::readPngText;
using bristle::render::writePng;

namespace {

// libpng's png_set_scale_16 computes (v * 255 + 32895) >> 16: correct rounding
// of v / 257 up to 16-bit fixed-point error (< 0.01 of an 8-bit step).
constexpr double kScale16Tol = 0.51;

using bristle::testing::TempDir;

// The names in a test's folder, sorted.
std::vector<std::string> listing(const TempDir& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir.path()))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

Image8 patternImage8(int width, int height, int channels) {
  Image8 image{width, height, channels, {}};
  for (int i = 0; i < width * height * channels; ++i) {
    image.pixels.push_back(static_cast<std::uint8_t>((i * 37 + 11) & 0xff));
  }
  return image;
}

std::string fileBytes(const fs::path& path) {
  std::string bytes(fs::file_size(path), '\0');
  std::ifstream in(path, std::ios::binary);
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  return bytes;
}

// Runs f, expecting a bristle::Error; returns it for inspection.
template <typename F>
Error expectError(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e;
  }
  FAIL("no bristle::Error thrown");
  return Error(ExitCode::kOk, "");
}

}  // namespace

TEST_CASE("png: 8-bit RGBA round-trips exactly", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "rgba.png").string();
  const Image8 image = patternImage8(7, 5, 4);
  writePng(path, image);
  const Image8 back = readPngRgba8(path);
  CHECK(back.width == 7);
  CHECK(back.height == 5);
  CHECK(back.channels == 4);
  CHECK(back.pixels == image.pixels);
  CHECK(listing(dir) == std::vector<std::string>{"rgba.png"});
}

TEST_CASE("png: 8-bit RGB reads back as RGBA with opaque alpha", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "rgb.png").string();
  const Image8 image = patternImage8(6, 3, 3);
  writePng(path, image);
  const Image8 back = readPngRgba8(path);
  REQUIRE(back.width == 6);
  REQUIRE(back.height == 3);
  REQUIRE(back.pixels.size() == 6u * 3u * 4u);
  for (int p = 0; p < 6 * 3; ++p) {
    INFO("pixel " << p);
    for (int c = 0; c < 3; ++c) REQUIRE(back.pixels[p * 4 + c] == image.pixels[p * 3 + c]);
    REQUIRE(back.pixels[p * 4 + 3] == 255);
  }
}

TEST_CASE("png: grey expands to equal RGB channels", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "grey.png").string();
  const Image8 image = patternImage8(4, 4, 1);
  writePng(path, image);
  const Image8 back = readPngRgba8(path);
  for (int p = 0; p < 16; ++p) {
    for (int c = 0; c < 3; ++c) REQUIRE(back.pixels[p * 4 + c] == image.pixels[p]);
    REQUIRE(back.pixels[p * 4 + 3] == 255);
  }
}

TEST_CASE("png: 16-bit is written and read back scaled to 8 bits", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "deep.png").string();
  Image16 image{5, 4, 4, {}};
  for (int i = 0; i < 5 * 4 * 4; ++i) {
    // Mix exact multiples of 257 (which must map to k exactly) with odd values.
    const int value = i % 2 == 0 ? 257 * ((i * 29) % 256) : (i * 4099 + 123) % 65536;
    image.pixels.push_back(static_cast<std::uint16_t>(value));
  }
  image.pixels[0] = 0;
  image.pixels[1] = 65535;
  writePng(path, image);
  const Image8 back = readPngRgba8(path);
  REQUIRE(back.pixels.size() == image.pixels.size());
  CHECK(back.pixels[0] == 0);
  CHECK(back.pixels[1] == 255);
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    INFO("sample " << i << " = " << image.pixels[i]);
    if (image.pixels[i] % 257 == 0) {
      REQUIRE(back.pixels[i] == image.pixels[i] / 257);
    } else {
      REQUIRE(std::abs(back.pixels[i] - image.pixels[i] / 257.0) <= kScale16Tol);
    }
  }
}

TEST_CASE("png: text chunks round-trip as tEXt, zTXt and iTXt", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "text.png").string();
  const PngText text = {
      {"Software", "bristle 0.1.0"},
      {"Comment", std::string(600, 'x') + " long enough to be deflated"},
      {"Title", "Pinselstrich \xC3\xBC \xE2\x80\x94 UTF-8"},
  };
  writePng(path, patternImage8(2, 2, 4), text);
  CHECK(readPngText(path) == text);
  const std::string bytes = fileBytes(path);
  CHECK(bytes.find("tEXtSoftware") != std::string::npos);
  CHECK(bytes.find("zTXtComment") != std::string::npos);
  CHECK(bytes.find("iTXtTitle") != std::string::npos);
  CHECK(readPngText((dir.path() / "text.png").string()).size() == 3);

  const std::string plain = (dir.path() / "plain.png").string();
  writePng(plain, patternImage8(2, 2, 3));
  CHECK(readPngText(plain).empty());
}

TEST_CASE("png: an existing file is replaced", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "out.png").string();
  writePng(path, patternImage8(3, 3, 4));
  const Image8 second = patternImage8(2, 5, 4);
  writePng(path, second);
  CHECK(readPngRgba8(path).pixels == second.pixels);
  CHECK(listing(dir) == std::vector<std::string>{"out.png"});
}

TEST_CASE("png: writing into a missing directory is kCantCreate and leaves nothing",
          "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "no-such-dir" / "out.png").string();
  const Error e = expectError([&] { writePng(path, patternImage8(2, 2, 4)); });
  CHECK(e.code() == ExitCode::kCantCreate);
  CHECK_THAT(e.what(), Catch::StartsWith(path + ": cannot create output: "));
  CHECK_THAT(e.what(), Catch::Contains("No such file or directory"));
  CHECK(listing(dir).empty());
}

TEST_CASE("png: a target that is a directory is kCantCreate and the temp is removed",
          "[png]") {
  TempDir dir;
  fs::create_directory(dir.path() / "taken.png");
  const std::string path = (dir.path() / "taken.png").string();
  const Error e = expectError([&] { writePng(path, patternImage8(2, 2, 4)); });
  CHECK(e.code() == ExitCode::kCantCreate);
  CHECK(listing(dir) == std::vector<std::string>{"taken.png"});
}

TEST_CASE("png: a missing or unreadable input is kNoInput", "[png]") {
  TempDir dir;
  const std::string missing = (dir.path() / "missing.png").string();
  Error e = expectError([&] { readPngRgba8(missing); });
  CHECK(e.code() == ExitCode::kNoInput);
  CHECK_THAT(e.what(), Catch::StartsWith(missing + ": cannot read: "));
  CHECK(expectError([&] { readPngText(missing); }).code() == ExitCode::kNoInput);
  // A directory opens but cannot be read.
  CHECK(expectError([&] { readPngRgba8(dir.path().string()); }).code() == ExitCode::kNoInput);
}

TEST_CASE("png: a text file named .png is kDataError", "[png]") {
  TempDir dir;
  const std::string path = (dir.path() / "notes.png").string();
  std::ofstream(path) << "this is not an image\n";
  const Error e = expectError([&] { readPngRgba8(path); });
  CHECK(e.code() == ExitCode::kDataError);
  CHECK(std::string(e.what()) == path + ": not a PNG file");
  CHECK(expectError([&] { readPngText(path); }).code() == ExitCode::kDataError);

  std::ofstream(dir.path() / "short.png") << "\x89PN";
  CHECK(expectError([&] { readPngRgba8((dir.path() / "short.png").string()); }).code() ==
        ExitCode::kDataError);
}

TEST_CASE("png: a truncated PNG is kDataError", "[png]") {
  TempDir dir;
  const fs::path path = dir.path() / "cut.png";
  writePng(path.string(), patternImage8(40, 30, 4));
  fs::resize_file(path, fs::file_size(path) / 2);
  const Error e = expectError([&] { readPngRgba8(path.string()); });
  CHECK(e.code() == ExitCode::kDataError);
  // The chunk cut short is named before libpng reads (or allocates) it.
  CHECK_THAT(e.what(), Catch::StartsWith(path.string() + ": IDAT: a chunk of "));
  CHECK_THAT(e.what(), Catch::EndsWith("bytes left in the file (corrupt or truncated PNG)"));
}

TEST_CASE("png: an image that does not match its size is a programming error", "[png]") {
  TempDir dir;
  Image8 image = patternImage8(3, 3, 4);
  image.pixels.pop_back();
  CHECK_THROWS_AS(writePng((dir.path() / "bad.png").string(), image), std::invalid_argument);
  CHECK_THROWS_AS(writePng((dir.path() / "bad.png").string(), patternImage8(2, 2, 4),
                           {{"", "empty key"}}),
                  std::invalid_argument);
  CHECK(listing(dir).empty());
}

TEST_CASE("png: a symbolic link as the target is kCantCreate, link and file untouched", "[png]") {
  TempDir dir;
  const fs::path target = dir.path() / "target.png", link = dir.path() / "link.png";
  const Image8 first = patternImage8(2, 2, 4);
  writePng(target.string(), first);
  fs::create_symlink("target.png", link);
  const Error e = expectError([&] { writePng(link.string(), patternImage8(3, 2, 4)); });
  CHECK(e.code() == ExitCode::kCantCreate);
  CHECK_THAT(std::string(e.what()), Catch::Matchers::Contains("is a symbolic link"));
  CHECK(fs::is_symlink(link));
  CHECK(readPngRgba8(target.string()).pixels == first.pixels);
  CHECK(listing(dir) == std::vector<std::string>{"link.png", "target.png"});
}

TEST_CASE("png: a FIFO or a device as the target is kCantCreate and is not replaced",
          "[png]") {
  TempDir dir;
  const std::string fifo = (dir.path() / "fifo.png").string();
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  Error e = expectError([&] { writePng(fifo, patternImage8(2, 2, 4)); });
  CHECK(e.code() == ExitCode::kCantCreate);
  CHECK(std::string(e.what()) ==
        fifo + ": cannot create output: is a FIFO; an output must be a regular file");
  CHECK(fs::is_fifo(fifo));
  // Behind a link too: the link is neither followed nor replaced.
  const fs::path link = dir.path() / "null.png";
  fs::create_symlink("/dev/null", link);
  e = expectError([&] { writePng(link.string(), patternImage8(2, 2, 4)); });
  CHECK(e.code() == ExitCode::kCantCreate);
  CHECK(fs::is_symlink(link));
  CHECK(fs::is_character_file("/dev/null"));
  CHECK(listing(dir) == std::vector<std::string>{"fifo.png", "null.png"});
}

// PNG files through libpng's classic API (the simplified png_image API cannot
// write or read text chunks). libpng reports errors by longjmp; the functions
// that call it with setjmp armed hold no C++ objects with destructors, so a
// longjmp never skips one. Allocation and throwing happen outside those frames.

#include "render/image/png_io.h"

#include <png.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <bit>
#include <cerrno>
#include <cstdint>
#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/base/atomic_output.h"
#include "engine/model/canvas.h"
#include "engine/base/error.h"
#include "engine/base/text_file.h"

namespace bristle::render {

namespace {

// Text values at least this long are deflated (zTXt/compressed iTXt): shorter
// ones would not shrink and stay readable with `strings`.
constexpr std::size_t kCompressTextFromBytes = 512;

// libpng's message for the last error, carried out of the longjmp.
struct PngFailure {
  char message[200] = "unknown libpng error";
};

void onPngError(png_structp png, png_const_charp message) {
  auto* failure = static_cast<PngFailure*>(png_get_error_ptr(png));
  std::snprintf(failure->message, sizeof failure->message, "%s", message);
  png_longjmp(png, 1);
}

void onPngWarning(png_structp, png_const_charp) {}  // warnings are not errors here

std::string describeErrno(int error) {
  return error != 0 ? std::strerror(error) : "unknown error";
}

// Closes a FILE* on scope exit; fclose's own result is checked where it matters.
struct FileCloser {
  std::FILE* file;
  ~FileCloser() {
    if (file != nullptr) std::fclose(file);
  }
};

// Everything encodePng needs, prepared by the caller (it may not allocate).
struct EncodeJob {
  int width, height, channels, bit_depth;
  png_bytep* rows;
  png_text* text;
  int text_count;
};

// Returns false (with failure->message set) when libpng reports an error.
bool encodePng(std::FILE* file, const EncodeJob& job, PngFailure* failure) {
  png_structp png =
      png_create_write_struct(PNG_LIBPNG_VER_STRING, failure, onPngError, onPngWarning);
  if (png == nullptr) return false;
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    return false;
  }
  // setjmp stands alone in the condition, as C requires.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  static constexpr int kColourType[] = {PNG_COLOR_TYPE_GRAY, PNG_COLOR_TYPE_GRAY_ALPHA,
                                        PNG_COLOR_TYPE_RGB, PNG_COLOR_TYPE_RGB_ALPHA};
  png_init_io(png, file);
  png_set_IHDR(png, info, job.width, job.height, job.bit_depth,
               kColourType[job.channels - 1], PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (job.text_count > 0) png_set_text(png, info, job.text, job.text_count);
  png_write_info(png, info);
  // PNG stores 16-bit samples big-endian; ours are in host order.
  if (job.bit_depth == 16 && std::endian::native == std::endian::little) png_set_swap(png);
  png_write_image(png, job.rows);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

bool isPrintableKeyword(const std::string& key) {
  if (key.empty() || key.size() > 79 || key.front() == ' ' || key.back() == ' ' ||
      key.find("  ") != std::string::npos) {
    return false;
  }
  for (unsigned char c : key) {
    if (c < 32 || c > 126) return false;
  }
  return true;
}

// ASCII values go to tEXt (zTXt when long); anything else is UTF-8 in iTXt.
std::vector<png_text> toPngText(const PngText& text) {
  std::vector<png_text> chunks;
  for (const auto& [key, value] : text) {
    if (!isPrintableKeyword(key) || value.find('\0') != std::string::npos) {
      throw std::invalid_argument("PNG text key '" + key +
                                  "': must be 1-79 printable ASCII characters without "
                                  "leading, trailing or double spaces, and the value "
                                  "must not contain NUL");
    }
    bool ascii = true;
    for (unsigned char c : value) ascii = ascii && c < 128;
    const bool compress = value.size() >= kCompressTextFromBytes;
    png_text chunk{};
    chunk.key = const_cast<char*>(key.c_str());  // libpng copies; never writes
    chunk.text = const_cast<char*>(value.c_str());
    chunk.text_length = value.size();
    if (ascii) {
      chunk.compression = compress ? PNG_TEXT_COMPRESSION_zTXt : PNG_TEXT_COMPRESSION_NONE;
    } else {
      chunk.compression = compress ? PNG_ITXT_COMPRESSION_zTXt : PNG_ITXT_COMPRESSION_NONE;
      chunk.itxt_length = value.size();
      chunk.lang = const_cast<char*>("");
      chunk.lang_key = const_cast<char*>("");
    }
    chunks.push_back(chunk);
  }
  return chunks;
}

// The whole PNG encoded in memory, so that a failure while encoding leaves
// nothing on standard output and no file. Throws kIoError naming `shown`.
std::string encodeToMemory(const EncodeJob& job, const std::string& shown) {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* memory = ::open_memstream(&buffer, &size);
  if (memory == nullptr)
    throw Error(ExitCode::kIoError, shown + ": cannot encode the PNG: " + std::strerror(errno));
  PngFailure failure;
  const bool encoded = encodePng(memory, job, &failure);
  const bool closed = std::fclose(memory) == 0;  // sets buffer and size
  std::string bytes = buffer != nullptr ? std::string(buffer, size) : std::string();
  std::free(buffer);
  if (!encoded || !closed)
    throw Error(ExitCode::kIoError, shown + ": cannot encode the PNG: " +
                                        (encoded ? "out of memory" : failure.message));
  return bytes;
}

// "-": a write error (a closed pipe, a full disk) is kIoError after some bytes
// may have gone out.
void writeToStdout(const std::string& bytes) {
  std::fflush(stdout);  // nothing buffered may follow the PNG's bytes out of order
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::write(STDOUT_FILENO, bytes.data() + sent, bytes.size() - sent);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0)
      throw Error(ExitCode::kIoError, "stdout: write failed after " + std::to_string(sent) +
                                          " of " + std::to_string(bytes.size()) +
                                          " bytes: " + std::strerror(errno));
    sent += static_cast<std::size_t>(n);
  }
}

void writePngRows(const std::string& path, int width, int height, int channels,
                  int bit_depth, const void* pixels, std::size_t pixel_bytes,
                  const PngText& text) {
  const std::size_t row_bytes =
      static_cast<std::size_t>(width) * channels * static_cast<std::size_t>(bit_depth / 8);
  if (width <= 0 || height <= 0 || channels < 1 || channels > 4 ||
      pixel_bytes != row_bytes * static_cast<std::size_t>(height)) {
    throw std::invalid_argument(path + ": cannot write a " + std::to_string(width) + "x" +
                                std::to_string(height) + "x" + std::to_string(channels) +
                                " image from " + std::to_string(pixel_bytes) + " bytes");
  }
  std::vector<png_text> chunks = toPngText(text);
  std::vector<png_bytep> rows(static_cast<std::size_t>(height));
  for (int r = 0; r < height; ++r) {
    // libpng reads the rows only; the cast drops const for its C signature.
    rows[r] = const_cast<png_bytep>(static_cast<const png_byte*>(pixels)) + row_bytes * r;
  }

  const EncodeJob job{width, height, channels, bit_depth, rows.data(), chunks.data(),
                      static_cast<int>(chunks.size())};
  if (path == kStdoutPath) {
    // After the run's files are in place (engine/base/atomic_output.h): a run that
    // fails on another output writes nothing to standard output.
    std::string bytes = encodeToMemory(job, "stdout");
    if (CommitGroup* group = CommitGroup::open())
      group->atCommit([bytes = std::move(bytes)] { writeToStdout(bytes); });
    else
      writeToStdout(bytes);
    return;
  }
  // One atomic output (engine/base/atomic_output.h): complete or absent, never
  // through a symbolic link, and renamed with the run's other outputs.
  writeFileAtomically(path, encodeToMemory(job, path));
}

// Refuse images larger than any canvas bristle writes (64 Mpx, engine/model/canvas.h):
// their 16-bit RGBA decode needs at most 512 MiB, and a small file whose header
// claims 16384 x 16384 px (a decompression bomb) is an error before anything
// is allocated for it, not 2 GiB per image and an allocation failure.
constexpr auto kMaxReadPixels = static_cast<std::uint64_t>(kMaxCanvasPixels);

constexpr std::size_t kSignatureBytes = 8;

// libpng allocates a chunk other than IDAT whole, at the length its header
// claims, before reading it (png_set_chunk_malloc_max does not bound tEXt): a
// 106-byte file whose tEXt claims 1.7 GB made `compare` take 1.7 GB (found by
// fuzz/png.cpp). A chunk cannot be longer than the rest of the file, so the
// headers are walked first and such a file is refused; then back to just
// after the signature.
void checkChunkLengths(std::FILE* file, const std::string& path) {
  struct stat st {};
  if (::fstat(::fileno(file), &st) != 0) return;
  const auto size = static_cast<std::uint64_t>(st.st_size);
  std::uint64_t at = kSignatureBytes;
  unsigned char header[8];
  while (at + sizeof header <= size && std::fseek(file, static_cast<long>(at), SEEK_SET) == 0 &&
         std::fread(header, 1, sizeof header, file) == sizeof header) {
    const std::uint64_t length = png_get_uint_32(header);
    const std::string type(reinterpret_cast<const char*>(header + 4), 4);
    const std::uint64_t left = size - at - sizeof header;
    if (length > left)
      throw Error(ExitCode::kDataError,
                  path + ": " + type + ": a chunk of " + std::to_string(length) +
                      " bytes is longer than the " + std::to_string(left) +
                      " bytes left in the file (corrupt or truncated PNG)");
    if (type == "IEND") break;
    at += sizeof header + length + 4;  // the data and its CRC
  }
  if (std::fseek(file, static_cast<long>(kSignatureBytes), SEEK_SET) != 0)
    throw Error(ExitCode::kNoInput, path + ": cannot read: " + std::strerror(errno));
}

// The name messages give a PNG's path: "-" is standard input.
std::string shownName(const std::string& path) {
  return path == kStdioPath ? std::string(kStdinName) : path;
}

// Standard input, read whole (engine/base/text_file.h's limits) into a memory file
// that is then read as any PNG file is.
int standardInputAsFile() {
  const std::string bytes = readStandardInput();
  const int fd = ::memfd_create("bristle-stdin", MFD_CLOEXEC);
  auto fail = [&](int fd_to_close) {
    const std::string reason = std::strerror(errno);
    if (fd_to_close >= 0) ::close(fd_to_close);
    return Error(ExitCode::kNoInput, std::string(kStdinName) + ": cannot read: " + reason);
  };
  if (fd < 0) throw fail(-1);
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw fail(fd);
    done += static_cast<std::size_t>(n);
  }
  if (::lseek(fd, 0, SEEK_SET) != 0) throw fail(fd);
  return fd;
}

// Opens a PNG and consumes its signature. Throws kNoInput / kDataError.
std::FILE* openPng(const std::string& path) {
  // A regular file (a FIFO or a device is refused, and never blocks), no larger
  // than any input may be; or standard input for "-", read into a memory file.
  const std::string name = shownName(path);
  std::string why;
  const int fd = path == kStdioPath ? standardInputAsFile() : openInputFile(path, &why);
  if (fd < 0) throw Error(ExitCode::kNoInput, name + ": cannot read: " + why);
  struct stat st {};
  if (::fstat(fd, &st) == 0 && static_cast<std::uint64_t>(st.st_size) > kMaxInputBytes) {
    ::close(fd);
    throw Error(ExitCode::kDataError, name + ": size: " + std::to_string(st.st_size) +
                                          " bytes is over the input limit of " +
                                          std::to_string(kMaxInputBytes) + " bytes (256 MiB)");
  }
  std::FILE* file = ::fdopen(fd, "rb");
  if (file == nullptr) {
    const int open_errno = errno;
    ::close(fd);
    throw Error(ExitCode::kNoInput, name + ": cannot read: " + describeErrno(open_errno));
  }
  png_byte signature[kSignatureBytes] = {};
  const std::size_t got = std::fread(signature, 1, kSignatureBytes, file);
  if (got != kSignatureBytes && std::ferror(file)) {  // e.g. a directory
    const int read_errno = errno;
    std::fclose(file);
    throw Error(ExitCode::kNoInput, name + ": cannot read: " + describeErrno(read_errno));
  }
  if (got != kSignatureBytes || png_sig_cmp(signature, 0, kSignatureBytes) != 0) {
    std::fclose(file);
    throw Error(ExitCode::kDataError, name + ": not a PNG file");
  }
  try {
    checkChunkLengths(file, name);
  } catch (...) {
    std::fclose(file);
    throw;
  }
  return file;
}

// libpng read state; the destructor runs in the caller's frame, never skipped.
struct Decoder {
  png_structp png = nullptr;
  png_infop info = nullptr;
  PngFailure failure;
  int file_bit_depth = 0, file_channels = 0;  // before any transform
  ~Decoder() { png_destroy_read_struct(&png, &info, nullptr); }
};

// The text chunks a finished decode saw, before and after the image data.
PngText textOf(const Decoder& decoder) {
  png_textp chunks = nullptr;
  const int count = png_get_text(decoder.png, decoder.info, &chunks, nullptr);
  PngText text;
  for (int i = 0; i < count; ++i) {
    // iTXt carries its length in itxt_length; tEXt/zTXt in text_length.
    const std::size_t length =
        chunks[i].compression >= PNG_ITXT_COMPRESSION_NONE ? chunks[i].itxt_length
                                                           : chunks[i].text_length;
    text.emplace_back(chunks[i].key, std::string(chunks[i].text, length));
  }
  return text;
}

// What the decoder turns the file's pixels into.
enum class Decode { kNative, kRgba8, kRgba16 };

// Reads the header and arms the transforms (to 8- or 16-bit RGBA when asked).
bool readHeader(std::FILE* file, Decode to, Decoder* d, int* passes) {
  d->png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &d->failure, onPngError,
                                  onPngWarning);
  if (d->png == nullptr) return false;
  d->info = png_create_info_struct(d->png);
  if (d->info == nullptr) return false;
  if (setjmp(png_jmpbuf(d->png))) return false;
  png_init_io(d->png, file);
  png_set_sig_bytes(d->png, static_cast<int>(kSignatureBytes));
  png_read_info(d->png, d->info);
  d->file_bit_depth = png_get_bit_depth(d->png, d->info);
  d->file_channels = png_get_channels(d->png, d->info);
  if (to == Decode::kRgba8) {
    png_set_expand(d->png);  // palette -> RGB, grey < 8 bit -> 8 bit, tRNS -> alpha
    png_set_scale_16(d->png);  // rounds 65535 -> 255, unlike strip_16's truncation
    png_set_gray_to_rgb(d->png);
    png_set_add_alpha(d->png, 0xff, PNG_FILLER_AFTER);  // only where alpha is absent
  } else if (to == Decode::kRgba16) {
    png_set_expand(d->png);
    png_set_expand_16(d->png);  // v -> v * 257: 0..255 onto 0..65535 exactly
    png_set_gray_to_rgb(d->png);
    png_set_add_alpha(d->png, 0xffff, PNG_FILLER_AFTER);
    // PNG stores 16-bit samples big-endian; callers get host order.
    if (std::endian::native == std::endian::little) png_set_swap(d->png);
  }
  *passes = png_set_interlace_handling(d->png);
  png_read_update_info(d->png, d->info);
  return true;
}

// Decodes the pixels: into rows[] when given, else through one scratch row (to
// reach the text chunks that may follow the image data).
bool readBody(Decoder* d, png_bytep* rows, png_bytep scratch, int passes) {
  if (setjmp(png_jmpbuf(d->png))) return false;
  if (rows != nullptr) {
    png_read_image(d->png, rows);
  } else {
    const png_uint_32 height = png_get_image_height(d->png, d->info);
    for (int pass = 0; pass < passes; ++pass) {
      for (png_uint_32 r = 0; r < height; ++r) png_read_row(d->png, scratch, nullptr);
    }
  }
  png_read_end(d->png, d->info);
  return true;
}

Error corruptPng(const std::string& path, const Decoder& d) {
  return Error(ExitCode::kDataError,
               path + ": corrupt or truncated PNG: " + d.failure.message);
}

// The decoded RGBA pixels of decodePng, and the file's own layout.
struct Decoded {
  int width = 0, height = 0;
  std::vector<png_byte> bytes;  // rows top to bottom, host-order samples
  PngFormat format;
};

// Opens, decodes and hands the decoder (with text and header) to the caller;
// with `image` null only the text chunks are wanted.
void decodePng(const std::string& path, Decode to, Decoder* d, Decoded* image) {
  const std::string name = shownName(path);
  std::FILE* file = openPng(path);
  FileCloser closer{file};
  int passes = 1;
  if (!readHeader(file, to, d, &passes)) throw corruptPng(name, *d);
  const std::uint64_t width = png_get_image_width(d->png, d->info);
  const std::uint64_t height = png_get_image_height(d->png, d->info);
  const std::size_t row_bytes = png_get_rowbytes(d->png, d->info);
  if (width * height > kMaxReadPixels) {
    throw Error(ExitCode::kDataError,
                name + ": IHDR: " + std::to_string(width) + " x " + std::to_string(height) +
                    " px is over the limit of " + std::to_string(kMaxReadPixels) +
                    " px (64 Mpx, the largest canvas bristle writes)");
  }
  if (image == nullptr) {
    std::vector<png_byte> scratch(row_bytes);
    if (!readBody(d, nullptr, scratch.data(), passes)) throw corruptPng(name, *d);
    return;
  }
  const std::uint64_t sample_bytes = to == Decode::kRgba16 ? 2 : 1;
  if (row_bytes != width * 4 * sample_bytes) {
    throw Error(ExitCode::kDataError, name + ": unsupported PNG pixel layout");
  }
  image->width = static_cast<int>(width);
  image->height = static_cast<int>(height);
  image->format.bit_depth = d->file_bit_depth;
  image->format.channels = d->file_channels;
  image->bytes.resize(row_bytes * height);
  std::vector<png_bytep> rows(height);
  for (std::size_t r = 0; r < height; ++r) rows[r] = image->bytes.data() + row_bytes * r;
  if (!readBody(d, rows.data(), nullptr, passes)) throw corruptPng(name, *d);
}

}  // namespace

void writePng(const std::string& path, const Image8& image, const PngText& text) {
  writePngRows(path, image.width, image.height, image.channels, 8, image.pixels.data(),
               image.pixels.size(), text);
}

void writePng(const std::string& path, const Image16& image, const PngText& text) {
  writePngRows(path, image.width, image.height, image.channels, 16, image.pixels.data(),
               image.pixels.size() * sizeof(std::uint16_t), text);
}

Image8 readPngRgba8(const std::string& path) {
  Decoder decoder;
  Decoded decoded;
  decodePng(path, Decode::kRgba8, &decoder, &decoded);
  return Image8{decoded.width, decoded.height, 4, std::move(decoded.bytes)};
}

Image16 readPngRgba16(const std::string& path, PngFormat* format, PngText* text) {
  Decoder decoder;
  Decoded decoded;
  decodePng(path, Decode::kRgba16, &decoder, &decoded);
  if (text != nullptr) *text = textOf(decoder);
  Image16 image{decoded.width, decoded.height, 4, {}};
  image.pixels.resize(decoded.bytes.size() / 2);
  std::memcpy(image.pixels.data(), decoded.bytes.data(), decoded.bytes.size());
  if (format != nullptr) *format = decoded.format;
  return image;
}

PngText readPngText(const std::string& path) {
  Decoder decoder;
  decodePng(path, Decode::kNative, &decoder, nullptr);
  return textOf(decoder);
}

}  // namespace bristle::render

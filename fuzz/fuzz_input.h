#pragma once
// What every fuzz target shares (docs/errors.md, "Fuzzing"): the input as a
// string or as a file, and the promise each reader keeps for any input.

#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "engine/base/error.h"

namespace bristle::fuzz {

inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A reader may refuse an input only with bristle::Error, whose message is one
// printable line (engine/base/error.h): anything else escaping it (std::bad_alloc,
// a nlohmann exception, std::out_of_range) is what the CLI reports as an
// internal error (exit 70), and the fuzzer reports it as a crash.
inline void checkRefusal(const Error& e) {
  const int code = static_cast<int>(e.code());
  for (const char* c = e.what(); *c != '\0'; ++c)
    if (static_cast<unsigned char>(*c) < 0x20) std::abort();  // a message cut or split
  if (code != 65 && code != 66) std::abort();                // a reader's errors are 65 or 66
}

// The input as a regular file for readers that take a path (sessions, PNGs):
// an anonymous memory file, named /proc/self/fd/N, removed with this object.
class MemoryFile {
 public:
  MemoryFile(const std::uint8_t* data, std::size_t size) {
    fd_ = ::memfd_create("bristle-fuzz", MFD_CLOEXEC);
    if (fd_ < 0) std::abort();
    for (std::size_t done = 0; done < size;) {
      const ssize_t n = ::write(fd_, data + done, size - done);
      if (n <= 0) std::abort();
      done += static_cast<std::size_t>(n);
    }
    path_ = "/proc/self/fd/" + std::to_string(fd_);
  }
  ~MemoryFile() { ::close(fd_); }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  int fd_ = -1;
  std::string path_;
};

}  // namespace bristle::fuzz

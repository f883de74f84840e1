#include "engine/base/fnv1a64.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

#include "engine/base/error.h"
#include "engine/base/text_file.h"

namespace bristle {

std::uint64_t fnv1a64Files(const std::vector<std::string>& paths) {
  std::uint64_t h = kFnv1a64Offset;
  std::vector<char> buf(1 << 16);
  for (const std::string& path : paths) {
    // The inputs were read before they are hashed, but may have been swapped
    // since: a FIFO or a device is refused here too, and never blocks.
    std::string why;
    const int fd = openInputFile(path, &why);
    if (fd < 0)
      throw Error(ExitCode::kNoInput, path + ": cannot be read (for the inputs hash): " + why);
    for (;;) {
      const ssize_t n = ::read(fd, buf.data(), buf.size());
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        const std::string reason = std::strerror(errno);
        ::close(fd);
        throw Error(ExitCode::kNoInput, path + ": read error (for the inputs hash): " + reason);
      }
      if (n == 0) break;
      h = fnv1a64(std::string_view(buf.data(), static_cast<size_t>(n)), h);
    }
    ::close(fd);
  }
  return h;
}

std::string hex64(std::uint64_t h) {
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

}  // namespace bristle

#include "engine/fnv1a64.h"

#include <cstdio>
#include <fstream>
#include <iterator>

#include "engine/error.h"

namespace bristle {

std::uint64_t fnv1a64Files(const std::vector<std::string>& paths) {
  std::uint64_t h = kFnv1a64Offset;
  std::vector<char> buf(1 << 16);
  for (const std::string& path : paths) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(ExitCode::kNoInput, path + ": cannot be read (for the inputs hash)");
    while (in) {
      in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
      h = fnv1a64(std::string_view(buf.data(), static_cast<size_t>(in.gcount())), h);
    }
  }
  return h;
}

std::string hex64(std::uint64_t h) {
  char out[17];
  std::snprintf(out, sizeof out, "%016llx", static_cast<unsigned long long>(h));
  return out;
}

}  // namespace bristle

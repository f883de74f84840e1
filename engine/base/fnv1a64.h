#pragma once
// FNV-1a, 64 bit (Fowler, Noll, Vo; the parameters of the IETF draft
// draft-eastlake-fnv): a fast, stable hash of the input files' bytes, written
// into output PNGs ("bristle:inputs-fnv1a64") so an image says what made it.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace bristle {

inline constexpr std::uint64_t kFnv1a64Offset = 0xcbf29ce484222325ULL;
inline constexpr std::uint64_t kFnv1a64Prime = 0x100000001b3ULL;

// Continues hash `h` over `bytes` (start with kFnv1a64Offset).
constexpr std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t h = kFnv1a64Offset) {
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= kFnv1a64Prime;
  }
  return h;
}

// The hash over the bytes of the files, in order. Throws Error(kNoInput) naming
// a file that cannot be read.
std::uint64_t fnv1a64Files(const std::vector<std::string>& paths);
// 16 lower-case hex digits.
std::string hex64(std::uint64_t h);

}  // namespace bristle

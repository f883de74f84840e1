// The process heap policy of engine/base/heap_policy.h: blocks of a few MiB come
// from the heap and stay mapped once freed, so that the next solve's work
// arrays do not fault fresh pages in; very large blocks are still mapped on
// their own. Read off glibc's own accounting (mallinfo2): hblks counts the
// blocks mapped on their own, keepcost the free memory at the heap's top.
// Each TEST_CASE runs in a fresh process under ctest, where glibc's defaults
// map every block from 128 KiB up on its own: without the policy, the first
// check below fails (as it did while keepFreedHeap was compiled to a no-op).

#include <catch2/catch.hpp>
#include <cstdlib>
#include <cstring>

#include "engine/base/heap_policy.h"

#if defined(__GLIBC__)
#include <malloc.h>

namespace {

// MUMPS's per-factorisation work array for the round brush is 2.1 MB; 8 MiB
// is four times that and, under glibc's defaults, far above the 128 KiB
// from which a fresh process maps blocks on its own.
constexpr size_t kSolverBlockBytes = 8u << 20;
// A 2048 x 2048 canvas of RGBA floats: above the policy's 32 MiB threshold.
constexpr size_t kCanvasBytes = 64u << 20;

// Allocates, touches and frees n bytes; returns how many blocks glibc had
// mapped on their own while the block was live, beyond those before.
size_t mappedWhileLive(size_t n) {
  const size_t before = mallinfo2().hblks;
  void* volatile p = std::malloc(n);
  REQUIRE(p != nullptr);
  std::memset(p, 1, n);
  const size_t during = mallinfo2().hblks;
  std::free(p);
  return during - before;
}

}  // namespace

TEST_CASE("after keepFreedHeap a solver-sized block comes from the heap and stays there freed",
          "[heap]") {
  REQUIRE(bristle::keepFreedHeap());
  CHECK(mappedWhileLive(kSolverBlockBytes) == 0);
  // Still there for the next solve: the heap's top was not trimmed back.
  CHECK(mallinfo2().keepcost >= kSolverBlockBytes);
}

TEST_CASE("after keepFreedHeap a canvas-sized block is still mapped on its own", "[heap]") {
  REQUIRE(bristle::keepFreedHeap());
  CHECK(mappedWhileLive(kCanvasBytes) == 1);
}

#endif

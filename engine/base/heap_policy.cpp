#include "engine/base/heap_policy.h"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace bristle {

namespace {
// The largest block taken from the heap rather than mapped on its own: far
// above MUMPS's work arrays for bristle's KKT systems (under 1 MiB for the
// badger's 240 rows), below a 4096 x 4096 RGBA float canvas (256 MiB).
constexpr int kMmapThresholdBytes = 32 << 20;
// Freed memory kept at the heap's top: twice the above, glibc's own ratio
// between the two when it adjusts them.
constexpr int kTrimThresholdBytes = 64 << 20;
}  // namespace

bool keepFreedHeap() {
#if defined(__GLIBC__)
  return mallopt(M_MMAP_THRESHOLD, kMmapThresholdBytes) == 1 &&
         mallopt(M_TRIM_THRESHOLD, kTrimThresholdBytes) == 1;
#else
  return false;
#endif
}

}  // namespace bristle

#pragma once
// The process's heap policy for many small solves (docs/PERFORMANCE.md,
// "The heap's trim threshold").
//
// glibc's malloc hands freed memory at the top of its heap back to the kernel
// once more than M_TRIM_THRESHOLD lies there, and by default it raises that
// threshold only as far as twice the largest block it ever had to mmap. A
// solver that allocates and frees a work array a little larger than that on
// every factorisation (MUMPS does) makes the heap grow and shrink with brk
// several times per iteration, and every growth page-faults fresh zeroed
// pages back in: system time and cache misses for nothing.
//
// keepFreedHeap() fixes both thresholds (which also stops glibc adjusting
// them): blocks below 32 MiB come from the heap, and up to 64 MiB of freed
// heap stays mapped for the next solve. Canvases and readback buffers larger
// than 32 MiB are still mapped and unmapped on their own. Process-wide, so
// programs call it (the CLI's main, the benchmarks), not the engine.

namespace bristle {

// Returns false where the C library refused (not glibc, or an old one); the
// process then runs with the library's defaults, only slower.
bool keepFreedHeap();

}  // namespace bristle

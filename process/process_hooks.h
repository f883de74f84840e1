#pragma once
// Process-wide set-up that bristle's programs (the CLI, the test and bench
// programs) opt into at start, and that the libraries never do on their own:
// a library must not change its user's process behind its back
// (docs/api.md, "Process-wide set-up").
//
//  - getrusage: linking this library (an OBJECT library, bristle::process)
//    puts process/getrusage_override.cpp's getrusage in the executable, in
//    place of the C library's, so that Ipopt 3.11's per-iteration timers cost
//    no system call inside the solver (engine/solvers/ipopt/ipopt_timers.h).
//  - installProcessHooks(): bristle's dense KKT solver becomes Ipopt's MA27
//    (engine/solvers/ipopt/dense_kkt.h), 13-22% of a render's time
//    (docs/PERFORMANCE.md, "A dense KKT solver for Ipopt").
//
// A program that does neither gets Ipopt's own timers and MUMPS: correct,
// slower, and not bit for bit the command line's pixels. The handlers that
// remove temporary files on a signal are a command's own choice and stay an
// explicit call (installTempFileCleanup, engine/base/temp_files.h).

namespace bristle {

// Call once at start, before any solve. Idempotent.
void installProcessHooks();

}  // namespace bristle

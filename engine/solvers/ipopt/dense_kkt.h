#pragma once
// A linear solver for Ipopt's KKT systems that factors each independent block
// of the matrix: a small one densely with LAPACK's Bunch-Kaufman LDL^T
// (dsytrf), a large one (the spines hair volume couples) as a sparse LDL^T
// in a fixed quasi-definite order (sparse_ldl.h). It sits behind the calling
// convention of HSL's MA27, which Debian's Ipopt 3.11 accepts through its HSL
// loader (LSL_setMA27; docs/dynamics.md, "Ipopt's linear solver").
//
// Why: bristle's KKT systems are small (a spine of J joints gives 4J rows at most)
// and, without hair volume, block diagonal, one block per spine. MUMPS 5.5
// pays a fixed cost on every call (its driver sizes its own save file after
// each analysis, factorisation and solve), 13-22% of a render's time
// (docs/PERFORMANCE.md, "A dense KKT solver for Ipopt"). A dense block of 20
// rows factors in a few microseconds.
//
// MA27 keeps no state between calls: its caller holds the arrays. So the
// block structure and the factors live in the caller's IW and A arrays, laid
// out as dense_kkt.cpp describes. Kept besides, per thread, are what follows
// from the structure alone (where each triplet goes) and each sparse block's
// last few symbolic analyses: the next factorisation of the same structure
// reuses them and gives the same bits as a fresh one.

namespace bristle {

// The Fortran-convention entry points, with MA27's argument lists (all
// pointers; indices 1-based). Exposed for the tests, which check them against
// direct solves.
extern "C" {
void bristleDenseMa27i(int* icntl, double* cntl);
void bristleDenseMa27a(int* n, int* nz, const int* irn, const int* icn, int* iw, int* liw,
                       int* ikeep, int* iw1, int* nsteps, int* iflag, int* icntl, double* cntl,
                       int* info, double* ops);
void bristleDenseMa27b(int* n, int* nz, const int* irn, const int* icn, double* a, int* la,
                       int* iw, int* liw, int* ikeep, int* nsteps, int* maxfrt, int* iw1,
                       int* icntl, double* cntl, int* info);
void bristleDenseMa27c(int* n, double* a, int* la, int* iw, int* liw, double* w, int* maxfrt,
                       double* rhs, int* iw1, int* nsteps, int* icntl, double* cntl);
}

// Hands the functions above to Ipopt's HSL loader as its MA27. After this, an
// Ipopt whose option linear_solver is "ma27" uses them. Idempotent.
// Process-wide (every Ipopt in the process asking for MA27 gets these), so
// the library never calls it: a program does at start (process/process_hooks.h).
void installDenseKktSolver();

// Whether installDenseKktSolver was called. Until it is, the Ipopt solver
// leaves linear_solver at Ipopt's default (MUMPS): the same optima, reached
// more slowly, and not bit for bit the dense solver's.
bool denseKktSolverInstalled();

// How many symbolic analyses of sparse blocks this thread has made (each
// factorisation of a block whose structure, row order or zero entries
// changed since its last one). For the tests.
long long sparseKktAnalyses();

// The entries below the diagonal of L in this thread's last factorisation of
// a sparse block. For the tests.
long long lastSparseKktFill();

}  // namespace bristle

#include "engine/solvers/ipopt/dense_kkt.h"

#include <HSLLoader.h>

#include "engine/solvers/ipopt/sparse_ldl.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <list>
#include <memory>
#include <numeric>
#include <type_traits>
#include <utility>
#include <vector>

// LAPACK (reference LAPACK 3.11 on Debian), with gfortran's hidden lengths of
// the character arguments.
extern "C" {
void dsytrf_(const char* uplo, const int* n, double* a, const int* lda, int* ipiv, double* work,
             const int* lwork, int* info, std::size_t uplo_len);
void dsytrs_(const char* uplo, const int* n, const int* nrhs, const double* a, const int* lda,
             const int* ipiv, double* b, const int* ldb, int* info, std::size_t uplo_len);
}

namespace bristle {

static_assert(std::is_same_v<ipfint, int>, "Ipopt's Fortran integer is int");

// How the calls share their state through the caller's arrays:
//   IKEEP (3n, written by ma27a): [0, n) the rows in block order; [n, 2n)
//     each row's position in its block; [2n, 3n) each row's block.
//   NSTEPS (from ma27a): the number of blocks.
//   IW (written by ma27b): [0] n, [1] blocks, [2, 3 + blocks) each block's
//     first position in block order, then n pivot indices (dsytrf's, 1-based
//     within the block), then the n rows in block order (for ma27c, which
//     does not get IKEEP).
//   A (written by ma27b): block after block, s x s reals each: a dense
//     block's factor, column-major, L and D in the lower triangle; a sparse
//     block's D (s) and then the values of its L (below).
//   IW past those: for each sparse block, in block order, its permutation
//     (s), the column starts of its L (s + 1) and L's row indices (at most
//     s (s - 1) / 2), each block given that worst case.
// Blocks are the connected components of the matrix's graph: rows i and j are
// in one block when an entry (i, j) is given, whatever its value.
//
// A block of kSparseMinRows rows or more (the spines that hair volume couples
// into one NLP) is factored sparsely, as sparse_ldl.h says; a smaller one
// densely, with LAPACK's Bunch-Kaufman LDL^T (dsytrf).

namespace {

constexpr int kInfoFlag = 0, kInfoError = 1, kInfoRealsNeeded = 4, kInfoIntsNeeded = 5,
              kInfoRealsUsed = 8, kInfoIntsUsed = 9, kInfoNegative = 14;
// MA27's INFO(1): 0 success; 3 a warning, the matrix is singular (rank in
// INFO(2)); -1 n < 1; -2 nz < 0; -3 IW too small, -4 A too small (the size
// needed in INFO(2)); 1 an index out of range.
constexpr int kOk = 0, kSingular = 3, kBadN = -1, kBadNz = -2, kIwSmall = -3, kASmall = -4,
              kBadIndex = 1;

int findRoot(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Block sizes from IKEEP's block of each row.
std::vector<int> blockSizes(int n, int blocks, const int* ikeep) {
  std::vector<int> size(blocks, 0);
  for (int i = 0; i < n; ++i) ++size[ikeep[2 * n + i]];
  return size;
}

long long realsNeeded(const std::vector<int>& size) {
  long long total = 0;
  for (int s : size) total += static_cast<long long>(s) * s;
  return total;
}

// At and above this block size a block is factored sparsely. Below it, the
// dense Bunch-Kaufman factor costs a few microseconds; the blocks of brushes
// without hair volume (one spine, 16-28 rows) all stay dense, with their
// pixels. The coupled blocks of the brushes with hair volume, factored
// sparsely, take about two thirds of MUMPS's time (docs/PERFORMANCE.md,
// "Hair-volume groups factored sparsely").
constexpr int kSparseMinRows = 32;

bool sparseBlock(int s) { return s >= kSparseMinRows; }

long long intsNeeded(int n, int blocks, const std::vector<int>& size) {
  long long total = 3 + blocks + 2LL * n;
  for (int s : size)
    if (sparseBlock(s)) total += sparseInts(s);
  return total;
}

}  // namespace

extern "C" void bristleDenseMa27i(int* icntl, double* cntl) {
  std::fill(icntl, icntl + 30, 0);
  std::fill(cntl, cntl + 5, 0.0);
  icntl[0] = 6;  // MA27's default output streams; nothing here prints
  icntl[1] = 6;
  cntl[0] = 0.1;  // its pivot threshold; Bunch-Kaufman's own is fixed
}

extern "C" void bristleDenseMa27a(int* n, int* nz, const int* irn, const int* icn, int*, int*,
                                  int* ikeep, int*, int* nsteps, int*, int*, double*,
                                  int* info, double* ops) {
  std::fill(info, info + 20, 0);
  if (*n < 1) { info[kInfoFlag] = kBadN; return; }
  if (*nz < 0) { info[kInfoFlag] = kBadNz; return; }
  const int N = *n;
  std::vector<int> parent(N);
  std::iota(parent.begin(), parent.end(), 0);
  for (int k = 0; k < *nz; ++k) {
    const int i = irn[k] - 1, j = icn[k] - 1;
    if (i < 0 || i >= N || j < 0 || j >= N) { info[kInfoFlag] = kBadIndex; return; }
    const int ri = findRoot(parent, i), rj = findRoot(parent, j);
    if (ri != rj) parent[std::max(ri, rj)] = std::min(ri, rj);
  }
  // Blocks numbered by their first row; rows in increasing order within each.
  std::vector<int> block_of_root(N, -1);
  int blocks = 0;
  for (int i = 0; i < N; ++i) {
    const int r = findRoot(parent, i);
    if (block_of_root[r] < 0) block_of_root[r] = blocks++;
    ikeep[2 * N + i] = block_of_root[r];
  }
  const std::vector<int> size = blockSizes(N, blocks, ikeep);
  std::vector<int> next(blocks, 0);
  for (int b = 1; b < blocks; ++b) next[b] = next[b - 1] + size[b - 1];
  std::vector<int> first = next;
  for (int i = 0; i < N; ++i) {
    const int b = ikeep[2 * N + i];
    ikeep[N + i] = next[b] - first[b];
    ikeep[next[b]++] = i;
  }
  *nsteps = blocks;
  const long long reals = std::max<long long>(realsNeeded(size), *nz);
  info[kInfoRealsNeeded] = static_cast<int>(std::min<long long>(reals, 2147483647));
  info[kInfoIntsNeeded] =
      static_cast<int>(std::min<long long>(intsNeeded(N, blocks, size), 2147483647));
  double flops = 0;
  for (int s : size) flops += double(s) * s * s / 3;
  *ops = flops;
}

namespace {

// Negative and zero eigenvalues of the D of one factored block (dsytrf's 1 x 1
// and 2 x 2 pivots, by Sylvester's law of inertia the matrix's own).
void countInertia(int s, const double* f, const int* ipiv, int* negative, int* zero) {
  for (int k = 0; k < s;) {
    if (ipiv[k] > 0 || k + 1 == s) {
      const double d = f[k * s + k];
      *negative += d < 0;
      *zero += d == 0;
      k += 1;
      continue;
    }
    const double a = f[k * s + k], b = f[k * s + k + 1], c = f[(k + 1) * s + k + 1];
    const double det = a * c - b * b, trace = a + c;
    if (det < 0) {
      *negative += 1;
    } else if (det == 0) {
      *zero += (trace == 0) ? 2 : 1;
      *negative += trace < 0;
    } else {
      *negative += trace < 0 ? 2 : 0;
    }
    k += 2;
  }
}


// Where each triplet goes: for a dense block, its place in the block's s x s
// factor (summed there in the triplets' order); for a sparse block, -1, and
// the block's triplets are listed (in their order) for assembleSparseBlock.
// Both follow the structure alone, so they are kept while Ipopt hands over
// the same structure as the last call.
struct TripletPlaces {
  std::vector<int> last_irn, last_icn;
  int last_n = -1;
  std::vector<long long> dest;
  std::vector<int> sparse_start;    // block b's triplets: [sparse_start[b], sparse_start[b + 1])
  std::vector<int> sparse_entries;  // the sparse blocks' triplet indices k, block by block
  // Brings the places up to this call's structure; true if it is the last
  // call's (nothing to do).
  bool follow(int n, int nz, const int* irn, const int* icn, const int* ikeep,
              const std::vector<int>& size, const std::vector<long long>& offset) {
    if (last_n == n && static_cast<int>(last_irn.size()) == nz &&
        std::equal(irn, irn + nz, last_irn.begin()) && std::equal(icn, icn + nz, last_icn.begin()))
      return true;
    const int blocks = static_cast<int>(size.size());
    last_n = -1;  // until the lists below are made
    dest.assign(nz, -1);
    sparse_start.assign(blocks + 1, 0);
    for (int k = 0; k < nz; ++k) {
      const int i = irn[k] - 1, j = icn[k] - 1;
      const int b = ikeep[2 * n + i];
      const int s = size[b];
      if (sparseBlock(s)) {
        ++sparse_start[b + 1];
        continue;
      }
      const int li = ikeep[n + i], lj = ikeep[n + j];
      dest[k] = offset[b] + static_cast<long long>(std::min(li, lj)) * s + std::max(li, lj);
    }
    for (int b = 0; b < blocks; ++b) sparse_start[b + 1] += sparse_start[b];
    sparse_entries.resize(sparse_start[blocks]);
    std::vector<int> fill(sparse_start.begin(), sparse_start.end() - 1);
    for (int k = 0; k < nz; ++k) {
      const int b = ikeep[2 * n + irn[k] - 1];
      if (sparseBlock(size[b])) sparse_entries[fill[b]++] = k;
    }
    last_irn.assign(irn, irn + nz);
    last_icn.assign(icn, icn + nz);
    last_n = n;
    return false;
  }
};

// This thread's places (each simulation thread runs its own solves).
TripletPlaces& tripletPlaces() {
  thread_local TripletPlaces places;
  return places;
}

}  // namespace

extern "C" void bristleDenseMa27b(int* n, int* nz, const int* irn, const int* icn, double* a,
                                  int* la, int* iw, int* liw, int* ikeep, int* nsteps,
                                  int* maxfrt, int*, int*, double*, int* info) {
  std::fill(info, info + 20, 0);
  if (*n < 1) { info[kInfoFlag] = kBadN; return; }
  if (*nz < 0) { info[kInfoFlag] = kBadNz; return; }
  const int N = *n, blocks = *nsteps;
  const std::vector<int> size = blockSizes(N, blocks, ikeep);
  const long long reals = std::max<long long>(realsNeeded(size), *nz);
  if (reals > *la) {
    info[kInfoFlag] = kASmall;
    info[kInfoError] = static_cast<int>(std::min<long long>(reals, 2147483647));
    return;
  }
  const long long ints = intsNeeded(N, blocks, size);
  if (ints > *liw) {
    info[kInfoFlag] = kIwSmall;
    info[kInfoError] = static_cast<int>(std::min<long long>(ints, 2147483647));
    return;
  }
  std::vector<long long> offset(blocks + 1, 0);
  for (int b = 0; b < blocks; ++b) offset[b + 1] = offset[b] + static_cast<long long>(size[b]) * size[b];
  // The values arrive in a[0, nz), where the factors go: copy them out first.
  thread_local std::vector<double> values;
  values.assign(a, a + *nz);
  TripletPlaces& places = tripletPlaces();
  const bool same_structure = places.follow(N, *nz, irn, icn, ikeep, size, offset);
  const std::vector<long long>& dest = places.dest;
  const std::vector<int>& sparse_start = places.sparse_start;
  const std::vector<int>& sparse_entries = places.sparse_entries;
  for (int b = 0; b < blocks; ++b)
    if (!sparseBlock(size[b])) std::fill(a + offset[b], a + offset[b + 1], 0.0);
  for (int k = 0; k < *nz; ++k)
    if (dest[k] >= 0) a[dest[k]] += values[k];
  iw[0] = N;
  iw[1] = blocks;
  int* first = iw + 2;
  int* ipiv = first + blocks + 1;
  int* order = ipiv + N;
  first[0] = 0;
  for (int b = 0; b < blocks; ++b) first[b + 1] = first[b] + size[b];
  std::copy(ikeep, ikeep + N, order);
  int negative = 0, zero = 0, largest = 0;
  thread_local std::vector<double> work;
  // One cache per block index, per thread (each simulation thread runs its
  // own solves).
  thread_local std::vector<std::unique_ptr<SparseBlockCache>> caches;
  int* sparse_ints = order + N;
  for (int b = 0; b < blocks; ++b) {
    const int s = size[b];
    largest = std::max(largest, s);
    if (sparseBlock(s)) {
      const SparseEntries entries{irn, icn, values.data(), ikeep + N,
                                  sparse_entries.data() + sparse_start[b],
                                  sparse_start[b + 1] - sparse_start[b]};
      if (static_cast<int>(caches.size()) <= b) caches.resize(b + 1);
      if (!caches[b]) caches[b] = std::make_unique<SparseBlockCache>();
      factorSparseBlock(s, entries, same_structure, caches[b].get(), a + offset[b], sparse_ints,
                        &negative, &zero);
      sparse_ints += sparseInts(s);
      continue;
    }
    const int lwork = std::max(1, 64 * s);
    work.resize(lwork);
    int lapack_info = 0;
    dsytrf_("L", &s, a + offset[b], &s, ipiv + first[b], work.data(), &lwork, &lapack_info, 1);
    countInertia(s, a + offset[b], ipiv + first[b], &negative, &zero);
  }
  *maxfrt = largest;
  info[kInfoNegative] = negative;
  info[kInfoRealsUsed] = static_cast<int>(std::min<long long>(offset[blocks], 2147483647));
  info[kInfoIntsUsed] = static_cast<int>(std::min<long long>(ints, 2147483647));
  if (zero > 0) {
    info[kInfoFlag] = kSingular;
    info[kInfoError] = N - zero;  // the rank
  } else {
    info[kInfoFlag] = kOk;
  }
}

extern "C" void bristleDenseMa27c(int*, double* a, int*, int* iw, int*, double* w, int*,
                                  double* rhs, int*, int*, int*, double*) {
  const int N = iw[0], blocks = iw[1];
  const int* first = iw + 2;
  const int* ipiv = first + blocks + 1;
  const int* order = ipiv + N;
  const int* sparse_ints = order + N;
  long long offset = 0;
  const int one = 1;
  for (int b = 0; b < blocks; ++b) {
    const int s = first[b + 1] - first[b];
    for (int k = 0; k < s; ++k) w[k] = rhs[order[first[b] + k]];
    if (sparseBlock(s)) {
      solveSparseBlock(s, a + offset, sparse_ints, w);
      sparse_ints += sparseInts(s);
    } else {
      int lapack_info = 0;
      dsytrs_("L", &s, &one, a + offset, &s, ipiv + first[b], w, &s, &lapack_info, 1);
    }
    for (int k = 0; k < s; ++k) rhs[order[first[b] + k]] = w[k];
    offset += static_cast<long long>(s) * s;
  }
}


namespace {
std::atomic<bool> g_dense_kkt_installed{false};
}  // namespace

void installDenseKktSolver() {
  LSL_setMA27(&bristleDenseMa27a, &bristleDenseMa27b, &bristleDenseMa27c, &bristleDenseMa27i);
  g_dense_kkt_installed.store(true, std::memory_order_release);
}

bool denseKktSolverInstalled() { return g_dense_kkt_installed.load(std::memory_order_acquire); }

}  // namespace bristle

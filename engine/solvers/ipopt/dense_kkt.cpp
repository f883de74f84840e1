#include "engine/solvers/ipopt/dense_kkt.h"

#include <HSLLoader.h>

#include <Eigen/Sparse>
#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

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
// into one NLP: the round brush's 7 make about 200 rows) is factored as a
// sparse LDL^T with 1 x 1 pivots in a fixed order: first the rows whose
// diagonal is positive (the variables and slacks, whose block of Ipopt's KKT
// matrix is W + Sigma + delta; in a block of kOrderedMinRows or more, in
// minimum degree order), then the others (the constraints, zero on the
// diagonal). With the variables' block positive definite and the
// constraints' Jacobian of full rank, such a quasi-definite matrix has an
// LDL^T in any order with that split, whose D has n_x positive and n_c
// negative entries: the inertia Ipopt asks for. Where the variables' block is
// not positive definite, D shows it by its signs (Sylvester's law of inertia),
// and Ipopt shifts the Hessian as it does for any solver. A zero or
// non-finite pivot reports the matrix singular, and Ipopt regularises it.
// Without pivoting for size, a tiny positive pivot could lose accuracy; Ipopt
// checks each solve's residual and refines it.

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

// The integers a sparse block of s rows keeps in IW, at most.
long long sparseInts(int s) {
  return static_cast<long long>(s) + (s + 1) + static_cast<long long>(s) * (s - 1) / 2;
}

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

// A sparse block's matrix. Its indices are Eigen::Index because Eigen 3.4
// skips the copy into its own ordering only for NaturalOrdering<Eigen::Index>
// (SimplicialCholeskyBase::ordering); with int indices every factorisation
// copied the matrix twice.
using SparseBlock = Eigen::SparseMatrix<double, Eigen::ColMajor, Eigen::Index>;

// One sparse block's entries: the triplets (1-based irn, icn) whose rows lie
// in it, `mine` indexing them in the caller's order, and each row's position
// in the block (IKEEP's second third).
struct SparseEntries {
  const int* irn;
  const int* icn;
  const double* values;
  const int* local;
  const int* mine;
  int count;
};

thread_local long long analyses = 0;  // sparseKktAnalyses()
thread_local long long last_fill = 0;  // lastSparseKktFill()

// One analysed pattern of a sparse block: a row order, the slots of the
// block's triplets in that order, which slots were not zero, and Eigen's
// symbolic analysis of the resulting compressed matrix.
struct SparseAnalysis {
  std::vector<int> perm;  // position k of the factor holds block row perm[k]
  // Each triplet's slot: an off-diagonal slot (>= 0), or -1 - its row's
  // position for a diagonal. Slots are numbered column by column of the
  // factor's upper triangle, rows ascending within a column.
  std::vector<int> slot;
  std::vector<int> column_start;  // slots of column c: [column_start[c], column_start[c + 1])
  std::vector<int> slot_row;
  std::vector<char> kept;  // slots whose sum was not zero
  bool analysed = false;   // ldlt has analysed m's pattern
  SparseBlock m;
  // The upper triangle with the natural order: Eigen factors it in place,
  // without a copy.
  Eigen::SimplicialLDLT<SparseBlock, Eigen::Upper, Eigen::NaturalOrdering<Eigen::Index>> ldlt;
};

// What one sparse block keeps from its recent factorisations, so that the
// next one with the same pattern skips the assembly's sorting and Eigen's
// symbolic analysis. Within a render the triplets' structure stays the same;
// the rows' order (positive diagonal first) and which off-diagonal sums are
// exactly zero follow the values. Both flip back and forth (Ipopt's inertia
// corrections shift the diagonal and drop the shift again), so a few
// patterns are kept, the most recently used first. A factorisation on a kept
// pattern is the same arithmetic as on a fresh analysis: the same sums in
// the triplets' order, the same compressed matrix, the same Eigen calls
// (compute is analyzePattern then factorize).
struct SparseBlockCache {
  std::vector<int> irn, icn;  // the block's triplets, in the caller's order
  std::list<SparseAnalysis> recent;  // the most recently used first
  // A large block's rows with a positive diagonal in minimum degree order:
  // for which rows it was computed, and the order (block rows).
  std::vector<char> ordered_positive;
  std::vector<int> positive_order;
};

// How many patterns a block keeps. A block's pattern changes as hairs touch
// the paper and volume links come in range, and often comes back: with 4
// kept the round analyses a fifth of its factorisations afresh, with 1 a
// third, and 8 gain little more; the rest change for good as the stroke
// goes on (docs/PERFORMANCE.md, "Hair-volume groups factored sparsely").
constexpr std::size_t kPatternsKept = 4;

// The slots of a block's structure in the order a->perm: off-diagonal
// triplets bucketed by their row in the factor (stably), then dealt to their
// columns row by row, so each column's rows ascend and the triplets of one
// entry share its slot.
void numberSlots(int s, const SparseEntries& e, SparseAnalysis* a) {
  thread_local std::vector<int> pos, count, next, column_of, by_row, last_row, per_column;
  pos.resize(s);
  for (int k = 0; k < s; ++k) pos[a->perm[k]] = k;
  count.assign(s + 1, 0);
  a->slot.assign(e.count, 0);
  column_of.assign(e.count, 0);
  for (int k = 0; k < e.count; ++k) {
    const int t = e.mine[k];
    const int i = pos[e.local[e.irn[t] - 1]], j = pos[e.local[e.icn[t] - 1]];
    if (i == j) {
      a->slot[k] = -1 - i;
      continue;
    }
    ++count[1 + std::min(i, j)];
    column_of[k] = std::max(i, j);
  }
  for (int r = 0; r < s; ++r) count[r + 1] += count[r];
  by_row.resize(count[s]);  // triplet k, grouped by its row in the factor
  next.assign(count.begin(), count.end() - 1);
  for (int k = 0; k < e.count; ++k) {
    if (a->slot[k] < 0) continue;
    const int t = e.mine[k];
    by_row[next[std::min(pos[e.local[e.irn[t] - 1]], pos[e.local[e.icn[t] - 1]])]++] = k;
  }
  // Rows in order; a triplet opens a slot unless its column's last slot is
  // on its row. Counted first, then numbered.
  last_row.assign(s, -1);
  per_column.assign(s, 0);
  for (int r = 0; r < s; ++r)
    for (int q = count[r]; q < count[r + 1]; ++q) {
      const int col = column_of[by_row[q]];
      if (last_row[col] != r) { last_row[col] = r; ++per_column[col]; }
    }
  a->column_start.assign(s + 1, 0);
  for (int col = 0; col < s; ++col) a->column_start[col + 1] = a->column_start[col] + per_column[col];
  a->slot_row.resize(a->column_start[s]);
  next.assign(a->column_start.begin(), a->column_start.end() - 1);
  last_row.assign(s, -1);
  for (int r = 0; r < s; ++r)
    for (int q = count[r]; q < count[r + 1]; ++q) {
      const int k = by_row[q], col = column_of[k];
      if (last_row[col] != r) {
        last_row[col] = r;
        a->slot_row[next[col]++] = r;
      }
      a->slot[k] = next[col] - 1;
    }
}

// The rows' order of a block with diagonal `diag`: the positive ones first.
void positiveFirst(const std::vector<double>& diag, std::vector<int>* perm) {
  const int s = static_cast<int>(diag.size());
  perm->resize(s);
  int j = 0;
  for (int k = 0; k < s; ++k)
    if (diag[k] > 0) (*perm)[j++] = k;
  for (int k = 0; k < s; ++k)
    if (!(diag[k] > 0)) (*perm)[j++] = k;
}

// At and above this many rows, a sparse block's rows of positive diagonal
// are put in approximate minimum degree order (Eigen's AMD) before the
// factorisation; smaller blocks keep the rows' own order. The badger's 15
// coupled spines make blocks of 140-220 rows whose natural order fills L to
// three or four times its entries, and ordering them saves an eighth of its render with the same
// iterations and pixels. The round's smaller blocks gain nothing, and a new
// order would move the last bits of their iterates (docs/PERFORMANCE.md,
// "Hair-volume groups factored sparsely").
constexpr int kOrderedMinRows = 144;

// The positive rows of a large block (perm's first part, from positiveFirst)
// put in approximate minimum degree order of their pattern, as Eigen's AMD
// computes it. Any order of them keeps the block quasi-definite (its
// constraints still come last), so D's signs still give the inertia. The
// order depends on the structure alone; it is kept for the same set of
// positive rows until the block's structure changes.
void positiveInDegreeOrder(int s, const SparseEntries& e, const std::vector<double>& diag,
                           SparseBlockCache* c, std::vector<int>* perm) {
  std::vector<char> positive(s);
  for (int k = 0; k < s; ++k) positive[k] = diag[k] > 0;
  if (positive != c->ordered_positive) {
    std::vector<int> index(s, -1);
    int np = 0;
    for (int k = 0; k < s; ++k)
      if (positive[k]) index[k] = np++;
    std::vector<Eigen::Triplet<double, int>> pattern;
    pattern.reserve(e.count + np);
    for (int k = 0; k < np; ++k) pattern.emplace_back(k, k, 1.0);
    for (int k = 0; k < e.count; ++k) {
      const int t = e.mine[k];
      const int i = index[e.local[e.irn[t] - 1]], j = index[e.local[e.icn[t] - 1]];
      if (i >= 0 && j >= 0 && i != j) pattern.emplace_back(std::max(i, j), std::min(i, j), 1.0);
    }
    Eigen::SparseMatrix<double, Eigen::ColMajor, int> m(np, np);
    m.setFromTriplets(pattern.begin(), pattern.end());
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> order;
    Eigen::AMDOrdering<int>()(m.selfadjointView<Eigen::Lower>(), order);
    std::vector<int> rows;
    rows.reserve(np);
    for (int k = 0; k < s; ++k)
      if (positive[k]) rows.push_back(k);
    c->positive_order.resize(np);
    for (int k = 0; k < np; ++k) c->positive_order[k] = rows[order.indices()[k]];
    c->ordered_positive = std::move(positive);
  }
  std::copy(c->positive_order.begin(), c->positive_order.end(), perm->begin());
}

// The kept analysis for this row order and these sums, moved to the front of
// c->recent, or a new one there (the least recently used dropped), whose
// pattern the caller analyses. `sums` are per slot of the order's numbering.
SparseAnalysis* patternFor(int s, const SparseEntries& e, const std::vector<int>& perm,
                           SparseBlockCache* c, std::vector<double>* sums) {
  auto& recent = c->recent;
  auto numbering = std::find_if(recent.begin(), recent.end(),
                                [&](const SparseAnalysis& a) { return a.perm == perm; });
  if (numbering == recent.end()) {
    recent.emplace_front();
    numbering = recent.begin();
    numbering->perm = perm;
    numberSlots(s, e, &*numbering);
  }
  const int slots = numbering->column_start[s];
  sums->assign(slots, 0.0);
  for (int k = 0; k < e.count; ++k)
    if (numbering->slot[k] >= 0) (*sums)[numbering->slot[k]] += e.values[e.mine[k]];
  auto same_zeros = [&](const SparseAnalysis& a) {
    if (!a.analysed || a.perm != perm) return false;
    for (int q = 0; q < slots; ++q)
      if (((*sums)[q] != 0) != bool(a.kept[q])) return false;
    return true;
  };
  auto hit = std::find_if(recent.begin(), recent.end(), same_zeros);
  if (hit != recent.end()) {
    recent.splice(recent.begin(), recent, hit);
    return &recent.front();
  }
  if (numbering->analysed) {  // the same order with other zeros: a new pattern
    recent.emplace_front();
    SparseAnalysis& fresh = recent.front();
    fresh.perm = perm;
    fresh.slot = numbering->slot;
    fresh.column_start = numbering->column_start;
    fresh.slot_row = numbering->slot_row;
    numbering = recent.begin();
  }
  recent.splice(recent.begin(), recent, numbering);
  if (recent.size() > kPatternsKept) recent.pop_back();
  SparseAnalysis& a = recent.front();
  a.kept.resize(slots);
  for (int q = 0; q < slots; ++q) a.kept[q] = (*sums)[q] != 0;
  a.m.resize(s, s);
  a.m.resizeNonZeros(std::count(a.kept.begin(), a.kept.end(), 1) + s);
  return &a;
}

// Assembles one sparse block, in the factor's order, as the upper triangle of
// a compressed-column matrix: duplicates summed from 0 in the triplets'
// order, off-diagonal zeros left out and every diagonal present. The order
// puts the rows with a positive diagonal first. Returns the analysis whose
// matrix m holds it, ready to factorize. `same_structure`: the caller's whole
// matrix has the structure of its last call.
SparseAnalysis* assembleSparseBlock(int s, const SparseEntries& e, bool same_structure,
                                    SparseBlockCache* c) {
  thread_local std::vector<double> diag, sums;
  thread_local std::vector<int> perm;
  diag.assign(s, 0.0);
  for (int k = 0; k < e.count; ++k) {
    const int t = e.mine[k];
    if (e.irn[t] == e.icn[t]) diag[e.local[e.irn[t] - 1]] += e.values[t];
  }
  positiveFirst(diag, &perm);
  // The whole matrix's structure as at the last call (which therefore left
  // this block's cache on it), or else this block's triplets compared.
  auto block_unchanged = [&] {
    if (static_cast<int>(c->irn.size()) != e.count) return false;
    for (int k = 0; k < e.count; ++k)
      if (c->irn[k] != e.irn[e.mine[k]] || c->icn[k] != e.icn[e.mine[k]]) return false;
    return true;
  };
  if (!same_structure && !block_unchanged()) {
    c->recent.clear();
    c->ordered_positive.clear();
    c->irn.resize(e.count);
    c->icn.resize(e.count);
    for (int k = 0; k < e.count; ++k) {
      c->irn[k] = e.irn[e.mine[k]];
      c->icn[k] = e.icn[e.mine[k]];
    }
  }
  if (s >= kOrderedMinRows) positiveInDegreeOrder(s, e, diag, c, &perm);
  SparseAnalysis* a = patternFor(s, e, perm, c, &sums);
  Eigen::Index* start = a->m.outerIndexPtr();
  Eigen::Index* row = a->m.innerIndexPtr();
  double* value = a->m.valuePtr();
  Eigen::Index out = 0;
  for (int col = 0; col < s; ++col) {
    start[col] = out;
    for (int q = a->column_start[col]; q < a->column_start[col + 1]; ++q) {
      if (!a->kept[q]) continue;
      row[out] = a->slot_row[q];
      value[out++] = sums[q];
    }
    row[out] = col;
    value[out++] = diag[perm[col]];
  }
  start[s] = out;
  if (!a->analysed) {
    a->ldlt.analyzePattern(a->m);
    a->analysed = true;
    ++analyses;
  }
  return a;
}

// Factors one sparse block from its entries into f (D, then L's values) and
// ints (the permutation, L's column starts and row indices). Adds D's
// negative and zero entries to the counts; a failed factorisation counts every
// row as zero. `cache` is the block's cache from the last factorisation.
void factorSparseBlock(int s, const SparseEntries& entries, bool same_structure,
                       SparseBlockCache* cache, double* f, int* ints, int* negative, int* zero) {
  SparseAnalysis* a = assembleSparseBlock(s, entries, same_structure, cache);
  int* perm = ints;  // position k of the factor holds row perm[k] of the block
  std::copy(a->perm.begin(), a->perm.end(), perm);
  auto& ldlt = a->ldlt;
  ldlt.factorize(a->m);
  bool ok = ldlt.info() == Eigen::Success;
  const Eigen::VectorXd d = ok ? Eigen::VectorXd(ldlt.vectorD()) : Eigen::VectorXd();
  for (int k = 0; ok && k < s; ++k) ok = std::isfinite(d(k)) && d(k) != 0;
  if (!ok) {
    *zero += s;
    std::fill(f, f + s, 0.0);
    std::fill(perm + s, perm + 2 * s + 1, 0);  // an empty L: a solve reads nothing stale
    return;
  }
  // L is unit lower triangular; its strict lower part, column by column.
  const SparseBlock& l = ldlt.matrixL().nestedExpression();
  int* start = perm + s;
  int* row = start + s + 1;
  double* value = f + s;
  int count = 0;
  for (int c = 0; c < s; ++c) {
    start[c] = count;
    for (SparseBlock::InnerIterator it(l, c); it; ++it) {
      if (it.row() <= c) continue;
      row[count] = static_cast<int>(it.row());
      value[count] = it.value();
      ++count;
    }
  }
  start[s] = count;
  last_fill = count;
  for (int k = 0; k < s; ++k) {
    f[k] = d(k);
    *negative += d(k) < 0;
  }
}

// Solves with a block factored by factorSparseBlock, in place on w (block order).
void solveSparseBlock(int s, const double* f, const int* ints, double* w) {
  const int* perm = ints;
  const int* start = perm + s;
  const int* row = start + s + 1;
  const double* value = f + s;
  thread_local std::vector<double> x;
  x.resize(s);
  for (int k = 0; k < s; ++k) x[k] = w[perm[k]];
  for (int c = 0; c < s; ++c)
    for (int p = start[c]; p < start[c + 1]; ++p) x[row[p]] -= value[p] * x[c];
  for (int k = 0; k < s; ++k) x[k] /= f[k];
  for (int c = s - 1; c >= 0; --c)
    for (int p = start[c]; p < start[c + 1]; ++p) x[c] -= value[p] * x[row[p]];
  for (int k = 0; k < s; ++k) w[perm[k]] = x[k];
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

long long sparseKktAnalyses() { return analyses; }
long long lastSparseKktFill() { return last_fill; }

namespace {
std::atomic<bool> g_dense_kkt_installed{false};
}  // namespace

void installDenseKktSolver() {
  LSL_setMA27(&bristleDenseMa27a, &bristleDenseMa27b, &bristleDenseMa27c, &bristleDenseMa27i);
  g_dense_kkt_installed.store(true, std::memory_order_release);
}

bool denseKktSolverInstalled() { return g_dense_kkt_installed.load(std::memory_order_acquire); }

}  // namespace bristle

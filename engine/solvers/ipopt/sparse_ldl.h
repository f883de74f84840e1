#pragma once
// The sparse LDL^T of dense_kkt.h's large blocks: the KKT block of the spines
// that hair volume couples into one NLP (the round's 7 make about 200 rows).
// Factored with 1 x 1 pivots in a fixed order: first the rows whose diagonal
// is positive (the variables and slacks, whose block of Ipopt's KKT matrix is
// W + Sigma + delta; in a block of kOrderedMinRows or more, in minimum degree
// order), then the others (the constraints, zero on the diagonal). With the
// variables' block positive definite and the constraints' Jacobian of full
// rank, such a quasi-definite matrix has an LDL^T in any order with that
// split, whose D has n_x positive and n_c negative entries: the inertia Ipopt
// asks for. Where the variables' block is not positive definite, D shows it by
// its signs (Sylvester's law of inertia), and Ipopt shifts the Hessian as it
// does for any solver. A zero or non-finite pivot reports the matrix
// singular, and Ipopt regularises it. Without pivoting for size, a tiny
// positive pivot could lose accuracy; Ipopt checks each solve's residual and
// refines it.
//
// The factor lives in the caller's arrays (MA27 keeps no state between
// calls): D and L's values in the reals, the permutation and L's pattern in
// the integers. What follows from the structure alone is kept per block
// (SparseBlockCache), so the next factorisation of the same pattern skips the
// symbolic work and gives the same bits as a fresh one.

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <list>
#include <vector>

namespace bristle {

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

// The integers a sparse block of s rows keeps in the caller's IW, at most:
// the permutation (s), L's column starts (s + 1) and its row indices.
inline long long sparseInts(int s) {
  return static_cast<long long>(s) + (s + 1) + static_cast<long long>(s) * (s - 1) / 2;
}

// Factors one sparse block from its entries into f (D, then L's values) and
// ints (the permutation, L's column starts and row indices). Adds D's
// negative and zero entries to the counts; a failed factorisation counts every
// row as zero. `cache` is the block's cache from the last factorisation.
void factorSparseBlock(int s, const SparseEntries& entries, bool same_structure,
                       SparseBlockCache* cache, double* f, int* ints, int* negative, int* zero);

// Solves with a block factored by factorSparseBlock, in place on w (block order).
void solveSparseBlock(int s, const double* f, const int* ints, double* w);

}  // namespace bristle

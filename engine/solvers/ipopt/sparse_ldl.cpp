#include "engine/solvers/ipopt/sparse_ldl.h"

#include <Eigen/OrderingMethods>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>

#include "engine/solvers/ipopt/dense_kkt.h"

namespace bristle {

namespace {

thread_local long long analyses = 0;  // sparseKktAnalyses()
thread_local long long last_fill = 0;  // lastSparseKktFill()

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

}  // namespace

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

long long sparseKktAnalyses() { return analyses; }
long long lastSparseKktFill() { return last_fill; }

}  // namespace bristle

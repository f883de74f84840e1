// The dense KKT solver that Ipopt can use in MA27's place (engine/solvers/ipopt/dense_kkt.h),
// through MA27's own calling sequence as Ipopt's interface makes it: solutions
// against the matrix, inertia against Eigen's eigenvalues, and MA27's error
// codes for singular matrices, short workspaces and bad indices.

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "engine/solvers/ipopt/dense_kkt.h"

using namespace bristle;

namespace {

// A solve of a well-conditioned system of size <= 48 in double precision
// leaves a residual of ~1e-14 relative to |A| |x|; 1e-10 is far above that
// and far below any wrong factor or permutation.
constexpr double kResidualTol = 1e-10;

// A symmetric matrix as Ipopt hands it over: 1-based triplets, each
// off-diagonal entry once (in either triangle), some entries split in two
// triplets that add up, and entries that are structurally there but zero.
struct Triplets {
  int n = 0;
  std::vector<int> irn, icn;
  std::vector<double> val;
  Eigen::MatrixXd dense() const {
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
    for (size_t k = 0; k < val.size(); ++k) {
      const int i = irn[k] - 1, j = icn[k] - 1;
      m(i, j) += val[k];
      if (i != j) m(j, i) += val[k];
    }
    return m;
  }
  void add(int i, int j, double v) {  // 0-based
    irn.push_back(i + 1);
    icn.push_back(j + 1);
    val.push_back(v);
  }
};

// Blocks of the given sizes, on the rows listed in `rows` (so that a block's
// rows are not contiguous), each a KKT matrix [H J^T; J 0] with H indefinite
// when `kkt`, else a dense random symmetric matrix.
Triplets blockMatrix(const std::vector<int>& sizes, const std::vector<int>& rows, bool kkt,
                     std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Triplets t;
  t.n = static_cast<int>(rows.size());
  int start = 0;
  for (int s : sizes) {
    const int m = kkt ? s / 3 : 0;  // constraint rows at the block's end
    for (int c = 0; c < s; ++c)
      for (int r = c; r < s; ++r) {
        const bool constraint_block = r >= s - m && c >= s - m;
        const int i = rows[start + r], j = rows[start + c];
        if (constraint_block) {
          if (r == c) t.add(i, j, 0.0);  // a structural zero on the diagonal
          continue;
        }
        double v = u(rng);
        if (r == c && !kkt) v += (c % 2 == 0 ? 3.0 : -3.0);
        if ((r + c) % 3 == 0) {  // split into two triplets, one transposed
          t.add(i, j, 0.25 * v);
          t.add(j, i, 0.75 * v);
        } else {
          t.add(r % 2 ? i : j, r % 2 ? j : i, v);
        }
      }
    start += s;
  }
  return t;
}

struct Ma27Run {
  int iflag_a = 0, iflag_b = 0, negative = 0, error_b = 0;
  std::vector<double> x;
};

// Ipopt's sequence (IpMa27TSolverInterface): ma27i, ma27a, workspaces from
// its advice (times `factor`), ma27b, then ma27c per right-hand side.
Ma27Run runMa27(const Triplets& t, const Eigen::VectorXd& b, double factor = 5) {
  int icntl[30];
  double cntl[5];
  bristleDenseMa27i(icntl, cntl);
  int n = t.n, nz = static_cast<int>(t.val.size());
  int liw = 2 * (2 * nz + 3 * n + 1);
  std::vector<int> iw(liw), ikeep(3 * n), iw1(2 * n);
  int nsteps = 0, iflag = 0, info[20];
  double ops = 0;
  Ma27Run run;
  bristleDenseMa27a(&n, &nz, t.irn.data(), t.icn.data(), iw.data(), &liw, ikeep.data(),
                    iw1.data(), &nsteps, &iflag, icntl, cntl, info, &ops);
  run.iflag_a = info[0];
  if (run.iflag_a != 0) return run;
  int la = std::max(nz, static_cast<int>(factor * info[4]));
  liw = std::max(1, static_cast<int>(factor * info[5]));
  std::vector<double> a(la);
  iw.assign(liw, 0);
  std::copy(t.val.begin(), t.val.end(), a.begin());
  int maxfrt = 0;
  bristleDenseMa27b(&n, &nz, t.irn.data(), t.icn.data(), a.data(), &la, iw.data(), &liw,
                    ikeep.data(), &nsteps, &maxfrt, iw1.data(), icntl, cntl, info);
  run.iflag_b = info[0];
  run.error_b = info[1];
  run.negative = info[14];
  if (run.iflag_b != 0) return run;
  std::vector<double> w(maxfrt);
  run.x.assign(b.data(), b.data() + n);
  std::vector<int> iw1_solve(std::max(1, nsteps));
  bristleDenseMa27c(&n, a.data(), &la, iw.data(), &liw, w.data(), &maxfrt, run.x.data(),
                    iw1_solve.data(), &nsteps, icntl, cntl);
  return run;
}

int negativeEigenvalues(const Eigen::MatrixXd& m) {
  const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(m).eigenvalues();
  return static_cast<int>((ev.array() < 0).count());
}

}  // namespace

TEST_CASE("dense KKT solver: solutions and inertia of block matrices, as MA27 gives them",
          "[solvers][dense_kkt]") {
  std::mt19937 rng(17);
  const bool kkt = GENERATE(false, true);
  const std::vector<int> sizes = kkt ? std::vector<int>{12, 6, 21, 3} : std::vector<int>{1, 5, 12, 2};
  int n = 0;
  for (int s : sizes) n += s;
  std::vector<int> rows(n);
  for (int i = 0; i < n; ++i) rows[i] = i;
  std::shuffle(rows.begin(), rows.end(), rng);
  const Triplets t = blockMatrix(sizes, rows, kkt, rng);
  const Eigen::MatrixXd m = t.dense();
  Eigen::VectorXd b(n);
  for (int i = 0; i < n; ++i) b[i] = std::sin(1.0 + i);
  const Ma27Run run = runMa27(t, b);
  REQUIRE(run.iflag_a == 0);
  REQUIRE(run.iflag_b == 0);
  CHECK(run.negative == negativeEigenvalues(m));
  if (kkt) {
    // [H J^T; J 0] with J of full row rank has at least m negative eigenvalues.
    int constraints = 0;
    for (int s : sizes) constraints += s / 3;
    CHECK(run.negative >= constraints);
  }
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(run.x.data(), n);
  const double scale = (m.cwiseAbs() * x.cwiseAbs()).maxCoeff();
  CHECK((m * x - b).cwiseAbs().maxCoeff() <= kResidualTol * scale);

  // The same structure again with other values, as Ipopt's next iteration
  // hands it over: the places of the triplets, kept from the last call, must
  // take the new values (dense_kkt.cpp keeps them while the structure holds).
  Triplets again = t;
  for (size_t k = 0; k < again.val.size(); ++k) again.val[k] *= 1.5;
  const Eigen::MatrixXd m2 = again.dense();
  const Ma27Run run2 = runMa27(again, b);
  REQUIRE(run2.iflag_b == 0);
  CHECK(run2.negative == negativeEigenvalues(m2));
  const Eigen::VectorXd x2 = Eigen::Map<const Eigen::VectorXd>(run2.x.data(), n);
  CHECK((m2 * x2 - b).cwiseAbs().maxCoeff() <=
        kResidualTol * (m2.cwiseAbs() * x2.cwiseAbs()).maxCoeff());
  CHECK((x2 - x / 1.5).cwiseAbs().maxCoeff() <= kResidualTol * x.cwiseAbs().maxCoeff());
}

namespace {

// A KKT matrix of Ipopt's shape for `spines` spines coupled in a chain, the
// size of the blocks hair volume makes: per spine 8 variables (a banded
// Hessian H, made indefinite by `indefinite`), 4 slacks with Sigma on the
// diagonal, and 4 constraint rows (zero on the diagonal) each coupling its
// slack (-1) and some of the spine's variables; neighbouring spines' variables
// coupled in H. Rows shuffled. With `empty_row`, one constraint row keeps only
// structural zeros, so the matrix is singular.
Triplets volumeKkt(int spines, bool indefinite, bool empty_row, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1, 1), sigma(0.01, 100);
  constexpr int kVars = 8, kCons = 4;
  const int per = kVars + 2 * kCons, n = spines * per;
  std::vector<int> rows(n);
  for (int i = 0; i < n; ++i) rows[i] = i;
  std::shuffle(rows.begin(), rows.end(), rng);
  auto var = [&](int s, int v) { return rows[s * per + v]; };
  auto slack = [&](int s, int c) { return rows[s * per + kVars + c]; };
  auto con = [&](int s, int c) { return rows[s * per + kVars + kCons + c]; };
  Triplets t;
  t.n = n;
  for (int s = 0; s < spines; ++s) {
    for (int v = 0; v < kVars; ++v) {
      t.add(var(s, v), var(s, v), (indefinite && v % 5 == 2 ? -4.0 : 4.0) + u(rng));
      for (int w = v + 1; w < std::min(kVars, v + 3); ++w) t.add(var(s, w), var(s, v), u(rng));
      if (s > 0) t.add(var(s, v), var(s - 1, kVars - 1 - v), 0.3 * u(rng));
    }
    for (int c = 0; c < kCons; ++c) {
      t.add(slack(s, c), slack(s, c), sigma(rng));
      t.add(con(s, c), con(s, c), 0.0);
      const bool empty = empty_row && s == spines / 2 && c == 1;
      t.add(con(s, c), slack(s, c), empty ? 0.0 : -1.0);
      for (int v = 0; v <= 2 * c + 1; ++v) t.add(con(s, c), var(s, v), empty ? 0.0 : u(rng));
    }
  }
  return t;
}

// The same matrix in Ipopt's way of handing it over: every third entry split
// in two triplets (the second in the other triangle), a second term on every
// diagonal (Ipopt adds its barrier and shift diagonals separately), and pairs
// that cancel to an entry that is structurally there but zero.
Triplets asIpoptHandsIt(const Triplets& t) {
  Triplets out;
  out.n = t.n;
  for (size_t k = 0; k < t.val.size(); ++k) {
    const int i = t.irn[k] - 1, j = t.icn[k] - 1;
    if (k % 3 == 0) {
      out.add(i, j, 0.25 * t.val[k]);
      out.add(j, i, 0.75 * t.val[k]);
    } else {
      out.add(i, j, t.val[k]);
    }
    if (i == j) {
      out.add(i, i, 0.5);
      out.add(i, i, -0.5);
    } else if (k % 5 == 0) {
      out.add(i, (i + 1) % t.n, 0.125);  // a zero entry, perhaps where none was
      out.add((i + 1) % t.n, i, -0.125);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("KKT solver: blocks that hair volume couples are factored sparsely, same answers",
          "[solvers][dense_kkt]") {
  // 3 spines make one 48-row block, past kSparseMinRows (32): it is factored
  // as a sparse LDL^T with the rows of positive diagonal first
  // (engine/solvers/ipopt/dense_kkt.cpp). Its solutions solve the matrix, and its inertia is
  // the eigenvalues' count, whether H is positive definite (then exactly the
  // 12 constraints are negative) or not. The residual bound is the dense
  // test's: these matrices are as well conditioned (Sigma within 0.01-100).
  // Entries split, repeated and cancelling (asIpoptHandsIt) are summed
  // before the factorisation, as MA27 sums them.
  std::mt19937 rng(29);
  const bool indefinite = GENERATE(false, true);
  const bool split = GENERATE(false, true);
  const Triplets plain = volumeKkt(3, indefinite, false, rng);
  const Triplets t = split ? asIpoptHandsIt(plain) : plain;
  const Eigen::MatrixXd m = t.dense();
  // The split halves round within an ulp or two of entries up to 100 (Sigma).
  CHECK((m - plain.dense()).cwiseAbs().maxCoeff() < 1e-13);
  Eigen::VectorXd b(t.n);
  for (int i = 0; i < t.n; ++i) b[i] = std::cos(0.5 + i);
  const Ma27Run run = runMa27(t, b);
  REQUIRE(run.iflag_a == 0);
  REQUIRE(run.iflag_b == 0);
  CHECK(run.negative == negativeEigenvalues(m));
  if (!indefinite) CHECK(run.negative == 3 * 4);
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(run.x.data(), t.n);
  const double scale = (m.cwiseAbs() * x.cwiseAbs()).maxCoeff();
  CHECK((m * x - b).cwiseAbs().maxCoeff() <= kResidualTol * scale);
}

TEST_CASE("KKT solver: a singular sparse block is MA27's warning 3", "[solvers][dense_kkt]") {
  // A constraint row with only structural zeros: its pivot is exactly zero.
  std::mt19937 rng(31);
  const Triplets t = volumeKkt(3, false, true, rng);
  const Ma27Run run = runMa27(t, Eigen::VectorXd::Ones(t.n));
  CHECK(run.iflag_b == 3);
  CHECK(run.error_b < t.n);  // the rank it reports is below n
}

TEST_CASE("dense KKT solver: a singular matrix is MA27's warning 3 with its rank",
          "[solvers][dense_kkt]") {
  // Two blocks; the second, [1 1; 1 1], has rank 1.
  Triplets t;
  t.n = 3;
  t.add(0, 0, 2.0);
  t.add(1, 1, 1.0);
  t.add(2, 1, 1.0);
  t.add(2, 2, 1.0);
  const Ma27Run run = runMa27(t, Eigen::VectorXd::Ones(3));
  CHECK(run.iflag_b == 3);
  CHECK(run.error_b == 2);
}

TEST_CASE("dense KKT solver: MA27's codes for short workspaces and bad input",
          "[solvers][dense_kkt]") {
  std::mt19937 rng(3);
  std::vector<int> rows(10);
  for (int i = 0; i < 10; ++i) rows[i] = i;
  const Triplets t = blockMatrix({10}, rows, false, rng);
  // A workspace of a tenth of the advice: -4 (A too small) with the size needed.
  const Ma27Run small = runMa27(t, Eigen::VectorXd::Ones(10), 0.1);
  CHECK(small.iflag_b == -4);
  CHECK(small.error_b == 100);
  Triplets bad = t;
  bad.irn[3] = 11;  // row 11 of 10
  CHECK(runMa27(bad, Eigen::VectorXd::Ones(10)).iflag_a == 1);
  Triplets empty;
  CHECK(runMa27(empty, Eigen::VectorXd()).iflag_a == -1);
}

TEST_CASE("KKT solver: a sparse block's analysis is reused only where it gives the same bits",
          "[solvers][dense_kkt]") {
  // Within one Ipopt solve the KKT structure is fixed and the values change;
  // dense_kkt.cpp keeps each sparse block's symbolic analysis per thread. A
  // factorisation that reuses it must give bit for bit the solution and
  // inertia of one analysed afresh, and the analysis must be made again when
  // the rows' order (which follows the diagonal's signs) or the set of
  // off-diagonal entries that sum to exactly zero changes. Each variant is
  // solved twice: warm, straight after `base` (same structure), and fresh,
  // after a matrix of another structure has emptied the block's cache.
  std::mt19937 rng(37);
  const Triplets base = asIpoptHandsIt(volumeKkt(3, false, false, rng));
  const Triplets other = volumeKkt(3, false, false, rng);  // rows shuffled otherwise
  REQUIRE(other.irn != base.irn);
  Eigen::VectorXd b(base.n);
  for (int i = 0; i < base.n; ++i) b[i] = std::sin(0.3 + 2 * i);

  // Same structure, every entry moved; an entry's triplets by one factor, so
  // those that cancel (asIpoptHandsIt) still cancel.
  Triplets values = base;
  for (size_t k = 0; k < values.val.size(); ++k) {
    const auto [i, j] = std::minmax(base.irn[k], base.icn[k]);
    values.val[k] *= 1 + 0.1 * std::cos(i + 3.0 * j);
  }
  Triplets signs = values;  // a variable's diagonal turned negative: a new row order
  Triplets zeros = values;  // an off-diagonal entry summing to exactly zero
  // How many triplets give each off-diagonal entry.
  std::map<std::pair<int, int>, int> triplets_of;
  for (size_t k = 0; k < base.val.size(); ++k)
    ++triplets_of[std::minmax(base.irn[k], base.icn[k])];
  bool flipped = false, zeroed = false;
  for (size_t k = 0; k < base.val.size(); ++k) {
    const bool diagonal = base.irn[k] == base.icn[k];
    if (!flipped && diagonal && base.val[k] > 1) {
      signs.val[k] = -1000;  // below any sum of the row's other diagonal triplets
      flipped = true;
    }
    if (!zeroed && !diagonal && base.val[k] != 0 &&
        triplets_of[std::minmax(base.irn[k], base.icn[k])] == 1) {
      zeros.val[k] = 0;
      zeroed = true;
    }
  }
  REQUIRE(flipped);
  REQUIRE(zeroed);

  struct Variant {
    const char* name;
    const Triplets* t;
    int analyses;  // made by the warm solve
  };
  for (const Variant& v : {Variant{"values", &values, 0}, Variant{"signs", &signs, 1},
                           Variant{"zeros", &zeros, 1}}) {
    INFO(v.name);
    runMa27(other, b);
    const Ma27Run fresh = runMa27(*v.t, b);  // the only pattern of its structure
    runMa27(other, b);
    runMa27(base, b);
    long long before = sparseKktAnalyses();
    const Ma27Run warm = runMa27(*v.t, b);
    CHECK(sparseKktAnalyses() - before == v.analyses);
    // Back and forth between the two, as inertia corrections go: both kept.
    before = sparseKktAnalyses();
    runMa27(base, b);
    const Ma27Run again = runMa27(*v.t, b);
    CHECK(sparseKktAnalyses() - before == 0);
    CHECK(again.x == fresh.x);
    REQUIRE(fresh.iflag_b == 0);
    REQUIRE(warm.iflag_b == 0);
    CHECK(warm.negative == fresh.negative);
    CHECK(warm.negative == negativeEigenvalues(v.t->dense()));
    CHECK(warm.x == fresh.x);  // bit for bit
    const Eigen::MatrixXd m = v.t->dense();
    const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(warm.x.data(), v.t->n);
    CHECK((m * x - b).cwiseAbs().maxCoeff() <= kResidualTol * (m.cwiseAbs() * x.cwiseAbs()).maxCoeff());
  }
}

TEST_CASE("KKT solver: a large sparse block is factored in minimum degree order, same answers, "
          "less fill", "[solvers][dense_kkt]") {
  // 10 spines coupled make one 160-row block, past kOrderedMinRows (144):
  // its rows of positive diagonal are factored in Eigen's approximate
  // minimum degree order (engine/solvers/ipopt/dense_kkt.cpp). The solutions and inertia
  // are held as for the smaller blocks. The fill is compared with the same
  // block factored in its rows' own order (the positive rows first, as the
  // smaller blocks are; these rows are shuffled, volumeKkt): the degree order
  // must leave L at most kFillShare of that. Measured: 0.74 and 0.80 (the
  // constraints, last in both, fill among themselves alike); the rows' own
  // order gives 1.
  constexpr double kFillShare = 0.9;
  std::mt19937 rng(41);
  const bool indefinite = GENERATE(false, true);
  const Triplets t = asIpoptHandsIt(volumeKkt(10, indefinite, false, rng));
  const Eigen::MatrixXd m = t.dense();
  Eigen::VectorXd b(t.n);
  for (int i = 0; i < t.n; ++i) b[i] = std::cos(0.7 + 3 * i);
  const Ma27Run run = runMa27(t, b);
  REQUIRE(run.iflag_a == 0);
  REQUIRE(run.iflag_b == 0);
  CHECK(run.negative == negativeEigenvalues(m));
  if (!indefinite) CHECK(run.negative == 10 * 4);
  const Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(run.x.data(), t.n);
  const double scale = (m.cwiseAbs() * x.cwiseAbs()).maxCoeff();
  CHECK((m * x - b).cwiseAbs().maxCoeff() <= kResidualTol * scale);

  // The reference: positive diagonals first, each part in row order, the
  // structure of the triplets (explicit zeros included, as the block keeps
  // every entry that does not sum to exactly zero).
  std::vector<int> order;
  for (int i = 0; i < t.n; ++i)
    if (m(i, i) > 0) order.push_back(i);
  for (int i = 0; i < t.n; ++i)
    if (!(m(i, i) > 0)) order.push_back(i);
  std::vector<int> at(t.n);
  for (int k = 0; k < t.n; ++k) at[order[k]] = k;
  std::vector<Eigen::Triplet<double>> entries;
  for (int i = 0; i < t.n; ++i)
    for (int j = 0; j <= i; ++j)
      if (m(i, j) != 0 || i == j) entries.emplace_back(std::max(at[i], at[j]), std::min(at[i], at[j]), 1.0);
  Eigen::SparseMatrix<double> pattern(t.n, t.n);
  pattern.setFromTriplets(entries.begin(), entries.end());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> ldlt;
  ldlt.analyzePattern(pattern);
  // L's entries below the diagonal, from the symbolic analysis.
  const long long natural = ldlt.matrixL().nestedExpression().nonZeros();
  INFO("fill: " << lastSparseKktFill() << " in degree order, " << natural << " in the rows' order");
  CHECK(lastSparseKktFill() > 0);
  CHECK(lastSparseKktFill() <= kFillShare * natural);
}

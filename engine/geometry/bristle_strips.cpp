#include "engine/geometry/bristle_strips.h"

#include <libqhull_r/qhull_ra.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "engine/mechanics/spine_kinematics.h"

namespace bristle {
namespace {

// Spine roots closer than this to a strip root are that root: eq. 17 gives them
// a zero coefficient, and they take the whole weight.
constexpr double kCoincidentMm = 1e-9;
// Delaunay triangles thinner than this (mm^2) are qhull's zero-area slivers of
// triangulated cocircular facets ('Qt'); they could never be sampled anyway.
constexpr double kMinTriangleAreaMm2 = 1e-12;
// Roots whose box is thinner than this fraction of its length are collinear.
constexpr double kCollinearRatio = 1e-9;
// Joint parameters of different spines closer than this are one sample.
constexpr double kSameParameter = 1e-9;

// Uniform in [0, 1) from the top 53 bits: the same on every standard library,
// unlike std::uniform_real_distribution.
double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// Delaunay triangulation of the roots with qhull ("qdelaunay Qt"): triangles as
// sorted spine indices, in sorted order, so the layout does not depend on the
// order qhull visits its facets. Empty when qhull fails.
std::vector<Eigen::Vector3i> delaunay(const std::vector<Eigen::Vector2d>& roots) {
  std::vector<coordT> pts;
  for (const Eigen::Vector2d& p : roots) pts.insert(pts.end(), {p.x(), p.y()});
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, stderr);
  char flags[] = "qhull d Qt Qbb Qc Qz";
  std::vector<Eigen::Vector3i> tris;
  if (qh_new_qhull(qh, 2, static_cast<int>(roots.size()), pts.data(), False, flags, nullptr,
                   stderr) == 0) {
    facetT* facet;
    FORALLfacets {
      if (facet->upperdelaunay) continue;
      Eigen::Vector3i t;
      int k = 0;
      vertexT *vertex, **vertexp;
      FOREACHvertex_(facet->vertices) if (k < 3) t[k++] = qh_pointid(qh, vertex->point);
      if (k != 3) continue;
      std::sort(t.data(), t.data() + 3);
      const Eigen::Vector2d e1 = roots[t[1]] - roots[t[0]], e2 = roots[t[2]] - roots[t[0]];
      if (0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x()) > kMinTriangleAreaMm2)
        tris.push_back(t);
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong, totlong;
  qh_memfreeshort(qh, &curlong, &totlong);
  std::sort(tris.begin(), tris.end(), [](const Eigen::Vector3i& a, const Eigen::Vector3i& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  return tris;
}

// Arc-length parameters of the joints (s of §4.2.2: 0 at the root, 1 at the tip).
void jointParameters(const Brush& brush, StripLayout* l) {
  l->joint_begin.assign(1, 0);
  for (const SpineSpec& sp : brush.spines) {
    const double total = sp.lengthMm();
    double acc = 0;
    l->joint_s.push_back(0);
    for (double seg : sp.segment_lengths_mm) {
      acc += seg;
      l->joint_s.push_back(total > 0 ? acc / total : 1.0);
    }
    l->joint_s.back() = 1.0;  // exactly, whatever the rounding of the sum
    l->joint_begin.push_back(static_cast<int>(l->joint_s.size()));
  }
  for (size_t k = 0; k < l->joint_s.size(); ++k) {
    const double ds = k + 1 < l->joint_s.size() ? l->joint_s[k + 1] - l->joint_s[k] : 0.0;
    l->joint_inv_ds.push_back(ds > 0 ? 1 / ds : 0.0);
  }
  const int ns = static_cast<int>(brush.spines.size());
  for (int i = 0; i < ns; ++i) {
    const int bi = l->joint_begin[i], ni = l->joint_begin[i + 1] - bi;
    int g = 0;
    for (; g < i; ++g) {
      const int bg = l->joint_begin[g];
      if (l->joint_begin[g + 1] - bg == ni &&
          std::equal(&l->joint_s[bi], &l->joint_s[bi] + ni, &l->joint_s[bg]) &&
          std::equal(&l->joint_inv_ds[bi], &l->joint_inv_ds[bi] + ni, &l->joint_inv_ds[bg]))
        break;
    }
    l->joint_group.push_back(g);
  }
  // A strip's vertices sit at every spine's joints (§4.2: "two vertices per joint").
  std::vector<double> s = l->joint_s;
  std::sort(s.begin(), s.end());
  for (double x : s)
    if (l->sample_s.empty() || x - l->sample_s.back() > kSameParameter) l->sample_s.push_back(x);
  l->sample_s.back() = 1.0;
  if (l->samples() > kMaxStripSamples) {
    l->sample_s.resize(kMaxStripSamples);
    for (int k = 0; k < kMaxStripSamples; ++k) l->sample_s[k] = double(k) / (kMaxStripSamples - 1);
  }
}

// Feasible start for the 1-D weights: linear interpolation between the spines
// whose line coordinates bracket tau.
Eigen::VectorXd bracketingWeights(const Eigen::RowVectorXd& tau, double t) {
  int lo = 0, hi = 0;
  for (int i = 0; i < tau.size(); ++i) {
    if (tau[i] <= t && (tau[lo] > t || tau[i] > tau[lo])) lo = i;
    if (tau[i] >= t && (tau[hi] < t || tau[i] < tau[hi])) hi = i;
  }
  Eigen::VectorXd w = Eigen::VectorXd::Zero(tau.size());
  const double span = tau[hi] - tau[lo];
  const double a = span > 0 ? (t - tau[lo]) / span : 0.0;
  w[lo] += 1 - a;
  w[hi] += a;
  return w;
}

}  // namespace

Eigen::VectorXd solveStripWeights(const Eigen::MatrixXd& roots, const Eigen::VectorXd& p,
                                  const Eigen::VectorXd& start) {
  const int n = static_cast<int>(roots.cols()), d = static_cast<int>(roots.rows());
  // Work relative to p: constraint rows are (1, p_i - p), right-hand side e_0
  // (eqs. 18 and 20 at s = 0); eq. 17's coefficients c_i = |p_i - p|^2.
  Eigen::MatrixXd a(d + 1, n);
  a.row(0).setOnes();
  a.bottomRows(d) = roots.colwise() - p;
  const Eigen::VectorXd c = a.bottomRows(d).colwise().squaredNorm().transpose();
  Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
  const double near = kCoincidentMm * kCoincidentMm;
  if ((c.array() <= near).any()) {  // the root is on a spine root: all weight there
    for (int i = 0; i < n; ++i) w[i] = c[i] <= near ? 1.0 : 0.0;
    return w / w.sum();
  }
  const Eigen::VectorXd b = Eigen::VectorXd::Unit(d + 1, 0);
  w = start;
  std::vector<bool> free(n);
  for (int i = 0; i < n; ++i) free[i] = w[i] > 0;
  Eigen::VectorXd lambda(d + 1), target(n);
  // Primal active-set method (Nocedal & Wright, Alg. 16.3); the working set is
  // the spines held at w_i = 0 (eq. 19). Each pass solves the equality-
  // constrained problem over the free spines in closed form: w_i = a_i.lambda / c_i
  // with (sum_free a_i a_i^T / c_i) lambda = b.
  for (int iter = 0; iter < 4 * n + 20; ++iter) {
    Eigen::MatrixXd m = Eigen::MatrixXd::Zero(d + 1, d + 1);
    for (int i = 0; i < n; ++i)
      if (free[i]) m.noalias() += a.col(i) * a.col(i).transpose() / c[i];
    // Jacobi scaling: 1/c spans many decades when p is near a spine root. M may
    // be singular (too few free spines); the pseudo-inverse still solves it,
    // because b stays in its range while the iterate is feasible.
    const Eigen::VectorXd scale = m.diagonal().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
    const Eigen::MatrixXd ms = scale.asDiagonal() * m * scale.asDiagonal();
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(ms);
    lambda = scale.asDiagonal() * cod.solve(scale.asDiagonal() * b);
    for (int i = 0; i < n; ++i) target[i] = free[i] ? a.col(i).dot(lambda) / c[i] : 0.0;
    const Eigen::VectorXd step = target - w;
    if (step.lpNorm<Eigen::Infinity>() < 1e-13) {
      // Optimal over the free set: a held spine with a_i.lambda > 0 has a
      // negative multiplier (mu_i = -a_i.lambda) and should carry weight.
      int enter = -1;
      double best = 1e-12;
      for (int i = 0; i < n; ++i)
        if (!free[i] && a.col(i).dot(lambda) > best) best = a.col(i).dot(lambda), enter = i;
      w = target;
      if (enter < 0) break;
      free[enter] = true;
      continue;
    }
    double alpha = 1;
    int block = -1;
    for (int i = 0; i < n; ++i)
      if (free[i] && step[i] < 0 && -w[i] / step[i] < alpha) alpha = -w[i] / step[i], block = i;
    w += alpha * step;
    if (block >= 0) w[block] = 0, free[block] = false;
  }
  return w.cwiseMax(0.0) / w.cwiseMax(0.0).sum();
}

namespace {

// Wet hair clumps: seeds picked by a partial Fisher-Yates shuffle, each strip
// to the nearest seed's root (ties to the lower seed), and each bunch's weights
// the mean of its strips' (so its eq. 16 centre line is their mean).
void assignClumps(const StripSpec& spec, StripLayout* l) {
  const int n = std::min(spec.clumps, l->count);
  if (n <= 0 || spec.clumping <= 0) return;
  // 0x636c756d7073 = "clumps": a generator of its own, so the roots stay put.
  std::mt19937_64 rng(spec.seed ^ 0x636c756d7073ULL);
  std::vector<int> pick(l->count);
  for (int j = 0; j < l->count; ++j) pick[j] = j;
  for (int g = 0; g < n; ++g) {
    const int r = g + static_cast<int>(uniform01(rng) * (l->count - g));
    std::swap(pick[g], pick[std::min(r, l->count - 1)]);
  }
  l->clump.assign(l->count, 0);
  l->clump_weights.assign(static_cast<size_t>(n) * l->spines, 0.0);
  std::vector<int> members(n, 0);
  for (int j = 0; j < l->count; ++j) {
    int best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (int g = 0; g < n; ++g) {
      const double d = (l->roots_mm[j] - l->roots_mm[pick[g]]).squaredNorm();
      if (d < best_d) best_d = d, best = g;
    }
    l->clump[j] = best;
    ++members[best];
    for (int i = 0; i < l->spines; ++i)
      l->clump_weights[static_cast<size_t>(best) * l->spines + i] += l->weight(j, i);
  }
  for (int g = 0; g < n; ++g)  // every seed is its own member: members[g] >= 1
    for (int i = 0; i < l->spines; ++i)
      l->clump_weights[static_cast<size_t>(g) * l->spines + i] /= members[g];
}

}  // namespace

StripLayout layoutStrips(const Brush& brush) {
  StripLayout l;
  const int ns = static_cast<int>(brush.spines.size());
  if (!brush.strips.present() || ns == 0) return l;
  l.count = brush.strips.count;
  l.spines = ns;
  jointParameters(brush, &l);
  SpineFk fk;
  for (const SpineSpec& sp : brush.spines) {
    std::vector<double> q;
    for (const Eigen::Vector2d& r : sp.rest_angles_rad) q.insert(q.end(), {r[0], r[1]});
    spineForwardKinematics(sp, Pose{}, q.data(), 0, &fk);
    l.rest_tips_mm.push_back(fk.x.back());
  }

  // Oriented bounding box of the roots by PCA (§4.2.2).
  std::vector<Eigen::Vector2d> roots;
  Eigen::MatrixXd roots_m(2, ns);
  for (int i = 0; i < ns; ++i) {
    roots.push_back(brush.spines[i].root_mm.head<2>());
    roots_m.col(i) = roots.back();
  }
  const Eigen::Vector2d centre = roots_m.rowwise().mean();
  const Eigen::Matrix2d cov = (roots_m.colwise() - centre) * (roots_m.colwise() - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  const Eigen::Vector2d major = eig.eigenvectors().col(1), minor = eig.eigenvectors().col(0);
  const Eigen::RowVectorXd tau = major.transpose() * (roots_m.colwise() - centre);
  const Eigen::RowVectorXd across = minor.transpose() * (roots_m.colwise() - centre);
  const double length = tau.maxCoeff() - tau.minCoeff();
  const double width = across.maxCoeff() - across.minCoeff();
  const std::string& mode = brush.strips.placement;
  l.one_dimensional = mode == "line" || (mode == "auto" && width < kStripThinBoxRatio * length);
  // Collinear roots ('area' asked of a flat brush) have no triangles: 1-D after
  // all, without asking qhull (which reports a flat simplex on stderr).
  if (!l.one_dimensional && width > kCollinearRatio * length) l.triangles = delaunay(roots);
  l.one_dimensional = l.triangles.empty();
  l.line_from_mm = centre + tau.minCoeff() * major;
  l.line_to_mm = centre + tau.maxCoeff() * major;

  // Triangles are picked with probability proportional to their area.
  std::vector<double> cumulative_area;
  double total_area = 0;
  for (const Eigen::Vector3i& t : l.triangles) {
    const Eigen::Vector2d e1 = roots[t[1]] - roots[t[0]], e2 = roots[t[2]] - roots[t[0]];
    cumulative_area.push_back(total_area += 0.5 * std::abs(e1.x() * e2.y() - e1.y() * e2.x()));
  }

  std::mt19937_64 rng(brush.strips.seed);
  l.weights.reserve(static_cast<size_t>(l.count) * ns);
  for (int j = 0; j < l.count; ++j) {
    Eigen::VectorXd w;
    Eigen::Vector2d root;
    if (l.one_dimensional) {
      // 1-D: uniform along the segment of the best-fit line; the weights solve
      // eqs. 17-20 in the line coordinate, and the root is where they put it
      // (on the line when the spine roots are, within the thin box otherwise).
      const double t = tau.minCoeff() + uniform01(rng) * length;
      w = solveStripWeights(tau, Eigen::VectorXd::Constant(1, t), bracketingWeights(tau, t));
      root = roots_m * w;
    } else {
      const double pick = uniform01(rng) * total_area;
      const size_t k = std::min<size_t>(
          std::upper_bound(cumulative_area.begin(), cumulative_area.end(), pick) -
              cumulative_area.begin(),
          cumulative_area.size() - 1);
      const Eigen::Vector3i& t = l.triangles[k];
      double r1 = uniform01(rng), r2 = uniform01(rng);
      if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;  // fold the square onto the triangle
      root = roots[t[0]] + r1 * (roots[t[1]] - roots[t[0]]) + r2 * (roots[t[2]] - roots[t[0]]);
      Eigen::VectorXd start = Eigen::VectorXd::Zero(ns);
      start[t[0]] = 1 - r1 - r2;
      start[t[1]] = r1;
      start[t[2]] = r2;
      w = solveStripWeights(roots_m, root, start);
    }
    l.roots_mm.push_back(root);
    l.weights.insert(l.weights.end(), w.data(), w.data() + ns);
    l.length_factor.push_back(1 - uniform01(rng) * brush.strips.length_jitter);
  }
  assignClumps(brush.strips, &l);
  return l;
}

Eigen::Vector2d stripBendDirection(const StripLayout& layout, const BrushState& state) {
  // Tip deflection in the brush frame: R^T (tip - handle) - rest tip; its x-y
  // part is the projection onto the cross-section plane (§4.2.1, Fig. 8).
  const Eigen::Quaterniond to_brush = state.handle.rotation.conjugate();
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  const int ns = std::min<int>(layout.spines, static_cast<int>(state.spines.size()));
  for (int i = 0; i < ns; ++i) {
    const Eigen::Vector3d tip = to_brush * (state.spines[i].joints_mm.back() -
                                            state.handle.position_mm);
    sum += (tip - layout.rest_tips_mm[i]).head<2>();
  }
  return ns > 0 ? Eigen::Vector2d(sum / ns) : sum;
}

namespace {

// How far above below_mm a strip's spines must all stay for buildStrips to
// skip it: far above the rounding of a convex combination (1e-15 relative)
// and of the vertices' float z (6e-8 relative), and far below anything drawn.
constexpr double kStripCullMarginMm = 1e-3;

// Dresses one strip's centre line c (layout.samples() points) as a quad
// strip (buildStrips): width tapering from root to tip, flat side in the
// canvas plane, texture row u and v = f s along it. Only the quads that reach
// down to below_mm are appended. c is read from sample `first` on: no quad
// that ends at or before sample first + 1 may reach below_mm.
void appendStripQuads(const StripSpec& spec, const StripLayout& layout, const Eigen::Vector3d* c,
                      int first, double f, float u, const Eigen::Vector3d& fallback,
                      double below_mm, std::vector<BrushVertex>* triangles) {
  const int samples = layout.samples();
  auto vert = [u](const Eigen::Vector3d& p, float v) {
    return BrushVertex{static_cast<float>(p.x()), static_cast<float>(p.y()),
                       static_cast<float>(p.z()), u, v};
  };
  // Both triangles of the quad between samples k - 1 and k have their
  // lowest vertex at the lower of the two samples' heights (the strip's
  // side lies in the canvas plane), so the quad is drawn when that reaches
  // down to below_mm (reachesDown), and a sample is dressed only for a
  // quad beside it that is drawn.
  auto quad = [&](int k) {
    const float z = std::min(static_cast<float>(c[k - 1].z()), static_cast<float>(c[k].z()));
    return !(z > below_mm);
  };
  Eigen::Vector3d prev_left = c[first], prev_right = c[first];
  float prev_v = 0;
  for (int k = first; k < samples; ++k) {
    const bool before = k > first && quad(k), after = k + 1 < samples && quad(k + 1);
    if (!before && !after) continue;
    // Tangent: the mean of the adjacent segment directions.
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    if (k > 0) t += (c[k] - c[k - 1]).normalized();  // Eigen: zero stays zero
    if (k + 1 < samples) t += (c[k + 1] - c[k]).normalized();
    // §4.2.1: the flat side faces the canvas, like a billboard whose viewer is
    // the canvas: side = z x t lies in the canvas plane.
    Eigen::Vector3d side(-t.y(), t.x(), 0);
    const double sn = side.norm();
    side = sn > 1e-6 * t.norm() && sn > 0 ? Eigen::Vector3d(side / sn) : fallback;
    // Linear taper along the strip's own length, so a shortened strip still
    // ends at the tip width.
    const double half = 0.5 * (spec.root_width_mm +
                               (spec.tip_width_mm - spec.root_width_mm) * layout.sample_s[k]);
    const Eigen::Vector3d left = c[k] - half * side, right = c[k] + half * side;
    const float v = static_cast<float>(f * layout.sample_s[k]);
    if (before) {
      // (side x t) points down for a level strip: counter-clockwise from below.
      triangles->push_back(vert(prev_left, prev_v));
      triangles->push_back(vert(prev_right, prev_v));
      triangles->push_back(vert(right, v));
      triangles->push_back(vert(prev_left, prev_v));
      triangles->push_back(vert(right, v));
      triangles->push_back(vert(left, v));
    }
    prev_left = left, prev_right = right, prev_v = v;
  }
}

// Where a strip's samples k >= first fall on spine i's polyline: segment
// seg[k], at fraction frac[k] of it (the strip's length factor f scales the
// sample parameters). Spine by spine, the samples (increasing s) and the
// joints are merged like two sorted lists.
struct SamplePlacement {
  int seg[kMaxStripSamples];
  double frac[kMaxStripSamples];
};

void placeSamples(const StripLayout& layout, int i, double f, int first, SamplePlacement* out) {
  const double* js = &layout.joint_s[layout.joint_begin[i]];
  const double* inv = &layout.joint_inv_ds[layout.joint_begin[i]];
  const int last_seg = layout.joint_begin[i + 1] - layout.joint_begin[i] - 2;
  int a = 0;
  for (int k = first; k < layout.samples(); ++k) {
    const double s = f * layout.sample_s[k];
    while (a < last_seg && js[a + 1] < s) ++a;
    out->seg[k] = a;
    out->frac[k] = std::min((s - js[a]) * inv[a], 1.0);
  }
}

// A strip's sample at s is a convex combination of its spines' points at s
// (eq. 19 keeps the weights >= 0, summing to 1; a bunch's are means of
// those, and clumping * s lies in [0, 1]), each on the segment of its
// polyline that holds s. So where every spine it follows is still on
// segments whose joints all stay clear of below_mm by more than rounding,
// the sample is too. Per spine, clear_s is the parameter up to which that
// holds: the start of its first segment with a joint within the margin (a
// sample at s <= clear_s lies on an earlier segment, see placeSamples),
// or kAllHeights if no joint is. A hanging brush's hair dips only near its
// tips, so most of each strip is not built at all; a strip all of whose
// spines stay clear is skipped whole.
void spinesClearUpTo(const StripLayout& layout, const BrushState& state, double below_mm,
                     double* clear_s) {
  for (int i = 0; i < layout.spines; ++i) {
    const double* js = &layout.joint_s[layout.joint_begin[i]];
    const std::vector<Eigen::Vector3d>& x = state.spines[i].joints_mm;
    const int joints = layout.joint_begin[i + 1] - layout.joint_begin[i];
    clear_s[i] = kAllHeights;
    for (int a = 0; a < joints; ++a) {
      if (!(x[a].z() > below_mm + kStripCullMarginMm)) {
        // Joint a ends segment a - 1 and starts segment a.
        clear_s[i] = a == 0 ? -kAllHeights : js[a - 1];
        break;
      }
    }
  }
}

}  // namespace

void buildStrips(const Brush& brush, const StripLayout& layout, const BrushState& state,
                 std::vector<BrushVertex>* triangles, double below_mm) {
  if (layout.count == 0) return;
  const int ns = layout.spines, samples = layout.samples();
  triangles->reserve(triangles->size() + 3 * static_cast<size_t>(layout.triangleCount()));

  // Rendering order (§4.2.1): decreasing root . d, so the strips on the side
  // the brush bends towards come first and the canvas-facing ones last (see
  // the header). Fixed-size scratch: no allocation per step.
  std::pair<double, int> order[kMaxStrips];
  const int count = std::min(layout.count, kMaxStrips);
  const Eigen::Vector2d bend = stripBendDirection(layout, state);
  const bool sorted = bend.norm() >= kStripBendEpsMm;
  const Eigen::Vector2d dir = sorted ? Eigen::Vector2d(bend.normalized()) : bend;
  for (int j = 0; j < count; ++j) order[j] = {sorted ? -layout.roots_mm[j].dot(dir) : 0.0, j};
  if (sorted) std::sort(order, order + count);  // ties keep layout order via the index

  // Side vector where the centre line is vertical: the brush's x axis laid into
  // the canvas plane (its y axis if x points straight up or down too).
  const Eigen::Vector3d bx = state.handle.rotation * Eigen::Vector3d::UnitX();
  const Eigen::Vector3d by = state.handle.rotation * Eigen::Vector3d::UnitY();
  Eigen::Vector3d fallback(bx.x(), bx.y(), 0);
  if (fallback.norm() < 1e-6) fallback = Eigen::Vector3d(by.x(), by.y(), 0);
  fallback.normalize();

  // How far along each spine stays clear of below_mm (spinesClearUpTo). (A
  // brush file holds at most kMaxSpines; one made otherwise is not culled.)
  const bool cull = ns <= kMaxSpines;
  double clear_s[kMaxSpines];
  if (cull) spinesClearUpTo(layout, state, below_mm, clear_s);
  const StripSpec& spec = brush.strips;
  Eigen::Vector3d c[kMaxStripSamples];   // one strip's centre line
  Eigen::Vector3d cg[kMaxStripSamples];  // its bunch's (clumping)
  // The samples' places on the spines, per group of spines with the same
  // joint parameters (joint_group), and the strip they were found for.
  SamplePlacement placed[kMaxSpines];
  int placed_for[kMaxSpines];
  std::fill(placed_for, placed_for + kMaxSpines, -1);
  SamplePlacement own;
  for (int o = 0; o < count; ++o) {
    const int j = order[o].second;
    const double f = layout.length_factor[j];
    const double* w = &layout.weights[static_cast<size_t>(j) * ns];
    // eq. 16: p(s) = sum_i w_i p_i(s), each spine a polyline parameterised by
    // arc length (placeSamples).
    // A clumped strip also follows its bunch's centre line (the same f, so the
    // two end together) and is drawn towards it by clumping * s below.
    const bool clumped = !layout.clump.empty();
    const double* wg =
        clumped ? &layout.clump_weights[static_cast<size_t>(layout.clump[j]) * ns] : nullptr;
    // The first sample that may dip (dip), and the first one built: the two
    // before it, the first of them for the tangent at the second.
    int dip = 0;
    if (cull) {
      double clear = kAllHeights;
      for (int i = 0; i < ns; ++i)
        if (w[i] != 0 || (clumped && wg[i] != 0)) clear = std::min(clear, clear_s[i]);
      while (dip < samples && f * layout.sample_s[dip] <= clear) ++dip;
      if (dip == samples) continue;
    }
    const int first = std::max(dip - 2, 0);
    std::fill(c + first, c + samples, Eigen::Vector3d::Zero());
    if (clumped) std::fill(cg + first, cg + samples, Eigen::Vector3d::Zero());
    for (int i = 0; i < ns; ++i) {
      if (w[i] == 0 && (!clumped || wg[i] == 0)) continue;
      const SamplePlacement* at = &own;
      if (cull) {
        const int g = layout.joint_group[i];
        if (placed_for[g] != o) placeSamples(layout, i, f, first, &placed[g]);
        placed_for[g] = o;
        at = &placed[g];
      } else {
        placeSamples(layout, i, f, first, &own);
      }
      const Eigen::Vector3d* x = state.spines[i].joints_mm.data();
      for (int k = first; k < samples; ++k) {
        const int a = at->seg[k];
        const double t = at->frac[k];
        const Eigen::Vector3d p = x[a] + t * (x[a + 1] - x[a]);
        c[k] += w[i] * p;
        if (clumped) cg[k] += wg[i] * p;
      }
    }
    if (clumped)
      for (int k = first; k < samples; ++k)
        c[k] += spec.clumping * layout.sample_s[k] * (cg[k] - c[k]);
    appendStripQuads(spec, layout, c, first, f, static_cast<float>((j + 0.5) / layout.count),
                     fallback, below_mm, triangles);
  }
}

}  // namespace bristle

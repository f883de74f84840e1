#include "engine/dynamics/simulation.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/base/error.h"
#include "engine/mechanics/friction.h"
#include "engine/base/smooth.h"
#include "engine/mechanics/spine_kinematics.h"

namespace bristle {

bool BrushState::anyContact() const {
  for (const SpineState& s : spines)
    for (bool c : s.contact)
      if (c) return true;
  return false;
}

namespace {

// Passes of the contact-set correction: each pass can only move joints from
// sticking to sliding or from contact to lifted, so it ends after at most two
// passes per contact joint; in practice one or two.
constexpr int kMaxStictionPasses = 4;

// A straight spine pressed straight down sits on a buckling point: the canvas
// constraint has no gradient there. Solves start from this small bend towards
// the brush's +y instead, so the spine always buckles the same way.
constexpr double kBucklingNudgeRad = 1e-3;

// A joint this close to the canvas rests on it (Ipopt leaves active constraints
// at ~1e-9 mm), whatever its multiplier.
constexpr double kTouchMm = 1e-5;
// predictStart: this many Gauss-Newton steps (measured: the held joints then
// sit within 1e-4 mm of their targets, a hundredth of SimOptions' slip
// distance), with Levenberg's damping relative to J^T J.
constexpr int kPredictIterations = 3;
constexpr double kPredictDamping = 1e-3;
// extrapolateStart: below this handle motion (mm, either step) the two
// steps' directions are round-off and nothing is extrapolated.
constexpr double kExtrapolateMinMoveMm = 1e-4;
// A contact joint the solution puts this far above the canvas has left it. Well
// above the solver's constraint accuracy, well below anything visible.
constexpr double kLiftedMm = 1e-3;

}  // namespace

Simulation::Simulation(const Brush& brush, const SimOptions& options,
                       std::unique_ptr<SpineSolver> solver, std::unique_ptr<SpineSolver> fallback)
    : brush_(brush),
      options_(options),
      solver_(std::move(solver)),
      fallback_(std::move(fallback)),
      volume_pairs_(brush.volume.present() ? volumePairs(brush) : std::vector<VolumePair>{}),
      rest_hair_mm_(restHairLengthMm(brush)),
      squash_rest_mm_(rest_hair_mm_ - brush.volume.squash_after_mm) {
  for (const SpineSpec& spec : brush.spines) rest_rot_.push_back(restRotations(spec));
  for (size_t i = 0; i < brush.spines.size(); ++i) {
    const SpineSpec& spec = brush.spines[i];
    SpineFk fk;
    const std::vector<double> zero(2 * spec.jointCount(), 0.0);
    spineForwardKinematics(spec, Pose{}, rest_rot_[i].data(), zero.data(), 0, &fk);
    std::vector<double> r;
    std::vector<Eigen::Vector3d> dir;
    for (const Eigen::Vector3d& x : fk.x) {
      r.push_back(x.head<2>().norm());
      dir.push_back(r.back() > 0 ? Eigen::Vector3d(x.x() / r.back(), x.y() / r.back(), 0)
                                 : Eigen::Vector3d::Zero());
    }
    rest_radius_mm_.push_back(r);
    rest_dir_.push_back(dir);
  }
}

Eigen::Vector2d axisOnPaper(const Pose& handle) {
  const Eigen::Vector3d down = handle.rotation * Eigen::Vector3d(0, 0, -1);
  if (down.z() >= 0) return handle.position_mm.head<2>();
  return (handle.position_mm + down * (handle.position_mm.z() / -down.z())).head<2>();
}

double bundleSquash(double rest_length_mm, const Pose& handle, double travel_mm) {
  // The hair hangs along the brush frame's -z; below the ferrule the paper
  // lies at H = z / cos(the axis's angle from straight down).
  const double down = -(handle.rotation * Eigen::Vector3d(0, 0, -1)).z();
  if (down <= 0 || rest_length_mm <= 0) return 1;
  const double height = handle.position_mm.z() / down + kTrailRoomPerMm * travel_mm;
  if (height >= rest_length_mm) return 1;
  if (height * kMaxSquash <= rest_length_mm) return kMaxSquash;
  return rest_length_mm / height;
}

std::vector<VolumePair> volumePairs(const Brush& brush) {
  const int ns = static_cast<int>(brush.spines.size());
  std::vector<std::vector<Eigen::Vector3d>> rest(ns);
  SpineFk fk;
  for (int s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush.spines[s];
    const std::vector<Eigen::Matrix3d> r = restRotations(spec);
    const std::vector<double> zero(2 * spec.jointCount(), 0.0);
    spineForwardKinematics(spec, Pose{}, r.data(), zero.data(), 0, &fk);
    rest[s] = fk.x;
  }
  auto meanDist = [&](int s, int t) {
    const size_t n = std::min(rest[s].size(), rest[t].size());
    double d = 0;
    for (size_t j = 0; j < n; ++j) d += (rest[s][j] - rest[t][j]).norm();
    return d / n;
  };
  std::vector<double> nearest(ns, HUGE_VAL);
  for (int s = 0; s < ns; ++s)
    for (int t = 0; t < ns; ++t)
      if (t != s) nearest[s] = std::min(nearest[s], meanDist(s, t));
  // Within 1.5x the nearest: a hexagonal ring's sides and spokes (1x) but not
  // its diagonals (1.73x), a row's next spines (1x) but not the one after (2x).
  constexpr double kNeighbourFactor = 1.5;
  std::vector<VolumePair> pairs;
  for (int s = 0; s < ns; ++s)
    for (int t = s + 1; t < ns; ++t) {
      const double d = meanDist(s, t);
      if (d > kNeighbourFactor * std::min(nearest[s], nearest[t])) continue;
      VolumePair p{s, t, {}};
      const size_t n = std::min(rest[s].size(), rest[t].size());
      for (size_t j = 1; j < n; ++j) p.rest_mm.push_back((rest[s][j] - rest[t][j]).norm());
      pairs.push_back(std::move(p));
    }
  return pairs;
}

// The limits hair volume puts on joint j (1..) of a neighbour pair
// (docs/dynamics.md): at least min_separation times the pair's rest distance at
// that joint, and with cohesion at most max_separation times that distance
// raised by tip_spread towards the pair's widest rest spacing (the belly's):
// at 1 a tip which converges to the point at rest may spread as wide as the
// belly, but not splay past it.
Simulation::VolumeLimits Simulation::volumeLimits(const VolumePair& vp, int j) const {
  const VolumeSpec& v = brush_.volume;
  const double widest = *std::max_element(vp.rest_mm.begin(), vp.rest_mm.end());
  const double rest = vp.rest_mm[j - 1];
  // A squashed bundle that spreads (addAxisSpread) holds together over
  // spacings grown as its section: cohesion's limit grows by the same sqrt(s).
  const double grown = v.spread_n_per_mm > 0 ? std::sqrt(squash_) : 1.0;
  return {v.min_separation * rest,
          grown * v.max_separation * (rest + v.tip_spread * (widest - rest))};
}

namespace {
// The direction a pair's push is held along for a step (VolumeLink): from the
// other joint to this one where the solve starts. Two joints closer than this
// have no direction to speak of; their push follows their own line.
constexpr double kPushDirMinMm = 1e-6;
Eigen::Vector3d heldPushDirection(const Eigen::Vector3d& offset) {
  const double r = offset.norm();
  return r > kPushDirMinMm ? Eigen::Vector3d(offset / r) : Eigen::Vector3d::Zero();
}
}  // namespace

// Spine s's volume contacts with every neighbour not in `group`, each held
// where `trial` puts it in this step (its solved, relaxed or carried pose).
void Simulation::setVolumeContacts(int s, const std::vector<SpineSolution>& trial,
                                   const std::vector<char>& group) {
  SpineProblem& p = problems_[s];
  p.volume.clear();
  p.volume_stiffness_n_per_mm = brush_.volume.stiffness_n_per_mm;
  p.cohesion_n_per_mm = brush_.volume.max_separation > 0 ? brush_.volume.cohesion_n_per_mm : 0.0;
  // Pushes are held along a direction for a solver of the coupled spines
  // (VolumeLink), so that its neighbours outside the group push as its links
  // do; one spine at a time keeps the joints' own line (docs/dynamics.md,
  // "The push's direction is held for a step").
  const bool hold = solver_->couplesSpines(static_cast<int>(brush_.spines.size()));
  for (const VolumePair& vp : volume_pairs_) {
    if (vp.s != s && vp.t != s) continue;
    const int other = vp.s == s ? vp.t : vp.s;
    if (!group.empty() && group[other]) continue;
    const std::vector<Eigen::Vector3d> theirs = jointsAt(other, trial[other]);
    for (int j = 1; j <= static_cast<int>(vp.rest_mm.size()); ++j) {
      const VolumeLimits lim = volumeLimits(vp, j);
      const Eigen::Vector3d held =
          hold ? heldPushDirection(volume_start_[s][j] - volume_start_[other][j])
               : Eigen::Vector3d::Zero();
      p.volume.push_back({j, theirs[j], lim.min_mm, lim.max_mm, held, 0.0});
    }
  }
  if (brush_.volume.spread_n_per_mm > 0 && squash_ > 1)
    addAxisSpread(s, hold ? volume_start_[s] : jointsAt(s, trial[s]));
}

// Incompressibility (docs/dynamics.md, "A squashed bundle spreads"): squashed
// by s (bundleSquash), the bundle's section across the handle's axis must grow
// s times, so each joint j of spine s keeps at least sqrt(s) times its rest
// distance from the axis, measured along its rest direction from the axis
// (turned with the handle): a bundle laid over to one side carries the near
// spines' joints across the axis, against their own outward, so it is not the
// spread the rule asks for. The push is a VolumeContact against the axis's
// point level with the joint where the solve starts (`start`). A spine rooted
// on the axis is the bundle's core, with no outward of its own: the others'
// volume pushes move it.
void Simulation::addAxisSpread(int s, const std::vector<Eigen::Vector3d>& start) {
  if (rest_radius_mm_[s][0] <= kPushDirMinMm) return;
  SpineProblem& p = problems_[s];
  const Eigen::Vector3d axis = p.handle.rotation * Eigen::Vector3d::UnitZ();
  const double grow = std::sqrt(squash_);
  // Wet hair packs before it resists (VolumeSpec::spread_ramp): the push's
  // stiffness grows with the squash over the ramp instead of switching on
  // whole, so that the step the squash starts in does not throw a point laid
  // over across the axis out in one jump (docs/dynamics.md, "The spread
  // ramps in"). squash_ > 1 here, so the stiffness is above 0, which would
  // take the volume's own.
  const VolumeSpec& v = brush_.volume;
  const double ramp = v.spread_ramp > 0 ? std::min(1.0, (squash_ - 1) / v.spread_ramp) : 1.0;
  for (int j = 1; j < static_cast<int>(start.size()); ++j) {
    const double rest = rest_radius_mm_[s][j];
    if (rest <= kPushDirMinMm) continue;
    const Eigen::Vector3d on_axis =
        p.handle.position_mm + axis * axis.dot(start[j] - p.handle.position_mm);
    p.volume.push_back({j, on_axis, grow * rest, 0.0, p.handle.rotation * rest_dir_[s][j],
                        v.spread_n_per_mm * ramp});
  }
}

std::vector<Eigen::Vector3d> Simulation::jointsAt(int s, const SpineSolution& sol) {
  const SpineProblem& p = problems_[s];
  spineForwardKinematics(brush_.spines[s], p.handle, p.baseData(), sol.q.data(), 0, &fk_);
  return {fk_.x.begin(), fk_.x.end()};
}

void Simulation::reset(const Pose& handle, double t_s) {
  state_ = BrushState{};
  state_.t_s = t_s;
  state_.handle = handle;
  state_.touch_xy_mm = axisOnPaper(handle);
  const size_t ns = brush_.spines.size();
  state_.spines.resize(ns);
  problems_.assign(ns, SpineProblem{});
  for (size_t s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush_.spines[s];
    const int n = spec.jointCount();
    SpineState& st = state_.spines[s];
    st.rot = restRotations(spec);
    st.solution.q.assign(2 * n, 0.0);
    st.solution.normal_force_n.assign(n, 0.0);
    st.summary.status = SolveStatus::kFree;
    SpineProblem& p = problems_[s];
    p.spine = &spec;
    p.handle = handle;
    p.friction_n.assign(n, 0.0);
    p.anchor_xy_mm.assign(n, Eigen::Vector2d::Zero());
    p.pull_dir.assign(n, Eigen::Vector2d::Zero());
    p.prev_q = st.solution.q;
    p.base = st.rot;
    p.cushion.clear();
    for (int j = 1; j <= n; ++j) p.cushion.push_back(hairCushion(spec, j));
    finishSpine(static_cast<int>(s), false, std::vector<bool>(n, false));
  }
  stats_ = SimStats{};
  failed_run_ = 0;
}

void Simulation::buildProblem(int s, const Pose& handle) {
  const SpineSpec& spec = brush_.spines[s];
  const SpineState& prev = state_.spines[s];
  const int n = spec.jointCount();
  SpineProblem& p = problems_[s];
  p.spine = &spec;
  p.handle = handle;
  // Re-base (docs/dynamics.md): the angles of this step are an increment from
  // the joints' rotations at the previous step, which keeps every solve far
  // from eq. 10's singularity however far the joints have turned.
  p.base = canonicalRotations(rest_rot_[s], prev.rot);
  p.prev_q.assign(2 * n, 0.0);
  p.anisotropy_strength = brush_.friction.anisotropy_strength;
  p.anisotropy_exponent = brush_.friction.anisotropy_exponent;
  p.anchor_xy_mm.resize(n);
  p.pull_dir.assign(n, Eigen::Vector2d::Zero());
  for (int j = 0; j < n; ++j) {
    // A sticking joint is held at the point where it stuck; a sliding one's
    // friction is the work of this step's slide (eq. 3).
    const bool stuck = j < static_cast<int>(prev.contact.size()) && prev.contact[j] &&
                       !prev.sliding[j] && j < static_cast<int>(prev.stuck_xy_mm.size());
    p.anchor_xy_mm[j] = stuck ? prev.stuck_xy_mm[j] : Eigen::Vector2d(prev.joints_mm[j + 1].head<2>());
    // eq. 14's d_p: from the joint towards the projection of its parent joint,
    // the way a trailing hair is dragged.
    const Eigen::Vector2d towards_parent = (prev.joints_mm[j] - prev.joints_mm[j + 1]).head<2>();
    if (towards_parent.norm() > 1e-9) p.pull_dir[j] = towards_parent.normalized();
  }
  setFriction(s, prev.sliding, {});
}

// eq. 3 with |F_n| of the previous step, held constant during this solve, and
// mu from each contact joint's stiction state (§3.4.1).
void Simulation::setFriction(int s, const std::vector<bool>& sliding,
                             const std::vector<bool>& lifted) {
  const SpineState& prev = state_.spines[s];
  SpineProblem& p = problems_[s];
  const int n = static_cast<int>(prev.contact.size());
  p.friction_n.assign(n, 0.0);
  for (int j = 0; j < n; ++j) {
    if (!prev.contact[j] || (!lifted.empty() && lifted[j])) continue;
    const double mu = sliding[j] ? brush_.friction.mu_kinetic : brush_.friction.mu_static;
    // The canvas's force on the joint itself: the hair under it (HairCushion)
    // bends sideways under its light load and slides over the paper, so its
    // push holds the joint by no friction (docs/dynamics.md, "The bundle
    // bears load").
    const double cushion = j < static_cast<int>(p.cushion.size())
                               ? cushionForceN(p.cushion[j], prev.joints_mm[j + 1].z())
                               : 0.0;
    p.friction_n[j] = mu * std::max(0.0, prev.solution.normal_force_n[j] - cushion);
  }
  const bool touching = std::any_of(p.friction_n.begin(), p.friction_n.end(),
                                    [](double f) { return f > 0; });
  // Lifting off: the contact joints of the previous step all left the paper in
  // this step's first solve. The coarse width there would let the spine creep
  // back towards rest and lose the bend plasticity leaves (spine_energy.h).
  const bool lifting = std::any_of(lifted.begin(), lifted.end(), [](bool l) { return l; });
  p.eps_damp_rad = touching || !lifting ? kSmoothDampContactRad : kSmoothDampRad;
}

// Hair volume couples the spines. A solver that takes the whole brush as one NLP
// (Ipopt; SLSQP up to SlsqpSettings::max_block_spines) gets every neighbour pair
// within `which` as links and solves them
// together, each pair's push held along its direction where the solve starts
// (VolumeLink); a neighbour outside `which` is held where it is. A solver
// of one spine at a time solves them in turn, each against its
// neighbours as last solved (Gauss-Seidel), the order reversed every step so
// that no side of the brush always goes first.
void Simulation::solveSpines(const std::vector<int>& which, std::vector<SpineSolution>* trial) {
  if (volume_pairs_.empty()) {
    solveGroup(which, trial, {});
    return;
  }
  const int ns = static_cast<int>(brush_.spines.size());
  if (solver_->couplesSpines(ns)) {
    // Where every spine's joints are as the solves start: the pushes' held
    // directions (VolumeLink), for the links and for the neighbours held
    // where they are alike.
    volume_start_.resize(ns);
    for (int s = 0; s < ns; ++s) volume_start_[s] = jointsAt(s, (*trial)[s]);
    std::vector<char> group(ns, 0);
    std::vector<int> index(ns, -1);
    for (size_t i = 0; i < which.size(); ++i) {
      group[which[i]] = 1;
      index[which[i]] = static_cast<int>(i);
    }
    for (int s : which) setVolumeContacts(s, *trial, group);
    std::vector<VolumeLink> links;
    const VolumeSpec& v = brush_.volume;
    for (const VolumePair& vp : volume_pairs_) {
      if (!group[vp.s] || !group[vp.t]) continue;
      for (int j = 1; j <= static_cast<int>(vp.rest_mm.size()); ++j) {
        const VolumeLimits lim = volumeLimits(vp, j);
        links.push_back({index[vp.s], index[vp.t], j, lim.min_mm, lim.max_mm,
                         v.stiffness_n_per_mm, v.max_separation > 0 ? v.cohesion_n_per_mm : 0.0,
                         heldPushDirection(volume_start_[vp.s][j] - volume_start_[vp.t][j])});
      }
    }
    solveGroup(which, trial, links);
    return;
  }
  std::vector<int> order = which;
  if (state_.step % 2 == 1) std::reverse(order.begin(), order.end());
  for (int s : order) {
    if (stopped_) return;
    setVolumeContacts(s, *trial, {});
    solveGroup({s}, trial, {});
  }
}

void Simulation::solveGroup(const std::vector<int>& which, std::vector<SpineSolution>* trial,
                            const std::vector<VolumeLink>& links) {
  std::vector<const SpineProblem*> problems;
  std::vector<SpineSolution*> solutions;
  for (int s : which) {
    problems.push_back(&problems_[s]);
    solutions.push_back(&(*trial)[s]);
  }
  SolveSummary summary = solver_->solve(problems, solutions, links);
  stats_.iterations += summary.iterations;
  stats_.recentred_solves += summary.recentred;
  stats_.rescue_iterations += summary.recentred_iterations;
  if (summary.stopped) {  // the step is given up: nothing to rescue
    stopped_ = true;
    return;
  }
  if (summary.usable()) {
    for (int s : which) state_.spines[s].summary = summary;
    return;
  }
  // Isolate the failure: each spine on its own from a cold start, then with the
  // fallback solver; a spine that still fails keeps its last good state. Alone,
  // a spine sees all its neighbours held where they were before this solve.
  ++stats_.isolated_solves;
  if (!links.empty())
    for (int s : which) setVolumeContacts(s, *trial, {});
  for (int s : which) {
    SpineSolution cold = state_.spines[s].solution;
    cold.lambda.clear();
    SpineSolution* one = &cold;
    const SpineProblem* pone = &problems_[s];
    SolveSummary si = solver_->solve({&pone, 1}, {&one, 1});
    stats_.iterations += si.iterations;
    stats_.rescue_iterations += si.iterations;
    if (si.stopped) {
      stopped_ = true;
      return;
    }
    if (!si.usable() && fallback_) {
      SpineSolution again = state_.spines[s].solution;
      again.lambda.clear();
      SpineSolution* two = &again;
      SolveSummary sf = fallback_->solve({&pone, 1}, {&two, 1});
      stats_.iterations += sf.iterations;
      stats_.rescue_iterations += sf.iterations;
      if (sf.usable()) {
        ++stats_.fallback_solves;
        sf.message = std::string(fallback_->name()) + " after " + solver_->name() + " " + si.message;
        si = sf;
        cold = std::move(again);
      }
    }
    if (si.usable()) (*trial)[s] = std::move(cold);
    state_.spines[s].summary = si;
  }
}

const BrushState& Simulation::step(const Pose& handle, double t_s) {
  return step(handle, t_s, JumpLimit{});
}

const BrushState& Simulation::step(const Pose& handle, double t_s, const JumpLimit& stop_on_jump) {
  stopped_ = false;
  if (stop_on_jump.limit_mm <= 0) return stepSplitting(handle, t_s, 0);
  const Snapshot before = snapshot();
  jump_limit_ = stop_on_jump;
  // The solver looks at this only during the step, whatever it throws.
  struct Unwatch {
    SpineSolver& solver;
    ~Unwatch() { solver.setWatch(nullptr); }
  } unwatch{*solver_};
  solver_->setWatch(this);
  stepSplitting(handle, t_s, 0);
  if (stopped_) {
    const SimStats tried = stats_;
    restore(before);
    keepWork(before.stats, tried);
    ++stats_.jump_stopped_steps;
  }
  return state_;
}

bool Simulation::stop(std::span<const SpineProblem* const> problems,
                      std::span<const double* const> q) {
  for (size_t i = 0; i < problems.size(); ++i) {
    const SpineProblem& p = *problems[i];
    const ptrdiff_t s = &p - problems_.data();
    if (s < 0 || s >= static_cast<ptrdiff_t>(problems_.size())) continue;  // not this brush's
    spineForwardKinematics(*p.spine, p.handle, p.baseData(), q[i], 0, &watch_fk_);
    // Until a step (or a half of a failed one) commits, the state's joints
    // are where it began.
    if (contactJumpMm(*p.spine, state_.spines[s].joints_mm, watch_fk_.x,
                      jump_limit_.contact_band_mm) > jump_limit_.limit_mm)
      return true;
  }
  return false;
}

double contactJumpMm(const SpineSpec& spine, const std::vector<Eigen::Vector3d>& a,
                     const std::vector<Eigen::Vector3d>& b, double contact_band_mm) {
  double jump = 0;
  const size_t n = std::min(a.size(), b.size());
  for (size_t j = 1; j < n; ++j) {
    const double reach = contact_band_mm + spine.bundleReachMm(j);  // geometry around the joint
    if (std::min(a[j].z(), b[j].z()) > reach) continue;
    jump = std::max(jump, (a[j].head<2>() - b[j].head<2>()).norm());
  }
  return jump;
}

// A step with a failed solve is redone as two half steps (the handle pose
// interpolated, paper §3.1 step 1): from a nearer start, a spine passing its
// buckling point converges. Up to 2^3 pieces; to the caller they are one step,
// failed if a piece still failed. A failure that persists from the previous
// step is kept without splitting.
const BrushState& Simulation::stepSplitting(const Pose& handle, double t_s, int depth) {
  constexpr int kMaxSplitDepth = 3;
  const Snapshot before = snapshot();
  const int run_before = before.failed_run;
  stepOnce(handle, t_s);
  if (stopped_) return state_;  // step() puts the state back
  // A failure that goes on from the previous step (a solve that cannot
  // converge at all, say with a tiny iteration limit) is not split again: only
  // the first failed step of a run pays for the halves.
  if (stats_.failed_steps == before.stats.failed_steps || depth >= kMaxSplitDepth ||
      (depth == 0 && run_before > 0))
    return state_;
  const SimStats tried = stats_;
  restore(before);
  const Pose from = state_.handle;
  const double t0 = state_.t_s;
  stepSplitting(interpolatePose(from, handle, 0.5), 0.5 * (t0 + t_s), depth + 1);
  if (stopped_) return state_;
  stepSplitting(handle, t_s, depth + 1);
  if (stopped_) return state_;
  const bool failed = stats_.failed_steps > before.stats.failed_steps;
  stats_.steps = before.stats.steps + 1;
  state_.step = before.state.step + 1;
  stats_.failed_steps = before.stats.failed_steps + (failed ? 1 : 0);
  failed_run_ = failed ? run_before + 1 : 0;
  stats_.longest_failed_run = std::max(before.stats.longest_failed_run, failed_run_);
  keepWork(before.stats, tried);  // the failed attempt's work stays counted
  ++stats_.split_steps;
  return state_;
}

HandleMove handleMove(const Pose& from, const Pose& to) {
  // 10 mm down the axis: among the hair of every library brush, so that a
  // turn of the handle counts as the hair feels it.
  const Eigen::Vector3d down(0, 0, -10);
  HandleMove m;
  m.head<3>() = to.position_mm - from.position_mm;
  m.tail<3>() = to.apply(down) - from.apply(down);
  return m;
}

const BrushState& Simulation::stepOnce(const Pose& handle, double t_s) {
  const int ns = static_cast<int>(brush_.spines.size());
  std::vector<SpineSolution> trial(ns);
  std::vector<std::vector<bool>> sliding(ns);

  for (int s = 0; s < ns; ++s) buildProblem(s, handle);
  // The hair lands where the axis meets the paper as it first comes down to
  // it; a handle that travels on from there drags it out from under the
  // ferrule and lays it along the paper (bundleSquash's travel).
  if (bundleSquash(rest_hair_mm_, handle) <= 1) state_.touch_xy_mm = axisOnPaper(handle);
  squash_ =
      bundleSquash(squash_rest_mm_, handle, (axisOnPaper(handle) - state_.touch_xy_mm).norm());
  const std::vector<int> which = startSpines(handle, &trial, &sliding);
  const bool settled = !which.empty() && settledAt(handle, which);
  if (settled) {
    // Nothing moved and nothing will: the last optimum stands bit for bit,
    // with its forces and warm start, on its own frames (q = 0).
    ++stats_.settled_steps;
    for (int s : which) {
      SpineState& st = state_.spines[s];
      problems_[s].base = st.rot;
      std::fill(st.solution.q.begin(), st.solution.q.end(), 0.0);
      st.summary = SolveSummary{SolveStatus::kSettled, 0, ""};
      st.moved_mm = 0;
    }
  } else if (!which.empty()) {
    ++stats_.solved_steps;
    const std::vector<SpineSolution> start = trial;
    solveSpines(which, &trial);
    if (stopped_) return state_;  // step() puts the state back
    correctContactSet(handle, which, start, &trial, &sliding);
    if (stopped_) return state_;
  }

  const bool step_failed = commitSpines(which, &trial, sliding, settled);
  if (step_failed) ++stats_.failed_steps;
  failed_run_ = step_failed ? failed_run_ + 1 : 0;
  stats_.longest_failed_run = std::max(stats_.longest_failed_run, failed_run_);

  state_.moved = handleMove(state_.handle, handle);
  state_.handle = handle;
  state_.t_s = t_s;
  ++state_.step;
  ++stats_.steps;
  sumCanvasForce();
  return state_;
}

bool Simulation::settledAt(const Pose& handle, const std::vector<int>& which) const {
  if (!(options_.settled_mm > 0)) return false;
  // Bit for bit the same pose: the same problem as the last step's but for
  // the damping's reference, which the last step's motion bounds.
  if (handle.position_mm != state_.handle.position_mm ||
      handle.rotation.coeffs() != state_.handle.rotation.coeffs())
    return false;
  // Hair volume couples the spines: all of them must be at rest together.
  if (!volume_pairs_.empty() && which.size() != brush_.spines.size()) return false;
  for (int s : which) {
    const SpineState& st = state_.spines[s];
    const SolveStatus status = st.summary.status;
    if (status != SolveStatus::kOk && status != SolveStatus::kAcceptable &&
        status != SolveStatus::kSettled)
      return false;
    if (std::find(st.sliding.begin(), st.sliding.end(), true) != st.sliding.end()) return false;
    if (!(st.moved_mm <= options_.settled_mm)) return false;
  }
  return true;
}

std::vector<int> Simulation::startSpines(const Pose& handle, std::vector<SpineSolution>* trial,
                                         std::vector<std::vector<bool>>* sliding) {
  const int ns = static_cast<int>(brush_.spines.size());
  std::vector<int> which;
  // How much of the last step's handle motion this one repeats: the same for
  // every spine (extrapolateStart).
  const double repeated = options_.extrapolate_start ? repeatedMotion(handle) : 0.0;
  for (int s = 0; s < ns; ++s) {
    const SpineSpec& spec = brush_.spines[s];
    const SpineState& prev = state_.spines[s];
    (*sliding)[s] = prev.sliding;
    (*trial)[s] = prev.solution;
    std::fill((*trial)[s].q.begin(), (*trial)[s].q.end(), 0.0);  // the re-based start
    // Step 2 of §3.1: the spine moves rigidly with the handle. If it then touches
    // nothing, and the canvas did not hold it in the previous step either (no
    // joint on the canvas, not even grazing it below the contact threshold),
    // only spring and joint friction act on it: it relaxes towards rest in
    // closed form (relaxInAir), with no solve, unless relaxing would take it
    // into the canvas.
    // A joint touches once the hair under it does (HairCushion).
    bool clear = true;
    for (int j = 1; j <= spec.jointCount() && clear; ++j)
      clear = prev.joints_mm[j].z() > kTouchMm + cushionReachMm(s, j);
    if (clear) {
      spineForwardKinematics(spec, handle, problems_[s].baseData(), (*trial)[s].q.data(), 0,
                             &fk_);
      for (int j = 1; j <= spec.jointCount() && clear; ++j)
        clear = fk_.x[j].z() > cushionReachMm(s, j);
    }
    if (clear && relaxInAir(s, handle)) continue;
    which.push_back(s);
    bool straight = true;
    for (const Eigen::Matrix3d& b : problems_[s].base)
      straight = straight && (b.col(2) - Eigen::Vector3d::UnitZ()).norm() < 1e-9;
    // At the buckling point the nudge alone picks the branch: the predicted
    // start would bend the spine whichever way its round-off leans.
    if (straight)
      (*trial)[s].q[0] = kBucklingNudgeRad;
    else if (options_.predict_start && solver_->wantsPredictedStart()) {
      extrapolateStart(s, repeated, &(*trial)[s].q);
      predictStart(s, handle, &(*trial)[s].q);
    }
  }
  return which;
}

// Where the solve of eq. 3 starts. The carried shape (q = 0) drags every joint
// along with the handle, but a joint that stuck to the paper stays stuck in
// most steps: its friction term then starts a whole step's motion from its
// kink at the anchor, where its curvature is 1 / eps_mm times larger than at
// the start, and Newton's steps overshoot until the line search has cut them
// down (about four times the iterations of a step whose joints slide;
// docs/PERFORMANCE.md, "Where a solve starts"). So the start is moved, by a few
// damped Gauss-Newton steps on the joint angles, to put
//   - each joint that stuck at the previous step back on its anchor (x, y) at
//     its previous height, and
//   - each other joint the carry pushed below the paper onto it (z = 0),
// the least change of angles doing so. Only the start moves: the energy, the
// constraints and so the minimum are those of eq. 3.
void Simulation::predictStart(int s, const Pose& handle, std::vector<double>* q) {
  const SpineSpec& spec = brush_.spines[s];
  const SpineState& prev = state_.spines[s];
  const SpineProblem& p = problems_[s];
  const int n = spec.jointCount();
  const int nv = p.vars();
  // The held joints and their targets, chosen once at the carried shape, so
  // that the start is a smooth function of the step's inputs (a set chosen
  // anew each iteration, or an early stop, would make it jump).
  enum class Hold : char { kFree, kAnchor, kPaper };
  std::vector<Hold> hold(n + 1, Hold::kFree);
  spineForwardKinematics(spec, handle, p.baseData(), q->data(), 0, &fk_);
  bool any = false;
  for (int j = 1; j <= n; ++j) {
    if (j - 1 < static_cast<int>(prev.contact.size()) && prev.contact[j - 1] &&
        !prev.sliding[j - 1])
      hold[j] = Hold::kAnchor;
    else if (fk_.x[j].z() < 0)
      hold[j] = Hold::kPaper;
    any = any || hold[j] != Hold::kFree;
  }
  if (!any) return;
  Eigen::MatrixXd jtj(nv, nv);
  Eigen::VectorXd jtr(nv);
  for (int it = 0; it < kPredictIterations; ++it) {
    spineForwardKinematics(spec, handle, p.baseData(), q->data(), 1, &fk_);
    jtj.setZero();
    jtr.setZero();
    for (int j = 1; j <= n; ++j) {
      if (hold[j] == Hold::kFree) continue;
      // The residual: to the anchor at the previous height, or (z only) to the paper.
      Eigen::Vector3d r = fk_.x[j], w(0, 0, 1);
      if (hold[j] == Hold::kAnchor) {
        r -= Eigen::Vector3d(p.anchor_xy_mm[j - 1].x(), p.anchor_xy_mm[j - 1].y(),
                             std::max(prev.joints_mm[j].z(), 0.0));
        w = Eigen::Vector3d::Ones();
      }
      for (int v = 0; v < nv; ++v) {
        const Eigen::Vector3d dv = fk_.d(j, v).cwiseProduct(w);
        jtr(v) += dv.dot(r);
        for (int u = 0; u <= v; ++u) jtj(v, u) += dv.dot(fk_.d(j, u));
      }
    }
    // Levenberg's damping, relative to J^T J's scale (mm^2 per rad^2): the
    // problem is underdetermined when few joints are held.
    const double damping = kPredictDamping * jtj.diagonal().sum() / nv;
    if (!(damping > 0)) return;
    jtj.diagonal().array() += damping;
    const Eigen::VectorXd dq = -jtj.selfadjointView<Eigen::Lower>().ldlt().solve(jtr);
    if (!dq.allFinite()) return;
    for (int v = 0; v < nv; ++v) (*q)[v] += dq(v);
  }
}

// The carried shape assumes the spine keeps its last pose relative to the
// handle. Over a stroke it does not: a sliding spine keeps bending back as it
// is dragged, a pressed one keeps splaying. Its last increment (the angles
// the previous step turned each joint through, relative to the pose before)
// is the best guess of this step's, scaled by how much of the previous
// handle motion this step repeats: u = <m, m_prev> / |m_prev|^2, clamped to
// [0, 1], so a stroke that reverses or stops starts from the carried shape
// and a steady one from the continued bend. This is the first-order
// predictor of continuation methods; only the start moves, never the
// minimum (eq. 3). It saves a fifth to two fifths of Ipopt's iterations
// (docs/PERFORMANCE.md, "Where a solve starts").
double Simulation::repeatedMotion(const Pose& handle) const {
  const HandleMove& before = state_.moved;
  const HandleMove now = handleMove(state_.handle, handle);
  const double min2 = kExtrapolateMinMoveMm * kExtrapolateMinMoveMm;
  const double before2 = before.squaredNorm();
  if (before2 < min2 || now.squaredNorm() < min2) return 0.0;
  return std::clamp(now.dot(before) / before2, 0.0, 1.0);
}

void Simulation::extrapolateStart(int s, double u, std::vector<double>* q) const {
  const SpineState& prev = state_.spines[s];
  if (u == 0 || !prev.summary.usable() || prev.solution.q.size() != q->size()) return;
  for (size_t v = 0; v < q->size(); ++v) (*q)[v] += u * prev.solution.q[v];
}

void Simulation::correctContactSet(const Pose& handle, const std::vector<int>& which,
                                   const std::vector<SpineSolution>& start,
                                   std::vector<SpineSolution>* trial,
                                   std::vector<std::vector<bool>>* sliding) {
  // The contact set of eq. 3 comes from the previous step. Correct it:
  // §3.4.1: a sticking joint whose solution slipped switches to sliding, and
  // the step is solved again with mu_kinetic for it; and a joint the solution
  // lifts off the canvas has no friction to hold it (else a brush lifting off
  // would stay pinned by the last contact's friction).
  const int ns = static_cast<int>(brush_.spines.size());
  std::vector<std::vector<bool>> lifted(ns);
  for (int s : which) lifted[s].assign((*sliding)[s].size(), false);
  for (int pass = 0; pass < kMaxStictionPasses && !stopped_; ++pass) {
    std::vector<int> again;
    for (int s : which) {
      if (!state_.spines[s].summary.usable()) continue;
      spineForwardKinematics(brush_.spines[s], handle, problems_[s].baseData(),
                             (*trial)[s].q.data(), 0, &fk_);
      std::vector<bool>& slides = (*sliding)[s];
      bool changed = false;
      for (size_t j = 0; j < slides.size(); ++j) {
        if (!state_.spines[s].contact[j] || lifted[s][j]) continue;
        if (fk_.x[j + 1].z() > kLiftedMm + cushionReachMm(s, static_cast<int>(j) + 1)) {
          lifted[s][j] = true;
          changed = true;
          continue;
        }
        if (slides[j]) continue;
        const double moved = (fk_.x[j + 1].head<2>() - problems_[s].anchor_xy_mm[j]).norm();
        if (moved > options_.slip_mm) {
          slides[j] = true;
          changed = true;
        }
      }
      if (changed) {
        setFriction(s, slides, lifted[s]);
        (*trial)[s] = start[s];
        again.push_back(s);
      }
    }
    if (again.empty()) break;
    ++stats_.resolves;
    solveSpines(again, trial);
  }
}

bool Simulation::commitSpines(const std::vector<int>& which, std::vector<SpineSolution>* trial,
                              const std::vector<std::vector<bool>>& sliding, bool settled) {
  bool step_failed = false;
  for (int s = 0; s < static_cast<int>(brush_.spines.size()); ++s) {
    SpineState& st = state_.spines[s];
    const bool solved = std::find(which.begin(), which.end(), s) != which.end();
    if (solved && settled) continue;  // kept as it was (stepOnce)
    if (!solved) st.summary = SolveSummary{SolveStatus::kFree, 0, ""};
    if (solved && !st.summary.usable()) {
      // Keep the last good pose (carried rigidly with the handle); report it.
      ++stats_.failed_spine_solves;
      step_failed = true;
      std::fill(st.solution.q.begin(), st.solution.q.end(), 0.0);
    } else if (solved) {
      st.solution = std::move((*trial)[s]);
    }
    finishSpine(s, solved, sliding[s]);
  }
  return step_failed;
}

void Simulation::sumCanvasForce() {
  // Force of the canvas on the brush (and so, through it, on the handle):
  // normal forces plus the friction forces -dE_f/dx on contact joints.
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (size_t s = 0; s < brush_.spines.size(); ++s) {
    SpineState& st = state_.spines[s];
    const SpineProblem& p = problems_[s];
    const Eigen::Vector3d f_before = f;
    Anisotropy a;
    a.strength = p.anisotropy_strength;
    a.exponent = p.anisotropy_exponent;
    for (size_t j = 0; j < st.contact.size(); ++j) {
      if (st.contact[j]) f.z() += st.solution.normal_force_n[j];
      if (p.friction_n[j] > 0) {
        const Eigen::Vector2d d = st.joints_mm[j + 1].head<2>() - p.anchor_xy_mm[j];
        a.pull_dir = p.pull_dir[j];
        f.head<2>() -= p.friction_n[j] * frictionTerm(d, a, p.eps_mm).grad;
      }
    }
    st.force_n = f - f_before;
  }
  state_.force_n = f;
}

void Simulation::finishSpine(int s, bool solved, const std::vector<bool>& sliding_before) {
  const SpineSpec& spec = brush_.spines[s];
  SpineState& st = state_.spines[s];
  const SpineProblem& problem = problems_[s];
  const int n = spec.jointCount();
  spineEnergy(problem, st.solution.q.data(), &fk_, &st.energy, nullptr, nullptr);
  st.moved_mm = st.joints_mm.size() == fk_.x.size() ? 0.0
                                                   : std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < st.joints_mm.size() && j < fk_.x.size(); ++j)
    st.moved_mm = std::max(st.moved_mm, (fk_.x[j] - st.joints_mm[j]).norm());
  st.joints_mm = fk_.x;
  st.rot.resize(n);
  for (int k = 0; k < n; ++k)
    st.rot[k] = problem.base[k] * jointRotation(st.solution.q[2 * k], st.solution.q[2 * k + 1]);
  const std::vector<bool> was_contact = st.contact;
  st.contact.assign(n, false);
  st.sliding.assign(n, false);
  st.stuck_xy_mm.resize(n);
  st.solution.normal_force_n.resize(n, 0.0);
  // The hair under a joint (HairCushion) presses the paper with the canvas's
  // force on the joint itself (eq. 5's multiplier, from the solver): the
  // joint's normal force. Only a fresh solution's: a kept one has it already.
  if (solved && st.summary.usable() && static_cast<int>(problem.cushion.size()) >= n)
    for (int j = 0; j < n; ++j)
      st.solution.normal_force_n[j] += cushionForceN(problem.cushion[j], st.joints_mm[j + 1].z());
  for (int j = 0; j < n; ++j) {
    const Eigen::Vector2d here = st.joints_mm[j + 1].head<2>();
    st.stuck_xy_mm[j] = here;
    st.contact[j] = st.solution.normal_force_n[j] > options_.contact_threshold_n;
    if (!st.contact[j]) {
      st.solution.normal_force_n[j] = 0.0;
      continue;  // a fresh contact starts out sticking, where it touched down
    }
    if (!solved || j >= static_cast<int>(was_contact.size()) || !was_contact[j]) continue;
    // Hysteresis: a sliding joint keeps sliding until it nearly stops; a
    // sticking one slips once it has crept slip_mm from where it stuck.
    const double moved = (here - problem.anchor_xy_mm[j]).norm();
    st.sliding[j] = sliding_before[j] ? moved >= options_.stick_mm : moved > options_.slip_mm;
    // Still sticking: held where it stuck, so that the creep smoothed friction
    // allows adds up over steps to a slip instead of going unseen one step at a
    // time.
    if (!sliding_before[j] && !st.sliding[j]) st.stuck_xy_mm[j] = problem.anchor_xy_mm[j];
  }
}

double Simulation::cushionReachMm(int s, int joint) const {
  const std::vector<HairCushion>& c = problems_[s].cushion;
  if (joint < 1 || joint > static_cast<int>(c.size())) return 0;
  return c[joint - 1].stiffness_n_per_mm > 0 ? c[joint - 1].reach_mm : 0;
}

bool Simulation::relaxInAir(int s, const Pose& handle) {
  const SpineSpec& spec = brush_.spines[s];
  SpineProblem& p = problems_[s];
  std::vector<Eigen::Matrix3d> relaxed = relaxedRotations(spec, rest_rot_[s], p.base);
  // The relaxed rotations are the new base, so the pose to check is at q = 0
  // (the previous solution's angles are increments from the old base).
  const std::vector<double> zero(p.vars(), 0.0);
  spineForwardKinematics(spec, handle, relaxed.data(), zero.data(), 0, &fk_);
  // Springing back would hit the canvas, or the hair under a joint would
  // reach it (HairCushion): solve.
  for (int j = 1; j <= spec.jointCount(); ++j)
    if (fk_.x[j].z() <= cushionReachMm(s, j)) return false;
  // The closed form knows nothing of hair volume: where the relaxed spine would
  // crowd a neighbour (or leave it beyond the cohesion limit), the neighbours
  // hold it and it is solved with them. (Relaxed regardless, such a spine
  // would spring back into its neighbour, be pushed out by the next step's
  // solve, and spring back again, every step.)
  if (!volume_pairs_.empty()) {
    const std::vector<Eigen::Vector3d> mine(fk_.x.begin(), fk_.x.end());
    for (const VolumePair& vp : volume_pairs_) {
      if (vp.s != s && vp.t != s) continue;
      const int other = vp.s == s ? vp.t : vp.s;
      const SpineProblem& po = problems_[other];
      const std::vector<double> carried(po.vars(), 0.0);  // moved rigidly with the handle
      spineForwardKinematics(brush_.spines[other], handle, po.baseData(), carried.data(), 0, &fk_);
      for (int j = 1; j <= static_cast<int>(vp.rest_mm.size()); ++j) {
        const VolumeLimits lim = volumeLimits(vp, j);
        const double r = (mine[j] - fk_.x[j]).norm();
        if (r < lim.min_mm || (lim.max_mm > 0 && r > lim.max_mm)) return false;
      }
    }
  }
  p.base = std::move(relaxed);
  std::fill(state_.spines[s].solution.q.begin(), state_.spines[s].solution.q.end(), 0.0);
  ++stats_.relaxed_spines;
  return true;
}

namespace {
// Below this dot product of a joint's axis with its rest axis (a bend within
// 0.1 degrees of a full reversal) the smallest turn between them is not
// defined well enough to measure twist by; such a joint keeps its rotation.
constexpr double kReversedDot = -1.0 + 1.5e-6;
}  // namespace

std::vector<Eigen::Matrix3d> canonicalRotations(const SpineSpec& spine,
                                                const std::vector<Eigen::Matrix3d>& rot) {
  return canonicalRotations(restRotations(spine), rot);
}

std::vector<Eigen::Matrix3d> canonicalRotations(const std::vector<Eigen::Matrix3d>& rest,
                                                const std::vector<Eigen::Matrix3d>& rot) {
  std::vector<Eigen::Matrix3d> out(rot.size());
  Eigen::Matrix3d carry = Eigen::Matrix3d::Identity();  // twist handed down the chain
  for (size_t k = 0; k < rot.size(); ++k) {
    // Relative to the parent's new frame, the joint turns by carry * rot[k]
    // (the parent's absolute frame changed by carry^-1, its axis unchanged).
    const Eigen::Matrix3d r = carry * rot[k];
    const Eigen::Vector3d a = r.col(2), a_rest = rest[k].col(2);
    if (a.dot(a_rest) < kReversedDot) {
      out[k] = r;
      carry.setIdentity();
      continue;
    }
    out[k] = minimalRotation(a_rest, a) * rest[k];  // same axis, twist as at rest
    carry = out[k].transpose() * r;                 // a turn about the joint's own axis
  }
  return out;
}

std::vector<Eigen::Matrix3d> relaxedRotations(const SpineSpec& spine,
                                              const std::vector<Eigen::Matrix3d>& rot) {
  return relaxedRotations(spine, restRotations(spine), rot);
}

std::vector<Eigen::Matrix3d> relaxedRotations(const SpineSpec& spine,
                                              const std::vector<Eigen::Matrix3d>& rest,
                                              const std::vector<Eigen::Matrix3d>& rot) {
  std::vector<Eigen::Matrix3d> out = rot;
  for (size_t k = 0; k < rot.size(); ++k) {
    const Eigen::Vector3d a = rot[k].col(2), a_rest = rest[k].col(2);
    const double beta = std::atan2(a_rest.cross(a).norm(), a_rest.dot(a));
    const double K = spine.stiffness_nmm_per_rad[k], D = spine.damping_nmm[k];
    // d/dbeta (K beta^2 / 2 + D (beta0 - beta)) = 0 at beta = D / K; a joint
    // already within that is held by its joint friction.
    if (K * beta <= D || a.dot(a_rest) < kReversedDot) continue;
    const double target = D / K;
    // The axis at angle `target` from rest on the great circle towards a.
    const Eigen::Vector3d perp = (a - a_rest * a_rest.dot(a)).normalized();
    const Eigen::Vector3d a_new = std::cos(target) * a_rest + std::sin(target) * perp;
    out[k] = minimalRotation(a_rest, a_new) * rest[k];
  }
  return out;
}

}  // namespace bristle

#pragma once
// The quasi-static brush simulation (paper §3.1): each step moves the handle,
// carries the spines rigidly with it (their joint angles unchanged), then solves
// every spine's constrained energy minimisation at the new pose, with stiction
// (§3.4.1), anisotropic friction (§3.4.2) and joint damping (§3.5).

#include <algorithm>
#include <limits>
#include <memory>
#include <vector>

#include "engine/model/brush.h"
#include "engine/solvers/spine_solver.h"
#include "engine/model/trajectory.h"

namespace bristle {

// How little a spine held still may have moved in its last step to count as
// at rest (SimOptions::settled_mm). Held still, a spine creeps to rest
// geometrically: eq. 4's joint friction D |dbeta|, smoothed over
// kSmoothDampContactRad, is viscous near rest, so each step moves it r times
// as far as the one before. Measured with the handle held on the paper
// (docs/dynamics.md, "A brush held still"): r is about 0.7 for the round and
// flat, 0.95 for the calligraphy brush and 0.97 for the badger, whose hair
// volume couples its 15 spines into slow modes. What a spine would still
// move is then under r / (1 - r) = 33 times this: 3e-5 mm, Ipopt's own
// accuracy at tol 1e-8 and a four-thousandth of a pixel at 8 px/mm.
inline constexpr double kSettledMm = 1e-6;

struct SimOptions {
  double max_step_mm = 0.25;  // no spine root moves further than this per step
  double min_rate_hz = 120;   // and steps come at least this often
  // Where the brush is steady (engine/dynamics/stepper.h), planned steps are
  // merged into one while the handle moves at most this far.
  double steady_step_mm = 0;
  // Each solve starts from the previous shape carried with the handle, with the
  // joints that stuck to the paper put back where they stuck and any joint the
  // carry pushed into the paper lifted onto it (docs/dynamics.md, "Where a
  // solve starts"). false: the carried shape alone (for comparisons).
  bool predict_start = true;
  // With predict_start: the carried shape first continues each spine's bend
  // at the rate of the previous step, in proportion to how far the handle
  // goes on the same way (docs/dynamics.md, "Where a solve starts"). false:
  // the prediction starts from the carried shape (for comparisons).
  bool extrapolate_start = true;
  // Canvas multipliers below this are grazing contact, not contact
  // (docs/design.md, "Solver notes": grazing joints show 1e-6..3e-4 N).
  double contact_threshold_n = 1e-3;
  // Stiction with hysteresis (§3.4.1): a sticking joint that has moved further
  // than slip_mm from where it stuck (SpineState::stuck_xy_mm) has slipped, and
  // the step is solved again with mu_kinetic; a sliding joint that moves less
  // than stick_mm in a step sticks again. Smoothed friction (engine/mechanics/friction.h)
  // reaches 99.5% of mu Fn at 10x its width and 98% at 5x: a joint creeping
  // less than that is held, not dragged.
  double slip_mm = 10 * kSmoothMm;
  double stick_mm = 5 * kSmoothMm;
  // A brush held still on the paper comes to rest: while the handle stays
  // exactly where it was, and every spine that touches has stopped sliding
  // and no joint of it moved further than this in the last step
  // (SpineState::moved_mm), the previous step's optimum stands and nothing
  // is solved (docs/dynamics.md, "A brush held still"). 0 solves every step.
  double settled_mm = kSettledMm;
};

struct SpineState {
  // angles, canvas forces, warm start. The angles q are this step's increment
  // from the base rotations of lastProblems() (engine/mechanics/spine_kinematics.h).
  SpineSolution solution;
  // Each joint's rotation relative to its parent at this step: B_k J(q_k).
  std::vector<Eigen::Matrix3d> rot;
  std::vector<Eigen::Vector3d> joints_mm;  // n + 1 world positions, root first
  std::vector<bool> contact;               // n: joint 1..n touches the canvas
  std::vector<bool> sliding;               // n: stiction state (false = sticks)
  // n: where each sticking contact joint stuck to the paper (x, y). Its
  // friction is measured from this point until it slips, not from where the
  // last step left it (docs/dynamics.md, "Where a stuck joint is held").
  std::vector<Eigen::Vector2d> stuck_xy_mm;
  EnergyTerms energy;
  SolveSummary summary;
  // Canvas force on this spine (normal + friction, N); BrushState::force_n is
  // the sum over spines. The haptic force model (paper eq. 21) is per spine.
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();
  // How far its joints moved in the step that led here, the largest of them
  // (mm; infinite after a reset): with the handle held still, whether the
  // spine has come to rest (SimOptions::settled_mm).
  double moved_mm = std::numeric_limits<double>::infinity();
};

// A handle's motion between two poses, for comparing one step's with the
// next: the displacement of its origin, then of a point 10 mm down its axis
// (where the hair is), so that a turn about the origin counts too.
using HandleMove = Eigen::Matrix<double, 6, 1>;
HandleMove handleMove(const Pose& from, const Pose& to);

struct BrushState {
  int step = 0;
  double t_s = 0;
  Pose handle;
  // How the handle moved in the step that led here, as the displacements of
  // its origin and of a point down its axis (mm): the measure by which the
  // next step extrapolates (Simulation::repeatedMotion). Zero at the start.
  HandleMove moved = HandleMove::Zero();
  std::vector<SpineState> spines;
  Eigen::Vector3d force_n = Eigen::Vector3d::Zero();  // canvas force on the brush
  // Where the handle's axis met the paper when the hair last came down to it
  // (bundleSquash first above 1): a handle travelling on from there lays the
  // hair along the paper (docs/dynamics.md, "A squashed bundle spreads").
  Eigen::Vector2d touch_xy_mm = Eigen::Vector2d::Zero();
  bool anyContact() const;
};

struct SimStats {
  int steps = 0;
  int solved_steps = 0;   // steps where at least one spine needed a solve
  int resolves = 0;       // extra solves after a stick -> slip transition
  int fallback_solves = 0;  // spine solves rescued by the fallback solver
  int failed_spine_solves = 0;
  int failed_steps = 0;
  // The longest run of consecutive steps in which some spine's solve failed and
  // it was carried along unchanged (frozen).
  int longest_failed_run = 0;
  int relaxed_spines = 0;  // spine-steps relaxed in the air in closed form
  int settled_steps = 0;   // steps of a brush held still at rest: nothing solved
  int split_steps = 0;     // steps or pieces of steps redone in halves after a failed solve
  long iterations = 0;
  int steady_steps = 0;       // steps that each took several planned steps at once
  int steady_merged = 0;      // planned steps those covered
  int steady_rejected = 0;    // merged steps redone as planned (the brush was not steady)
  // Steps redone in halves because the touching part jumped further than a
  // step may move it (engine/dynamics/stepper.h); their first try's
  // iterations stay in `iterations`.
  int jump_split_steps = 0;
  // Of those, the ones whose first try was stopped mid-solve, as soon as an
  // iterate showed the jump (Simulation::JumpLimit; Ipopt only).
  int jump_stopped_steps = 0;
  // Solves of a group of spines (or of one) that failed from a warm start and
  // were solved again from a re-centred one (Ipopt), and solves that failed
  // outright and were redone spine by spine from cold starts.
  int recentred_solves = 0;
  int isolated_solves = 0;
  // Of `iterations`, those the rescues above took: the re-centred tries and
  // the spine-by-spine redos (with their fallback solves).
  long rescue_iterations = 0;

  // Sums another run's figures into these (a scene's strokes, a sheet's cells).
  void add(const SimStats& r) {
    steps += r.steps;
    solved_steps += r.solved_steps;
    resolves += r.resolves;
    fallback_solves += r.fallback_solves;
    failed_spine_solves += r.failed_spine_solves;
    failed_steps += r.failed_steps;
    longest_failed_run = std::max(longest_failed_run, r.longest_failed_run);
    relaxed_spines += r.relaxed_spines;
    settled_steps += r.settled_steps;
    split_steps += r.split_steps;
    iterations += r.iterations;
    steady_steps += r.steady_steps;
    steady_merged += r.steady_merged;
    steady_rejected += r.steady_rejected;
    jump_split_steps += r.jump_split_steps;
    jump_stopped_steps += r.jump_stopped_steps;
    recentred_solves += r.recentred_solves;
    rescue_iterations += r.rescue_iterations;
    isolated_solves += r.isolated_solves;
  }
};

// Neighbouring spines for hair volume (docs/dynamics.md): pairs whose mean
// distance at rest, over their corresponding points, is within 1.5 times the
// nearest such distance of either spine; with the rest distance of each
// joint j = 1..min(n_s, n_t) (index j - 1).
struct VolumePair {
  int s = 0, t = 0;
  std::vector<double> rest_mm;
};
std::vector<VolumePair> volumePairs(const Brush& brush);

// Incompressibility (docs/dynamics.md, "A squashed bundle spreads"): hair of
// rest length L held with the ferrule at a height H < L above the paper,
// measured along the handle's axis, has its volume squashed into H, so its
// section across the axis must grow by s = L / H and each joint's distance
// from the axis by sqrt(s). A handle that has travelled `travel_mm` across the
// paper since its hair came down to it has dragged the squashed hair out from
// under the ferrule and laid it along the paper behind: the hair's room is
// H + kTrailRoomPerMm * travel. Returns s, 1 where the hair is not squashed
// (room >= L, or a handle that does not point the hair at the paper), at most
// kMaxSquash.
inline constexpr double kMaxSquash = 16;
// How fast a pull gives the squashed hair room, per mm of travel. Fitted
// (docs/dynamics.md, "A squashed bundle spreads"): at 1 the round's
// pressed-in pull at 30 % of its hair widened as it set off, its width's CV
// 0.19 over the middle 60 % of the stroke; at 3, 0.014.
inline constexpr double kTrailRoomPerMm = 3;
double bundleSquash(double rest_length_mm, const Pose& handle, double travel_mm = 0);
// Where the handle's axis meets the paper (z = 0); the handle's x-y when the
// axis does not point down at it.
Eigen::Vector2d axisOnPaper(const Pose& handle);

// How far a spine's hair near the paper moved across it between two sets of
// its joint positions (n + 1 each, root first): the largest x-y move of a
// joint j >= 1 that is, in either set, within the contact band plus its
// bundle's reach (SpineSpec::bundleReachMm) of the paper. Where it is larger
// than a stamp covers, a step is redone in halves (engine/dynamics/stepper.h).
double contactJumpMm(const SpineSpec& spine, const std::vector<Eigen::Vector3d>& a,
                     const std::vector<Eigen::Vector3d>& b, double contact_band_mm);

// Simulation is a SolveWatch only while a step with a JumpLimit runs.
class Simulation : private SolveWatch {
 public:
  // `fallback` (optional) is tried on a spine whose solve failed with `solver`.
  Simulation(const Brush& brush, const SimOptions& options, std::unique_ptr<SpineSolver> solver,
             std::unique_ptr<SpineSolver> fallback = nullptr);

  // The brush at rest at this pose (no contact).
  void reset(const Pose& handle, double t_s);
  // One step (paper §3.1 steps 1-3) to the new handle pose. A step whose solve
  // fails is redone in halves (up to 8 pieces) before a failure is kept.
  const BrushState& step(const Pose& handle, double t_s);
  // A step that is given up as soon as the hair near the paper is seen to
  // jump: when an iterate of one of its solves (a solver that shows them,
  // SolveWatch) has moved it further than `limit_mm` across the paper
  // (contactJumpMm), the step stops there, the state stays as before it, and
  // stepStopped() is true; the work done stays counted. The caller then
  // redoes the step in halves, as it would have after the whole step.
  struct JumpLimit {
    double limit_mm = 0;  // 0: never stop
    double contact_band_mm = 0;
  };
  const BrushState& step(const Pose& handle, double t_s, const JumpLimit& stop_on_jump);
  bool stepStopped() const { return stopped_; }

  const BrushState& state() const { return state_; }
  const SimStats& stats() const { return stats_; }
  const Brush& brush() const { return brush_; }
  // The problems of the last step, one per spine (for tests of the optimum).
  const std::vector<SpineProblem>& lastProblems() const { return problems_; }

  // Save and return to a state, e.g. to redo a step in smaller pieces.
  struct Snapshot {
    BrushState state;
    SimStats stats;
    int failed_run = 0;  // consecutive failed steps up to this state
  };
  Snapshot snapshot() const { return {state_, stats_, failed_run_}; }
  void restore(const Snapshot& s) {
    state_ = s.state;
    stats_ = s.stats;
    failed_run_ = s.failed_run;
  }

 private:
  // The walk (engine/dynamics/stepper.h) counts its merged, rejected and
  // split steps here, where a snapshot's stats are restored with the state.
  friend class Stepper;
  void countSteady(int merged) {
    ++stats_.steady_steps;
    stats_.steady_merged += merged;
  }
  // A try that ran from stats `before` to `tried` and was then undone
  // (restore): a merged step redone as planned, or a step redone in halves
  // because the hair on the paper jumped. Its solver work stays counted.
  void countRejectedSteady(const SimStats& before, const SimStats& tried) {
    ++stats_.steady_rejected;
    keepWork(before, tried);
  }
  void countJumpSplit(const SimStats& before, const SimStats& tried) {
    ++stats_.jump_split_steps;
    keepWork(before, tried);
  }
  // The solver work done between `before` and `tried`, added to stats_: a try
  // that was undone still cost its iterations.
  void keepWork(const SimStats& before, const SimStats& tried) {
    stats_.iterations += tried.iterations - before.iterations;
    stats_.jump_stopped_steps += tried.jump_stopped_steps - before.jump_stopped_steps;
    stats_.recentred_solves += tried.recentred_solves - before.recentred_solves;
    stats_.rescue_iterations += tried.rescue_iterations - before.rescue_iterations;
    stats_.isolated_solves += tried.isolated_solves - before.isolated_solves;
  }
  void buildProblem(int s, const Pose& handle);
  void setFriction(int s, const std::vector<bool>& sliding, const std::vector<bool>& lifted);
  void solveSpines(const std::vector<int>& which, std::vector<SpineSolution>* trial);
  void solveGroup(const std::vector<int>& which, std::vector<SpineSolution>* trial,
                  const std::vector<VolumeLink>& links);
  void finishSpine(int s, bool solved, const std::vector<bool>& sliding_before);
  bool relaxInAir(int s, const Pose& handle);
  // How far below joint `joint` (1..n) of spine s the hair that bears load
  // reaches (HairCushion, engine/mechanics/spine_energy.h): 0 without one.
  double cushionReachMm(int s, int joint) const;
  void predictStart(int s, const Pose& handle, std::vector<double>* q);
  double repeatedMotion(const Pose& handle) const;
  void extrapolateStart(int s, double u, std::vector<double>* q) const;
  // One step without splitting (§3.1), in stages: start each spine (carried
  // rigidly, relaxed in air when clear: returns those left to solve), solve,
  // correct the contact set and re-solve, commit, sum the canvas force.
  const BrushState& stepOnce(const Pose& handle, double t_s);
  // Whether the spines in `which` are at rest and the handle has not moved:
  // their last optimum is this step's (SimOptions::settled_mm).
  bool settledAt(const Pose& handle, const std::vector<int>& which) const;
  std::vector<int> startSpines(const Pose& handle, std::vector<SpineSolution>* trial,
                               std::vector<std::vector<bool>>* sliding);
  void correctContactSet(const Pose& handle, const std::vector<int>& which,
                         const std::vector<SpineSolution>& start,
                         std::vector<SpineSolution>* trial,
                         std::vector<std::vector<bool>>* sliding);
  // Returns whether a solved spine failed (it keeps its last good pose).
  // With `settled` (settledAt), the spines in `which` are left as they are.
  bool commitSpines(const std::vector<int>& which, std::vector<SpineSolution>* trial,
                    const std::vector<std::vector<bool>>& sliding, bool settled);
  void sumCanvasForce();
  const BrushState& stepSplitting(const Pose& handle, double t_s, int depth);
  // SolveWatch: whether an iterate moved a spine's hair near the paper
  // further than jump_limit_ allows (step with a JumpLimit).
  bool stop(std::span<const SpineProblem* const> problems,
            std::span<const double* const> q) override;

  const Brush& brush_;
  SimOptions options_;
  std::unique_ptr<SpineSolver> solver_, fallback_;
  BrushState state_;
  SimStats stats_;
  std::vector<SpineProblem> problems_;
  SpineFk fk_;
  int failed_run_ = 0;
  JumpLimit jump_limit_;  // of the step running
  bool stopped_ = false;  // the step running, or the last one, was stopped
  SpineFk watch_fk_;      // the iterate stop() looks at
  std::vector<VolumePair> volume_pairs_;
  // Every spine's joints where this step's solves start (solveSpines).
  std::vector<std::vector<Eigen::Vector3d>> volume_start_;
  std::vector<std::vector<Eigen::Matrix3d>> rest_rot_;  // per spine, restRotations
  struct VolumeLimits {
    double min_mm, max_mm;
  };
  VolumeLimits volumeLimits(const VolumePair& pair, int joint) const;
  double rest_hair_mm_ = 0;  // restHairLengthMm
  // The length bundleSquash takes as the hair's: less the press the point
  // takes up lying down (VolumeSpec::squash_after_mm).
  double squash_rest_mm_ = 0;
  double squash_ = 1;        // bundleSquash of the step being solved
  // Per spine, each point's distance from the brush's axis at rest (root first).
  std::vector<std::vector<double>> rest_radius_mm_;
  std::vector<std::vector<Eigen::Vector3d>> rest_dir_;  // unit x-y from the axis at rest
  // The squashed bundle's spread on spine s, its joints at `start` where the
  // solve starts, added to its volume contacts.
  void addAxisSpread(int s, const std::vector<Eigen::Vector3d>& start);
  // The joints of spine s with the angles of `sol` (x_0 .. x_n).
  std::vector<Eigen::Vector3d> jointsAt(int s, const SpineSolution& sol);
  void setVolumeContacts(int s, const std::vector<SpineSolution>& trial,
                         const std::vector<char>& group);
};


// Re-bases a spine's joint rotations (docs/dynamics.md, "Re-basing"): returns
// rotations with the same joint positions, each joint's twist about its own
// axis measured from its rest rotation by the smallest turn of the axis, any
// twist so removed handed on to the child joint.
std::vector<Eigen::Matrix3d> canonicalRotations(const SpineSpec& spine,
                                                const std::vector<Eigen::Matrix3d>& rot);
// The same with the spine's rest rotations (restRotations) given.
std::vector<Eigen::Matrix3d> canonicalRotations(const std::vector<Eigen::Matrix3d>& rest,
                                                const std::vector<Eigen::Matrix3d>& rot);

// The minimum of E_s + E_d (eqs. 2, 4) for a spine touching nothing, in closed
// form per joint: a joint whose spring torque K beta exceeds its joint
// friction D returns towards rest along the great circle until K beta = D
// (eq. 15's plastic residual D / K); one below that stays. `rot` must be
// canonical (canonicalRotations).
std::vector<Eigen::Matrix3d> relaxedRotations(const SpineSpec& spine,
                                              const std::vector<Eigen::Matrix3d>& rot);
std::vector<Eigen::Matrix3d> relaxedRotations(const SpineSpec& spine,
                                              const std::vector<Eigen::Matrix3d>& rest,
                                              const std::vector<Eigen::Matrix3d>& rot);

}  // namespace bristle

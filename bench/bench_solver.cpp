// Solver benchmarks (docs/PERFORMANCE.md): Ipopt time per simulation step for one
// spine and for whole brushes, while pressing and while dragging. Every benchmark
// times single Simulation::step calls with a steady clock (manual time, so the
// reported Time is the mean per timed step) and adds the median and p95 over all
// timed steps as counters: on a shared, noisy machine the mean hides outliers.
// Only steps that solve are timed, except in BM_RoundSCurve, which times every
// step and reports the solving ones apart (solve_*); untimed steps (set-up,
// replaying the press before a drag) still run, but off the clock.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "bench/bench_stats.h"
#include "bench/bench_main.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/mechanics/spine_kinematics.h"
#include "engine/model/trajectory.h"
#include "tests/support/build_paths.h"

namespace {

using namespace bristle;
using bench::Clock;
using bench::percentile;
using bench::seconds;

// The probe spine of docs/design.md ("Solver notes") and of the paper's §6 anchor: 4 mm
// segments, K 10 -> 5 N mm/rad root to tip, D 0.005 N mm, mu 0.4, handle tilted
// 20 degrees towards the motion, 60 steps of pressing, 140 of dragging 0.2 mm.
constexpr double kSegmentMm = 4;
constexpr double kRootStiffness = 10, kTipStiffness = 5;
constexpr double kDampingNmm = 0.005;
constexpr double kMu = 0.4;
constexpr double kRestThetaRad = 0.03;  // joint 0: the spine is not perfectly straight
constexpr double kTiltRad = 20 * std::numbers::pi / 180;
constexpr double kApproachMm = 0.5;     // start this far above the first touch
constexpr double kPressFraction = 0.4;  // press the root 0.4 spine lengths below it
constexpr int kPressSteps = 60, kDragSteps = 140;
constexpr double kDragStepMm = 0.2;
constexpr double kDiscRadiusMm = 2;  // roots of multi-spine brushes spread on this disc
constexpr double kStepDtS = 0.01;


SpineSpec makeSpine(int joints, const Eigen::Vector3d& root_mm) {
  SpineSpec s;
  s.root_mm = root_mm;
  for (int k = 0; k < joints; ++k) {
    const double u = joints > 1 ? double(k) / (joints - 1) : 0.0;
    s.segment_lengths_mm.push_back(kSegmentMm);
    s.stiffness_nmm_per_rad.push_back(kRootStiffness + u * (kTipStiffness - kRootStiffness));
    s.damping_nmm.push_back(kDampingNmm);
    s.rest_angles_rad.emplace_back(k == 0 ? kRestThetaRad : 0.0, 0.0);
  }
  s.width_mm.assign(joints + 1, 1.0);
  return s;
}

// Copies of one spine, roots spread evenly (sunflower pattern) on the disc.
Brush makeBrush(int spines, int joints) {
  Brush b;
  b.name = "bench";
  b.path = "bench-brush";
  b.friction.mu_static = b.friction.mu_kinetic = kMu;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int i = 0; i < spines; ++i) {
    const double r = spines > 1 ? kDiscRadiusMm * std::sqrt((i + 0.5) / spines) : 0.0;
    b.spines.push_back(makeSpine(joints, Eigen::Vector3d(r * std::cos(i * golden),
                                                         r * std::sin(i * golden), 0)));
  }
  return b;
}

// Handle poses: [0] at rest above the canvas, then kPressSteps straight down,
// then kDragSteps along +x. The handle leans towards +x so the hairs trail.
struct Scenario {
  std::vector<Pose> poses;
  int press_begin = 1, drag_begin = 1 + kPressSteps;
};

Scenario pressThenDrag(const Brush& brush) {
  Pose p;
  p.rotation = Eigen::AngleAxisd(kTiltRad, Eigen::Vector3d::UnitY());
  // Handle height at which the lowest joint at rest touches z = 0.
  double touch_mm = 0, length_mm = 0;
  SpineFk fk;
  for (const SpineSpec& s : brush.spines) {
    std::vector<double> q;
    for (const Eigen::Vector2d& r : s.rest_angles_rad) q.insert(q.end(), {r[0], r[1]});
    spineForwardKinematics(s, p, q.data(), 0, &fk);
    for (const Eigen::Vector3d& x : fk.x) touch_mm = std::max(touch_mm, -x.z());
    length_mm = std::max(length_mm, s.lengthMm());
  }
  Scenario sc;
  const double top = touch_mm + kApproachMm, bottom = touch_mm - kPressFraction * length_mm;
  p.position_mm.z() = top;
  sc.poses.push_back(p);
  for (int i = 1; i <= kPressSteps; ++i) {
    p.position_mm.z() = top + (bottom - top) * i / kPressSteps;
    sc.poses.push_back(p);
  }
  for (int i = 1; i <= kDragSteps; ++i) {
    p.position_mm.x() = kDragStepMm * i;
    sc.poses.push_back(p);
  }
  return sc;
}

// The same press, then the handle held where the press ended for as many
// steps as the drag takes: each solve after the first few starts at its own
// minimum, so what it costs is the solver's cost per solve, not its search.
Scenario pressThenHold(const Brush& brush) {
  Scenario sc = pressThenDrag(brush);
  std::fill(sc.poses.begin() + sc.drag_begin, sc.poses.end(), sc.poses[sc.drag_begin - 1]);
  return sc;
}

// The benchmarks' solver argument: 0 Ipopt as bristle runs it, 1 SLSQP, 2 Ipopt
// with its own getrusage timers on, as Ipopt 3.11 runs by itself
// (engine/solvers/ipopt/ipopt_timers.h), for the cost of those timers side by side; 3 Ipopt
// with MUMPS for every KKT matrix, as before bristle's dense solver
// (engine/solvers/ipopt/dense_kkt.h).
std::unique_ptr<SpineSolver> makeBenchSolver(long solver) {
  if (solver == 1) return makeSlsqpSolver();
  IpoptSettings settings;
  if (solver == 2) settings.extra_options.emplace_back("timing_statistics", "yes");
  if (solver == 3) settings.extra_options.emplace_back("linear_solver", "mumps");
  return makeIpoptSolver(settings);
}

// Forwards to Ipopt (or SLSQP) and adds the time spent inside solve() to a total.
class TimedSolver : public SpineSolver {
 public:
  TimedSolver(double* total_s, long solver)
      : inner_(makeBenchSolver(solver)), total_s_(total_s) {}
  SolveSummary solve(std::span<const SpineProblem* const> problems,
                     std::span<SpineSolution* const> solutions,
                     std::span<const VolumeLink> links) override {
    const Clock::time_point t0 = Clock::now();
    SolveSummary s = inner_->solve(problems, solutions, links);
    *total_s_ += seconds(t0, Clock::now());
    return s;
  }
  bool couplesSpines(int spines) const override { return inner_->couplesSpines(spines); }
  bool wantsPredictedStart() const override { return inner_->wantsPredictedStart(); }
  void setWatch(SolveWatch* watch) override { inner_->setWatch(watch); }
  const char* name() const override { return inner_->name(); }

 private:
  std::unique_ptr<SpineSolver> inner_;
  double* total_s_;
};

struct StepSample {
  double step_s = 0, solve_s = 0;
  long iterations = 0;
  bool solved = false, failed = false;
};

// Per-step samples and the counters docs/PERFORMANCE.md quotes.
struct Samples {
  std::vector<double> step_us, solve_us, iterations;
  int failed = 0;
  void add(const StepSample& s) {
    step_us.push_back(1e6 * s.step_s);
    solve_us.push_back(1e6 * s.solve_s);
    iterations.push_back(double(s.iterations));
    failed += s.failed;
  }
  void report(benchmark::State& state, const std::string& prefix = "") {
    double it_sum = 0;
    for (double i : iterations) it_sum += i;
    state.counters[prefix + "steps"] = double(step_us.size());
    state.counters[prefix + "median_us"] = percentile(step_us, 50);
    state.counters[prefix + "p95_us"] = percentile(step_us, 95);
    state.counters[prefix + "solver_median_us"] = percentile(solve_us, 50);
    state.counters[prefix + "solver_p95_us"] = percentile(solve_us, 95);
    state.counters[prefix + "iter_mean"] = iterations.empty() ? 0 : it_sum / iterations.size();
    state.counters[prefix + "iter_median"] = percentile(iterations, 50);
    state.counters[prefix + "failed"] = failed;
  }
};

// Runs a brush through a scenario and times the steps of [begin, end) that
// solve; at the end of the range it starts over with a fresh simulation.
class Runner {
 public:
  Runner(Brush brush, int begin, int end, long solver, bool hold = false,
         SimOptions options = {})
      : brush_(std::move(brush)), sc_(hold ? pressThenHold(brush_) : pressThenDrag(brush_)),
        begin_(begin), end_(end), solver_(solver), options_(options) {}

  // Spines touching the canvas when the timed range begins (after a restart).
  int spinesInContactAtBegin() {
    restart();
    int n = 0;
    for (const SpineState& s : sim_->state().spines)
      n += std::any_of(s.contact.begin(), s.contact.end(), [](bool c) { return c; });
    return n;
  }

  // The next solving step of the range; solved is false if the range has none.
  StepSample next() {
    for (int restarts = 0; restarts < 2;) {
      if (!sim_ || next_ == end_) {
        restart();
        ++restarts;
      }
      const SimStats before = sim_->stats();
      solve_s_ = 0;
      const Clock::time_point t0 = Clock::now();
      sim_->step(sc_.poses[next_], next_ * kStepDtS);
      const Clock::time_point t1 = Clock::now();
      ++next_;
      const SimStats& after = sim_->stats();
      if (after.solved_steps == before.solved_steps) continue;
      return {seconds(t0, t1), solve_s_, after.iterations - before.iterations, true,
              after.failed_steps > before.failed_steps};
    }
    return {};
  }

 private:
  void restart() {
    sim_ = std::make_unique<Simulation>(brush_, options_,
                                        std::make_unique<TimedSolver>(&solve_s_, solver_));
    sim_->reset(sc_.poses[0], 0);
    for (int i = 1; i < begin_; ++i) sim_->step(sc_.poses[i], i * kStepDtS);
    next_ = begin_;
  }

  Brush brush_;
  Scenario sc_;
  int begin_, end_, next_ = 0;
  long solver_ = 0;
  SimOptions options_;
  double solve_s_ = 0;
  std::unique_ptr<Simulation> sim_;
};

void timeSteps(benchmark::State& state, Runner& runner) {
  Samples samples;
  for (auto _ : state) {
    const StepSample s = runner.next();
    if (!s.solved) {
      state.SkipWithError("no step of the range needs a solve");
      break;
    }
    state.SetIterationTime(s.step_s);
    samples.add(s);
  }
  samples.report(state);
}

// One spine of 3 or 4 joints; range(1): 0 = pressing, 1 = dragging;
// range(2): the solver (makeBenchSolver).
void BM_SpineStep(benchmark::State& state) {
  const bool drag = state.range(1) != 0;
  const Brush brush = makeBrush(1, static_cast<int>(state.range(0)));
  Runner runner(brush, drag ? 1 + kPressSteps : 1,
                drag ? 1 + kPressSteps + kDragSteps : 1 + kPressSteps, state.range(2));
  timeSteps(state, runner);
}
BENCHMARK(BM_SpineStep)
    ->ArgNames({"joints", "drag", "solver"})
    ->ArgsProduct({{3, 4}, {0, 1}, {0, 1, 2, 3}})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// Whole-brush steps while dragging: copies of the 4-joint spine, all pressed.
void BM_BrushDragStep(benchmark::State& state) {
  Runner runner(makeBrush(static_cast<int>(state.range(0)), 4), 1 + kPressSteps,
                1 + kPressSteps + kDragSteps, state.range(1));
  const int touching = runner.spinesInContactAtBegin();
  timeSteps(state, runner);
  state.counters["in_contact"] = touching;
}
BENCHMARK(BM_BrushDragStep)
    ->ArgNames({"spines", "solver"})
    ->ArgsProduct({{1, 5, 10, 20}, {0, 1, 2, 3}})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// Whole-brush steps with the handle held still after the press, from the
// tenth held step on (kHoldSettleSteps), when each solve starts next to the
// minimum it ends at: what a solve costs with nothing to search for. Every
// held step is solved here (settled_mm = 0); by default a brush at rest
// solves nothing (docs/dynamics.md, "A brush held still"; docs/PERFORMANCE.md
// has both).
constexpr int kHoldSettleSteps = 10;
void BM_BrushHeldStep(benchmark::State& state) {
  SimOptions every_step;
  every_step.settled_mm = 0;
  Runner runner(makeBrush(static_cast<int>(state.range(0)), 4),
                1 + kPressSteps + kHoldSettleSteps, 1 + kPressSteps + kDragSteps,
                state.range(1), /*hold=*/true, every_step);
  const int touching = runner.spinesInContactAtBegin();
  timeSteps(state, runner);
  state.counters["in_contact"] = touching;
}
BENCHMARK(BM_BrushHeldStep)
    ->ArgNames({"spines", "solver"})
    ->ArgsProduct({{1, 5, 10, 20}, {0, 1}})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond);

// The round brush (7 spines x 4 joints) along s-curve.csv, one whole stroke per
// iteration. Time: the stroke's steps. Counters: all steps, and solving steps
// only (prefix solve_). volume:0 takes the library round's hair volume out
// (docs/dynamics.md), for the cost of that term side by side. extrapolate:0
// starts Ipopt's solves without the previous step's bend continued
// (SimOptions::extrapolate_start), for the start's gain side by side:
//   bench_solver --benchmark_filter='RoundSCurve/solver:0/volume:1'
void BM_RoundSCurve(benchmark::State& state) {
  const std::string dir = BRISTLE_SOURCE_DIR;
  Brush brush = loadBrush(dir + "/scenes/brushes/round.json");
  if (state.range(1) == 0) brush.volume = VolumeSpec{};
  const Trajectory traj = loadTrajectory(dir + "/scenes/trajectories/s-curve.csv");
  SimOptions options;
  options.extrapolate_start = state.range(2) != 0;
  const std::vector<double> times = planStepTimes(traj, brush, options);
  Samples all, solving;
  double total_s = 0;
  long iterations = 0;
  for (auto _ : state) {
    double solve_s = 0, stroke_s = 0;
    Simulation sim(brush, options, std::make_unique<TimedSolver>(&solve_s, state.range(0)));
    sim.reset(traj.poseAt(times.front()), times.front());
    for (size_t i = 1; i < times.size(); ++i) {
      const SimStats before = sim.stats();
      solve_s = 0;
      const Pose pose = traj.poseAt(times[i]);
      const Clock::time_point t0 = Clock::now();
      sim.step(pose, times[i]);
      const double dt = seconds(t0, Clock::now());
      const SimStats& after = sim.stats();
      const StepSample s{dt, solve_s, after.iterations - before.iterations,
                         after.solved_steps > before.solved_steps,
                         after.failed_steps > before.failed_steps};
      all.add(s);
      if (s.solved) solving.add(s);
      stroke_s += dt;
    }
    state.SetIterationTime(stroke_s);
    total_s += stroke_s;
    iterations += sim.stats().iterations;
  }
  const double steps = double(all.step_us.size()), solves = double(solving.step_us.size());
  all.report(state);
  solving.report(state, "solve_");
  const double strokes = std::max<double>(1, double(state.iterations()));
  state.counters["steps"] = steps / strokes;  // per stroke
  state.counters["solve_steps"] = solves / strokes;
  state.counters["steps_per_s"] = total_s > 0 ? steps / total_s : 0;
  state.counters["solver_iterations"] = double(iterations) / strokes;  // per stroke
}
BENCHMARK(BM_RoundSCurve)
    ->ArgNames({"solver", "volume", "extrapolate"})
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}, {1}})
    ->Args({0, 0, 0})
    ->Args({0, 1, 0})
    ->Iterations(3)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) { return bristle::bench::runBenchmarks(argc, argv); }

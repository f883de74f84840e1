#include "haptics/live_session.h"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "engine/mechanics/spine_kinematics.h"
#include "engine/solvers/solver_pair.h"

namespace bristle::haptics {

namespace {

void addNs(timespec* t, long ns) {
  t->tv_nsec += ns;
  while (t->tv_nsec >= 1000000000L) {
    t->tv_nsec -= 1000000000L;
    ++t->tv_sec;
  }
}

// The sim thread: steps the brush to the latest stylus pose at the sim rate
// and publishes a force model after every frame.
class SimThread {
 public:
  SimThread(const Brush& brush, const LiveOptions& options, ServoLoop* servo)
      : brush_(brush), options_(options), servo_(servo) {
    // SLSQP sweeps the spines one at a time here: its block solve of the
    // spines hair volume couples takes the round 8-13 times the CPU
    // (docs/PERFORMANCE.md, "SLSQP's block solve"), and a live session must
    // keep its sim rate (paper §5: 30-60 Hz) more than it must converge the
    // belly's pushes within each frame.
    SolverSettings settings{options.solver, kDefaultSolverMaxIterations, {}};
    settings.slsqp_max_block_spines = 0;
    SolverPair solvers = makeSolverPair(settings, brush);
    sim_ = std::make_unique<Simulation>(brush, options.sim, std::move(solvers.primary),
                                        std::move(solvers.fallback));
    WalkOptions walk;
    walk.sim = options.sim;
    stepper_ = std::make_unique<Stepper>(*sim_, walk);
  }
  void start() { thread_ = std::thread([this] { run(); }); }
  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  std::uint64_t frames() const { return frame_.load(); }
  SimStats stats() const { return stats_; }  // after stop()
  bool waitedForClearance() const { return waited_.load(); }

 private:
  void run() {
    const long period_ns = std::lround(1e9 / options_.sim_rate_hz);
    timespec next{};
    clock_gettime(CLOCK_MONOTONIC, &next);
    bool started = false;
    while (!stop_.load()) {
      StylusState st;
      servo_->stylus().load(&st);
      if (st.valid) {
        const Pose pose = st.pose();
        if (!started) {
          if (brushClearOfCanvas(brush_, pose)) {
            sim_->reset(pose, st.t_s);
            started = true;
          } else {
            waited_ = true;
          }
        } else {
          stepper_->stepTo(pose, st.t_s);
        }
        if (started) {
          const std::uint64_t f = frame_.load() + 1;
          servo_->models().store(buildForceModel(sim_.get(), f, options_.force_model));
          frame_.store(f);
        }
      }
      addNs(&next, period_ns);
      timespec now{};
      clock_gettime(CLOCK_MONOTONIC, &now);
      // Late (a slow frame): start the next one now rather than catch up.
      if (now.tv_sec > next.tv_sec || (now.tv_sec == next.tv_sec && now.tv_nsec > next.tv_nsec))
        next = now;
      else
        while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next, nullptr) != 0) {
        }
    }
    stats_ = sim_->stats();
  }

  const Brush& brush_;
  const LiveOptions& options_;
  ServoLoop* servo_;
  std::unique_ptr<Simulation> sim_;
  // Steps towards each stylus pose as a trajectory's plan steps a segment.
  std::unique_ptr<Stepper> stepper_;
  std::thread thread_;
  std::atomic<bool> stop_{false}, waited_{false};
  std::atomic<std::uint64_t> frame_{0};
  SimStats stats_;
};

}  // namespace

bool brushClearOfCanvas(const Brush& brush, const Pose& handle) {
  SpineFk fk;
  for (const SpineSpec& spec : brush.spines) {
    std::vector<double> q(2 * spec.jointCount());
    for (int k = 0; k < spec.jointCount(); ++k) {
      q[2 * k] = spec.rest_angles_rad[k][0];
      q[2 * k + 1] = spec.rest_angles_rad[k][1];
    }
    spineForwardKinematics(spec, handle, q.data(), 0, &fk);
    for (const Eigen::Vector3d& x : fk.x)
      if (x.z() < 0) return false;
  }
  return true;
}

LiveResult runLiveSession(const Brush& brush, Device* device, SessionWriter* writer,
                          const LiveOptions& options) {
  ServoOptions so = options.servo;
  so.safety.stale_after_s = 3.0 / options.sim_rate_hz;  // three sim frames
  ServoLoop servo(device, so);
  SimThread sim(brush, options, &servo);
  LiveResult r;
  sim.start();
  servo.start();
  bool told_wait = false;
  ServoSample smp;
  auto drain = [&] {
    while (servo.samples().pop(&smp)) {
      writer->add(smp);
      if (options.tick_wall_ns != nullptr) options.tick_wall_ns->push_back(smp.wall_ns);
      const double f = Eigen::Vector3d(smp.force_n[0], smp.force_n[1], smp.force_n[2]).norm();
      r.max_force_n = std::max(r.max_force_n, f);
    }
  };
  // A servo loop that has not ticked for this long has lost its device.
  constexpr auto kStalled = std::chrono::seconds(2);
  std::uint64_t last_ticks = 0;
  auto last_progress = std::chrono::steady_clock::now();
  bool stalled = false;
  while (!servo.finished()) {
    if (options.interrupt != nullptr && options.interrupt->load()) servo.requestStop();
    const auto now = std::chrono::steady_clock::now();
    if (servo.ticks() != last_ticks) {
      last_ticks = servo.ticks();
      last_progress = now;
    } else if (now - last_progress > kStalled) {
      stalled = true;
      break;
    }
    drain();
    writer->flushIfDue();
    if (!told_wait && sim.waitedForClearance() && sim.frames() == 0 && options.notice) {
      options.notice("waiting for the brush to be above the canvas before simulating");
      told_wait = true;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  servo.join();
  sim.stop();
  drain();
  r.end = servo.end();
  r.error = servo.fatalError();
  if (stalled) {
    r.end = ServoLoop::End::kDeviceError;
    r.error.code = 0xffff;
    r.error.fatal = true;
    r.error.message = "the servo loop stopped ticking for 2 s (device scheduler stalled)";
  }
  r.servo_ticks = servo.ticks();
  r.dropped_samples = servo.samples().dropped();
  r.device_errors = servo.deviceErrors();
  r.sim_frames = sim.frames();
  r.sim_stats = sim.stats();
  writer->close();
  r.session_rows = writer->sessionRows();
  r.force_rows = writer->forceRows();
  return r;
}

}  // namespace bristle::haptics

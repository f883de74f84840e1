#pragma once
// A live session (paper §5): the device's servo loop at 1 kHz, the simulation
// on its own thread at the sim rate from the latest stylus pose, and the
// recorder (the calling thread) writing the session as it goes.
//
//   device --pose--> servo loop --StylusState seqlock--> sim thread
//   sim thread --ForceModel seqlock--> servo loop --force--> device
//   servo loop --ServoSample ring--> recorder --> session.csv, forces.csv

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "engine/model/brush.h"
#include "engine/dynamics/stepper.h"
#include "engine/solvers/solver_pair.h"
#include "haptics/device.h"
#include "haptics/force_model.h"
#include "haptics/servo_loop.h"
#include "haptics/session_file.h"

namespace bristle::haptics {

struct LiveOptions {
  double sim_rate_hz = 30;  // paper §5: the simulation runs at 30-60 Hz
  SimOptions sim;
  ForceModelOptions force_model;
  ServoOptions servo;       // safety.stale_after_s is set to three sim frames
  SolverKind solver = SolverKind::kIpopt;  // primary; the other one is the fallback
  // Set (e.g. by a SIGINT handler) to end the session cleanly.
  const std::atomic<bool>* interrupt = nullptr;
  std::function<void(const std::string&)> notice;  // one-line messages
  // If set, receives every servo tick's wall-clock start (CLOCK_MONOTONIC ns),
  // in order, for period and jitter measurements (bench/bench_servo.cpp).
  std::vector<std::int64_t>* tick_wall_ns = nullptr;
};

struct LiveResult {
  ServoLoop::End end = ServoLoop::End::kRunning;
  DeviceStatus error;          // the fatal device error, if that ended it
  std::uint64_t servo_ticks = 0, dropped_samples = 0, device_errors = 0;
  std::uint64_t sim_frames = 0;
  double max_force_n = 0;      // largest force sent to the device
  long session_rows = 0, force_rows = 0;
  SimStats sim_stats;
};

// Runs until the device ends (end of a played trajectory, device error),
// options.servo.duration_s of device time passes, or *interrupt is set.
// Always leaves the servo loop stopped (zero force sent) and the files closed.
LiveResult runLiveSession(const Brush& brush, Device* device, SessionWriter* writer,
                          const LiveOptions& options);

// True when the brush at rest at this pose is entirely above the canvas: a
// simulation may start there.
bool brushClearOfCanvas(const Brush& brush, const Pose& handle);

}  // namespace bristle::haptics

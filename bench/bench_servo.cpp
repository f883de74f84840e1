// The servo loop's achieved rate and period jitter (paper §5): a real
// live session -- the none device playing a trajectory at 1 kHz, the sim
// thread (round brush, SLSQP, force model probes) and the recorder -- for
// 10 s, timing every servo tick's start on CLOCK_MONOTONIC.
//
//   build/bench/bench_servo [seconds] [sim_rate_hz]
//
// Not a Google Benchmark: one long run, whose figure is the distribution of
// 10 000 periods. Results in docs/PERFORMANCE.md, "Haptic servo loop".

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <vector>

#include "bench/bench_stats.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "haptics/live_session.h"
#include "haptics/none_device.h"
#include "tests/support/build_paths.h"

using namespace bristle;

namespace {

// The round brush pressed 6 mm past first contact, tilted 20 degrees, drawing
// circles of 10 mm radius, one every 2 s, for `seconds`.
Trajectory circles(double seconds) {
  Trajectory t;
  t.path = "circles";
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.35, Eigen::Vector3d::UnitY()));
  for (int i = 0; i <= static_cast<int>(seconds * 100); ++i) {
    TrajectorySample s;
    s.t_s = i * 0.01;
    const double press = std::min(1.0, s.t_s / 0.5);  // press in over 0.5 s
    const double a = 2 * M_PI * s.t_s / 2.0;
    s.pose.position_mm = Eigen::Vector3d(60 + 10 * std::cos(a), 60 + 10 * std::sin(a),
                                         24 - 7 * press);
    s.pose.rotation = tilt;
    s.line = i + 1;
    t.samples.push_back(s);
  }
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  const double sim_rate = argc > 2 ? std::atof(argv[2]) : 30.0;
  const Brush brush = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/round.json");
  haptics::NoneDevice device(circles(seconds));
  const std::string session =
      (std::filesystem::temp_directory_path() / "bristle-bench-servo.csv").string();
  haptics::SessionHeader header;
  header.device_model = device.model();
  haptics::SessionWriter writer(session, "", header);
  haptics::LiveOptions live;
  live.sim_rate_hz = sim_rate;
  live.solver = SolverKind::kSlsqp;
  std::vector<std::int64_t> wall;
  wall.reserve(static_cast<size_t>(seconds * 1000) + 100);
  live.tick_wall_ns = &wall;
  const haptics::LiveResult r = haptics::runLiveSession(brush, &device, &writer, live);
  std::filesystem::remove(session);

  std::vector<double> period_us, jitter_us;
  for (size_t i = 1; i < wall.size(); ++i) {
    const double p = (wall[i] - wall[i - 1]) / 1e3;
    period_us.push_back(p);
    jitter_us.push_back(std::fabs(p - 1000.0));
  }
  const double span_s = (wall.back() - wall.front()) / 1e9;
  const double rate = (wall.size() - 1) / span_s;
  std::vector<double> j = jitter_us;
  const double p50 = bench::percentile(j, 50), p99 = bench::percentile(j, 99),
               p999 = bench::percentile(j, 99.9);
  const double worst = j.empty() ? 0 : j.back();
  long late_2ms = 0;
  for (double p : period_us) late_2ms += p > 2000;
  std::printf(
      "servo ticks %zu over %.3f s: %.2f Hz achieved\n"
      "period jitter |period - 1 ms|: median %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f "
      "us; periods > 2 ms: %ld\n"
      "sim frames %llu (%.1f Hz of %.0f asked), dropped samples %llu, servo thread %s\n",
      wall.size(), span_s, rate, p50, p99, p999, worst, late_2ms,
      static_cast<unsigned long long>(r.sim_frames), r.sim_frames / span_s, sim_rate,
      static_cast<unsigned long long>(r.dropped_samples),
      device.realtime() ? "SCHED_FIFO" : "normal priority (SCHED_FIFO refused)");
  return 0;
}

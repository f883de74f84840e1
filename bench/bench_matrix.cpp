// The press matrix (tests/support/press_matrix.h) over the brush library: every
// brush pressed to 0..80% of its hair length, at tilts 0/30/60 degrees, pulled
// 30 mm along +x at 10/50/200 mm/s, and pressed and lifted in place -- counting
// failed simulation steps and timing every step. A plain program, not a Google
// Benchmark and not a test: `bench_matrix [--solver ipopt|slsqp] [--no-fallback]
// [--brush NAME|FILE]... [--quick] [--csv FILE]`. Exits 1 when any step failed,
// 64 on a bad command line.

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "bench/bench_stats.h"
#include "engine/formats/brush_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "process/process_hooks.h"
#include "tests/support/press_matrix.h"
#include "tests/support/build_paths.h"

namespace {

using namespace bristle;
using namespace bristle::testsupport;

const std::vector<std::string> kLibrary = {"round",  "flat", "bright",     "filbert",
                                           "badger", "fan",  "calligraphy"};

struct Matrix {
  std::vector<double> fractions, tilts, speeds;  // pulls: all combinations
  std::vector<double> lift_fractions, lift_tilts;  // press_lift: all combinations
};

Matrix fullMatrix() {
  Matrix m;
  for (int i = 0; i <= 8; ++i) m.fractions.push_back(i / 10.0);
  m.tilts = {0, 30, 60};
  m.speeds = {10, 50, 200};
  m.lift_fractions = m.fractions;
  m.lift_tilts = m.tilts;
  return m;
}

// Light, medium and the heaviest presses at every tilt, one moderate speed;
// press_lift light and heaviest, upright and at the steepest tilt.
Matrix quickMatrix() {
  Matrix m;
  m.fractions = {0.1, 0.4, 0.8};
  m.tilts = {0, 30, 60};
  m.speeds = {50};
  m.lift_fractions = {0.2, 0.8};
  m.lift_tilts = {0, 60};
  return m;
}

std::vector<Case> casesFor(const std::string& path, const Matrix& m) {
  std::vector<Case> out;
  for (double f : m.fractions)
    for (double t : m.tilts)
      for (double v : m.speeds) out.push_back({path, f, t, v, CaseKind::kPull});
  for (double f : m.lift_fractions)
    for (double t : m.lift_tilts) out.push_back({path, f, t, 0, CaseKind::kPressLift});
  return out;
}

struct Row {
  std::string brush;
  int cases = 0, clamped = 0, steps = 0, failed_steps = 0, failed_cases = 0, rescued = 0;
  int longest_failed_run = 0;
  std::string worst = "-";
  int worst_failed = 0;
  std::vector<double> step_ms;
  double light_s = 0, heavy_s = 0;
  int light_steps = 0, heavy_steps = 0;
  long light_spines = 0, heavy_spines = 0;  // spine-steps with contact
  double wall_s = 0;
};

void usage(FILE* to) {
  std::fprintf(to,
               "usage: bench_matrix [--solver ipopt|slsqp] [--no-fallback] [--brush NAME|FILE]...\n"
               "                    [--quick] [--csv FILE]\n"
               "  As bristle render, the other solver rescues a spine whose solve failed\n"
               "  (counted as rescued); --no-fallback leaves such a failure standing.\n"
               "  Library brushes: round flat bright filbert badger fan calligraphy, or a\n"
               "  brush file of one's own (a path with a slash or ending in .json).\n"
               "  Full matrix per brush: press 0..0.8 of the hair length (step 0.1) x tilt\n"
               "  0/30/60 x speed 10/50/200 mm/s pulls, and press_lift at every press and\n"
               "  tilt (108 cases). --quick: press 0.1/0.4/0.8 x tilt 0/30/60 at 50 mm/s, and\n"
               "  press_lift 0.2/0.8 at tilt 0/60 (13 cases). Exit 1 if any step failed.\n");
}

std::string fmtMs(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", s * 1e3);
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  bristle::installProcessHooks();  // the CLI's solver set-up (process/process_hooks.h)
  std::string solver = "ipopt", csv_path;
  std::vector<std::string> brushes;
  bool quick = false, fallback = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "bench_matrix: %s needs a value\n", a.c_str());
        std::exit(64);
      }
      return argv[++i];
    };
    if (a == "--solver") {
      solver = value();
    } else if (a == "--brush") {
      brushes.push_back(value());
    } else if (a == "--no-fallback") {
      fallback = false;
    } else if (a == "--quick") {
      quick = true;
    } else if (a == "--csv") {
      csv_path = value();
    } else if (a == "-h" || a == "--help") {
      usage(stdout);
      return 0;
    } else {
      std::fprintf(stderr, "bench_matrix: unknown argument '%s'\n", a.c_str());
      usage(stderr);
      return 64;
    }
  }
  if (solver != "ipopt" && solver != "slsqp") {
    std::fprintf(stderr, "bench_matrix: --solver must be ipopt or slsqp\n");
    return 64;
  }
  if (brushes.empty()) brushes = kLibrary;
  // A name with a slash or a .json ending is a brush file of one's own.
  auto isFile = [](const std::string& b) {
    return b.find('/') != std::string::npos ||
           (b.size() > 5 && b.compare(b.size() - 5, 5, ".json") == 0);
  };
  for (const std::string& b : brushes)
    if (!isFile(b) && std::find(kLibrary.begin(), kLibrary.end(), b) == kLibrary.end()) {
      std::fprintf(stderr, "bench_matrix: unknown brush '%s'\n", b.c_str());
      return 64;
    }

  std::ofstream csv;
  if (!csv_path.empty()) {
    csv.open(csv_path);
    if (!csv) {
      std::fprintf(stderr, "bench_matrix: cannot create %s\n", csv_path.c_str());
      return 73;
    }
    csv << "solver,brush,kind,press_fraction,tilt_deg,speed_mm_s,clamped,depth_mm,steps,"
           "failed_steps,failed_spine_solves,longest_failed_run,wall_s,ms_per_step,"
           "median_ms,p95_ms,iterations,resolves,split_steps,contact_spine_steps\n";
  }

  const Matrix matrix = quick ? quickMatrix() : fullMatrix();
  const bool progress = isatty(STDERR_FILENO);
  const size_t total_cases = brushes.size() * casesFor("", matrix).size();

  std::vector<Row> rows;
  size_t done = 0;
  try {
    for (const std::string& name : brushes) {
      const std::string path =
          isFile(name) ? name
                       : std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/" + name + ".json";
      const Brush brush = loadBrush(path);
      Row row;
      row.brush = name;
      for (const Case& c : casesFor(path, matrix)) {
        ++done;
        if (progress) {
          std::fprintf(stderr, "\r\033[K[%zu/%zu] %s %s", done, total_cases, name.c_str(),
                       describe(c).c_str());
          std::fflush(stderr);
        }
        CaseResult r = runCase(brush, c, solver, fallback);
        ++row.cases;
        row.clamped += r.clamped;
        row.steps += r.steps;
        row.failed_steps += r.failed_steps;
        row.failed_cases += r.failed_steps > 0;
        row.rescued += r.fallback_solves;
        row.longest_failed_run = std::max(row.longest_failed_run, r.longest_failed_run);
        row.wall_s += r.wall_s;
        if (r.failed_steps > row.worst_failed) {
          row.worst_failed = r.failed_steps;
          row.worst = describe(c) + " (" + std::to_string(r.failed_steps) + "/" +
                      std::to_string(r.steps) + ")";
        }
        if (c.press_fraction <= 0.2 + 1e-9) {
          row.light_s += r.wall_s;
          row.light_steps += r.steps;
          row.light_spines += r.contact_spine_steps;
        }
        if (c.press_fraction >= 0.6 - 1e-9) {
          row.heavy_s += r.wall_s;
          row.heavy_steps += r.steps;
          row.heavy_spines += r.contact_spine_steps;
        }
        std::vector<double> ms;
        ms.reserve(r.step_s.size());
        for (double s : r.step_s) ms.push_back(s * 1e3);
        row.step_ms.insert(row.step_ms.end(), ms.begin(), ms.end());
        if (csv) {
          const double med = bench::percentile(ms, 50), p95 = bench::percentile(ms, 95);
          char line[512];
          std::snprintf(line, sizeof line,
                        "%s,%s,%s,%.2f,%g,%g,%d,%.4f,%d,%d,%d,%d,%.6f,%.4f,%.4f,%.4f,%ld,%d,%d,%ld\n",
                        solver.c_str(), name.c_str(), toString(c.kind), c.press_fraction,
                        c.tilt_deg, c.kind == CaseKind::kPull ? c.speed_mm_s : 0.0,
                        int(r.clamped), r.depth_mm, r.steps, r.failed_steps,
                        r.failed_spine_solves, r.longest_failed_run, r.wall_s,
                        r.s_per_step * 1e3, med, p95, r.iterations, r.resolves,
                        r.split_steps, r.contact_spine_steps);
          csv << line;
          csv.flush();
        }
      }
      rows.push_back(std::move(row));
    }
  } catch (const Error& e) {
    if (progress) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "bench_matrix: %s\n", e.what());
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    if (progress) std::fprintf(stderr, "\r\033[K");
    std::fprintf(stderr, "bench_matrix: %s\n", e.what());
    return 70;
  }
  if (progress) std::fprintf(stderr, "\r\033[K");

  std::printf("solver %s%s, %s matrix; ms/step: median and p95 over every step, light (press "
              "<= 0.2) and heavy (>= 0.6) = wall / steps; us/spine: wall per spine-step with\n"
              "contact, light and heavy\n",
              solver.c_str(), fallback ? " (fallback: the other)" : " alone",
              quick ? "quick" : "full");
  std::printf("%-12s %5s %7s %7s %7s %7s %7s %7s %7s %7s %7s %7s %8s %8s  %s\n", "brush",
              "cases", "clamped", "steps", "failed", "f.cases", "f.run", "rescued", "median",
              "p95", "light", "heavy", "us/sp.L", "us/sp.H", "worst case (failed/steps)");
  int total_failed = 0, total_steps = 0;
  for (Row& r : rows) {
    total_failed += r.failed_steps;
    total_steps += r.steps;
    auto perSpine = [](double s, long n) {
      char buf[32];
      if (n <= 0) return std::string("-");
      std::snprintf(buf, sizeof buf, "%.1f", s * 1e6 / static_cast<double>(n));
      return std::string(buf);
    };
    std::printf("%-12s %5d %7d %7d %7d %7d %7d %7d %7s %7s %7s %7s %8s %8s  %s\n", r.brush.c_str(),
                r.cases, r.clamped, r.steps, r.failed_steps, r.failed_cases, r.longest_failed_run,
                r.rescued,
                fmtMs(bench::percentile(r.step_ms, 50) / 1e3).c_str(),
                fmtMs(bench::percentile(r.step_ms, 95) / 1e3).c_str(),
                r.light_steps ? fmtMs(r.light_s / r.light_steps).c_str() : "-",
                r.heavy_steps ? fmtMs(r.heavy_s / r.heavy_steps).c_str() : "-",
                perSpine(r.light_s, r.light_spines).c_str(),
                perSpine(r.heavy_s, r.heavy_spines).c_str(), r.worst.c_str());
  }
  std::printf("total: %d failed of %d steps\n", total_failed, total_steps);
  return total_failed > 0 ? 1 : 0;
}

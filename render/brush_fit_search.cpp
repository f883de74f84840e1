// The search of a fit (render/brush_fit.h; docs/fit.md): BOBYQA over the free
// parameters normalised to [0, 1], each evaluation the measurement protocol
// run on the brush with the parameters applied, its measures cached on disk.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <nlopt.hpp>

#include "bristle/version.h"
#include "engine/base/atomic_output.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/base/text_file.h"
#include "engine/formats/brush_reader.h"
#include "render/brush_fit.h"

namespace bristle::render {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// BOBYQA's first trust region, in the normalised unit box: 15 % of each
// parameter's range (a factor of 1.5 for the default stiffness range 0.25-4),
// far enough that the first steps move the measures by more than a pixel.
constexpr double kInitialStep = 0.15;
// It stops when a step would move every parameter by less than 1 % of its
// range: a 2.8 % change of a 0.25-4 factor, which moves a footprint by less
// than the protocol's 0.1 mm pixel.
constexpr double kStepTolerance = 0.01;
constexpr const char* kCacheFormat = "bristle-fit-cache/1";

double valueAt(const FitParam& p, double x) {
  return p.log ? p.min * std::pow(p.max / p.min, x) : p.min + x * (p.max - p.min);
}

double unitOf(const FitParam& p, double v) {
  const double u = p.log ? std::log(v / p.min) / std::log(p.max / p.min)
                         : (v - p.min) / (p.max - p.min);
  return std::clamp(u, 0.0, 1.0);
}

// What an evaluation's measures depend on, besides the brush: the protocol,
// the solvers and the version of bristle that simulated them.
std::string cacheKeyText(const std::string& brush_json, const MeasureProtocol& p,
                         const SolverSettings& s) {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "%s\nbristle %s\nprotocol speed %.17g pull %.17g descend %.17g px %.17g "
                "samples %d\nsolver %s %d\n",
                kCacheFormat, kVersion, p.speed_mm_s, p.pull_mm, p.descend_s, p.px_per_mm,
                p.samples, solverKindName(s.kind), s.max_iterations);
  std::string key = buf;
  for (const auto& [name, value] : s.ipopt_options) key += "ipopt " + name + "=" + value + "\n";
  key += "depths";
  for (double d : p.depths_mm) {
    std::snprintf(buf, sizeof buf, " %.17g", d);
    key += buf;
  }
  return key + "\n" + brush_json;
}

std::string cacheEntry(const std::string& key, const std::vector<DepthMeasure>& rows) {
  nlohmann::json j = {{"format", kCacheFormat}, {"key", key}, {"rows", nlohmann::json::array()}};
  for (const DepthMeasure& m : rows)
    j["rows"].push_back({m.depth_mm, m.shape.touched, m.shape.width_mm, m.shape.drag_mm,
                         m.shape.offset_mm, m.failed_steps});
  return j.dump() + "\n";
}

// An entry's measures when it is whole and made for exactly this key; a
// missing, unreadable, corrupt or foreign entry is a miss, never trusted.
bool readCacheEntry(const std::string& file, const std::string& key, size_t depths,
                    std::vector<DepthMeasure>* out) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return false;
  try {
    const nlohmann::json j = nlohmann::json::parse(readTextFile(file), nullptr, false);
    if (!j.is_object() || j.value("format", "") != kCacheFormat || j.value("key", "") != key)
      return false;
    const nlohmann::json& rows = j.at("rows");
    if (!rows.is_array() || rows.size() != depths) return false;
    std::vector<DepthMeasure> m;
    for (const nlohmann::json& r : rows) {
      DepthMeasure d;
      d.depth_mm = r.at(0).get<double>();
      d.shape.touched = r.at(1).get<bool>();
      d.shape.width_mm = r.at(2).get<double>();
      d.shape.drag_mm = r.at(3).get<double>();
      d.shape.offset_mm = r.at(4).get<double>();
      d.failed_steps = r.at(5).get<int>();
      for (double v : {d.depth_mm, d.shape.width_mm, d.shape.drag_mm, d.shape.offset_mm})
        if (!std::isfinite(v)) return false;
      m.push_back(d);
    }
    *out = std::move(m);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

class Evaluator {
 public:
  Evaluator(const std::string& brush_text, const MeasurementTable& table,
            const std::vector<FitParam>& params, const FitOptions& o, const FitProgress& progress)
      : text_(brush_text), table_(table), params_(params), o_(o), progress_(progress) {
    o_.protocol.depths_mm = table.depths();
    if (!o_.cache_dir.empty()) {
      std::error_code ec;
      fs::create_directories(o_.cache_dir, ec);
      if (ec) {
        warning_ = o_.cache_dir + ": cannot create the cache folder (" + ec.message() +
                   "); measuring without a cache";
        o_.cache_dir.clear();
      }
    }
  }

  std::vector<double> values(const std::vector<double>& x) const {
    std::vector<double> v;
    for (size_t i = 0; i < params_.size(); ++i) v.push_back(valueAt(params_[i], x[i]));
    return v;
  }

  // The measures of the brush with `values` applied, and their squared error.
  double evaluate(const std::vector<double>& x, std::vector<DepthMeasure>* measures);

  double sse(const std::vector<DepthMeasure>& m) const {
    double s = 0;
    for (const MeasuredRow& r : table_.rows)
      for (FitColumn c : o_.columns) {
        const double e = r.value[size_t(c)] - predicted(m, r.depth_mm, c);
        s += e * e;
      }
    return s;
  }

  static double predicted(const std::vector<DepthMeasure>& m, double depth, FitColumn c) {
    for (const DepthMeasure& d : m)
      if (d.depth_mm == depth) return d.shape.touched ? columnOf(d.shape, c) : 0;
    return 0;
  }

  double rmse(double sse) const {
    return std::sqrt(sse / double(table_.rows.size() * o_.columns.size()));
  }

  const FitOptions& options() const { return o_; }
  int evaluations = 0, cache_hits = 0, strokes = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  std::vector<double> best_x;
  std::vector<DepthMeasure> best_measures;
  std::string warning_;

 private:
  std::vector<DepthMeasure> measure(const std::string& json);

  const std::string& text_;
  const MeasurementTable& table_;
  const std::vector<FitParam>& params_;
  FitOptions o_;
  const FitProgress& progress_;
  std::map<std::uint64_t, std::vector<DepthMeasure>> memo_;
};

std::vector<DepthMeasure> Evaluator::measure(const std::string& json) {
  const std::string key = cacheKeyText(json, o_.protocol, o_.solvers);
  const std::uint64_t h = fnv1a64(key);
  if (const auto it = memo_.find(h); it != memo_.end()) {
    ++cache_hits;
    return it->second;
  }
  const std::string file =
      o_.cache_dir.empty() ? "" : (fs::path(o_.cache_dir) / (hex64(h) + ".json")).string();
  std::vector<DepthMeasure> m;
  if (!file.empty() && readCacheEntry(file, key, o_.protocol.depths_mm.size(), &m)) {
    ++cache_hits;
  } else {
    const Brush brush = parseBrush(json, "the brush with the parameters applied");
    const double best = best_sse;
    m = measureBrush(brush, o_.protocol, o_.solvers, [&](int d, int n, int step, int steps) {
      if (progress_) progress_(evaluations, d, n, step, steps, rmse(best));
    });
    strokes += static_cast<int>(m.size());
    if (!file.empty()) {
      try {
        writeFileBeneath(o_.cache_dir, hex64(h) + ".json", cacheEntry(key, m));
      } catch (const Error& e) {
        if (warning_.empty()) warning_ = std::string(e.what()) + " (the cache is not kept)";
      }
    }
  }
  memo_[h] = m;
  return m;
}

double Evaluator::evaluate(const std::vector<double>& x, std::vector<DepthMeasure>* measures) {
  ++evaluations;
  const std::string json = applyFitParams(text_, params_, values(x), "", "");
  *measures = measure(json);
  const double s = sse(*measures);
  if (s < best_sse) {
    best_sse = s;
    best_x = x;
    best_measures = *measures;
  }
  return s;
}

const char* stopText(nlopt::result r, bool* converged) {
  *converged = r != nlopt::MAXEVAL_REACHED && r != nlopt::MAXTIME_REACHED;
  switch (r) {
    case nlopt::MAXEVAL_REACHED: return "stopped by the evaluation limit before converging";
    case nlopt::MAXTIME_REACHED: return "stopped by the time limit before converging";
    case nlopt::ROUNDOFF_LIMITED:
      return "converged as far as the measures' resolution allows (BOBYQA: roundoff limited)";
    default: return "converged (BOBYQA's steps below 1 % of each parameter's range)";
  }
}

}  // namespace

FitResult fitBrush(const std::string& brush_text, const std::string& brush_path,
                   const MeasurementTable& table, const std::vector<FitParam>& params,
                   const FitOptions& options, const FitProgress& progress) {
  if (params.empty()) throw Error(ExitCode::kUsage, "fit: no free parameter");
  if (!(options.time_limit_s > 0) || options.max_evals < 1)
    throw Error(ExitCode::kUsage, "fit: the time limit and the evaluation limit must be > 0");
  const auto start = Clock::now();
  Evaluator ev(brush_text, table, params, options, progress);
  const size_t n = params.size();
  std::vector<double> x(n);
  for (size_t i = 0; i < n; ++i) x[i] = unitOf(params[i], params[i].start);

  FitResult r;
  r.params = params;
  r.before_rmse = ev.rmse(ev.evaluate(x, &r.before));

  nlopt::opt opt(nlopt::LN_BOBYQA, static_cast<unsigned>(n));
  opt.set_lower_bounds(std::vector<double>(n, 0.0));
  opt.set_upper_bounds(std::vector<double>(n, 1.0));
  opt.set_initial_step(std::vector<double>(n, kInitialStep));
  opt.set_xtol_abs(kStepTolerance);
  // The start's evaluation above counts against the limits, as BOBYQA's own
  // first one (a memory hit) does not.
  opt.set_maxeval(std::max(1, options.max_evals - 1));
  const double spent = std::chrono::duration<double>(Clock::now() - start).count();
  opt.set_maxtime(std::max(1e-3, options.time_limit_s - spent));
  std::exception_ptr error;
  struct Ctx {
    Evaluator* ev;
    std::exception_ptr* error;
  } ctx{&ev, &error};
  opt.set_min_objective(
      [](const std::vector<double>& xs, std::vector<double>&, void* data) -> double {
        auto* c = static_cast<Ctx*>(data);
        try {
          std::vector<DepthMeasure> unused;
          return c->ev->evaluate(xs, &unused);
        } catch (...) {
          *c->error = std::current_exception();
          throw nlopt::forced_stop();
        }
      },
      &ctx);
  nlopt::result result = nlopt::FAILURE;
  double f = 0;
  if (options.max_evals > 1) {
    try {
      result = opt.optimize(x, f);
    } catch (const nlopt::roundoff_limited&) {
      result = nlopt::ROUNDOFF_LIMITED;
    } catch (const nlopt::forced_stop&) {
      if (error) std::rethrow_exception(error);
      throw;
    }
    if (error) std::rethrow_exception(error);
  } else {
    result = nlopt::MAXEVAL_REACHED;  // the start was the one evaluation allowed
  }
  r.stop = stopText(result, &r.converged);

  r.best = ev.values(ev.best_x);
  r.after = ev.best_measures;
  r.after_rmse = ev.rmse(ev.best_sse);
  r.evaluations = ev.evaluations;
  r.cache_hits = ev.cache_hits;
  r.simulated_strokes = ev.strokes;
  r.cache_warning = ev.warning_;
  r.fitted_json = applyFitParams(brush_text, params, r.best, options.name, options.description);
  std::vector<std::string> problems;
  parseBrush(r.fitted_json, "the fitted brush", &problems);
  if (!problems.empty())
    throw Error(ExitCode::kSoftware, "fit: the fitted brush of " + brush_path +
                                         " fails validation, not written: " + problems.front());
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return r;
}

}  // namespace bristle::render

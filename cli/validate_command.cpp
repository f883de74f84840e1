// `bristle validate FILE...`: checks bristle's input files and reports each
// file's verdict, so a batch of inputs can be checked before a long run. A file
// is a trajectory when it is a .csv or begins "# bristle-trajectory/"; else it
// is JSON whose "format" says what it is: a brush, a scene, a sheet, a batch
// manifest or a golden manifest, each checked with every file it names.
// Brushes and trajectories given together are then checked in pairs, as
// `render --brush B --trajectory T` would check them before its run.

#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "batch/job_key.h"
#include "batch/manifest.h"
#include "cli/commands.h"
#include "cli/golden_manifest.h"
#include "cli/inputs.h"
#include "cli/options.h"
#include "cli/run_stats.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/geometry/brush_geometry.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/formats/input_warnings.h"
#include "engine/base/json_reader.h"
#include "engine/formats/scene.h"
#include "engine/formats/sheet.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/base/text_file.h"
#include "engine/model/trajectory.h"
#include "render/image/png_io.h"

namespace bristle::cli {
namespace {

// The kinds validate tells apart, for the message of a file it cannot place.
constexpr const char* kKnownFormats =
    "bristle-brush/1, bristle-scene/1, bristle-sheet/1, bristle-batch/1, bristle-golden/1; a "
    "trajectory is a bristle-trajectory/1 CSV";

enum class FileKind { kTrajectory, kBrush, kScene, kSheet, kBatch, kGolden };

// What a file is, by its first line (a trajectory) or its JSON "format" (by
// the prefix: the kind's own reader then names a version it does not know).
// Malformed JSON, or JSON that names no known format, is a data error.
FileKind kindOf(const std::string& file, const std::string& text) {
  if (text.rfind("# bristle-trajectory/", 0) == 0) return FileKind::kTrajectory;
  const nlohmann::json doc = parseJsonText(text, file);
  const std::string known = std::string(" (known: ") + kKnownFormats + ")";
  if (!doc.is_object())
    throw dataError(file, "/", "must be a JSON object whose \"format\" names its kind" + known);
  const auto format = doc.find("format");
  if (format == doc.end())
    throw dataError(file, "/format", "required key is missing: it names the file's kind" + known);
  std::string shown = format->dump();
  if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
  if (!format->is_string())
    throw dataError(file, "/format = " + shown, "must be a string naming the file's kind" + known);
  const std::string& name = format->get_ref<const std::string&>();
  const std::pair<const char*, FileKind> kinds[] = {
      {"bristle-brush/", FileKind::kBrush},  {"bristle-scene/", FileKind::kScene},
      {"bristle-sheet/", FileKind::kSheet},  {"bristle-batch/", FileKind::kBatch},
      {"bristle-golden/", FileKind::kGolden}};
  for (const auto& [prefix, kind] : kinds)
    if (name.rfind(prefix, 0) == 0) return kind;
  throw dataError(file, "/format = " + shown, "unknown format" + known);
}

// "1 stroke", "2 strokes"; "1 brush", "2 brushes" with the plural given.
std::string counted(size_t n, const std::string& noun, const std::string& plural = "") {
  return std::to_string(n) + " " + (n == 1 ? noun : plural.empty() ? noun + "s" : plural);
}

// Runs `check`; an error it throws is rethrown naming the manifest and the
// field that named the file ("m.json: /jobs/3/brush: b.json: ...").
template <class Check>
auto naming(const std::string& manifest, const std::string& pointer, const Check& check) {
  try {
    return check();
  } catch (const Error& e) {
    throw Error(e.code(), manifest + ": " + pointer + ": " + e.what());
  }
}

// A brush read as render reads it, and its geometry built, which checks what
// the reader cannot: the cage's topology (OpenSubdiv; non-manifold cages) and
// the strip layout.
Brush checkedBrush(const std::string& f) {
  Brush b = loadBrush(f);
  const BrushGeometry geometry(b);
  return b;
}

// A scene, with everything it references: brushes, trajectories, and each
// trajectory placed and held against its brush.
Scene checkedScene(const std::string& f) {
  Scene scene = loadScene(f);
  for (const Brush& b : scene.brushes) const BrushGeometry geometry(b);
  return scene;
}

void validateScene(const std::string& f) {
  const Scene scene = checkedScene(f);
  printWarnings(sceneWarnings(scene));
  const SceneCanvas& c = scene.canvas;
  std::cout << f << ": ok (scene '" << scene.name << "', " << counted(scene.strokes.size(), "stroke")
            << ", " << counted(scene.brushes.size(), "brush", "brushes") << ", " << c.width_mm
            << " x " << c.height_mm << " mm at " << c.px_per_mm << " px/mm)\n";
}

// A sheet is checked with every brush and trajectory it lists, and every pair
// held against each other (the ferrule must stay off the canvas).
void validateSheet(const std::string& f) {
  const Sheet sheet = loadSheet(f);
  for (const Brush& b : sheet.brushes) const BrushGeometry geometry(b);
  printWarnings(sheetInputWarnings(sheet));
  const size_t nb = sheet.brushes.size(), nt = sheet.trajectories.size();
  std::cout << f << ": ok (sheet '" << sheet.name << "', " << nb
            << (nb == 1 ? " brush x " : " brushes x ") << nt
            << (nt == 1 ? " trajectory)\n" : " trajectories)\n");
}

// A command line a manifest gives (a job's, a golden's) must be one its
// command accepts: each option alone, named by its pointer, then all of them
// together. A manifest's option is its data: a refusal is a data error (65).
void checkOptionsOf(const std::string& manifest, const std::vector<std::string>& bare,
                    const std::vector<std::pair<std::string, std::vector<std::string>>>& options,
                    const std::string& options_pointer) {
  const auto check = [&](std::vector<std::string> args, const std::string& pointer) {
    args.insert(args.end(), {"-o", "validate.png"});  // parsed, never written
    try {
      checkCommandLine(args);
    } catch (const Error& e) {
      throw Error(ExitCode::kDataError,
                  manifest + ": " + pointer + ": bristle " + bare[0] + " refuses it: " + e.what());
    }
  };
  std::vector<std::string> all = bare;
  for (const auto& [pointer, words] : options) {
    std::vector<std::string> one = bare;
    one.insert(one.end(), words.begin(), words.end());
    check(one, pointer);
    all.insert(all.end(), words.begin(), words.end());
  }
  check(all, options_pointer);
}

// A job is checked as `bristle batch --dry-run` checks it (batchJobInputs: its
// files read by the render's own readers, a scene or a sheet whole), then a
// stroke's or a preview's brush and trajectory parse as such, and its options
// are ones its command takes.
void checkBatchJob(const BatchJob& job, const std::string& manifest) {
  batchJobInputs(job, manifest);
  if (!job.brush.empty()) {
    const std::string field = job.kind == BatchJobKind::kPreview ? "/preview" : "/brush";
    const Brush brush = naming(manifest, job.pointer + field, [&] { return checkedBrush(job.brush); });
    if (!job.trajectory.empty())
      naming(manifest, job.pointer + "/trajectory",
             [&] { return loadTrajectoryArg(job.trajectory, brush); });
  }
  BatchJob bare = job;
  bare.options.clear();
  std::vector<std::pair<std::string, std::vector<std::string>>> options;
  for (const auto& [name, words] : job.options) {
    options.push_back({job.option_pointers.at(name), {"--" + name}});
    options.back().second.insert(options.back().second.end(), words.begin(), words.end());
  }
  checkOptionsOf(manifest, batchJobArguments(bare), options, job.pointer + "/options");
}

// Every job is checked, each broken one a line; the first's code is returned.
int validateBatch(const std::string& f) {
  const BatchManifest manifest = loadBatchManifest(f);
  int code = 0;
  std::map<BatchJobKind, size_t> kinds;
  for (const BatchJob& job : manifest.jobs) {
    ++kinds[job.kind];
    try {
      checkBatchJob(job, f);
    } catch (const Error& e) {
      printError(e.what());
      if (code == 0) code = static_cast<int>(e.code());
    }
  }
  if (code != 0) return code;
  std::string what;
  for (const auto& [kind, n] : kinds)
    what += (what.empty() ? "" : ", ") + counted(n, batchJobKindName(kind));
  std::cout << f << ": ok (batch manifest, " << counted(manifest.jobs.size(), "job") << ": "
            << what << ")\n";
  return 0;
}

// A golden: its scene, or its brush, trajectory and render options, and its
// image, a PNG.
void checkGolden(const Golden& g, const std::string& manifest) {
  if (!g.scene.empty()) {
    naming(manifest, g.pointer + "/scene", [&] { return checkedScene(g.scene); });
  } else {
    const Brush brush = naming(manifest, g.pointer + "/brush", [&] { return checkedBrush(g.brush); });
    naming(manifest, g.pointer + "/trajectory",
           [&] { return loadTrajectoryArg(g.trajectory, brush); });
    checkOptionsOf(manifest, {"render", "--brush", g.brush, "--trajectory", g.trajectory},
                   {{g.pointer + "/options", g.options}}, g.pointer + "/options");
  }
  naming(manifest, g.pointer, [&] { return render::readPngRgba8(g.png); });
}

int validateGolden(const std::string& f) {
  const GoldenManifest manifest = loadGoldenManifest(f);
  int code = 0;
  size_t scenes = 0;
  for (const Golden& g : manifest.goldens) {
    scenes += g.scene.empty() ? 0 : 1;
    try {
      checkGolden(g, f);
    } catch (const Error& e) {
      printError(e.what());
      if (code == 0) code = static_cast<int>(e.code());
    }
  }
  if (code != 0) return code;
  const size_t n = manifest.goldens.size();
  std::cout << f << ": ok (golden manifest, " << counted(n, "golden") << ": "
            << counted(n - scenes, "stroke") << ", " << counted(scenes, "scene") << ")\n";
  return 0;
}

// A brush's or a trajectory's own warning (engine/formats/input_warnings.h), by the
// file as a pair names it: told once the pairs are known, and not for a file
// whose pair is refused, so that a refusal stays its one line.
using FileWarnings = std::vector<std::pair<std::string, std::string>>;

// A brush given alone: every problem of the file at once, one line each.
int validateBrush(const std::string& arg, const std::string& f,
                  std::vector<std::pair<std::string, Brush>>* brushes,
                  FileWarnings* file_warnings) {
  const std::vector<std::string> problems = checkBrush(f);
  for (const std::string& p : problems) printError(p);
  if (!problems.empty()) return static_cast<int>(ExitCode::kDataError);
  const Brush b = checkedBrush(f);
  std::cout << f << ": ok (brush '" << b.name << "', " << b.spines.size() << " spines"
            << (b.surface.present() ? ", surface" : "")
            << (b.strips.present() ? ", " + std::to_string(b.strips.count) + " strips" : "")
            << ")\n";
  brushes->emplace_back(arg, b);
  file_warnings->emplace_back(arg, brushScaleWarning(b));
  return 0;
}

// The checks `render` makes of a brush with a trajectory before its run
// (validateTrajectoryForBrush and the step limits: the same functions, so the
// same messages and exit codes, with render's default options): the
// trajectory for the brush, and its planned steps in *steps.
Trajectory checkPair(const Trajectory& given, const Brush& brush, double* steps) {
  Trajectory t = resolveDepths(given, brush);
  validateTrajectoryForBrush(t, brush);
  *steps = plannedStepCount(t, brush, SimOptions{});
  return t;
}

// The files (a brush as given, a trajectory's path) of the pairs checkPair refuses.
std::set<std::string> refusedFiles(const std::vector<std::pair<std::string, Brush>>& brushes,
                                   const std::vector<Trajectory>& trajectories) {
  std::set<std::string> refused;
  double steps = 0;
  for (const auto& [path, brush] : brushes)
    for (const Trajectory& given : trajectories) try {
        checkPair(given, brush, &steps);
      } catch (const Error&) {
        refused.insert(path);
        refused.insert(given.path);
      }
  return refused;
}

// Each brush with each trajectory: checkPair, a warning when the brush never
// comes within reach of the paper (render's image would be blank), and one
// when the pair plans over a million steps (a trajectory over ten minutes is
// named on its own).
int validatePairs(const std::vector<std::pair<std::string, Brush>>& brushes,
                  const std::vector<Trajectory>& trajectories) {
  int code = 0;
  for (const auto& [path, brush] : brushes)
    for (const Trajectory& given : trajectories) {
      Trajectory t;
      double steps = 0;
      try {
        t = checkPair(given, brush, &steps);
      } catch (const Error& e) {
        printError(e.what());
        if (code == 0) code = static_cast<int>(e.code());
        continue;
      }
      if (t.endTime() - t.startTime() <= kLongTrajectoryS)
        if (const std::string w = trajectoryWarning(t, steps, &brush, SimOptions{}); !w.empty())
          printWarnings({w});
      const bool reaches = t.comesWithinReach(brush.reachMm());
      if (!reaches)
        printError("warning: " + t.path + ": the brush '" + brush.name +
                   "' never comes within reach of the paper: render's image would be blank");
      std::cout << path << " with " << t.path << ": ok (starts above the paper"
                << (reaches ? ", comes within reach of it" : ", never reaches it") << ")\n";
    }
  return code;
}

}  // namespace

int runValidate(const std::vector<std::string>& files) {
  int code = 0;
  std::vector<std::pair<std::string, Brush>> brushes;
  std::vector<Trajectory> trajectories;
  FileWarnings file_warnings;
  for (const std::string& arg : files) {
    try {
      const bool csv = arg.size() >= 4 && arg.compare(arg.size() - 4, 4, ".csv") == 0;
      const std::string f = csv ? arg : findBrushFile(arg, "");  // a library name is a brush
      const FileKind kind = csv ? FileKind::kTrajectory : kindOf(f, readTextFile(f));
      int file_code = 0;
      switch (kind) {
        case FileKind::kTrajectory: {
          Trajectory t = loadTrajectory(f);
          file_warnings.emplace_back(f, trajectoryWarning(t, 0, nullptr, {}));
          std::cout << f << ": ok (trajectory, " << t.samples.size() << " samples, "
                    << t.endTime() - t.startTime() << " s)\n";
          trajectories.push_back(std::move(t));
          break;
        }
        case FileKind::kBrush: file_code = validateBrush(arg, f, &brushes, &file_warnings); break;
        case FileKind::kScene: validateScene(f); break;
        case FileKind::kSheet: validateSheet(f); break;
        case FileKind::kBatch: file_code = validateBatch(f); break;
        case FileKind::kGolden: file_code = validateGolden(f); break;
      }
      if (code == 0) code = file_code;
    } catch (const Error& e) {
      printError(e.what());
      if (code == 0) code = static_cast<int>(e.code());
    }
  }
  const bool pairs = code == 0 && !brushes.empty() && !trajectories.empty();
  const std::set<std::string> refused =
      pairs ? refusedFiles(brushes, trajectories) : std::set<std::string>();
  for (const auto& [file, w] : file_warnings)
    if (!w.empty() && !refused.count(file)) printWarnings({w});
  if (pairs) code = validatePairs(brushes, trajectories);
  return code;
}

Subcommand registerValidate(CLI::App& app) {
  auto files = std::make_shared<std::vector<std::string>>();
  CLI::App* validate = app.add_subcommand(
      "validate",
      "Check brush and scene files, sheets, batch and golden manifests (.json) and "
      "trajectories (.csv)");
  validate->footer(
      "Examples:\n"
      "  bristle validate round\n"
      "  bristle validate scenes/brushes/flat.json scenes/trajectories/s-curve.csv\n"
      "  bristle validate scenes/paintings/calligraphy.json scenes/sheets/small.json\n"
      "  bristle validate scenes/batch/standard.json golden/golden.json\n"
      "Each file is checked on its own with every file it names: a .csv (or a file that\n"
      "begins '# bristle-trajectory/') is a trajectory; a .json is what its \"format\" says:\n"
      "a brush, a scene, a sheet, a batch manifest (each job's files, and its options as\n"
      "its command takes them) or a golden manifest (each golden's files and options).\n"
      "Brushes and trajectories given together are then checked in pairs as render checks\n"
      "them before its run (the same messages): a brush that starts below the paper is\n"
      "exit 65, one that never comes within reach of it a warning. So are a trajectory\n"
      "over 10 minutes or a million steps and a brush whose spines and surface differ\n"
      "tenfold in size (docs/errors.md, Warnings). Exit: the first error's.");
  validate->add_option("files", *files, "Files to check; a library brush by its name (round)")
      ->required();
  return {validate, [files] { return runValidate(*files); }};
}

}  // namespace bristle::cli

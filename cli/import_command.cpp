// `bristle import IN -o OUT`: a pen recording (MyPaint events, a Pointer
// Events CSV) or an SVG's paths as a bristle-trajectory/1 file with a depth_mm
// column, or as a bristle-scene/1 painting with one trajectory per pen-down
// stroke (docs/input.md).

#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "cli/commands.h"
#include "cli/inputs.h"
#include "cli/options.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/formats/scene.h"
#include "input/import.h"
#include "input/svg_geometry.h"

namespace bristle::cli {

namespace fs = std::filesystem;

namespace {

struct ImportArgs {
  std::string input, output, from, brush = "round", paint = "sumi-ink";
  input::ImportOptions options;
  double dpi = 0, px_per_mm = 0;
  double canvas_px_per_mm = 8;
  std::vector<double> tilt_deg;
  bool quiet = false;
};

bool isHexColour(const std::string& s) {
  return s.size() == 7 && s[0] == '#' &&
         s.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
}

bool endsWith(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

// The trajectory files of a scene written to OUT.json: OUT-stroke-001.csv, ...
std::string strokeFile(const std::string& scene, std::size_t k) {
  char num[16];
  std::snprintf(num, sizeof num, "%03zu", k + 1);
  return scene.substr(0, scene.size() - 5) + "-stroke-" + num + ".csv";
}

// How the scene names its brush: a library name as it is, a file relative to
// the scene's folder.
std::string sceneBrushRef(const std::string& brush, const std::string& scene) {
  if (isBrushName(brush)) return brush;
  const fs::path dir = fs::absolute(scene).parent_path();
  return fs::absolute(brush).lexically_normal().lexically_relative(dir).string();
}

std::string sceneJson(const ImportArgs& a, const input::Placement& place,
                      const std::vector<std::string>& files, const std::string& description) {
  nlohmann::ordered_json scene;
  scene["format"] = "bristle-scene/1";
  scene["name"] = fs::path(a.output).stem().string();
  scene["description"] = description;
  scene["canvas"] = {{"size_mm", {place.width_mm, place.height_mm}},
                     {"px_per_mm", a.canvas_px_per_mm}};
  nlohmann::ordered_json strokes = nlohmann::ordered_json::array();
  const std::string brush = sceneBrushRef(a.brush, a.output);
  for (const std::string& f : files)
    strokes.push_back({{"brush", brush},
                       {"trajectory", fs::path(f).filename().string()},
                       {"paint", {{"paints", {a.paint}}}}});
  scene["strokes"] = strokes;
  return scene.dump(2) + "\n";
}

int runImport(ImportArgs a) {
  if (a.output.empty()) throw Error(ExitCode::kUsage, "import: give -o OUT.csv or OUT.json");
  const bool scene = endsWith(a.output, ".json");
  if (!scene && !endsWith(a.output, ".csv") && !isStdio(a.output))
    throw Error(ExitCode::kUsage,
                "-o " + a.output +
                    ": must end in .csv (one trajectory) or .json (a scene, one trajectory per "
                    "stroke), or be - (the trajectory on standard output)");
  if (!a.from.empty())
    a.options.from = a.from == "mypaint"       ? input::Format::kMyPaint
                     : a.from == "pointer-csv" ? input::Format::kPointerCsv
                                               : input::Format::kSvg;
  if (a.dpi > 0) a.options.mapping.mm_per_unit = 25.4 / a.dpi;
  if (a.px_per_mm > 0) a.options.mapping.mm_per_unit = 1 / a.px_per_mm;
  if (a.tilt_deg.size() == 2) {
    a.options.mapping.tilt_x_deg = a.tilt_deg[0];
    a.options.mapping.tilt_y_deg = a.tilt_deg[1];
  }
  if (scene && !isKnownPigment(a.paint) && !isHexColour(a.paint))
    throw Error(ExitCode::kUsage, "--paint " + a.paint + ": unknown pigment (known: " +
                                      knownPigmentList() + "; or a colour #rrggbb)");

  // --pressure is the command line's: refused as such (64) before the
  // recording is read, so that no SVG element is blamed for it.
  try {
    input::parsePressureProfile(a.options.svg.pressure_profile, "--pressure",
                                a.options.svg.pressure_profile);
  } catch (const Error& e) {
    throw Error(ExitCode::kUsage, e.what());
  }

  const std::string brush_file = findBrushFile(a.brush, "--brush");
  checkCliFiles({{"-o", a.output}}, {{"recording", a.input}, {"--brush", brush_file}}, {"-o"},
                {"recording"});
  const Brush brush = loadBrush(brush_file);
  const std::string depth_rule = input::resolveMaxDepth(&a.options, brush, a.brush);
  const std::string name = isStdio(a.input) ? std::string(kStdinName) : a.input;
  const std::string text = isStdio(a.input) ? stdinText() : readTextFile(a.input);
  const input::Recording rec = input::readInput(text, name, a.options);
  for (const std::string& w : rec.warnings) printError("warning: " + w);
  const std::vector<std::string> notes = input::mappingNotes(rec, a.options.mapping, depth_rule);

  if (!scene) {
    const Trajectory traj = input::toTrajectory(rec, a.options.mapping);
    const std::string csv = input::trajectoryCsv(traj, notes);
    parseTrajectory(csv, a.output);  // what was written reads back
    if (isStdio(a.output)) {
      std::cout << csv << std::flush;
      if (!std::cout) throw Error(ExitCode::kIoError, "standard output: write failed");
      return 0;
    }
    writeFileAtomically(a.output, csv);
    if (!a.quiet) std::cout << a.output << "\n";
    return 0;
  }

  const std::vector<Trajectory> strokes = input::toStrokeTrajectories(rec, a.options.mapping);
  if (strokes.size() > 10000)
    throw dataError(name, "size",
                    std::to_string(strokes.size()) +
                        " pen-down strokes: a scene holds at most 10000 (write one trajectory, "
                        "-o OUT.csv)");
  std::vector<std::string> files;
  for (std::size_t k = 0; k < strokes.size(); ++k) files.push_back(strokeFile(a.output, k));
  std::vector<NamedFile> outputs = {{"-o", a.output}};
  for (const std::string& f : files) outputs.push_back({"-o (a stroke's trajectory)", f});
  checkCliFiles(outputs, {{"recording", a.input}, {"--brush", brush_file}}, {}, {"recording"});
  const input::Placement place = input::placementOf(rec, a.options.mapping);
  const std::string json = sceneJson(a, place, files, notes.front());
  parseScene(json, a.output, fs::path(a.output).parent_path().string());  // reads back
  // Every file is written to its temporary first and renamed only when all
  // are (engine/base/atomic_output.h), one file open at a time.
  CommitGroup group;
  for (std::size_t k = 0; k < strokes.size(); ++k) {
    std::vector<std::string> stroke_notes = notes;
    stroke_notes.push_back("stroke " + std::to_string(k + 1) + " of " +
                           std::to_string(strokes.size()) + " (source lines " +
                           std::to_string(strokes[k].samples.front().line) + "-" +
                           std::to_string(strokes[k].samples.back().line) +
                           "); t_s from the hover before it");
    const std::string csv = input::trajectoryCsv(strokes[k], stroke_notes);
    parseTrajectory(csv, files[k]);
    writeFileAtomically(files[k], csv);
  }
  writeFileAtomically(a.output, json);
  group.commit();
  if (!a.quiet)
    std::cout << a.output << " (" << strokes.size() << " strokes: " << files.front()
              << (files.size() > 1 ? " ... " + files.back() : std::string()) << ")\n";
  return 0;
}

}  // namespace

Subcommand registerImport(CLI::App& app) {
  auto a = std::make_shared<ImportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "import", "Turn a tablet recording or an SVG into a trajectory or a scene");
  cmd->footer(
      "Examples:\n"
      "  bristle import scenes/recordings/painting30sec-excerpt.dat -o painting.csv\n"
      "  bristle render --brush round --trajectory painting.csv -o painting.png --solver slsqp\n"
      "  bristle import scenes/recordings/painting30sec-excerpt.dat -o painting.json \\\n"
      "      --brush flat --paint ultramarine\n"
      "  bristle import scenes/recordings/three-strokes.svg -o svg.csv --speed-mm-s 60 \\\n"
      "      --max-depth-frac 0.3\n"
      "  bristle import scenes/recordings/pointer-events.csv -o tilted.csv --smooth-ms 20\n"
      "Inputs: MyPaint events (.dat: 't x y pressure' lines), a Pointer Events CSV (a\n"
      "header naming timeStamp, x, y, pressure, tiltX, ...), an SVG (<path>, <polyline>,\n"
      "<polygon>, <line>, <circle>, <ellipse>, <rect>). Pressure p becomes the depth\n"
      "D * p^gamma past the brush's first contact, D = --max-depth-mm, or --max-depth-frac\n"
      "x the --brush's hair length; the pen up hovers --hover-mm above it. docs/input.md\n"
      "has every rule.");
  cmd->add_option("recording", a->input, "The recording or SVG; - reads stdin")->required();
  cmd->add_option("-o,--output", a->output,
                  "OUT.csv: one trajectory (- : stdout); OUT.json: a scene, each pen-down "
                  "stroke its own OUT-stroke-NNN.csv beside it")
      ->required();
  cmd->add_option("--from", a->from, "The input's format (default: from its name and content)")
      ->check(CLI::IsMember({"mypaint", "pointer-csv", "svg"}));
  cmd->add_option("--brush", a->brush,
                  "The brush the depths are scaled for (--max-depth-frac), and a scene's brush")
      ->capture_default_str();
  auto* depth_mm = cmd->add_option("--max-depth-mm", a->options.max_depth_mm,
                                   "Press depth at full pressure (mm past first contact)")
                       ->check(CLI::Range(0.01, 100.0));
  cmd->add_option("--max-depth-frac", a->options.max_depth_frac,
                  "Press depth at full pressure as a fraction of the brush's hair length")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 2.0))
      ->excludes(depth_mm);
  cmd->add_option("--pressure-gamma", a->options.mapping.pressure_gamma,
                  "depth = max depth * pressure^gamma (< 1: light pressure presses more)")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 10.0));
  cmd->add_option("--hover-mm", a->options.mapping.hover_mm,
                  "Where the pen is up, the brush hovers this far above first contact")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 100.0));
  auto* dpi = cmd->add_option("--dpi", a->dpi,
                              "Source pixels per inch (default 96: CSS pixels; SVG: its own "
                              "width/viewBox)")
                  ->check(CLI::Range(1.0, 100000.0));
  cmd->add_option("--px-per-mm", a->px_per_mm, "Source units per mm (instead of --dpi)")
      ->check(CLI::Range(0.001, 10000.0))
      ->excludes(dpi);
  cmd->add_flag("--flip-y,!--no-flip-y", a->options.mapping.flip_y,
                "Flip y (default: the sources' y points down the screen, the canvas's up)");
  cmd->add_option("--margin-mm", a->options.mapping.margin_mm,
                  "Canvas margin around the recording's bounding box (mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1000.0));
  cmd->add_option("--smooth-ms", a->options.mapping.smooth_ms,
                  "Centred moving average over this window (ms) within each stroke; 0: none")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--lead-s", a->options.mapping.lead_s,
                  "Hover before the first and after the last touch (s)")
      ->capture_default_str()
      ->check(CLI::Range(0.001, 10.0));
  cmd->add_option("--tilt-deg", a->tilt_deg,
                  "TX TY: pen tilt (tiltX, tiltY in degrees) for inputs that record none")
      ->expected(2)
      ->check(CLI::Range(-89.0, 89.0));
  cmd->add_option("--twist-deg", a->options.mapping.twist_deg,
                  "Pen twist (degrees clockwise from above) for inputs that record none")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 360.0));
  cmd->add_option("--speed-mm-s", a->options.svg.speed_mm_s, "SVG: drawing speed (mm/s)")
      ->capture_default_str()
      ->check(CLI::Range(0.1, 10000.0));
  cmd->add_option("--sample-mm", a->options.svg.sample_mm,
                  "SVG: sample spacing along a path (mm)")
      ->capture_default_str()
      ->check(CLI::Range(0.01, 100.0));
  cmd->add_option("--pressure", a->options.svg.pressure_profile,
                  "SVG: pressure profile 'u:p ...' over each path's length (an element's "
                  "data-bristle-pressure overrides it)")
      ->capture_default_str();
  cmd->add_option("--paint", a->paint, "A scene's paint, reloaded for every stroke")
      ->capture_default_str();
  cmd->add_option("--canvas-px-per-mm", a->canvas_px_per_mm, "A scene's canvas resolution")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 100.0));
  cmd->add_flag("-q,--quiet", a->quiet, "No output path on stdout");
  return {cmd, [a] { return runImport(*a); }};
}

}  // namespace bristle::cli

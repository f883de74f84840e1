#include "batch/manifest.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "engine/formats/brush_library.h"
#include "engine/base/error.h"
#include "engine/solvers/ipopt/ipopt_options.h"
#include "engine/base/json_reader.h"
#include "engine/base/text_file.h"

namespace bristle {
namespace {

namespace fs = std::filesystem;


// Options a job may not set: the batch owns where the job writes and what it
// prints, and a job writes nothing but its PNG (side files such as a trace
// would escape the atomic write and the up-to-date check).
// --batch-key is the batch's own (batch/job_key.h).
const std::set<std::string> kReservedOptions = {
    "o", "output", "quiet", "help", "trace", "forces", "brush", "trajectory", "version",
    "batch-key"};

std::string resolve(const std::string& base_dir, const std::string& p) {
  const fs::path path(p);
  if (path.is_absolute() || base_dir.empty()) return path.lexically_normal().string();
  return (fs::path(base_dir) / path).lexically_normal().string();
}

// An output must stay inside the output folder: relative, no "..", a file name.
bool isSafeOutput(const std::string& out) {
  const fs::path p(out);
  if (out.empty() || p.is_absolute() || !p.has_filename()) return false;
  for (const fs::path& part : p.lexically_normal())
    if (part == "..") return false;
  return p.lexically_normal().string().rfind("..", 0) != 0;
}

// What a job's option holds. Each becomes argv words of a known shape, so no
// value from a manifest can become an option of its own (docs/batch.md).
enum class OptionType {
  kFlag,     // true (the flag) or false (left out)
  kNumber,   // a JSON number: one word
  kString,   // a word that does not start with '-' and holds no control character
  kNumbers3, // a list of three numbers (--offset-mm X Y Z)
  kStrings,  // a string, or a non-empty list of them (repeatable NAME=VALUE)
};

// The options of `render`, `sheet` and `preview` (cli/*_command.cpp) a job may set, with their
// types. Whether the job's command accepts an option (a scene sets its own
// paint) is the command's to say: the job then fails with its usage error.
const std::map<std::string, OptionType>& knownOptions() {
  static const std::map<std::string, OptionType> kOptions = {
      {"amount", OptionType::kNumber},          {"at", OptionType::kNumber},
      {"background", OptionType::kString},      {"height", OptionType::kNumber},
      {"bits", OptionType::kNumber},            {"color", OptionType::kString},
      {"colour", OptionType::kString},          {"contact-band-mm", OptionType::kNumber},
      {"impasto", OptionType::kFlag},           {"ipopt-option", OptionType::kStrings},
      {"load", OptionType::kString},            {"max-step-mm", OptionType::kNumber},
      {"min-rate-hz", OptionType::kNumber},     {"mix", OptionType::kString},
      {"offset-mm", OptionType::kNumbers3},     {"paint", OptionType::kString},
      {"paper-scale", OptionType::kNumber},     {"paper-seed", OptionType::kNumber},
      {"paper-tooth", OptionType::kNumber},     {"px-per-mm", OptionType::kNumber},
      {"solver", OptionType::kString},          {"solver-max-iterations", OptionType::kNumber},
      {"steady-step-mm", OptionType::kNumber},
      {"tip-length", OptionType::kNumber},      {"width", OptionType::kNumber},
  };
  return kOptions;
}

std::string knownOptionList() {
  std::string list;
  for (const auto& [name, type] : knownOptions()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

// A string value is one argv word that cannot be read as an option.
bool isWord(const nlohmann::json& v) {
  if (!v.is_string()) return false;
  const std::string& s = v.get_ref<const std::string&>();
  return !s.empty() && s[0] != '-' && !hasControlCharacter(s);
}

const char* typeRule(OptionType type) {
  switch (type) {
    case OptionType::kFlag: return "must be true or false (a flag)";
    case OptionType::kNumber: return "must be a number";
    case OptionType::kString:
      return "must be a non-empty string that does not start with '-' and holds no control "
             "character";
    case OptionType::kNumbers3: return "must be a list of three numbers";
    case OptionType::kStrings:
      return "must be a string, or a non-empty list of strings, none starting with '-' or "
             "holding a control character";
  }
  return "?";
}

bool hasType(const nlohmann::json& v, OptionType type) {
  switch (type) {
    case OptionType::kFlag: return v.is_boolean();
    case OptionType::kNumber: return v.is_number();
    case OptionType::kString: return isWord(v);
    case OptionType::kNumbers3:
      return v.is_array() && v.size() == 3 &&
             std::all_of(v.begin(), v.end(), [](const nlohmann::json& x) { return x.is_number(); });
    case OptionType::kStrings:
      return isWord(v) || (v.is_array() && !v.empty() && std::all_of(v.begin(), v.end(), isWord));
  }
  return false;
}

// Each Ipopt option meets the allow-list a command line meets
// (engine/solvers/ipopt/ipopt_options.h), here before any job runs.
void checkIpoptOptions(const JsonObject& owner, const std::string& where,
                       const nlohmann::json& value) {
  for (size_t i = 0; i < (value.is_array() ? value.size() : 1); ++i) {
    const nlohmann::json& text = value.is_array() ? value[i] : value;
    const std::string at = value.is_array() ? where + "/" + std::to_string(i) : where;
    if (const std::optional<std::string> problem =
            ipoptOptionTextProblem(text.get_ref<const std::string&>()))
      owner.fail(at, *problem);
  }
}

void checkOptions(const JsonObject& owner, const std::string& key, const nlohmann::json& options) {
  const std::string pointer = owner.childPointer(key);
  if (!options.is_object())
    owner.fail(pointer + " = " + options.dump(), "must be an object of render options");
  static const std::regex kName("[a-z][a-z0-9-]*");
  for (const auto& [name, value] : options.items()) {
    const std::string where = pointer + "/" + name;
    if (!std::regex_match(name, kName))
      owner.fail(where, "option names are long options without '--' (e.g. \"px-per-mm\")");
    if (kReservedOptions.count(name))
      owner.fail(where, "a batch job cannot set --" + name +
                            " (the batch chooses the output and writes only PNGs)");
    const auto known = knownOptions().find(name);
    if (known == knownOptions().end())
      owner.fail(where, "unknown option '" + name + "' (known: " + knownOptionList() + ")");
    if (!hasType(value, known->second))
      owner.requireAt(false, where, value, typeRule(known->second));
    if (name == "ipopt-option") checkIpoptOptions(owner, where, value);
  }
}

std::string optionValue(const nlohmann::json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
}

// Sets each option of `options` (checked by checkOptions; at `pointer`) on
// *merged as the words of its command line, and its pointer in *pointers;
// false removes a flag a default set.
void mergeOptions(const nlohmann::json& options, const std::string& pointer,
                  BatchJobOptions* merged, std::map<std::string, std::string>* pointers) {
  for (const auto& [name, value] : options.items()) {
    (*pointers)[name] = pointer + "/" + name;
    if (value.is_boolean()) {
      if (value.get<bool>()) {
        (*merged)[name] = {};
      } else {
        merged->erase(name);
        pointers->erase(name);
      }
      continue;
    }
    std::vector<std::string>& words = (*merged)[name];
    words.clear();
    if (value.is_array()) {
      for (const nlohmann::json& v : value) words.push_back(optionValue(v));
    } else {
      words.push_back(optionValue(value));
    }
  }
}

}  // namespace

const char* batchJobKindName(BatchJobKind kind) {
  switch (kind) {
    case BatchJobKind::kScene: return "scene";
    case BatchJobKind::kSheet: return "sheet";
    case BatchJobKind::kStroke: return "stroke";
    case BatchJobKind::kPreview: return "preview";
  }
  return "?";
}

namespace {

// What a job renders and from which files. A preview names its brush in
// "preview" and may take a trajectory (the brush deformed at --at); a stroke
// is a brush with a trajectory.
void readJobKind(const JsonObject& o, const std::string& path, const std::string& base_dir,
                 BatchJob* job) {
  const bool scene = o.has("scene"), sheet = o.has("sheet"), preview = o.has("preview");
  const bool stroke = o.has("brush") || (o.has("trajectory") && !preview);
  const int kinds = int(scene) + int(sheet) + int(stroke) + int(preview);
  if (kinds == 0)
    for (const char* key : {"scene", "sheet", "preview", "brush"}) o.rejectMisspellingOf(key);
  if (kinds != 1)
    o.fail(o.pointer(), "a job renders exactly one of: \"scene\", \"sheet\", \"preview\" "
                        "(with an optional \"trajectory\"), or \"brush\" with \"trajectory\"");
  const auto brushAt = [&](const std::string& key) {
    const std::string brush = o.string(key);
    return isBrushName(brush) ? findBrushByName(brush, path + ": " + o.childPointer(key))
                              : resolve(base_dir, brush);
  };
  if (scene) {
    job->kind = BatchJobKind::kScene;
    job->input = resolve(base_dir, o.string("scene"));
  } else if (sheet) {
    job->kind = BatchJobKind::kSheet;
    job->input = resolve(base_dir, o.string("sheet"));
  } else if (preview) {
    job->kind = BatchJobKind::kPreview;
    job->brush = brushAt("preview");
    if (o.has("trajectory")) job->trajectory = resolve(base_dir, o.string("trajectory"));
  } else {
    job->kind = BatchJobKind::kStroke;
    // A misspelt "preview" beside its "trajectory" reads as a stroke here.
    for (const char* key : {"brush", "trajectory", "preview"})
      if (!o.has(key)) o.rejectMisspellingOf(key);
    if (!o.has("brush") || !o.has("trajectory"))
      o.fail(o.pointer(), "a stroke job needs both \"brush\" and \"trajectory\"");
    job->brush = brushAt("brush");
    job->trajectory = resolve(base_dir, o.string("trajectory"));
  }
}

}  // namespace

BatchManifest parseBatchManifest(const std::string& text, const std::string& path,
                                 const std::string& base_dir) {
  const nlohmann::json doc = parseJsonText(text, path);
  if (!doc.is_object()) throw dataError(path, "/", "a batch manifest is a JSON object");
  JsonObject root(doc, "", path);
  root.declareKeys({"format", "defaults", "jobs"});
  const std::string format = root.string("format");
  root.require(format == kBatchFormat, "format", std::string("must be \"") + kBatchFormat + "\"");

  BatchJobOptions defaults;
  std::map<std::string, std::string> default_pointers;
  if (root.has("defaults")) {
    const JsonObject d = root.object("defaults");
    d.declareKeys({"options"});
    if (d.has("options")) {
      checkOptions(d, "options", d.raw("options"));
      mergeOptions(d.raw("options"), d.childPointer("options"), &defaults, &default_pointers);
    }
    d.rejectUnknownKeys();
  }

  BatchManifest manifest;
  manifest.path = path;
  const std::vector<JsonObject> jobs = root.objects("jobs");
  root.require(!jobs.empty(), "jobs", "must list at least one job");
  root.rejectUnknownKeys();

  std::map<std::string, std::string> ids, outputs;  // value -> pointer of first use
  for (size_t i = 0; i < jobs.size(); ++i) {
    const JsonObject& o = jobs[i];
    o.declareKeys({"scene", "sheet", "preview", "brush", "trajectory", "id", "output", "options"});
    BatchJob job;
    job.index = static_cast<int>(i);
    job.pointer = o.pointer();

    readJobKind(o, path, base_dir, &job);
    job.id = o.string("id", "");
    job.output = o.string("output", "");
    if (job.id.empty() && job.output.empty())
      o.fail(o.pointer(), "a job needs an \"id\" or an \"output\"");
    o.require(!hasControlCharacter(job.id), "id", "must hold no control character");
    o.require(!hasControlCharacter(job.output), "output", "must hold no control character");
    if (job.output.empty()) job.output = job.id + ".png";
    if (job.id.empty()) job.id = fs::path(job.output).stem().string();
    o.require(isSafeOutput(job.output), "output",
              "must be a relative path inside the output folder (no '..')");
    job.output = fs::path(job.output).lexically_normal().string();
    o.require(fs::path(job.output).extension() == ".png", "output", "must end in .png");
    if (auto [it, fresh] = ids.emplace(job.id, job.pointer); !fresh)
      o.fail(job.pointer + "/id = \"" + job.id + "\"", "repeats the id of " + it->second);
    if (auto [it, fresh] = outputs.emplace(job.output, job.pointer); !fresh)
      o.fail(job.pointer + "/output = \"" + job.output + "\"",
             "repeats the output of " + it->second);

    job.options = defaults;
    job.option_pointers = default_pointers;
    if (o.has("options")) {
      const nlohmann::json& own = o.raw("options");
      checkOptions(o, "options", own);
      mergeOptions(own, o.childPointer("options"), &job.options, &job.option_pointers);
    }
    o.rejectUnknownKeys();
    manifest.jobs.push_back(std::move(job));
  }
  return manifest;
}

BatchManifest loadBatchManifest(const std::string& path) {
  return parseBatchManifest(readTextFile(path), path, fs::path(path).parent_path().string());
}

std::vector<std::string> batchJobArguments(const BatchJob& job) {
  std::vector<std::string> args;
  switch (job.kind) {
    case BatchJobKind::kScene: args = {"render", job.input}; break;
    case BatchJobKind::kSheet: args = {"sheet", job.input}; break;
    case BatchJobKind::kStroke:
      args = {"render", "--brush", job.brush, "--trajectory", job.trajectory};
      break;
    case BatchJobKind::kPreview:
      args = {"preview", job.brush};
      if (!job.trajectory.empty()) args.insert(args.end(), {"--trajectory", job.trajectory});
      break;
  }
  for (const auto& [name, words] : job.options) {
    args.push_back("--" + name);
    args.insert(args.end(), words.begin(), words.end());
  }
  return args;
}

}  // namespace bristle

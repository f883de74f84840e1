#include "engine/batch.h"

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <set>

#include "bristle/version.h"
#include "engine/brush_library.h"
#include "engine/error.h"
#include "engine/fnv1a64.h"
#include "engine/json_reader.h"
#include "engine/scene.h"
#include "engine/sheet.h"
#include "engine/text_file.h"

namespace bristle {
namespace {

namespace fs = std::filesystem;

constexpr const char* kFormat = "bristle-batch/1";

// Options a job may not set: the batch owns where the job writes and what it
// prints, and a job writes nothing but its PNG (side files such as a trace
// would escape the atomic write and the up-to-date check).
const std::set<std::string> kReservedOptions = {"o",     "output",     "quiet", "help",
                                                "trace", "forces",     "brush", "trajectory",
                                                "version"};

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

// The options of `render`, `sheet` and `preview` (cli/main.cpp) a job may set, with their
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
      {"tip-length", OptionType::kNumber},      {"width", OptionType::kNumber},
  };
  return kOptions;
}

std::string knownOptionList() {
  std::string list;
  for (const auto& [name, type] : knownOptions()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

bool hasControlCharacter(const std::string& s) {
  return std::any_of(s.begin(), s.end(), [](char c) {
    return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
  });
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
  }
}

std::string optionValue(const nlohmann::json& v) {
  return v.is_string() ? v.get<std::string>() : v.dump();
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

BatchManifest parseBatchManifest(const std::string& text, const std::string& path,
                                 const std::string& base_dir) {
  const nlohmann::json doc = parseJsonText(text, path);
  if (!doc.is_object()) throw dataError(path, "/", "a batch manifest is a JSON object");
  JsonObject root(doc, "", path);
  const std::string format = root.string("format");
  root.require(format == kFormat, "format", std::string("must be \"") + kFormat + "\"");

  nlohmann::json defaults = nlohmann::json::object();
  if (root.has("defaults")) {
    const JsonObject d = root.object("defaults");
    if (d.has("options")) {
      defaults = d.raw("options");
      checkOptions(d, "options", defaults);
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
    BatchJob job;
    job.index = static_cast<int>(i);
    job.pointer = o.pointer();

    // A preview names its brush in "preview" and may take a trajectory (the
    // brush deformed at --at); a stroke is a brush with a trajectory.
    const bool scene = o.has("scene"), sheet = o.has("sheet"), preview = o.has("preview");
    const bool stroke = o.has("brush") || (o.has("trajectory") && !preview);
    if (int(scene) + int(sheet) + int(stroke) + int(preview) != 1)
      o.fail(o.pointer(), "a job renders exactly one of: \"scene\", \"sheet\", \"preview\" "
                          "(with an optional \"trajectory\"), or \"brush\" with \"trajectory\"");
    const auto brushAt = [&](const std::string& key) {
      const std::string brush = o.string(key);
      return isBrushName(brush) ? findBrushByName(brush, path + ": " + o.childPointer(key))
                                : resolve(base_dir, brush);
    };
    if (scene) {
      job.kind = BatchJobKind::kScene;
      job.input = resolve(base_dir, o.string("scene"));
    } else if (sheet) {
      job.kind = BatchJobKind::kSheet;
      job.input = resolve(base_dir, o.string("sheet"));
    } else if (preview) {
      job.kind = BatchJobKind::kPreview;
      job.brush = brushAt("preview");
      if (o.has("trajectory")) job.trajectory = resolve(base_dir, o.string("trajectory"));
    } else {
      job.kind = BatchJobKind::kStroke;
      if (!o.has("brush") || !o.has("trajectory"))
        o.fail(o.pointer(), "a stroke job needs both \"brush\" and \"trajectory\"");
      job.brush = brushAt("brush");
      job.trajectory = resolve(base_dir, o.string("trajectory"));
    }

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
    if (o.has("options")) {
      const nlohmann::json& own = o.raw("options");
      checkOptions(o, "options", own);
      for (const auto& [name, value] : own.items()) job.options[name] = value;
    }
    o.rejectUnknownKeys();
    manifest.jobs.push_back(std::move(job));
  }
  return manifest;
}

BatchManifest loadBatchManifest(const std::string& path) {
  return parseBatchManifest(readTextFile(path), path, fs::path(path).parent_path().string());
}

Shard parseShard(const std::string& text) {
  static const std::regex kShard("([0-9]{1,6})/([0-9]{1,6})");
  std::smatch m;
  if (std::regex_match(text, m, kShard)) {
    const Shard s{std::stoi(m[1]), std::stoi(m[2])};
    if (s.count >= 1 && s.index < s.count) return s;
  }
  throw Error(ExitCode::kUsage, "--shard " + text +
                                    ": must be I/N with N >= 1 and 0 <= I < N (e.g. 0/4)");
}

namespace {

// A non-negative integer variable, or -1 when unset; throws for junk.
long envInteger(const std::function<const char*(const char*)>& env, const char* name) {
  const char* v = env(name);
  if (v == nullptr || *v == '\0') return -1;
  char* end = nullptr;
  const long n = std::strtol(v, &end, 10);
  if (*end != '\0' || n < 0)
    throw Error(ExitCode::kUsage, std::string(name) + "=" + v + ": not a non-negative integer");
  return n;
}

}  // namespace

Shard shardFromEnvironment(const std::function<const char*(const char*)>& env,
                           int explicit_count) {
  const long slurm_id = envInteger(env, "SLURM_ARRAY_TASK_ID");
  if (slurm_id >= 0) {
    const long count = envInteger(env, "SLURM_ARRAY_TASK_COUNT");
    const long min = std::max(0L, envInteger(env, "SLURM_ARRAY_TASK_MIN"));
    const long step = std::max(1L, envInteger(env, "SLURM_ARRAY_TASK_STEP"));
    const long index = (slurm_id - min) / step;
    if (count < 1 || slurm_id < min || (slurm_id - min) % step != 0 || index >= count) {
      throw Error(ExitCode::kUsage,
                  "SLURM_ARRAY_TASK_ID=" + std::to_string(slurm_id) + " with _MIN=" +
                      std::to_string(min) + " _STEP=" + std::to_string(step) + " _COUNT=" +
                      std::to_string(count) + ": not a task of the array");
    }
    return Shard{int(index), int(count)};
  }
  const long k8s = envInteger(env, "JOB_COMPLETION_INDEX");
  if (k8s >= 0) {
    if (explicit_count < 1 || k8s >= explicit_count)
      throw Error(ExitCode::kUsage,
                  "JOB_COMPLETION_INDEX=" + std::to_string(k8s) +
                      ": give the Job's completions as --shard-count N (N > index)");
    return Shard{int(k8s), explicit_count};
  }
  if (explicit_count > 1)
    throw Error(ExitCode::kUsage,
                "--shard-count without JOB_COMPLETION_INDEX: give --shard I/N instead");
  return Shard{};
}

std::vector<int> jobsOfShard(int n, const Shard& shard) {
  std::vector<int> mine;
  for (int k = shard.index; k < n; k += shard.count) mine.push_back(k);
  return mine;
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
  // nlohmann's object keeps keys sorted: the same options give the same line.
  for (const auto& [name, value] : job.options.items()) {
    if (value.is_boolean()) {
      if (value.get<bool>()) args.push_back("--" + name);
      continue;
    }
    args.push_back("--" + name);
    if (value.is_array()) {
      for (const nlohmann::json& v : value) args.push_back(optionValue(v));
    } else {
      args.push_back(optionValue(value));
    }
  }
  return args;
}

namespace {

// A file the manifest names must be readable; else 66 naming the job's field.
void requireReadable(const std::string& manifest, const std::string& pointer,
                     const std::string& file) {
  try {
    readTextFile(file);
  } catch (const Error& e) {
    throw Error(e.code(), manifest + ": " + pointer + ": " + e.what());
  }
}

}  // namespace

std::vector<std::string> batchJobInputs(const BatchJob& job, const std::string& manifest) {
  switch (job.kind) {
    case BatchJobKind::kScene:
      requireReadable(manifest, job.pointer + "/scene", job.input);
      return loadScene(job.input).inputs;
    case BatchJobKind::kSheet:
      // The sheet, then its brushes and trajectories in the order listed: the
      // files sheetInputsHash (engine/sheet.h) hashes into the sheet's PNG.
      requireReadable(manifest, job.pointer + "/sheet", job.input);
      return loadSheet(job.input).inputs;
    case BatchJobKind::kStroke:
      requireReadable(manifest, job.pointer + "/brush", job.brush);
      requireReadable(manifest, job.pointer + "/trajectory", job.trajectory);
      return {job.brush, job.trajectory};
    case BatchJobKind::kPreview:
      requireReadable(manifest, job.pointer + "/preview", job.brush);
      if (job.trajectory.empty()) return {job.brush};
      requireReadable(manifest, job.pointer + "/trajectory", job.trajectory);
      return {job.brush, job.trajectory};
  }
  return {};
}

std::uint64_t batchJobKey(const BatchJob& job, const std::vector<std::string>& inputs,
                          std::uint64_t program) {
  std::uint64_t h = fnv1a64(std::string(kFormat) + "\n" + kVersion + "\n");
  h = fnv1a64(std::to_string(program) + "\n", h);
  for (const std::string& a : batchJobArguments(job)) {
    // Input paths are replaced by their contents below; only the options count.
    if (a == job.input || a == job.brush || a == job.trajectory) continue;
    h = fnv1a64(a + "\n", h);
  }
  h = fnv1a64(std::to_string(fnv1a64Files(inputs)), h);
  return h;
}

}  // namespace bristle

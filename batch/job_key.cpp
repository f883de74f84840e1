#include "batch/job_key.h"

#include <filesystem>
#include <nlohmann/json.hpp>

#include "bristle/version.h"
#include "engine/base/error.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/scene.h"
#include "engine/formats/sheet.h"
#include "engine/base/text_file.h"

namespace bristle {

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
      // files sheetInputsHash (engine/formats/sheet.h) hashes into the sheet's PNG.
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
  std::uint64_t h = fnv1a64(std::string(kBatchFormat) + "\n" + kVersion + "\n");
  h = fnv1a64(std::to_string(program) + "\n", h);
  for (const std::string& a : batchJobArguments(job)) {
    // Input paths are replaced by their contents below; only the options count.
    if (a == job.input || a == job.brush || a == job.trajectory) continue;
    h = fnv1a64(a + "\n", h);
  }
  h = fnv1a64(std::to_string(fnv1a64Files(inputs)), h);
  return h;
}

bool batchOutputUpToDate(const std::string& path, const std::string& key,
                         std::vector<std::string>* warnings) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  bool same = false;
  try {
    for (const auto& [k, v] : render::readPngText(path)) {
      if (k == kBatchKeyText) same = v == key;
      if (k == kBatchWarningsText) {
        const nlohmann::json list = nlohmann::json::parse(v, nullptr, false);
        if (list.is_array())
          for (const nlohmann::json& w : list)
            if (w.is_string()) warnings->push_back(w.get<std::string>());
      }
    }
  } catch (const std::exception&) {
    return false;
  }
  return same;
}

render::PngText batchPngText(const std::string& key, const std::vector<std::string>& warnings) {
  render::PngText text;
  if (key.empty()) return text;
  text.push_back({kBatchKeyText, key});
  // ASCII (ensure_ascii) so that the chunk is plain tEXt/zTXt.
  if (!warnings.empty())
    text.push_back({kBatchWarningsText, nlohmann::json(warnings).dump(-1, ' ', true)});
  return text;
}

}  // namespace bristle

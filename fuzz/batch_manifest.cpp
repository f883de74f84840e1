// Fuzz target: the batch manifest reader (bristle-batch/1 JSON), then the
// command line each job would run: whatever the manifest says, every word that
// starts with '-' is one of the job's own options or a number, never a value
// turned into an option (docs/batch.md).

#include <cstdlib>

#include "batch/manifest.h"
#include "fuzz/fuzz_input.h"

namespace {

bool isNumber(const std::string& word) {
  char* end = nullptr;
  std::strtod(word.c_str(), &end);
  return !word.empty() && end == word.c_str() + word.size();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const bristle::BatchManifest m =
        bristle::parseBatchManifest(bristle::fuzz::text(data, size), "m.json", "/nonexistent");
    for (const bristle::BatchJob& job : m.jobs) {
      const std::vector<std::string> args = bristle::batchJobArguments(job);
      // The words the job's kind fixes: the command and its inputs.
      const std::size_t fixed = job.kind == bristle::BatchJobKind::kStroke ? 5
                                : job.kind == bristle::BatchJobKind::kPreview && !job.trajectory.empty()
                                    ? 4
                                    : 2;
      for (std::size_t i = fixed; i < args.size(); ++i) {
        const std::string& a = args[i];
        for (const char c : a)
          if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) std::abort();
        if (a.empty() || a[0] != '-' || isNumber(a)) continue;
        if (a.rfind("--", 0) != 0 || !job.options.contains(a.substr(2))) std::abort();
      }
    }
  } catch (const bristle::Error& e) {
    bristle::fuzz::checkRefusal(e);
  }
  return 0;
}

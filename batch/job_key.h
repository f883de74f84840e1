#pragma once
// Whether a batch job's output is up to date: the key of what the job reads and
// runs, and the PNG text that carries it. The job's own process writes that
// text (batchPngText, through the hidden option --batch-key of render, sheet
// and preview), so the batch never rewrites a PNG.

#include <cstdint>
#include <string>
#include <vector>

#include "batch/manifest.h"
#include "render/image/png_io.h"

namespace bristle {

// The PNG text key that carries a job's up-to-date key (16 hex digits), and the
// one that carries its warnings (a JSON list of strings), so that a run that
// skips the job still reports them.
inline constexpr const char* kBatchKeyText = "bristle:batch-key";
inline constexpr const char* kBatchWarningsText = "bristle:batch-warnings";

// Every file the job reads (the scene or sheet first, then what it references),
// by loading the job's input with the render's own readers; throws their
// bristle::Error (66 missing, 65 bad data) so a broken job fails before a
// process is started for it. A file the manifest itself names is reported as
// `manifest: /jobs/N/field: ...`.
std::vector<std::string> batchJobInputs(const BatchJob& job, const std::string& manifest);

// The up-to-date key of a job: FNV-1a 64 over the bristle version, the program
// that renders, the job's command line (batchJobArguments) and the bytes of
// every input file. `program` identifies the renderer's code: the command line
// passes the FNV-1a 64 of its own executable, so a rebuilt bristle (same
// version, changed code) renders every job again instead of keeping pixels an
// older build made. Paths do not enter the key, so a checkout moved elsewhere
// keeps its outputs.
std::uint64_t batchJobKey(const BatchJob& job, const std::vector<std::string>& inputs,
                          std::uint64_t program = 0);

// Whether `path` is a complete PNG whose kBatchKeyText is `key` (a missing,
// corrupt or truncated file is not: it is rendered again); *warnings gets the
// warnings kept with it.
bool batchOutputUpToDate(const std::string& path, const std::string& key,
                         std::vector<std::string>* warnings);

// The PNG text a job's own process adds when the batch runs it with
// `--batch-key KEY`: the key and, when there are any, the job's warnings.
render::PngText batchPngText(const std::string& key, const std::vector<std::string>& warnings);

}  // namespace bristle

// Batch manifests (batch/manifest.h, batch/shard.h, batch/job_key.h): the reader's rules, sharding that covers
// every job exactly once, the shard a scheduler's environment names, the
// command line a job runs, and the key that decides whether an output is up to
// date.

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <map>
#include <set>
#include <tuple>

#include "batch/job_cost.h"
#include "batch/job_key.h"
#include "batch/manifest.h"
#include "batch/shard.h"
#include "engine/base/atomic_output.h"
#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/geometry/first_contact.h"
#include "engine/base/fnv1a64.h"
#include "engine/formats/scene.h"
#include "engine/dynamics/simulation.h"
#include "engine/dynamics/stepper.h"
#include "engine/model/trajectory.h"
#include "render/image/png_io.h"
#include "engine/formats/sheet.h"
#include "test_helpers.h"
#include "temp_dir.h"

using namespace bristle;
using Catch::Matchers::Contains;

namespace {

namespace fs = std::filesystem;

BatchManifest parse(const std::string& text) {
  return parseBatchManifest(text, "jobs.json", "/data/batch");
}

// The exit code and message of parsing `text`, which must fail.
std::pair<int, std::string> parseError(const std::string& text) {
  try {
    parse(text);
  } catch (const Error& e) {
    return {static_cast<int>(e.code()), e.what()};
  }
  FAIL("manifest was accepted: " << text);
  return {};
}

std::pair<int, std::string> shardError(const std::string& text) {
  try {
    parseShard(text);
  } catch (const Error& e) {
    return {static_cast<int>(e.code()), e.what()};
  }
  FAIL("shard was accepted: " << text);
  return {};
}

using bristle::testing::TempDir;

}  // namespace

TEST_CASE("batch manifest: jobs, defaults and resolved paths", "[batch]") {
  const BatchManifest m = parse(R"({
    "format": "bristle-batch/1",
    "defaults": {"options": {"solver": "slsqp", "px-per-mm": 4}},
    "jobs": [
      {"id": "p", "scene": "../paintings/petals.json", "options": {"impasto": true, "px-per-mm": 6}},
      {"output": "strokes/round-s.png", "brush": "b.json", "trajectory": "/abs/t.csv"},
      {"id": "sheet", "sheet": "lib.json"}
    ]})");
  REQUIRE(m.jobs.size() == 3);
  CHECK(m.jobs[0].kind == BatchJobKind::kScene);
  CHECK(m.jobs[0].input == "/data/paintings/petals.json");
  CHECK(m.jobs[0].output == "p.png");
  // A job's own options win over the defaults; the rest of the defaults stay.
  using Words = std::vector<std::string>;
  CHECK(m.jobs[0].options.at("px-per-mm") == Words{"6"});
  CHECK(m.jobs[0].options.at("solver") == Words{"slsqp"});
  CHECK(m.jobs[0].options.at("impasto").empty());  // a flag: no words after it
  CHECK(m.jobs[1].kind == BatchJobKind::kStroke);
  CHECK(m.jobs[1].id == "round-s");
  CHECK(m.jobs[1].brush == "/data/batch/b.json");
  CHECK(m.jobs[1].trajectory == "/abs/t.csv");
  CHECK(m.jobs[2].kind == BatchJobKind::kSheet);
  CHECK(m.jobs[2].pointer == "/jobs/2");
}

TEST_CASE("batch manifest: preview jobs, at rest and along a trajectory", "[batch]") {
  const BatchManifest m = parse(R"({"format": "bristle-batch/1", "jobs": [
      {"id": "rest", "preview": "b.json"},
      {"id": "bent", "preview": "b.json", "trajectory": "t.csv", "options": {"at": 1.2}}]})");
  REQUIRE(m.jobs.size() == 2);
  CHECK(m.jobs[0].kind == BatchJobKind::kPreview);
  CHECK(std::string(batchJobKindName(m.jobs[0].kind)) == "preview");
  CHECK(m.jobs[0].brush == "/data/batch/b.json");
  CHECK(m.jobs[0].trajectory.empty());
  CHECK(batchJobArguments(m.jobs[0]) == std::vector<std::string>{"preview", "/data/batch/b.json"});
  CHECK(batchJobArguments(m.jobs[1]) ==
        std::vector<std::string>{"preview", "/data/batch/b.json", "--trajectory",
                                 "/data/batch/t.csv", "--at", "1.2"});

  // Only strokes and previews take a trajectory; a preview names its brush
  // once, in "preview".
  const std::string head = R"({"format": "bristle-batch/1", "jobs": [)";
  for (const auto& [job, pointer, rule] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {R"({"id": "a", "preview": "b.json", "brush": "b.json", "trajectory": "t.csv"})",
            "/jobs/0", "exactly one of"},
           {R"({"id": "a", "scene": "s.json", "trajectory": "t.csv"})", "/jobs/0",
            "exactly one of"},
           {R"({"id": "a", "preview": "b.json", "options": {"at": "1.2"}})", "/jobs/0/options/at",
            "must be a number"}}) {
    INFO(job);
    const auto [code, message] = parseError(head + job + "]}");
    CHECK(code == 65);
    CHECK_THAT(message, Contains("jobs.json: " + pointer));
    CHECK_THAT(message, Contains(rule));
  }
}

TEST_CASE("batch manifest: every broken rule is a data error naming its field", "[batch][errors]") {
  const std::string head = R"({"format": "bristle-batch/1", "jobs": [)";
  const std::string ok = R"({"id": "a", "scene": "a.json"})";
  struct Case {
    std::string jobs, pointer, rule;
  };
  const std::vector<Case> cases = {
      {"", "/jobs", "at least one job"},
      {R"({"id": "a"})", "/jobs/0", "exactly one of"},
      {R"({"id": "a", "scene": "s.json", "sheet": "t.json"})", "/jobs/0", "exactly one of"},
      {R"({"id": "a", "brush": "b.json"})", "/jobs/0", "both \"brush\" and \"trajectory\""},
      {R"({"scene": "s.json"})", "/jobs/0", "an \"id\" or an \"output\""},
      {ok + "," + ok, "/jobs/1/id", "repeats the id of /jobs/0"},
      {ok + R"(, {"id": "b", "output": "a.png", "scene": "s.json"})", "/jobs/1/output",
       "repeats the output of /jobs/0"},
      {R"({"id": "a", "output": "../a.png", "scene": "s.json"})", "/jobs/0/output", "inside the output folder"},
      {R"({"id": "a", "output": "/tmp/a.png", "scene": "s.json"})", "/jobs/0/output", "inside the output folder"},
      {R"({"id": "a", "output": "a.jpg", "scene": "s.json"})", "/jobs/0/output", ".png"},
      {R"({"id": "a", "scene": "s.json", "options": {"trace": "t.jsonl"}})", "/jobs/0/options/trace",
       "cannot set --trace"},
      {R"({"id": "a", "scene": "s.json", "options": {"--bits": 16}})", "/jobs/0/options/--bits",
       "without '--'"},
      {R"({"id": "a", "scene": "s.json", "options": {"paint": {"x": 1}}})", "/jobs/0/options/paint",
       "must be a non-empty string"},
      // Options are typed: nothing from a manifest becomes an option of its own.
      {R"({"id": "a", "scene": "s.json", "options": {"offset-mm": [1, "--trace", "/x"]}})",
       "/jobs/0/options/offset-mm", "must be a list of three numbers"},
      {R"({"id": "a", "scene": "s.json", "options": {"paint": "--trace=/x"}})",
       "/jobs/0/options/paint", "does not start with '-'"},
      {R"({"id": "a", "scene": "s.json", "options": {"ipopt-option": ["tol=1", "-o"]}})",
       "/jobs/0/options/ipopt-option", "none starting with '-'"},
      {R"({"id": "a", "scene": "s.json", "options": {"ipopt-option": ["tol=1e-8", "tol=nan"]}})",
       "/jobs/0/options/ipopt-option/1", "tol=nan: tol must be a finite number in [1e-12, 0.1]"},
      {R"({"id": "a", "scene": "s.json", "options": {"ipopt-option": "output_file=x"}})",
       "/jobs/0/options/ipopt-option", "output_file is not an Ipopt option bristle allows"},
      {R"({"id": "a", "scene": "s.json", "options": {"paint": "red\nbristle: fake"}})",
       "/jobs/0/options/paint", "no control character"},
      {R"({"id": "a", "scene": "s.json", "options": {"impasto": 1}})", "/jobs/0/options/impasto",
       "must be true or false"},
      {R"({"id": "a", "scene": "s.json", "options": {"bits": "16"}})", "/jobs/0/options/bits",
       "must be a number"},
      {R"({"id": "a", "scene": "s.json", "options": {"frobnicate": 1}})",
       "/jobs/0/options/frobnicate", "unknown option 'frobnicate' (known: amount, "},
      {R"({"id": "a\u0007", "scene": "s.json"})", "/jobs/0/id", "no control character"},
      {R"({"id": "a", "scene": "s.json", "colour": "red"})", "/jobs/0/colour", "unknown"},
      // A misspelt key is named with the key it most likely meant, also where
      // the job's kind or its brush is missing.
      {R"({"id": "a", "secne": "s.json"})", "/jobs/0/secne",
       "unknown key 'secne'; did you mean /jobs/0/scene?"},
      {R"({"id": "a", "brsh": "b.json", "trajectory": "t.csv"})", "/jobs/0/brsh",
       "unknown key 'brsh'; did you mean /jobs/0/brush?"},
      {R"({"id": "a", "previw": "b.json", "trajectory": "t.csv"})", "/jobs/0/previw",
       "unknown key 'previw'; did you mean /jobs/0/preview?"},
      {R"({"id": "a", "scene": "s.json", "ouptut": "x.png"})", "/jobs/0/ouptut",
       "unknown key 'ouptut'; did you mean /jobs/0/output?"},
  };
  for (const Case& c : cases) {
    INFO(c.jobs);
    const auto [code, message] = parseError(head + c.jobs + "]}");
    CHECK(code == 65);
    CHECK_THAT(message, Contains("jobs.json: " + c.pointer));
    CHECK_THAT(message, Contains(c.rule));
  }
  CHECK(parseError(R"({"format": "bristle-scene/1", "jobs": [{"id": "a", "scene": "s"}]})").second.find(
            "/format") != std::string::npos);
  CHECK(parseError("[1, 2]").first == 65);
  CHECK(parseError("{\"format\": ").first == 65);
}

TEST_CASE("batch shards: I/N parses, and 5/4, 0/0 and junk are usage errors", "[batch][errors]") {
  CHECK(parseShard("0/1").count == 1);
  CHECK(parseShard("3/4").index == 3);
  for (const std::string bad : {"5/4", "4/4", "0/0", "-1/3", "1", "a/b", "1/2/3", " 1/2", ""}) {
    INFO(bad);
    const auto [code, message] = shardError(bad);
    CHECK(code == 64);
    CHECK_THAT(message, Contains("--shard"));
  }
}

TEST_CASE("batch shards cover every job exactly once, in near-equal parts", "[batch]") {
  for (int n = 0; n <= 23; ++n) {
    for (int count = 1; count <= 7; ++count) {
      std::map<int, int> seen;
      size_t smallest = size_t(-1), largest = 0;
      for (int i = 0; i < count; ++i) {
        const std::vector<int> mine = jobsOfShard(n, Shard{i, count});
        CHECK(std::is_sorted(mine.begin(), mine.end()));
        for (const int k : mine) ++seen[k];
        smallest = std::min(smallest, mine.size());
        largest = std::max(largest, mine.size());
      }
      INFO("n=" << n << " count=" << count);
      CHECK(static_cast<int>(seen.size()) == n);
      for (const auto& [k, times] : seen) {
        CHECK(k >= 0);
        CHECK(k < n);
        CHECK(times == 1);
      }
      CHECK(largest - smallest <= 1);
    }
  }
}

TEST_CASE("batch shards come from Slurm job arrays and Kubernetes Indexed Jobs", "[batch]") {
  std::map<std::string, std::string> vars;
  const auto env = [&vars](const char* name) -> const char* {
    auto it = vars.find(name);
    return it == vars.end() ? nullptr : it->second.c_str();
  };
  // Nothing set: the whole manifest.
  Shard s = shardFromEnvironment(env, 0);
  CHECK((s.index == 0 && s.count == 1));

  // sbatch --array=4-7: ids 4..7, min 4, count 4.
  vars = {{"SLURM_ARRAY_TASK_ID", "6"}, {"SLURM_ARRAY_TASK_MIN", "4"}, {"SLURM_ARRAY_TASK_COUNT", "4"}};
  s = shardFromEnvironment(env, 0);
  CHECK((s.index == 2 && s.count == 4));
  // sbatch --array=0-6:2: ids 0, 2, 4, 6 with step 2.
  vars = {{"SLURM_ARRAY_TASK_ID", "4"}, {"SLURM_ARRAY_TASK_MIN", "0"},
          {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_STEP", "2"}};
  s = shardFromEnvironment(env, 0);
  CHECK((s.index == 2 && s.count == 4));
  // An array with gaps (--array=0,3) cannot be mapped onto 0..N-1.
  vars = {{"SLURM_ARRAY_TASK_ID", "3"}, {"SLURM_ARRAY_TASK_MIN", "0"}, {"SLURM_ARRAY_TASK_COUNT", "2"}};
  CHECK_THROWS_WITH(shardFromEnvironment(env, 0), Contains("not a task of the array"));
  vars = {{"SLURM_ARRAY_TASK_ID", "x"}};
  CHECK_THROWS_WITH(shardFromEnvironment(env, 0), Contains("SLURM_ARRAY_TASK_ID=x"));
  // A step of 0, and numbers past the shard limit, are refused, never read as another shard.
  vars = {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_MIN", "0"},
          {"SLURM_ARRAY_TASK_COUNT", "4"}, {"SLURM_ARRAY_TASK_STEP", "0"}};
  CHECK_THROWS_WITH(shardFromEnvironment(env, 0),
                    "SLURM_ARRAY_TASK_STEP=0: must be at least 1 (the array's step between "
                    "task ids)");
  vars = {{"SLURM_ARRAY_TASK_ID", "1"}, {"SLURM_ARRAY_TASK_COUNT", "99999999999999999999"}};
  CHECK_THROWS_WITH(shardFromEnvironment(env, 0),
                    "SLURM_ARRAY_TASK_COUNT=99999999999999999999: not a non-negative integer up "
                    "to 999999999");
  vars = {{"SLURM_ARRAY_TASK_ID", "-1"}};
  CHECK_THROWS_WITH(shardFromEnvironment(env, 0), Contains("not a non-negative integer"));

  // Kubernetes: the pod knows its index; the count comes from the command line.
  vars = {{"JOB_COMPLETION_INDEX", "2"}};
  s = shardFromEnvironment(env, 3);
  CHECK((s.index == 2 && s.count == 3));
  CHECK_THROWS_WITH(shardFromEnvironment(env, 0), Contains("--shard-count"));
  CHECK_THROWS_WITH(shardFromEnvironment(env, 2), Contains("--shard-count"));
  vars.clear();
  CHECK_THROWS_WITH(shardFromEnvironment(env, 4), Contains("JOB_COMPLETION_INDEX"));
  try {
    shardFromEnvironment(env, 4);
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::kUsage);
  }
}

TEST_CASE("batch job command lines: sorted options, flags, lists", "[batch]") {
  const BatchManifest m = parse(R"({"format": "bristle-batch/1", "jobs": [
      {"id": "a", "brush": "b.json", "trajectory": "t.csv",
       "options": {"solver": "slsqp", "impasto": true, "offset-mm": [1, 2.5, 0], "bits": 16,
                   "ipopt-option": ["tol=1e-8", "mu_strategy=monotone"]}},
      {"id": "c", "sheet": "sh.json", "options": {"impasto": false, "ipopt-option": "tol=0.1"}},
      {"id": "b", "scene": "s.json"}]})");
  CHECK(batchJobArguments(m.jobs[0]) ==
        std::vector<std::string>{"render", "--brush", "/data/batch/b.json", "--trajectory",
                                 "/data/batch/t.csv", "--bits", "16", "--impasto",
                                 "--ipopt-option", "tol=1e-8", "mu_strategy=monotone",
                                 "--offset-mm", "1", "2.5", "0", "--solver", "slsqp"});
  CHECK(batchJobArguments(m.jobs[2]) == std::vector<std::string>{"render", "/data/batch/s.json"});
  // false leaves a flag out; a string is one word.
  CHECK(batchJobArguments(m.jobs[1]) ==
        std::vector<std::string>{"sheet", "/data/batch/sh.json", "--ipopt-option", "tol=0.1"});
}

TEST_CASE("batch job keys follow file contents and options, not paths", "[batch]") {
  TempDir a, b;
  const std::string brush = "{\"brush\": 1}\n", traj = "t_s\n0\n";
  const auto job = [](const TempDir& s, const std::string& options) {
    BatchManifest m = parseBatchManifest(
        R"({"format": "bristle-batch/1", "jobs": [{"id": "x", "brush": "b.json",
            "trajectory": "t.csv", "options": )" + options + "}]}",
        (s.path() / "m.json").string(), s.path().string());
    return m.jobs[0];
  };
  a.write("b.json", brush);
  a.write("t.csv", traj);
  b.write("b.json", brush);
  b.write("t.csv", traj);
  const BatchJob ja = job(a, "{}"), jb = job(b, "{}");
  const std::uint64_t key = batchJobKey(ja, batchJobInputs(ja, "m.json"));
  // The same bytes in another folder: the same key (a moved checkout keeps
  // its outputs).
  CHECK(batchJobKey(jb, batchJobInputs(jb, "m.json")) == key);
  // An option changes it.
  const BatchJob jo = job(a, R"({"bits": 16})");
  CHECK(batchJobKey(jo, batchJobInputs(jo, "m.json")) != key);
  // One byte of one input changes it.
  b.write("t.csv", "t_s\n1\n");
  CHECK(batchJobKey(jb, batchJobInputs(jb, "m.json")) != key);
  // A preview of the same files is another render: another key.
  const BatchJob jp = parseBatchManifest(
      R"({"format": "bristle-batch/1", "jobs": [{"id": "x", "preview": "b.json",
          "trajectory": "t.csv"}]})", (a.path() / "m.json").string(), a.path().string()).jobs[0];
  CHECK(batchJobInputs(jp, "m.json") == batchJobInputs(ja, "m.json"));
  CHECK(batchJobKey(jp, batchJobInputs(jp, "m.json")) != key);
  // The program that renders is part of the key: a rebuilt bristle of the same
  // version renders again.
  CHECK(batchJobKey(ja, batchJobInputs(ja, "m.json"), 1) != key);
  CHECK(batchJobKey(ja, batchJobInputs(ja, "m.json"), 1) ==
        batchJobKey(ja, batchJobInputs(ja, "m.json"), 1));
  // A missing input is the job's own error (66), naming the manifest field.
  fs::remove(b.path() / "b.json");
  try {
    batchJobInputs(jb, "m.json");
    FAIL("missing brush accepted");
  } catch (const Error& e) {
    CHECK(e.code() == ExitCode::kNoInput);
    CHECK_THAT(e.what(), Contains("m.json: /jobs/0/brush: "));
  }
}

TEST_CASE("batch outputs are written beneath --out, never through a symbolic link", "[batch][errors]") {
  TempDir s;
  const std::string out = (s.path() / "out").string();
  fs::create_directories(s.path() / "out");
  fs::create_directories(s.path() / "elsewhere");
  // New folders are created beneath --out and the file renamed into place.
  writeFileBeneath(out, "a/b/x.png", "bytes");
  CHECK(fs::is_regular_file(s.path() / "out/a/b/x.png"));
  writeFileBeneath(out, "a/b/x.png", "again");
  std::ifstream in(s.path() / "out/a/b/x.png");
  std::string text;
  in >> text;
  CHECK(text == "again");

  // A link to a folder outside, at any depth, or as the file itself: refused
  // (73), here where the write happens as well as in the check before a run,
  // so a link made between the two does not let a job out either.
  fs::create_directory_symlink("../../elsewhere", s.path() / "out/a/link");
  fs::create_symlink("../elsewhere/victim.png", s.path() / "out/file.png");
  for (const std::string rel : {"a/link/x.png", "a/link/new/x.png", "file.png"}) {
    INFO(rel);
    const testing::Caught write = testing::catchError([&] { writeFileBeneath(out, rel, "x"); });
    CHECK(write.code == 73);
    CHECK_THAT(write.message, Contains("is a symbolic link; a batch writes only beneath --out"));
    CHECK(testing::catchError([&] { checkBeneath(out, rel); }).code == 73);
  }
  CHECK(fs::is_empty(s.path() / "elsewhere"));
  CHECK(!fs::exists(s.path() / "elsewhere/victim.png"));
  // Nothing is left beside the files: no temporary file.
  for (const auto& e : fs::recursive_directory_iterator(s.path() / "out"))
    CHECK(e.path().filename().string().find(".tmp-") == std::string::npos);
  // A folder not yet made is fine for the check; a file in the way is not.
  CHECK_FALSE(testing::catchError([&] { checkBeneath(out, "new/x.png"); }).thrown);
  CHECK(testing::catchError([&] { checkBeneath(out, "a/b/x.png/y.png"); }).code == 73);
}

TEST_CASE("batch: a false flag in a job takes back the defaults' true", "[batch]") {
  const BatchManifest m = parse(R"({"format": "bristle-batch/1",
      "defaults": {"options": {"impasto": true, "bits": 16}},
      "jobs": [{"id": "a", "scene": "s.json", "options": {"impasto": false}},
               {"id": "b", "scene": "s.json"}]})");
  CHECK(batchJobArguments(m.jobs[0]) ==
        std::vector<std::string>{"render", "/data/batch/s.json", "--bits", "16"});
  CHECK(batchJobArguments(m.jobs[1]) ==
        std::vector<std::string>{"render", "/data/batch/s.json", "--bits", "16", "--impasto"});
}

TEST_CASE("a batch job cannot set the batch's own --batch-key", "[batch][errors]") {
  const auto [code, message] = parseError(
      R"({"format": "bristle-batch/1", "jobs": [{"id": "a", "scene": "s.json",
          "options": {"batch-key": "0123456789abcdef"}}]})");
  CHECK(code == 65);
  CHECK_THAT(message, Contains("/jobs/0/options/batch-key") && Contains("cannot set --batch-key"));
}

TEST_CASE("a batch sheet job is keyed by the sheet's inputs: a trajectory edit re-renders it",
          "[sheet][batch]") {
  TempDir d;
  const fs::path src(BRISTLE_SOURCE_DIR);
  fs::create_directories(d.path() / "b");
  fs::create_directories(d.path() / "t");
  fs::copy_file(src / "scenes/brushes/round.json", d.path() / "b/round.json");
  fs::copy_file(src / "scenes/trajectories/straight-pull.csv", d.path() / "t/straight-pull.csv");
  const std::string sheet = d.write("sheet.json", R"({"format": "bristle-sheet/1", "name": "copy",
      "brushes": ["b/round.json"], "trajectories": ["t/straight-pull.csv"]})");
  const BatchManifest m = parseBatchManifest(
      R"({"format": "bristle-batch/1", "jobs": [{"id": "s", "sheet": "sheet.json"}]})",
      d.file("m.json"), d.path().string());
  REQUIRE(m.jobs.size() == 1);
  const BatchJob& job = m.jobs[0];
  // The same files, in the same order, as the sheet's PNG hash covers.
  const std::vector<std::string> inputs = batchJobInputs(job, "m.json");
  CHECK(inputs == loadSheet(sheet).inputs);
  CHECK(fnv1a64Files(inputs) == sheetInputsHash(loadSheet(sheet)));
  const std::uint64_t key = batchJobKey(job, inputs);
  std::ofstream(d.path() / "t/straight-pull.csv", std::ios::app) << "# edited\n";
  CHECK(batchJobKey(job, batchJobInputs(job, "m.json")) != key);
}

TEST_CASE("batch PNG text: the key a job's process writes is what the up-to-date check reads",
          "[batch]") {
  TempDir d;
  const std::string png = d.file("x.png");
  const render::Image8 image{2, 1, 3, {1, 2, 3, 4, 5, 6}};
  // No key: no text at all (a render outside a batch is unchanged).
  CHECK(batchPngText("", {"w"}).empty());
  render::writePng(png, image, batchPngText("0123456789abcdef", {}));
  std::vector<std::string> warnings;
  CHECK(batchOutputUpToDate(png, "0123456789abcdef", &warnings));
  CHECK(warnings.empty());
  CHECK_FALSE(batchOutputUpToDate(png, "fedcba9876543210", &warnings));
  // Warnings travel with the key, any text included.
  const std::vector<std::string> said = {"the brush never touched the canvas (t.csv)",
                                         "caf\u00e9 \"quoted\""};
  render::writePng(png, image, batchPngText("0123456789abcdef", said));
  CHECK(batchOutputUpToDate(png, "0123456789abcdef", &warnings));
  CHECK(warnings == said);
  // A truncated file or none is not up to date.
  const std::string bytes = [&] {
    std::ifstream in(png, std::ios::binary);
    std::ostringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  std::ofstream(png, std::ios::binary) << bytes.substr(0, bytes.size() - 10);
  CHECK_FALSE(batchOutputUpToDate(png, "0123456789abcdef", &warnings));
  CHECK_FALSE(batchOutputUpToDate(d.file("none.png"), "0123456789abcdef", &warnings));
}

TEST_CASE("batch outputs are moved beneath --out, never through a symbolic link",
          "[batch][errors]") {
  TempDir s;
  const std::string out = s.file("out");
  fs::create_directories(s.path() / "out/.private");
  fs::create_directories(s.path() / "elsewhere");
  const std::string from = s.write("out/.private/0.png", "bytes");
  moveFileBeneath(from, out, "a/b/x.png");
  CHECK(fs::is_regular_file(s.path() / "out/a/b/x.png"));
  CHECK_FALSE(fs::exists(from));
  fs::create_directory_symlink("../../elsewhere", s.path() / "out/a/link");
  s.write("out/.private/1.png", "bytes");
  const testing::Caught moved = testing::catchError(
      [&] { moveFileBeneath(s.file("out/.private/1.png"), out, "a/link/x.png"); });
  CHECK(moved.code == 73);
  CHECK_THAT(moved.message, Contains("is a symbolic link; a batch writes only beneath --out"));
  CHECK(fs::is_empty(s.path() / "elsewhere"));
}

TEST_CASE("batch job costs: planned spine-steps, a scene the sum of its strokes", "[batch]") {
  // What the pool orders by when it has several workers (batch/job_cost.h).
  auto inSource = [](const std::string& rel) {
    return std::string(BRISTLE_SOURCE_DIR) + "/" + rel;
  };
  auto stroke = [&](const std::string& brush, const std::string& trajectory) {
    BatchJob j;
    j.kind = BatchJobKind::kStroke;
    j.brush = inSource("scenes/brushes/" + brush + ".json");
    j.trajectory = inSource("scenes/trajectories/depth/" + trajectory + ".csv");
    return j;
  };
  const Brush round = loadBrush(inSource("scenes/brushes/round.json"));
  const Trajectory pull = resolveDepths(
      loadTrajectory(inSource("scenes/trajectories/depth/straight-pull.csv")), round);
  // Exactly the render's plan times the spines: the figure is not a guess.
  CHECK(estimateJobCost(stroke("round", "straight-pull")) ==
        static_cast<double>(planStepTimes(pull, round, SimOptions{}).size() * round.spines.size()));
  // The S-curve is the standard set's long stroke; more spines cost more.
  CHECK(estimateJobCost(stroke("round", "s-curve")) >
        estimateJobCost(stroke("round", "straight-pull")));
  CHECK(estimateJobCost(stroke("badger", "straight-pull")) >
        estimateJobCost(stroke("round", "straight-pull")));

  BatchJob scene;
  scene.kind = BatchJobKind::kScene;
  scene.input = inSource("scenes/paintings/petals.json");
  const Scene petals = loadScene(scene.input);
  double sum = 0;
  for (const SceneStroke& s : petals.strokes) {
    const Brush& b = petals.brushes[s.brush];
    sum += static_cast<double>(
        planStepTimes(resolveDepths(s.trajectory, b), b, SimOptions{}).size() * b.spines.size());
  }
  REQUIRE(petals.strokes.size() > 1);
  CHECK(estimateJobCost(scene) == sum);

  // What cannot be read here, and sheets, start first; a preview is one state.
  CHECK(estimateJobCost(stroke("no-such-brush", "straight-pull")) == kUnknownJobCost);
  BatchJob sheet;
  sheet.kind = BatchJobKind::kSheet;
  sheet.input = inSource("scenes/sheets/library.json");
  CHECK(estimateJobCost(sheet) == kUnknownJobCost);
  BatchJob preview;
  preview.kind = BatchJobKind::kPreview;
  CHECK(estimateJobCost(preview) == 1);
}

// `bristle batch` end to end: the same pixels whatever the parallelism or
// sharding, up-to-date outputs skipped (and re-rendered when an input changes
// or with --overwrite), a broken job failing alone and logged, usage errors,
// and a stopped batch leaving no partial PNG (docs/batch.md).

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <algorithm>
#include <map>
#include <set>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>

#include "cli_runner.h"
#include "engine/base/fnv1a64.h"
#include "render/image/png_io.h"

using namespace bristle;
using namespace bristle::testing;
using Catch::Matchers::Contains;
using Catch::Matchers::Matches;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

const std::string kFlat = sourcePath("scenes/brushes/flat.json");

// A short dab: the vertical round comes down 3 mm past first contact (its hairs
// are 20 mm long), drifts `dx` mm along x and lifts, in 0.5 s. Cheap enough to
// render many times.
std::string dab(double dx) {
  std::ostringstream s;
  s << "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  for (int i = 0; i <= 25; ++i) {
    const double t = i * 0.02, u = t / 0.5;
    const double z = 22 - 5 * std::sin(M_PI * u);
    s << t << "," << 20 + dx * u << ",20," << z << ",1,0,0,0\n";
  }
  return s.str();
}

// A manifest of `n` stroke jobs over dab trajectories written into dir.
json manifest(const TempDir& dir, int n) {
  json jobs = json::array();
  for (int k = 0; k < n; ++k) {
    const std::string traj = "dab" + std::to_string(k) + ".csv";
    dir.write(traj, dab(2.0 * k));
    jobs.push_back({{"id", "dab" + std::to_string(k)},
                    {"brush", k % 2 ? kFlat : kRound},
                    {"trajectory", traj}});
  }
  return {{"format", "bristle-batch/1"},
          {"defaults", {{"options", {{"solver", "ipopt"}, {"px-per-mm", 4}}}}},
          {"jobs", jobs}};
}

// A job "above" whose brush stays far above the paper, never touching it: a
// render with a warning.
void addJobAbovePaper(const TempDir& dir, json* m) {
  std::string high = "# bristle-trajectory/1\nt_s,x_mm,y_mm,z_mm,qw,qx,qy,qz\n";
  for (int i = 0; i <= 5; ++i) high += std::to_string(i * 0.1) + ",20,20,80,1,0,0,0\n";
  dir.write("high.csv", high);
  (*m)["jobs"].push_back({{"id", "above"}, {"brush", kRound}, {"trajectory", "high.csv"}});
}

std::string writeManifest(const TempDir& dir, const json& m) {
  return dir.write("jobs.json", m.dump(2));
}

std::uint64_t pixelHash(const std::string& png) {
  const render::Image8 img = render::readPngRgba8(png);
  return fnv1a64(std::string_view(reinterpret_cast<const char*>(img.pixels.data()),
                                  img.pixels.size()));
}

// The JSON lines of a --json run, by job id (the summary under "summary").
std::map<std::string, json> jsonLines(const std::string& out) {
  std::map<std::string, json> lines;
  std::istringstream in(out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const json j = json::parse(line);
    lines[j.contains("summary") ? "summary" : j["job"].get<std::string>()] = j;
  }
  return lines;
}

std::vector<std::string> pngsIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.path().extension() == ".png") names.push_back(fs::relative(e.path(), dir).string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST_CASE("batch: --jobs 1, --jobs 2 and 4 shards give the same pixels", "[cli][batch][determinism]") {
  TempDir dir;
  const std::string m = writeManifest(dir, manifest(dir, 5));
  const std::string one = dir.file("one"), two = dir.file("two"), sharded = dir.file("sharded");

  RunResult r = runBristle("batch '" + m + "' --out '" + one + "' --jobs 1 --quiet");
  REQUIRE(r.code == 0);
  r = runBristle("batch '" + m + "' --out '" + two + "' --jobs 2 --json");
  REQUIRE(r.code == 0);
  const auto lines = jsonLines(r.out);
  CHECK(lines.at("summary")["rendered"] == 5);
  CHECK(lines.at("dab3")["status"] == "rendered");
  for (int i = 0; i < 4; ++i) {
    r = runBristle("batch '" + m + "' --out '" + sharded + "' --shard " + std::to_string(i) +
                   "/4 --json");
    REQUIRE(r.code == 0);
    // Round-robin: shard 0 owns jobs 0 and 4, the others one job each.
    CHECK(jsonLines(r.out).at("summary")["jobs"] == (i == 0 ? 2 : 1));
  }
  const std::vector<std::string> expected = {"dab0.png", "dab1.png", "dab2.png", "dab3.png",
                                             "dab4.png"};
  REQUIRE(pngsIn(one) == expected);
  REQUIRE(pngsIn(two) == expected);
  REQUIRE(pngsIn(sharded) == expected);
  std::set<std::uint64_t> distinct;
  for (const std::string& png : expected) {
    INFO(png);
    const std::uint64_t h = pixelHash(one + "/" + png);
    CHECK(pixelHash(two + "/" + png) == h);
    CHECK(pixelHash(sharded + "/" + png) == h);
    // The same bytes too: the stamped key depends on the job alone.
    CHECK(readAll(two + "/" + png) == readAll(one + "/" + png));
    distinct.insert(h);
  }
  // Five different dabs, five different images (a batch that wrote one image
  // five times would pass the checks above).
  CHECK(distinct.size() == 5);
  // Every run keeps its own job log; no private folder is left behind.
  int logs = 0;
  for (const auto& e : fs::directory_iterator(sharded + "/logs")) logs += e.path().extension() == ".jsonl";
  CHECK(logs == 4);
  for (const auto& e : fs::directory_iterator(sharded))
    CHECK(e.path().filename().string().rfind(".bristle-batch-", 0) == std::string::npos);
}

TEST_CASE("batch: up-to-date outputs are skipped, and a changed input or --overwrite renders again",
          "[cli][batch]") {
  TempDir dir;
  const std::string m = writeManifest(dir, manifest(dir, 3));
  const std::string out = dir.file("out");
  REQUIRE(runBristle("batch '" + m + "' --out '" + out + "' --jobs 2 --quiet").code == 0);
  const auto stamp = [&](const std::string& id) {
    return fs::last_write_time(out + "/" + id + ".png");
  };
  const auto t0 = stamp("dab0"), t1 = stamp("dab1"), t2 = stamp("dab2");
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // mtime granularity

  RunResult r = runBristle("batch '" + m + "' --out '" + out + "' --json");
  REQUIRE(r.code == 0);
  auto lines = jsonLines(r.out);
  CHECK(lines.at("summary")["skipped"] == 3);
  CHECK(lines.at("summary")["rendered"] == 0);
  CHECK(stamp("dab0") == t0);

  // One trajectory changes: only its job renders.
  dir.write("dab1.csv", dab(7.5));
  r = runBristle("batch '" + m + "' --out '" + out + "' --json");
  REQUIRE(r.code == 0);
  lines = jsonLines(r.out);
  CHECK(lines.at("dab1")["status"] == "rendered");
  CHECK(lines.at("dab0")["status"] == "skipped");
  CHECK(lines.at("dab2")["status"] == "skipped");
  CHECK(stamp("dab1") != t1);
  CHECK(stamp("dab2") == t2);

  // A truncated output is not up to date.
  const std::string bytes = readAll(out + "/dab2.png");
  std::ofstream(out + "/dab2.png", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  r = runBristle("batch '" + m + "' --out '" + out + "' --json");
  CHECK(jsonLines(r.out).at("dab2")["status"] == "rendered");
  CHECK(readAll(out + "/dab2.png") == bytes);

  r = runBristle("batch '" + m + "' --out '" + out + "' --json --overwrite");
  REQUIRE(r.code == 0);
  CHECK(jsonLines(r.out).at("summary")["rendered"] == 3);
}

TEST_CASE("batch: a rebuilt bristle renders again what an older build made", "[cli][batch]") {
  // The same version, other code: a copy of the executable with one byte
  // appended (ELF ignores trailing bytes, so it runs as before). Its outputs
  // must not be taken as up to date, or a fix would never reach them.
  TempDir dir;
  const std::string m = writeManifest(dir, manifest(dir, 1));
  const std::string out = dir.file("out");
  REQUIRE(runBristle("batch '" + m + "' --out '" + out + "' --quiet").code == 0);
  const std::string rebuilt = dir.file("bristle-rebuilt");
  fs::copy_file(BRISTLE_BIN, rebuilt);
  std::ofstream(rebuilt, std::ios::binary | std::ios::app) << '\n';
  fs::permissions(rebuilt, fs::perms::owner_exec, fs::perm_options::add);
  const RunResult again = runCaptured("env -u GALLIUM_DRIVER '" + rebuilt + "' batch '" + m +
                                          "' --out '" + out + "' --json",
                                      dir.file("again.out"), dir.file("again.err"));
  INFO(again.err);
  REQUIRE(again.code == 0);
  CHECK(jsonLines(again.out).at("dab0")["status"] == "rendered");
  // And the same build again keeps it.
  const RunResult same = runCaptured("env -u GALLIUM_DRIVER '" + rebuilt + "' batch '" + m +
                                         "' --out '" + out + "' --json",
                                     dir.file("same.out"), dir.file("same.err"));
  REQUIRE(same.code == 0);
  CHECK(jsonLines(same.out).at("dab0")["status"] == "skipped");
}

TEST_CASE("batch: a broken job fails alone, is logged, and sets the exit code", "[cli][batch][errors]") {
  TempDir dir;
  json m = manifest(dir, 3);
  m["jobs"][1]["brush"] = dir.file("no-such-brush.json");
  m["jobs"][2]["options"] = {{"bits", 12}};  // rejected by render's option check
  const std::string path = writeManifest(dir, m);
  const std::string out = dir.file("out");
  const RunResult r = runBristle("batch '" + path + "' --out '" + out + "' --jobs 2");
  CHECK(r.code == 66);  // the first failed job's code, in manifest order
  CHECK(pngsIn(out) == std::vector<std::string>{"dab0.png"});
  CHECK_THAT(r.err, Contains("job 'dab1' failed (66): " + path + ": /jobs/1/brush: "));
  CHECK_THAT(r.err, Contains("job 'dab2' failed (64): --bits"));
  CHECK_THAT(r.err, Contains("1 rendered, 0 up to date, 2 failed"));
  // stderr is no terminal here: one line per job as it ends, counted 1/3 .. 3/3.
  std::vector<std::string> ended;
  std::istringstream err(r.err);
  for (std::string line; std::getline(err, line);)
    if (line.rfind("batch: ", 0) == 0 && line.find(" jobs (shard") == std::string::npos)
      ended.push_back(line);
  REQUIRE(ended.size() == 3);
  for (int k = 0; k < 3; ++k) CHECK(ended[size_t(k)].rfind("batch: " + std::to_string(k + 1) + "/3 ", 0) == 0);
  std::sort(ended.begin(), ended.end(), [](const std::string& a, const std::string& b) {
    return a.substr(11) < b.substr(11);
  });
  CHECK_THAT(ended[0], Matches("batch: [123]/3 dab0 rendered in [0-9]+\\.[0-9] s"));
  CHECK_THAT(ended[1], Matches("batch: [123]/3 dab1 failed \\(exit 66\\)"));
  CHECK_THAT(ended[2], Matches("batch: [123]/3 dab2 failed \\(exit 64\\)"));

  // The log: one line per job plus the summary.
  std::string log;
  for (const auto& e : fs::directory_iterator(out + "/logs")) log = readAll(e.path().string());
  const auto lines = jsonLines(log);
  REQUIRE(lines.size() == 4);
  CHECK(lines.at("dab0")["status"] == "rendered");
  CHECK(lines.at("dab0")["input_hash"].get<std::string>().size() == 16);
  CHECK(lines.at("dab1")["status"] == "failed");
  CHECK(lines.at("dab1")["exit_code"] == 66);
  CHECK(lines.at("dab2")["exit_code"] == 64);
  CHECK(lines.at("dab1").contains("seconds"));
  CHECK(lines.at("summary")["failed"] == 2);
}

TEST_CASE("batch: usage and manifest errors stop before any job", "[cli][batch][errors]") {
  TempDir dir;
  const std::string m = writeManifest(dir, manifest(dir, 2));
  const std::string out = dir.file("out");
  for (const std::string shard : {"5/4", "0/0"}) {
    const RunResult r = runBristle("batch '" + m + "' --out '" + out + "' --shard " + shard);
    CHECK(r.code == 64);
    CHECK_THAT(r.err, Contains("--shard " + shard));
  }
  RunResult r = runBristle("batch '" + dir.file("missing.json") + "' --out '" + out + "'");
  CHECK(r.code == 66);
  CHECK_THAT(r.err, Contains("missing.json"));
  r = runBristle("batch '" + dir.write("bad.json", R"({"format": "bristle-batch/1", "jobs": []})") +
                 "' --out '" + out + "'");
  CHECK(r.code == 65);
  CHECK_THAT(r.err, Contains("bad.json: /jobs"));
  // An output folder that cannot be created (a file is in the way).
  r = runBristle("batch '" + m + "' --out '" + dir.write("file", "x") + "/sub'");
  CHECK(r.code == 73);
  CHECK(!fs::exists(out));
}

TEST_CASE("batch: Slurm's array variables pick the shard", "[cli][batch]") {
  TempDir dir;
  const std::string m = writeManifest(dir, manifest(dir, 5));
  // sbatch --array=10-13 runs 4 tasks; task 12 is shard 2 of 4: job 2 only.
  const RunResult r = runBristle(
      "batch '" + m + "' --out '" + dir.file("out") + "' --dry-run --json");
  CHECK(jsonLines(r.out).size() == 6);
  const std::string env =
      "SLURM_ARRAY_TASK_ID=12 SLURM_ARRAY_TASK_MIN=10 SLURM_ARRAY_TASK_COUNT=4 ";
  const std::string cmd = "env " + env + "'" + BRISTLE_BIN + "' batch '" + m + "' --out '" +
                          dir.file("out") + "' --dry-run --json > '" + dir.file("so") + "'";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const auto lines = jsonLines(readAll(dir.file("so")));
  CHECK(lines.size() == 2);
  CHECK(lines.count("dab2") == 1);
  CHECK(lines.at("summary")["shard"] == "2/4");
  // A dry run renders nothing.
  CHECK(!fs::exists(dir.file("out/dab2.png")));
}

TEST_CASE("batch: SIGTERM abandons the running job and leaves no partial PNG", "[cli][batch]") {
  TempDir dir;
  // One job long enough to be caught running (a pressed S-curve with Ipopt:
  // seconds), then a dab that must not start.
  json m = manifest(dir, 2);
  m["jobs"][0]["trajectory"] = sourcePath("scenes/trajectories/s-curve.csv");
  m["jobs"][0]["options"] = {{"solver", "ipopt"}};
  const std::string path = writeManifest(dir, m);
  const std::string out = dir.file("out");
  // (Built with append: GCC 12 warns, wrongly, on a long chain of '+'.)
  std::string script = "'";
  script.append(BRISTLE_BIN).append("' batch '").append(path).append("' --out '").append(out);
  script.append("' --jobs 1 & echo $! > '").append(dir.file("pid"));
  script.append("'; wait $!; echo $? > '").append(dir.file("rc")).append("'");
  const std::string cmd =
      "env -u GALLIUM_DRIVER sh '" + dir.write("run.sh", script + "\n") + "' >/dev/null 2>&1 &";
  REQUIRE(std::system(cmd.c_str()) == 0);

  // Wait until the job's process has started (its stderr file appears in the
  // batch's private folder), then stop the batch. 30 s is far beyond any
  // start-up here; the loop ends as soon as it is seen.
  bool started = false;
  for (int i = 0; i < 3000 && !started; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    std::error_code ec;
    if (fs::is_directory(out, ec))
      for (const auto& e : fs::directory_iterator(out, ec))
        if (e.path().filename().string().rfind(".bristle-batch-", 0) == 0 &&
            fs::exists(e.path() / "0.stderr"))
          started = true;
  }
  REQUIRE(started);
  const std::string pid = readAll(dir.file("pid"));
  REQUIRE(std::system(("kill -TERM " + pid).c_str()) == 0);
  for (int i = 0; i < 3000 && !fs::exists(dir.file("rc")); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  REQUIRE(fs::exists(dir.file("rc")));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // rc written and closed
  CHECK(std::stoi(readAll(dir.file("rc"))) == 143);  // 128 + SIGTERM
  CHECK(pngsIn(out).empty());
  for (const auto& e : fs::directory_iterator(out)) CHECK(e.path().filename() == "logs");
  std::string log;
  for (const auto& e : fs::directory_iterator(out + "/logs")) log = readAll(e.path().string());
  const auto lines = jsonLines(log);
  CHECK(lines.at("dab0")["status"] == "abandoned");
  CHECK(lines.at("dab1")["status"] == "abandoned");
  CHECK(lines.at("summary")["abandoned"] == 2);
}

TEST_CASE("batch: a sheet job is keyed by every file the sheet reads", "[cli][batch]") {
  TempDir dir;
  // A 1 x 2 sheet whose trajectories live in the temp folder.
  dir.write("a.csv", dab(0));
  dir.write("b.csv", dab(4));
  const json sheet = {{"format", "bristle-sheet/1"},
                      {"name", "tiny"},
                      {"brushes", {kRound}},
                      {"trajectories", {"a.csv", "b.csv"}},
                      {"px_per_mm", 4},
                      {"solver", "ipopt"}};
  dir.write("tiny.json", sheet.dump());
  const json m = {{"format", "bristle-batch/1"},
                  {"jobs", {{{"id", "tiny"}, {"sheet", "tiny.json"}}}}};
  const std::string path = writeManifest(dir, m);
  const std::string out = dir.file("out");
  RunResult r = runBristle("batch '" + path + "' --out '" + out + "' --json");
  REQUIRE(r.code == 0);
  CHECK(jsonLines(r.out).at("tiny")["kind"] == "sheet");
  CHECK(jsonLines(r.out).at("tiny")["status"] == "rendered");
  // The batch's output is the sheet command's picture, plus the key.
  REQUIRE(runBristle("sheet '" + dir.file("tiny.json") + "' -o '" + dir.file("direct.png") + "' -q")
              .code == 0);
  CHECK(pixelHash(out + "/tiny.png") == pixelHash(dir.file("direct.png")));

  r = runBristle("batch '" + path + "' --out '" + out + "' --json");
  CHECK(jsonLines(r.out).at("tiny")["status"] == "skipped");
  // A trajectory the sheet lists (not the sheet itself) changes.
  dir.write("b.csv", dab(6));
  r = runBristle("batch '" + path + "' --out '" + out + "' --json");
  CHECK(jsonLines(r.out).at("tiny")["status"] == "rendered");
}

TEST_CASE("batch: each job logs its warnings and figures, and --fail-on-warning fails on them",
          "[cli][batch][warnings]") {
  TempDir d;
  json m = manifest(d, 1);
  addJobAbovePaper(d, &m);
  const std::string jobs = writeManifest(d, m);
  const std::string out = d.file("out");

  const RunResult r = runBristle("batch '" + jobs + "' --out '" + out + "' --json");
  REQUIRE(r.code == 0);  // warnings alone do not fail a batch ...
  std::map<std::string, json> lines = jsonLines(r.out);
  const json& dab = lines["dab0"];
  CHECK(dab["status"] == "rendered");
  CHECK(dab["warnings"].empty());
  CHECK(dab["figures"]["painted_pixels"].get<long>() > 100);
  CHECK(dab["figures"]["paint_laid_mm3"].get<double>() > 0);
  CHECK(dab["figures"]["failed_steps"] == 0);
  const json& above = lines["above"];
  CHECK(above["status"] == "rendered");
  REQUIRE(above["warnings"].size() == 1);
  CHECK_THAT(above["warnings"][0].get<std::string>(),
             Contains("the brush never touched the canvas") && Contains("high.csv"));
  CHECK(above["figures"]["painted_pixels"] == 0);
  CHECK(above["figures"]["paint_laid_mm3"] == 0.0);
  CHECK(lines["summary"]["warned"] == 1);
  // Each job's process wrote the key and warnings of its log entry into its
  // PNG, beside the render's own text.
  for (const std::string id : {"dab0", "above"}) {
    INFO(id);
    std::map<std::string, std::string> text;
    for (const auto& [k, v] : render::readPngText(out + "/" + id + ".png")) text[k] = v;
    CHECK(text.at("bristle:batch-key") == lines[id]["input_hash"].get<std::string>());
    CHECK(text.count("bristle:canvas") == 1);
    if (lines[id]["warnings"].empty())
      CHECK(text.count("bristle:batch-warnings") == 0);
    else
      CHECK(json::parse(text.at("bristle:batch-warnings")) == lines[id]["warnings"]);
  }
  // The job log holds the same entries.
  const std::string log = lines["summary"]["log"].get<std::string>();
  CHECK_THAT(readAll(log), Contains("the brush never touched the canvas"));

  // ... --fail-on-warning does, also when the job is skipped as up to date: its
  // warnings were kept in its PNG.
  const RunResult again = runBristle("batch '" + jobs + "' --out '" + out + "' --fail-on-warning");
  CHECK(again.code == 1);
  CHECK_THAT(again.err, Contains("job 'above': warning: the brush never touched the canvas"));
  CHECK_THAT(again.err, Contains("0 rendered, 2 up to date, 0 failed, 1 with warnings"));
  CHECK_THAT(again.err, Contains("bristle: batch: 1 job has warnings (--fail-on-warning)"));
  m["jobs"].erase(1);
  writeManifest(d, m);
  CHECK(runBristle("batch '" + jobs + "' --out '" + out + "' --fail-on-warning -q").code == 0);
}

TEST_CASE("batch --dry-run ends with a summary line, also when all is up to date",
          "[cli][batch]") {
  TempDir d;
  json m = manifest(d, 2);
  m["jobs"][1]["brush"] = kRound;  // the flat's dab stays above the paper: a warning
  const std::string jobs = writeManifest(d, m);
  const std::string out = d.file("out");
  const RunResult before = runBristle("batch '" + jobs + "' --out '" + out + "' --dry-run");
  CHECK(before.code == 0);
  CHECK_THAT(before.out, Contains("dab0  ->  ") && Contains("(would render)"));
  CHECK_THAT(before.out,
             Contains("batch: 2 jobs (shard 0/1): 2 would render, 0 up to date, 0 failed (dry run)\n"));
  REQUIRE(runBristle("batch '" + jobs + "' --out '" + out + "' -q").code == 0);
  const RunResult after = runBristle("batch '" + jobs + "' --out '" + out + "' --dry-run");
  CHECK(after.code == 0);
  CHECK(after.out == "batch: 2 jobs (shard 0/1): 0 would render, 2 up to date, 0 failed (dry run)\n");
  CHECK(runBristle("batch '" + jobs + "' --out '" + out + "' --dry-run -q").out.empty());
}

TEST_CASE("batch: a preview job is the preview command's picture, keyed by its brush and trajectory",
          "[cli][batch][preview]") {
  TempDir dir;
  dir.write("dab.csv", dab(2));
  const json m = {{"format", "bristle-batch/1"},
                  {"jobs",
                   {{{"id", "rest"}, {"preview", "round"}, {"options", {{"width", 200}, {"height", 150}}}},
                    {{"id", "bent"},
                     {"preview", kRound},
                     {"trajectory", "dab.csv"},
                     {"options", {{"at", 0.25}, {"width", 200}, {"height", 150}}}}}}};
  const std::string path = writeManifest(dir, m);
  const std::string out = dir.file("out");
  RunResult r = runBristle("batch '" + path + "' --out '" + out + "' --json --jobs 2");
  REQUIRE(r.code == 0);
  auto lines = jsonLines(r.out);
  CHECK(lines.at("rest")["kind"] == "preview");
  CHECK(lines.at("bent")["status"] == "rendered");
  CHECK(lines.at("bent")["warnings"] == json::array());
  CHECK_FALSE(lines.at("bent").contains("figures"));  // `preview` reports none
  REQUIRE(runBristle("preview round --width 200 --height 150 -q -o '" + dir.file("rest.png") + "'")
              .code == 0);
  REQUIRE(runBristle("preview '" + kRound + "' --trajectory '" + dir.file("dab.csv") +
                     "' --at 0.25 --width 200 --height 150 -q -o '" + dir.file("bent.png") + "'")
              .code == 0);
  CHECK(pixelHash(out + "/rest.png") == pixelHash(dir.file("rest.png")));
  CHECK(pixelHash(out + "/bent.png") == pixelHash(dir.file("bent.png")));
  CHECK(pixelHash(out + "/rest.png") != pixelHash(out + "/bent.png"));

  r = runBristle("batch '" + path + "' --out '" + out + "' --json");
  CHECK(jsonLines(r.out).at("summary")["skipped"] == 2);
  // The trajectory changes: only the deformed preview renders again.
  dir.write("dab.csv", dab(5));
  r = runBristle("batch '" + path + "' --out '" + out + "' --json");
  lines = jsonLines(r.out);
  CHECK(lines.at("rest")["status"] == "skipped");
  CHECK(lines.at("bent")["status"] == "rendered");
}

// scripts/demo renders through scenes/batch/demo.json so that a second run
// renders nothing. The whole manifest takes minutes, so: every job of it must
// resolve (a dry run), and one job of each shape it holds (kind, trajectory or
// not, option names), with quick inputs in place of the long ones, must render
// once and then be skipped, its file untouched.
TEST_CASE("batch: the demo's manifest resolves, and a second run renders nothing",
          "[cli][batch][demo]") {
  TempDir dir;
  const std::string demo = sourcePath("scenes/batch/demo.json");
  RunResult r = runBristle("batch '" + demo + "' --out '" + dir.file("dry") + "' --dry-run --json");
  REQUIRE(r.code == 0);
  const json full = json::parse(readAll(demo));
  CHECK(jsonLines(r.out).at("summary")["jobs"] == full["jobs"].size());
  CHECK(jsonLines(r.out).at("summary")["failed"] == 0);

  // The quick variant: one job per shape, its paths made absolute, a dab for
  // each trajectory and a 1 x 1 sheet for each sheet.
  dir.write("dab.csv", dab(2));
  const json sheet = {{"format", "bristle-sheet/1"}, {"name", "quick"}, {"brushes", {kRound}},
                      {"trajectories", {"dab.csv"}}, {"px_per_mm", 4}, {"solver", "ipopt"}};
  dir.write("quick-sheet.json", sheet.dump());
  std::set<std::string> shapes;
  json jobs = json::array();
  for (json job : full["jobs"]) {
    std::string shape;
    for (const auto& [key, value] : job.items()) shape += key == "id" ? "" : key + ",";
    const json options = job.value("options", json::object());
    for (const auto& [key, value] : options.items()) shape += key + ",";
    if (!shapes.insert(shape).second) continue;
    for (const char* key : {"brush", "preview"})
      if (job.contains(key))
        job[key] = sourcePath("scenes/batch/" + job[key].get<std::string>());
    if (job.contains("trajectory")) job["trajectory"] = dir.file("dab.csv");
    if (job.contains("sheet")) job["sheet"] = dir.file("quick-sheet.json");
    if (job.contains("options") && job["options"].contains("at")) job["options"]["at"] = 0.25;
    jobs.push_back(job);
  }
  // A sheet, strokes (in press depths, none lifted), a preview at rest and one
  // along a trajectory.
  REQUIRE(jobs.size() == 4);
  const std::string path = writeManifest(dir, {{"format", "bristle-batch/1"}, {"jobs", jobs}});
  const std::string out = dir.file("out");
  r = runBristle("batch '" + path + "' --out '" + out + "' --json --jobs 2");
  REQUIRE(r.code == 0);
  CHECK(jsonLines(r.out).at("summary")["rendered"] == jobs.size());
  std::map<std::string, std::pair<std::string, fs::file_time_type>> first;
  for (const std::string& png : pngsIn(out))
    first[png] = {readAll(out + "/" + png), fs::last_write_time(out + "/" + png)};
  REQUIRE(first.size() == jobs.size());
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // mtime granularity

  r = runBristle("batch '" + path + "' --out '" + out + "' --json --jobs 2");
  REQUIRE(r.code == 0);
  const auto lines = jsonLines(r.out);
  CHECK(lines.at("summary")["rendered"] == 0);
  CHECK(lines.at("summary")["skipped"] == jobs.size());
  for (const json& job : jobs) CHECK(lines.at(job["id"].get<std::string>())["status"] == "skipped");
  CHECK(pngsIn(out).size() == first.size());
  for (const auto& [png, before] : first) {
    INFO(png);
    CHECK(readAll(out + "/" + png) == before.first);
    CHECK(fs::last_write_time(out + "/" + png) == before.second);
  }
}

TEST_CASE("render --batch-key: the PNG carries the key, and the pixels and --help are unchanged",
          "[cli][batch]") {
  TempDir d;
  const std::string traj = d.write("dab.csv", dab(2));
  const std::string options = " --px-per-mm 4 --solver ipopt -q -o '";
  REQUIRE(runBristle("render --brush round --trajectory '" + traj + "'" + options +
                     d.file("k.png") + "' --batch-key 0123456789abcdef")
              .code == 0);
  REQUIRE(runBristle("render --brush round --trajectory '" + traj + "'" + options +
                     d.file("plain.png") + "'")
              .code == 0);
  bool keyed = false, plain_keyed = false;
  for (const auto& [k, v] : render::readPngText(d.file("k.png")))
    keyed = keyed || (k == "bristle:batch-key" && v == "0123456789abcdef");
  for (const auto& [k, v] : render::readPngText(d.file("plain.png")))
    plain_keyed = plain_keyed || k == "bristle:batch-key";
  CHECK(keyed);
  CHECK_FALSE(plain_keyed);
  // The same pixels either way, as bristle compare reads them.
  CHECK(runBristle("compare '" + d.file("plain.png") + "' '" + d.file("k.png") + "'").code == 0);
  // It is the batch's option, not one shown to people.
  for (const std::string command : {"render", "sheet", "preview"})
    CHECK(runBristle(command + " --help").out.find("batch-key") == std::string::npos);
}

TEST_CASE("batch: a scene job renders, with and without the scene options a job may give",
          "[cli][batch][scene]") {
  // A one-stroke scene over a dab: the batch passes each scene job its key
  // (--batch-key), which must count as one of the options a scene allows.
  TempDir dir;
  dir.write("dab.csv", dab(2));
  const json scene = {{"format", "bristle-scene/1"},
                      {"name", "one dab"},
                      {"canvas", {{"size_mm", {40, 40}}, {"px_per_mm", 4}}},
                      {"solver", "ipopt"},
                      {"strokes",
                       {{{"brush", kRound},
                         {"trajectory", "dab.csv"},
                         {"paint", {{"paints", {"#1c2433"}}}}}}}};
  dir.write("scene.json", scene.dump());
  const json m = {{"format", "bristle-batch/1"},
                  {"jobs",
                   {{{"id", "flat"}, {"scene", "scene.json"}},
                    {{"id", "lit"}, {"scene", "scene.json"}, {"options", {{"impasto", true}}}}}}};
  const std::string out = dir.file("out");
  const RunResult r = runBristle("batch '" + writeManifest(dir, m) + "' --out '" + out + "' --json");
  INFO(r.err);
  CHECK(r.code == 0);
  CHECK(jsonLines(r.out).at("summary")["rendered"] == 2);
  CHECK(pngsIn(out) == std::vector<std::string>{"flat.png", "lit.png"});
  // A scene option that the scene sets is still refused, by its name.
  const json bad = {{"format", "bristle-batch/1"},
                    {"jobs", {{{"id", "fine"}, {"scene", "scene.json"}, {"options", {{"px-per-mm", 2}}}}}}};
  const RunResult refused =
      runBristle("batch '" + dir.write("bad.json", bad.dump()) + "' --out '" + out + "'");
  CHECK(refused.code == 64);
  CHECK_THAT(refused.err, Contains(": --px-per-mm cannot be used with a scene (the scene sets it)"));
}

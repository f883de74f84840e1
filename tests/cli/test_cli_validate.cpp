// `bristle validate` tells each file's kind by its "format" (a trajectory by
// its first line or .csv) and checks it with every file it names: the shipped
// files of every kind pass, and a broken batch or golden manifest fails with
// one line naming the manifest, the field and the rule.

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_runner.h"

using namespace bristle::testing;
using Catch::Matchers::Contains;
using nlohmann::json;
namespace fs = std::filesystem;

namespace {

// (Built with append: GCC 12's -Wrestrict warns, wrongly, on a chain of '+'.)
std::string shellQuoted(const std::string& path) {
  return std::string(1, '\'').append(path).append("'");
}

json readJson(const std::string& path) { return json::parse(std::ifstream(path)); }

// "1 stroke", "2 strokes".
std::string counted(size_t n, const std::string& noun) {
  return std::to_string(n) + " " + noun + (n == 1 ? "" : "s");
}

// validate's line for a shipped batch manifest, its jobs counted from the file.
std::string batchLine(const std::string& path) {
  const json m = readJson(path);
  std::map<std::string, size_t> kinds;  // validate lists them in this order
  for (const json& job : m.at("jobs")) {
    const std::string kind = job.contains("scene")     ? "0scene"
                             : job.contains("sheet")   ? "1sheet"
                             : job.contains("preview") ? "3preview"
                                                       : "2stroke";
    ++kinds[kind];
  }
  std::string what;
  for (const auto& [kind, n] : kinds) what += (what.empty() ? "" : ", ") + counted(n, kind.substr(1));
  return path + ": ok (batch manifest, " + counted(m.at("jobs").size(), "job") + ": " + what +
         ")\n";
}

}  // namespace

TEST_CASE("validate tells each shipped file's kind by its format and checks it", "[cli][validate]") {
  std::vector<std::string> batches;
  for (const char* name : {"demo", "paintings", "standard"})
    batches.push_back(sourcePath("scenes/batch/" + std::string(name) + ".json"));
  const std::string golden = sourcePath("golden/golden.json");
  std::string args;
  for (const std::string& b : batches) args.append(" ").append(shellQuoted(b));
  const RunResult manifests = runBristle("validate" + args + " " + shellQuoted(golden));
  INFO(manifests.err);
  CHECK(manifests.code == 0);
  CHECK(manifests.err.empty());
  size_t goldens = 0, scenes = 0;
  const json golden_doc = readJson(golden);
  for (const json& g : golden_doc.at("goldens")) {
    ++goldens;
    scenes += g.contains("scene") ? 1 : 0;
  }
  CHECK(manifests.out == batchLine(batches[0]) + batchLine(batches[1]) + batchLine(batches[2]) +
                             golden + ": ok (golden manifest, " + counted(goldens, "golden") +
                             ": " + counted(goldens - scenes, "stroke") + ", " +
                             counted(scenes, "scene") + ")\n");

  // One line per file, each of its own kind.
  const std::vector<std::pair<std::string, std::string>> files = {
      {"scenes/paintings/petals.json", "scene 'One-Stroke wreath'"},
      {"scenes/paintings/calligraphy.json", "scene "},
      {"scenes/paintings/landscape.json", "scene "},
      {"scenes/sheets/library.json", "sheet 'library'"},
      {"scenes/sheets/small.json", "sheet 'small'"},
      {"scenes/brushes/round.json", "brush 'round'"},
      {"scenes/brushes/fan.json", "brush 'fan'"},
      {"scenes/trajectories/s-curve.csv", "trajectory, 321 samples"}};
  args.clear();
  for (const auto& [file, kind] : files) args.append(" ").append(shellQuoted(sourcePath(file)));
  const RunResult each = runBristle("validate" + args);
  INFO(each.err);
  CHECK(each.code == 0);
  CHECK(each.err.empty());
  for (const auto& [file, kind] : files) CHECK_THAT(each.out, Contains(sourcePath(file) + ": ok (" + kind));
}

TEST_CASE("validate: a broken batch manifest gives one line naming the job's field",
          "[cli][validate]") {
  TempDir d;
  const std::string round = sourcePath("scenes/brushes/round.json");
  const std::string traj = sourcePath("scenes/trajectories/s-curve.csv");
  auto manifestOf = [&](const std::string& name, const json& job) {
    json jobs = json::array();
    jobs.push_back(job);
    return d.write(name, json{{"format", "bristle-batch/1"}, {"jobs", jobs}}.dump());
  };
  auto stroke = [&](const std::string& brush, const json& options) {
    json job = {{"id", "j"}, {"brush", brush}, {"trajectory", traj}};
    if (!options.is_null()) job["options"] = options;
    return job;
  };
  {
    const std::string m = manifestOf("missing.json", stroke("gone.json", nullptr));
    const RunResult r = runBristle("validate " + shellQuoted(m));
    CHECK(r.code == 66);
    CHECK(r.err == "bristle: " + m + ": /jobs/0/brush: " + d.file("gone.json") +
                       ": cannot read: No such file or directory\n");
    CHECK(r.out.empty());
  }
  {
    // An option the manifest knows that the job's command does not take.
    const std::string m = manifestOf("at.json", stroke(round, {{"at", 1.2}}));
    const RunResult r = runBristle("validate " + shellQuoted(m));
    CHECK(r.code == 65);
    CHECK(r.err == "bristle: " + m + ": /jobs/0/options/at: bristle render refuses it: The "
                   "following argument was not expected: --at\n");
  }
  {
    // An option no command has: the manifest's reader refuses it, as batch does.
    const std::string m = manifestOf("bogus.json", stroke(round, {{"bogus", 1}}));
    const RunResult r = runBristle("validate " + shellQuoted(m));
    const RunResult dry = runBristle("batch " + shellQuoted(m) + " --out " + shellQuoted(d.file("out")) +
                                     " --dry-run");
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("bristle: " + m + ": /jobs/0/options/bogus: unknown option "
                               "'bogus' (known: amount, at, "));
    CHECK(r.err == dry.err);
  }
  {
    // A default the job's command refuses is named where the manifest sets it;
    // every broken job is a line, the first one's code the exit code.
    const json m_doc = {{"format", "bristle-batch/1"},
                        {"defaults", {{"options", {{"paint", "cadmium-rd"}}}}},
                        {"jobs", json::array({stroke(round, nullptr), {{"id", "p"}, {"preview", round}}})}};
    const std::string m = d.write("defaults.json", m_doc.dump());
    const RunResult r = runBristle("validate " + shellQuoted(m));
    CHECK(r.code == 65);
    CHECK_THAT(r.err, Contains("bristle: " + m + ": /defaults/options/paint: bristle render "
                               "refuses it: --paint cadmium-rd: unknown pigment 'cadmium-rd'"));
    CHECK_THAT(r.err, Contains("bristle: " + m + ": /defaults/options/paint: bristle preview "
                               "refuses it: The following arguments were not expected: "
                               "cadmium-rd --paint\n"));
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 2);
  }
}

TEST_CASE("validate: a broken golden manifest gives one line naming the golden's field",
          "[cli][validate]") {
  TempDir d;
  const json round_pull = {{"name", "round-pull"},
                           {"brush", sourcePath("scenes/brushes/round.json")},
                           {"trajectory", sourcePath("scenes/trajectories/straight-pull.csv")},
                           {"options", {"--solver", "slsqp"}},
                           {"tolerance", "strict"}};
  auto goldenOf = [&](const json& golden) {
    return d.write("golden.json",
                   json{{"format", "bristle-golden/1"}, {"goldens", json::array({golden})}}.dump());
  };
  // No image yet.
  std::string m = goldenOf(round_pull);
  RunResult r = runBristle("validate " + shellQuoted(m));
  CHECK(r.code == 66);
  CHECK(r.err == "bristle: " + m + ": /goldens/0: " + d.file("round-pull.png") +
                     ": cannot read: No such file or directory\n");
  // Its image, then options render does not take.
  fs::copy_file(sourcePath("golden/round-straight-pull.png"), d.file("round-pull.png"));
  CHECK(runBristle("validate " + shellQuoted(m)).code == 0);
  json bad = round_pull;
  bad["options"] = {"--solver", "newton"};
  m = goldenOf(bad);
  r = runBristle("validate " + shellQuoted(m));
  CHECK(r.code == 65);
  CHECK(r.err == "bristle: " + m + ": /goldens/0/options: bristle render refuses it: --solver: "
                 "newton not in {ipopt,slsqp}\n");
  // The manifest's own rules, as scripts/golden.py holds it to them.
  bad = round_pull;
  bad["tolerance"] = "close";
  m = goldenOf(bad);
  r = runBristle("validate " + shellQuoted(m));
  CHECK(r.code == 65);
  CHECK(r.err == "bristle: " + m + ": /goldens/0/tolerance = \"close\": must be exact, strict or "
                 "loose\n");
  // A misspelt key is named with the key it most likely meant.
  for (const auto& [key, meant] : {std::pair{"tolerence", "tolerance"}, {"trajectry", "trajectory"}}) {
    bad = round_pull;
    bad[key] = bad[meant];
    bad.erase(meant);
    m = goldenOf(bad);
    r = runBristle("validate " + shellQuoted(m));
    CHECK(r.code == 65);
    CHECK(r.err == "bristle: " + m + ": /goldens/0/" + key + ": unknown key '" + key +
                       "'; did you mean /goldens/0/" + meant + "?\n");
  }
}

// The brush reader (`bristle-brush/1` JSON, engine/formats/brush_reader.h):
// good files read with their values, and every bad input refused with the
// sysexits code of docs/design.md ("Exit codes") and a one-line message that
// names the file, the JSON pointer and the broken rule.

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "engine/formats/brush_reader.h"
#include "engine/formats/trajectory_reader.h"
#include "engine/model/brush.h"
#include "engine/base/error.h"
#include "engine/base/json_reader.h"
#include "engine/base/spelling.h"
#include "engine/base/text_file.h"
#include "engine/model/trajectory.h"
#include "temp_dir.h"
#include "tests/engine/formats/reader_checks.h"
#include "tests/support/build_paths.h"

using namespace bristle;
using bristle::testing::Caught;
using bristle::testing::catchError;
using bristle::testing::kBrush;
using bristle::testing::kSourceDir;
using bristle::testing::kTraj;
using bristle::testing::TempDir;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

namespace {

namespace fs = std::filesystem;

// kBrush with the value at a JSON pointer replaced (or added).
std::string brushWith(const std::string& pointer, const nlohmann::json& value) {
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  doc[nlohmann::json::json_pointer(pointer)] = value;
  return doc.dump(2);
}

// kBrush with raw JSON text (e.g. a number literal nlohmann cannot hold) at a pointer.
std::string brushWithRaw(const std::string& pointer, const std::string& raw) {
  std::string text = brushWith(pointer, "@RAW@");
  const size_t at = text.find("\"@RAW@\"");
  return text.replace(at, 7, raw);
}

// kBrush without the key at a JSON pointer.
std::string brushWithout(const std::string& pointer) {
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  const nlohmann::json::json_pointer p(pointer);
  doc[p.parent_pointer()].erase(p.back());
  return doc.dump(2);
}

// Spine 0 of kBrush resized to n joints, all arrays consistent.
std::string brushWithJoints(size_t n) {
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  nlohmann::json& s = doc["spines"][0];
  s["segment_lengths_mm"] = std::vector<double>(n, 1.0);
  s["stiffness_nmm_per_rad"] = std::vector<double>(n, 5.0);
  s["damping_nmm"] = std::vector<double>(n, 0.0);
  s["rest_angles_rad"] = std::vector<std::vector<double>>(n, {0.0, 0.0});
  s["width_mm"] = std::vector<double>(n + 1, 1.0);
  return doc.dump();
}

std::string brushWithSpines(size_t n) {
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  doc["spines"] = std::vector<nlohmann::json>(n, doc["spines"][1]);
  return doc.dump();
}

}  // namespace

// ---------------------------------------------------------------- brush: good input

TEST_CASE("round.json parses with the values in the file", "[readers]") {
  const Brush b = loadBrush((kSourceDir / "scenes/brushes/round.json").string());
  CHECK(b.name == "round");
  CHECK_THAT(b.description, StartsWith("Round, size 8"));
  REQUIRE(b.spines.size() == 7);
  for (const SpineSpec& s : b.spines) {
    REQUIRE(s.jointCount() == 4);
    // The centre spine (the first) ends 1 mm inside the outer spines' point.
    const bool centre = &s == &b.spines.front();
    CHECK(s.segment_lengths_mm == std::vector<double>{6.0, 5.5, 5.0, centre ? 2.5 : 3.5});
    CHECK(s.stiffness_nmm_per_rad == std::vector<double>{30.0, 12.0, 3.0, 0.8});
    CHECK(s.damping_nmm == std::vector<double>{0.008, 0.006, 0.005, 0.004});
    CHECK(s.rest_angles_rad.size() == 4);
    CHECK(s.width_mm.size() == 5);
    CHECK(s.lengthMm() == Approx(centre ? 19.0 : 20.0));
  }
  CHECK(b.spines[0].root_mm == Eigen::Vector3d(0, 0, 0));
  CHECK(b.spines[0].rest_angles_rad[0] == Eigen::Vector2d(0.03, 0.0));
  CHECK(b.spines[0].width_mm == std::vector<double>{3.2, 3.6, 3.2, 2.4, 0.8});
  CHECK(b.spines[1].root_mm == Eigen::Vector3d(1.4722, 0.85, 0));
  CHECK(b.spines[1].rest_angles_rad[2] == Eigen::Vector2d(-0.1, 0.1732));
  CHECK(b.spines[3].root_mm == Eigen::Vector3d(-1.4722, 0.85, 0));
  CHECK(b.spines[6].rest_angles_rad[3] == Eigen::Vector2d(0.06, 0.1039));
  CHECK(b.spines[6].width_mm == std::vector<double>{2.4, 2.8, 2.5, 1.8, 0.5});
  CHECK(b.friction.mu_static == 0.45);
  CHECK(b.friction.mu_kinetic == 0.35);
  CHECK(b.friction.anisotropy_strength == 0.3);
  CHECK(b.friction.anisotropy_exponent == 2.0);
  // The cage: 5 rings of 10 around the spines plus the tip, skinned to them.
  REQUIRE(b.surface.present());
  CHECK(b.surface.cage_mm.size() == 51);
  CHECK(b.surface.faces.size() == 50);
  CHECK(b.surface.skin.size() == 51);
  CHECK(b.surface.refinement_level == 2);
  CHECK_FALSE(b.strips.present());
  CHECK(b.paint_capacity == 1.0);
  CHECK(b.reachMm() == Approx(21.7).margin(1e-3));  // spine 2: |root| = 1.7 mm
}

TEST_CASE("a brush with every optional block parses, and omitted fields take defaults",
          "[readers]") {
  const Brush b = parseBrush(kBrush, "brush.json");
  CHECK(b.path == "brush.json");
  CHECK(b.description == "two spines");
  REQUIRE(b.spines.size() == 2);
  CHECK(b.spines[0].damping_nmm == std::vector<double>{0.01, 0.02});
  CHECK(b.spines[0].rest_angles_rad[1] == Eigen::Vector2d(0.1, -0.1));
  CHECK(b.spines[1].root_mm == Eigen::Vector3d(1, 0, -0.5));
  CHECK(b.spines[1].damping_nmm == std::vector<double>{0, 0});
  CHECK(b.spines[1].rest_angles_rad[1] == Eigen::Vector2d::Zero());
  CHECK(b.spines[1].width_mm == std::vector<double>{2, 1.5, 0});  // tip width 0 is fine
  CHECK(b.friction.mu_static == 0.5);
  CHECK(b.friction.mu_kinetic == 0.4);
  CHECK(b.friction.anisotropy_strength == 0.3);
  CHECK(b.friction.anisotropy_exponent == 3.0);
  CHECK(b.paint_capacity == 1.5);

  const Brush minimal = parseBrush(
      R"({"format": "bristle-brush/1", "name": "m", "spines": [{"root_mm": [0, 0, 0],
          "segment_lengths_mm": [3], "stiffness_nmm_per_rad": [1], "width_mm": [1, 1]}]})",
      "m.json");
  CHECK(minimal.description.empty());
  CHECK(minimal.friction.mu_static == FrictionSpec{}.mu_static);
  CHECK(minimal.friction.mu_kinetic == FrictionSpec{}.mu_kinetic);
  CHECK(minimal.paint_capacity == 1.0);

  // mu_kinetic defaults to mu_static; the anisotropy exponent to 2.
  const Brush f = parseBrush(brushWith("/friction", {{"mu_static", 0.7},
                                                     {"anisotropy", {{"strength", 1}}}}),
                             "brush.json");
  CHECK(f.friction.mu_kinetic == 0.7);
  CHECK(f.friction.anisotropy_strength == 1.0);
  CHECK(f.friction.anisotropy_exponent == 2.0);
}

TEST_CASE("brush limits are inclusive: 64 spines and 16 joints parse", "[readers]") {
  CHECK(parseBrush(brushWithSpines(kMaxSpines), "brush.json").spines.size() == 64);
  CHECK(parseBrush(brushWithJoints(kMaxJointsPerSpine), "brush.json").spines[0].jointCount() ==
        16);
  CHECK(parseBrush(brushWithJoints(1), "brush.json").spines[0].jointCount() == 1);
}

// ---------------------------------------------------------------- files

TEST_CASE("a missing file or a directory is 66 naming the path", "[readers]") {
  const TempDir dir;
  const std::string missing_brush = dir.file("no-such-brush.json");
  const std::string missing_traj = dir.file("no-such.csv");
  CHECK_READER_ERROR(loadBrush(missing_brush), ExitCode::kNoInput, missing_brush,
                     "No such file");
  CHECK_READER_ERROR(loadTrajectory(missing_traj), ExitCode::kNoInput, missing_traj,
                     "No such file");
  CHECK_READER_ERROR(loadBrush(dir.path().string()), ExitCode::kNoInput, dir.path().string(),
                     "directory");
  CHECK_READER_ERROR(loadTrajectory(dir.path().string()), ExitCode::kNoInput, dir.path().string(),
                     "directory");
  const std::string in_missing_dir = dir.file("nodir/brush.json");
  CHECK_READER_ERROR(loadBrush(in_missing_dir), ExitCode::kNoInput, in_missing_dir);
}

TEST_CASE("files on disk: good ones load, bad data is 65 naming the path", "[readers]") {
  const TempDir dir;
  const std::string brush = dir.write("b.json", kBrush);
  CHECK(loadBrush(brush).path == brush);
  const std::string t = dir.write("t.csv", kTraj);
  CHECK(loadTrajectory(t).path == t);

  const std::string empty = dir.write("empty.json", "");
  CHECK_READER_ERROR(loadBrush(empty), ExitCode::kDataError, empty, "line 1, column 1",
                     "malformed JSON");
  const std::string empty_csv = dir.write("empty.csv", "");
  CHECK_READER_ERROR(loadTrajectory(empty_csv), ExitCode::kDataError, empty_csv, "line 1");
}

// ---------------------------------------------------------------- brush: JSON syntax

TEST_CASE("malformed JSON is 65 with the line and column of the error", "[readers]") {
  // Columns are 1-based and count bytes; each points at the character where
  // the parser noticed the error.
  SECTION("trailing comma in an array") {
    CHECK_BRUSH_ERROR("{\n"
                      "  \"format\": \"bristle-brush/1\",\n"
                      "  \"spines\": [1, 2,]\n"
                      "}",
                      "brush.json: line 3, column 19: malformed JSON");
  }
  SECTION("trailing comma in an object") {
    CHECK_BRUSH_ERROR("{\n  \"a\": 1,\n}", "line 3, column 1", "malformed JSON");
  }
  SECTION("invalid literal") {
    CHECK_BRUSH_ERROR("{\n"
                      "  \"format\": \"bristle-brush/1\",\n"
                      "  \"name\": tru,\n"
                      "  \"spines\": []\n"
                      "}",
                      "line 3, column 14", "invalid literal");
  }
  SECTION("NaN and Infinity are not JSON") {
    CHECK_BRUSH_ERROR("{\n"
                      "  \"friction\": {\n"
                      "    \"mu_static\": NaN\n"
                      "  }\n"
                      "}",
                      "line 3, column 18", "malformed JSON");
    CHECK_BRUSH_ERROR("{\n"
                      "  \"friction\": {\n"
                      "    \"mu_static\": -Infinity\n"
                      "  }\n"
                      "}",
                      "line 3, column 19", "malformed JSON");
  }
  SECTION("raw newline inside a string") {
    CHECK_BRUSH_ERROR("{\n  \"name\": \"ab\ncd\"\n}", "line 2, column 14", "control character");
  }
  SECTION("missing comma between members is reported on the line of the next member") {
    CHECK_BRUSH_ERROR("{\n"
                      "  \"format\": \"bristle-brush/1\"\n"
                      "  \"name\": \"x\"\n"
                      "}",
                      "brush.json: line 3, column ", "malformed JSON");
  }
  SECTION("unexpected end of input points just past the end") {
    CHECK_BRUSH_ERROR("{\n  \"spines\": [1, 2\n", "line 3, column 1", "end of input");
    CHECK_BRUSH_ERROR("{\"a\": 1", "line 1, column 8", "end of input");
  }
  SECTION("text after the document") {
    CHECK_BRUSH_ERROR("{}\n]", "line 2, column 1", "malformed JSON");
  }
  SECTION("empty text") { CHECK_BRUSH_ERROR("", "line 1, column 1", "malformed JSON"); }
  SECTION("a document that is not an object") {
    CHECK_BRUSH_ERROR("[1, 2]", "brush.json: /: must be a JSON object");
    CHECK_BRUSH_ERROR("\"bristle-brush/1\"", "brush.json: /: must be a JSON object");
  }
}

TEST_CASE("a key twice in one object is 65 naming it by its JSON pointer", "[readers]") {
  const auto refused = [](const std::string& text) {
    return catchError([&] { parseJsonText(text, "d.json"); });
  };
  const std::string rule = ": the object already holds it (one of the two would be lost)";
  Caught c = refused(R"({"a": 1, "a": 1})");
  CHECK(c.code == 65);
  CHECK(c.message == "d.json: /a: duplicate key \"a\"" + rule);
  // The pointer counts array elements, scalars and containers alike.
  c = refused(R"({"x": [1, {"y": 2}, [3], {"z": {"k": 1, "k": 2}}]})");
  CHECK(c.message == "d.json: /x/3/z/k: duplicate key \"k\"" + rule);
  // Keys are escaped in the pointer (~0, ~1) and in the message's quotes.
  c = refused(R"({"a/b": {"t~": 1, "t~": 1}})");
  CHECK(c.message == "d.json: /a~1b/t~0: duplicate key \"t~\"" + rule);
  c = refused("{\"n\\u0007\": 1, \"n\\u0007\": 1}");
  CHECK(c.message == "d.json: /n\\u0007: duplicate key \"n\\u0007\"" + rule);
  // The same key in sibling or nested objects is no duplicate.
  CHECK_FALSE(refused(R"({"a": {"a": 1}, "b": [{"a": 1}, {"a": 2}], "c": {"a": {"a": 0}}})").thrown);
  CHECK_FALSE(refused("[1, 2, {\"a\": 1}]").thrown);
  // A brush file through its reader.
  c = catchError([] {
    parseBrush(R"({"format": "bristle-brush/1", "name": "a", "name": "b"})", "b.json");
  });
  CHECK(c.message == "b.json: /name: duplicate key \"name\"" + rule);
  CHECK(parseJsonOrDiscarded(R"({"a": 1, "a": 2})").is_discarded());
}

TEST_CASE("messages: one escaping rule for C0, DEL, C1 and bytes that are not UTF-8",
          "[readers]") {
  CHECK(oneLine("plain, caf\xc3\xa9, \xe2\x80\xa6 \xf0\x9f\x96\x8c") ==
        "plain, caf\xc3\xa9, \xe2\x80\xa6 \xf0\x9f\x96\x8c");
  CHECK(oneLine(std::string("a\0b\nc\x1b[2J\x7f", 10)) == "a\\u0000b\\u000ac\\u001b[2J\\u007f");
  CHECK(oneLine("csi \xc2\x9b" "2J, nel \xc2\x85, nbsp \xc2\xa0") ==
        "csi \\u009b2J, nel \\u0085, nbsp \xc2\xa0");
  // Not UTF-8: a lone continuation byte, a lead byte without its tail, an
  // overlong form, a surrogate, past U+10FFFF, a raw C1 byte.
  CHECK(oneLine("\x80") == "\\x80");
  CHECK(oneLine("\xc3(") == "\\xc3(");
  CHECK(oneLine("\xc0\xaf") == "\\xc0\\xaf");
  CHECK(oneLine("\xed\xa0\x80") == "\\xed\\xa0\\x80");
  CHECK(oneLine("\xf4\x90\x80\x80") == "\\xf4\\x90\\x80\\x80");
  CHECK(oneLine("\x9b") == "\\x9b");
  CHECK(oneLine("\xe2\x80") == "\\xe2\\x80");  // cut short at the end
  CHECK(hasControlCharacter("one\xc2\x9b"));
  CHECK(hasControlCharacter("one\x1b"));
  CHECK(hasControlCharacter("\xff"));
  CHECK_FALSE(hasControlCharacter("caf\xc3\xa9"));
  // Every Error is made one line by the same rule.
  CHECK(std::string(Error(ExitCode::kDataError, "x\xc2\x9by").what()) == "x\\u009by");
}

TEST_CASE("numbers beyond double range (1e999) are 65 with line and column", "[readers]") {
  // nlohmann refuses them with out_of_range 406 (not a parse_error); the reader
  // must still report 65 with a position, and not mistake a string for the number.
  const std::string head = "{\n"
                           "  \"format\": \"bristle-brush/1\",\n"
                           "  \"name\": \"1e999\",\n"
                           "  \"friction\": {\n";
  CHECK_BRUSH_ERROR(head + "    \"mu_static\": 1e999\n  }\n}", "line 5, column 18", "1e999",
                    "out of range");
  CHECK_BRUSH_ERROR(head + "    \"mu_static\": -1e999\n  }\n}", "line 5, column 18", "-1e999");
  CHECK_BRUSH_ERROR(head + "    \"mu_static\": 0.5, \"mu_kinetic\": 1E400\n  }\n}",
                    "line 5, column 37", "1E400");
  CHECK_BRUSH_ERROR("{\n"
                    "  \"spines\": [\n"
                    "    {\"segment_lengths_mm\": [5, 1e999]}\n"
                    "  ]\n"
                    "}",
                    "line 3, column 32");
  CHECK_BRUSH_ERROR(brushWithRaw("/spines/1/rest_angles_rad", "[[0, 0], [1e999, 0]]"),
                    "out of range");
  CHECK_BRUSH_ERROR(brushWithRaw("/paint/capacity", "1e309"), "1e309", "out of range");
  // Underflow is not an error: it reads as 0 (and 0 is then checked by the rules).
  CHECK_BRUSH_ERROR(brushWithRaw("/paint/capacity", "1e-999"), "/paint/capacity", "> 0");
  // The largest doubles are finite and fine where the rules allow them.
  CHECK(parseBrush(brushWithRaw("/paint/capacity", "1.7e308"), "brush.json").paint_capacity ==
        1.7e308);
}

// ---------------------------------------------------------------- brush: keys

TEST_CASE("format version: missing or unknown is 65 naming it", "[readers]") {
  CHECK_BRUSH_ERROR(brushWithout("/format"), "brush.json: /format: required key is missing");
  CHECK_BRUSH_ERROR(brushWith("/format", "bristle-brush/2"), "/format", "\"bristle-brush/2\"",
                    "unknown format version");
  CHECK_BRUSH_ERROR(brushWith("/format", "bristle-scene/1"), "/format", "bristle-scene/1",
                    "unknown format version");
  CHECK_BRUSH_ERROR(brushWith("/format", "bristle-brush/1 "), "/format",
                    "unknown format version");
  CHECK_BRUSH_ERROR(brushWith("/format", 1), "/format", "must be a string");
}

TEST_CASE("unknown keys anywhere in a brush are 65 naming pointer and key", "[readers]") {
  CHECK_BRUSH_ERROR(brushWith("/colour", "red"), "brush.json: /colour: unknown key 'colour'");
  CHECK_BRUSH_ERROR(brushWith("/spines/1/colour", 1), "/spines/1/colour", "unknown key 'colour'");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/stiffness", {1, 2}), "/spines/0/stiffness",
                    "unknown key 'stiffness'");
  CHECK_BRUSH_ERROR(brushWith("/friction/mu", 0.1), "/friction/mu", "unknown key 'mu'");
  CHECK_BRUSH_ERROR(brushWith("/friction/anisotropy/k", 2), "/friction/anisotropy/k",
                    "unknown key 'k'");
  CHECK_BRUSH_ERROR(brushWith("/paint/colour", "red"), "/paint/colour", "unknown key 'colour'");
  // Keys that need escaping: '/' becomes ~1 in the pointer, a newline must not
  // split the one-line message.
  CHECK_BRUSH_ERROR(brushWith("/a~1b", 1), "/a~1b", "unknown key 'a/b'");
  CHECK_BRUSH_ERROR(brushWith("/line\nbreak", 1), "/line\\u000abreak",
                    "unknown key 'line\\u000abreak'");
  // Keys are case-sensitive.
  CHECK_BRUSH_ERROR(brushWith("/Name", "x"), "/Name", "unknown key 'Name'");
}

TEST_CASE("a misspelt brush key is named with the key it most likely meant", "[readers]") {
  // An optional key misspelt is unknown; the message names the declared key
  // (spine 1 of kBrush gives no damping_nmm).
  CHECK_BRUSH_ERROR(brushWith("/spines/1/dampnig_nmm", {0.1, 0.1}),
                    "brush.json: /spines/1/dampnig_nmm: unknown key 'dampnig_nmm'; did you mean "
                    "/spines/1/damping_nmm?");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"tip_sprad", 0.5}}),
                    "brush.json: /volume/tip_sprad: unknown key 'tip_sprad'; did you mean "
                    "/volume/tip_spread?");
  // A required key misspelt is named where it is, not as the correct key missing.
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  doc["spnies"] = doc["spines"];
  doc.erase("spines");
  CHECK_BRUSH_ERROR(doc.dump(), "brush.json: /spnies: unknown key 'spnies'; did you mean /spines?");
  doc = nlohmann::json::parse(kBrush);
  doc["spines"][1]["segment_length_mm"] = doc["spines"][1]["segment_lengths_mm"];
  doc["spines"][1].erase("segment_lengths_mm");
  CHECK_BRUSH_ERROR(doc.dump(),
                    "brush.json: /spines/1/segment_length_mm: unknown key 'segment_length_mm'; "
                    "did you mean /spines/1/segment_lengths_mm?");
  // validate lists every problem: the misspelling once, not again as unknown.
  TempDir dir;
  const std::string path = dir.file("brush.json");
  std::ofstream(path) << doc.dump();
  const std::vector<std::string> problems = checkBrush(path);
  REQUIRE(problems.size() == 1);
  CHECK_THAT(problems[0], Contains("/spines/1/segment_length_mm: unknown key"));
  // No guess where nothing is close, nor for a short key two edits away, nor
  // at a key that is present itself ("Name" beside "name").
  CHECK_BRUSH_ERROR(brushWith("/colour", "red"), "brush.json: /colour: unknown key 'colour'");
  CHECK(catchError([] { parseBrush(brushWith("/colour", "red"), "brush.json"); })
            .message.find("did you mean") == std::string::npos);
  CHECK(catchError([] { parseBrush(brushWith("/Name", "x"), "brush.json"); })
            .message.find("did you mean") == std::string::npos);
  CHECK(catchError([] { parseBrush(brushWith("/friction/mu", 0.1), "brush.json"); })
            .message.find("did you mean") == std::string::npos);
  // A legitimate key beside a missing one it resembles is no misspelling:
  // max_separation is declared, so min_separation is reported missing.
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"max_separation", 2}}),
                    "brush.json: /volume/min_separation: required key is missing");
}

TEST_CASE("edit distance: insertions, deletions, replacements and swaps", "[readers]") {
  CHECK(editDistance("", "") == 0);
  CHECK(editDistance("spines", "spines") == 0);
  CHECK(editDistance("spine", "spines") == 1);
  CHECK(editDistance("spnies", "spines") == 1);  // a swap is one edit
  CHECK(editDistance("min_separation", "max_separation") == 2);
  CHECK(editDistance("", "abc") == 3);
  CHECK(editDistance("kitten", "sitting") == 3);
  // Close: at most 2 edits and a third of the candidate's length.
  CHECK(closestSpelling("segment_length_mm", {"root_mm", "segment_lengths_mm"}) ==
        "segment_lengths_mm");
  CHECK(closestSpelling("ix", {"id"}) == std::nullopt);
  CHECK(closestSpelling("nmae", {"name"}) == "name");
  CHECK(closestSpelling("width", {"width_mm"}) == std::nullopt);  // 3 edits
  CHECK(closestSpelling("name", {"name", "nme"}) == std::nullopt);  // it is a candidate
}

TEST_CASE("required brush keys are 65 naming the missing pointer", "[readers]") {
  for (const char* p : {"/name", "/spines", "/spines/0/root_mm", "/spines/1/segment_lengths_mm",
                        "/spines/0/stiffness_nmm_per_rad", "/spines/1/width_mm",
                        "/friction/mu_static", "/friction/anisotropy/strength"}) {
    INFO(p);
    CHECK_BRUSH_ERROR(brushWithout(p), std::string(p) + ": required key is missing");
  }
  // Optional ones may go.
  for (const char* p : {"/description", "/friction", "/paint", "/paint/capacity",
                        "/friction/mu_kinetic", "/friction/anisotropy",
                        "/friction/anisotropy/exponent", "/spines/0/damping_nmm",
                        "/spines/0/rest_angles_rad"}) {
    INFO(p);
    CHECK_NOTHROW(parseBrush(brushWithout(p), "brush.json"));
  }
}

TEST_CASE("wrong JSON types are 65 naming the pointer", "[readers]") {
  CHECK_BRUSH_ERROR(brushWith("/name", 7), "/name", "must be a string");
  CHECK_BRUSH_ERROR(brushWith("/name", ""), "/name", "must not be empty");
  CHECK_BRUSH_ERROR(brushWith("/description", nullptr), "/description", "must be a string");
  CHECK_BRUSH_ERROR(brushWith("/spines", nlohmann::json::object()), "/spines",
                    "must be an array of objects");
  CHECK_BRUSH_ERROR(brushWith("/spines/1", 3), "brush.json: /spines/1: must be a JSON object");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/segment_lengths_mm/1", "4"),
                    "/spines/0/segment_lengths_mm/1", "must be a number");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/stiffness_nmm_per_rad", 8),
                    "/spines/0/stiffness_nmm_per_rad", "must be an array of numbers");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/root_mm/2", nullptr), "/spines/0/root_mm/2",
                    "must be a number");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/rest_angles_rad/1/0", true),
                    "/spines/0/rest_angles_rad/1", "[theta, phi]");
  CHECK_BRUSH_ERROR(brushWith("/friction", 0.4), "/friction", "must be a JSON object");
  CHECK_BRUSH_ERROR(brushWith("/friction/anisotropy", nlohmann::json::array()),
                    "/friction/anisotropy", "must be a JSON object");
  CHECK_BRUSH_ERROR(brushWith("/friction/mu_static", "0.4"), "/friction/mu_static",
                    "must be a number");
  CHECK_BRUSH_ERROR(brushWith("/paint/capacity", true), "/paint/capacity", "must be a number");
  CHECK_BRUSH_ERROR(brushWith("/spines/1/bundle_bears_load", "yes"),
                    "brush.json: /spines/1/bundle_bears_load = \"yes\": must be true or false");
}

TEST_CASE("a bundle bears load only where its spine says so, not where it declares a flat load",
          "[readers]") {
  // flat_load_n says how easily a bundle splays; bundle_bears_load whether
  // its hair bears load in the solve (docs/brush-format.md): writing the
  // default flat load out must not change what the solve does.
  const Brush plain = parseBrush(brushWith("/spines/0/flat_load_n", 0.05), "brush.json");
  CHECK(plain.spines[0].flat_load_n == 0.05);
  CHECK_FALSE(plain.spines[0].bundle_bears_load);
  const Brush soft = parseBrush(brushWith("/spines/0/bundle_bears_load", true), "brush.json");
  CHECK(soft.spines[0].bundle_bears_load);
  CHECK_FALSE(soft.spines[1].bundle_bears_load);
  CHECK(soft.spines[0].flatLoadN() == kBundleFlatLoadN);
  const Brush badger = loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/badger.json");
  for (const SpineSpec& s : badger.spines) CHECK(s.bundle_bears_load);
}

// ---------------------------------------------------------------- brush: values

TEST_CASE("non-positive lengths and stiffness, negative damping are 65 naming the element",
          "[readers]") {
  CHECK_BRUSH_ERROR(brushWith("/spines/1/segment_lengths_mm/0", -3),
                    "brush.json: /spines/1/segment_lengths_mm/0 = -3", "must be > 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/segment_lengths_mm/1", 0),
                    "/spines/0/segment_lengths_mm/1 = 0", "must be > 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/stiffness_nmm_per_rad/1", 0),
                    "/spines/0/stiffness_nmm_per_rad/1", "must be > 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/1/stiffness_nmm_per_rad/0", -8),
                    "/spines/1/stiffness_nmm_per_rad/0", "must be > 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/damping_nmm/1", -0.01), "/spines/0/damping_nmm/1",
                    "must be >= 0");
  CHECK_NOTHROW(parseBrush(brushWith("/spines/0/damping_nmm/1", 0), "brush.json"));
  CHECK_BRUSH_ERROR(brushWith("/spines/0/width_mm/2", -0.5), "/spines/0/width_mm/2",
                    "must be >= 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/width_mm/0", 0), "/spines/0/width_mm",
                    "root width must be > 0");
  // A slab's thickness: one per point, >= 0, and 0 exactly where the width is.
  CHECK_NOTHROW(parseBrush(brushWith("/spines/1/thickness_mm", {1, 0.8, 0}), "brush.json"));
  CHECK(parseBrush(brushWith("/spines/1/thickness_mm", {1, 0.8, 0}), "brush.json")
            .spines[1]
            .thicknessMm(1) == 0.8);
  CHECK(parseBrush(kBrush, "brush.json").spines[1].thicknessMm(1) == 1.5);  // round: = width
  CHECK_BRUSH_ERROR(brushWith("/spines/1/thickness_mm", {1, 0.8}), "/spines/1/thickness_mm",
                    "must have 3 entries");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/thickness_mm", {1, -0.8, 0.2}),
                    "/spines/0/thickness_mm/1", "must be >= 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/thickness_mm", {1, 0, 0.2}),
                    "/spines/0/thickness_mm/1", "> 0 where width_mm is");
  CHECK_BRUSH_ERROR(brushWith("/spines/1/thickness_mm", {1, 0.8, 0.3}),
                    "/spines/1/thickness_mm/2", "0 where it is 0");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/thickness_mm", {1, 2000, 0.2}),
                    "/spines/0/thickness_mm/1", "must be <= 1000 mm");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/rest_angles_rad/1/1", 1.3),
                    "/spines/0/rest_angles_rad/1/1", "1.2 rad");
  CHECK_NOTHROW(parseBrush(brushWith("/spines/0/rest_angles_rad/1/1", -1.2), "brush.json"));
  CHECK_BRUSH_ERROR(brushWith("/spines/1/root_mm/2", 0.5), "/spines/1/root_mm/2", "z <= 0");
  CHECK_BRUSH_ERROR(brushWith("/paint/capacity", 0), "/paint/capacity", "must be > 0");
}

TEST_CASE("wrong array lengths are 65 naming the array", "[readers]") {
  CHECK_BRUSH_ERROR(brushWith("/spines/0/root_mm", {0, 0}), "/spines/0/root_mm", "[x, y, z]");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/root_mm", {0, 0, 0, 0}), "/spines/0/root_mm");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/segment_lengths_mm", nlohmann::json::array()),
                    "/spines/0/segment_lengths_mm", "1..16 segments");
  CHECK_BRUSH_ERROR(brushWith("/spines/1/stiffness_nmm_per_rad", {8, 6, 4}),
                    "/spines/1/stiffness_nmm_per_rad", "must have 2 entries");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/stiffness_nmm_per_rad", {8}),
                    "/spines/0/stiffness_nmm_per_rad", "must have 2 entries");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/damping_nmm", {0.01}), "/spines/0/damping_nmm",
                    "must have 2 entries");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/width_mm", {2, 1}), "/spines/0/width_mm",
                    "must have 3 entries");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/rest_angles_rad", {{0, 0}}),
                    "/spines/0/rest_angles_rad", "2 [theta, phi] pairs");
  CHECK_BRUSH_ERROR(brushWith("/spines/0/rest_angles_rad/1", {0.1, 0.1, 0.1}),
                    "/spines/0/rest_angles_rad/1", "[theta, phi]");
}

TEST_CASE("spine and joint counts outside the limits are 65", "[readers]") {
  CHECK_BRUSH_ERROR(brushWith("/spines", nlohmann::json::array()), "brush.json: /spines",
                    "1..64 spines");
  CHECK_BRUSH_ERROR(brushWithSpines(kMaxSpines + 1), "brush.json: /spines", "1..64 spines");
  CHECK_BRUSH_ERROR(brushWithJoints(kMaxJointsPerSpine + 1), "/spines/0/segment_lengths_mm",
                    "1..16 segments");
}

TEST_CASE("friction out of range is 65 naming the field", "[readers]") {
  CHECK_BRUSH_ERROR(brushWith("/friction/mu_static", -0.1), "/friction/mu_static",
                    "must be in [0, 2]");
  CHECK_BRUSH_ERROR(brushWith("/friction/mu_static", 2.01), "/friction/mu_static",
                    "must be in [0, 2]");
  CHECK_BRUSH_ERROR(brushWith("/friction/mu_kinetic", -0.1), "/friction/mu_kinetic",
                    "must be in [0, 2]");
  CHECK_BRUSH_ERROR(brushWith("/friction/mu_kinetic", 0.6), "/friction/mu_kinetic = 0.6",
                    "must not exceed mu_static");
  CHECK_BRUSH_ERROR(brushWith("/friction/anisotropy/strength", -0.01),
                    "/friction/anisotropy/strength", "must be in [0, 1]");
  CHECK_BRUSH_ERROR(brushWith("/friction/anisotropy/strength", 1.01),
                    "/friction/anisotropy/strength", "must be in [0, 1]");
  CHECK_BRUSH_ERROR(brushWith("/friction/anisotropy/exponent", 0.99),
                    "/friction/anisotropy/exponent", "must be >= 1");
  // The bounds themselves are allowed.
  const Brush lo = parseBrush(brushWith("/friction", {{"mu_static", 0}, {"mu_kinetic", 0},
                                                      {"anisotropy", {{"strength", 0},
                                                                      {"exponent", 1}}}}),
                              "brush.json");
  CHECK(lo.friction.mu_static == 0);
  CHECK(lo.friction.anisotropy_exponent == 1);
  const Brush hi = parseBrush(brushWith("/friction", {{"mu_static", 2}, {"mu_kinetic", 2},
                                                      {"anisotropy", {{"strength", 1}}}}),
                              "brush.json");
  CHECK(hi.friction.mu_kinetic == 2);
  CHECK(hi.friction.anisotropy_strength == 1);
}

TEST_CASE("solver hints: friction_form is auto, objective or epigraph, and optional",
          "[readers]") {
  CHECK(parseBrush(kBrush, "brush.json").solver.friction_form.empty());
  for (const char* form : {"auto", "objective", "epigraph"})
    CHECK(parseBrush(brushWith("/solver/friction_form", form), "brush.json")
              .solver.friction_form == form);
  CHECK(parseBrush(brushWith("/solver", nlohmann::json::object()), "brush.json")
            .solver.friction_form.empty());
  CHECK_BRUSH_ERROR(brushWith("/solver/friction_form", "kink"), "/solver/friction_form",
                    "must be \"auto\", \"objective\" or \"epigraph\"");
  CHECK_BRUSH_ERROR(brushWith("/solver/friction_form", 1), "/solver/friction_form", "string");
  CHECK_BRUSH_ERROR(brushWith("/solver/max_iter", 10), "/solver", "unknown key 'max_iter'");
  // The library's fan carries the epigraph form (docs/brush-format.md, "solver").
  CHECK(loadBrush(std::string(BRISTLE_SOURCE_DIR) + "/scenes/brushes/fan.json")
            .solver.friction_form == "epigraph");
}

// ------------------------------------------------------- brush geometry sections

namespace {
// kBrush with a small valid surface (a quad strip around the two spines) and strips.
std::string brushWithGeometry() {
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  doc["surface"] = {
      {"cage_vertices_mm", {{-1, -1, 0}, {2, -1, 0}, {2, 1, 0}, {-1, 1, 0}, {0, 0, -9}}},
      {"faces", {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}},
      {"skin", {{{0, 0, 1.0}}, {{1, 0, 1.0}}, {{1, 0, 0.5}, {0, 0, 0.5}}, {{0, 0, 1}}, {{0, 2, 1}}}},
      {"refinement_level", 1}};
  doc["strips"] = {{"count", 40}, {"seed", 3}, {"placement", "line"}};
  return doc.dump();
}
std::string geometryWith(const std::string& pointer, const nlohmann::json& value) {
  nlohmann::json doc = nlohmann::json::parse(brushWithGeometry());
  doc[nlohmann::json::json_pointer(pointer)] = value;
  return doc.dump();
}
}  // namespace

TEST_CASE("surface and strips sections parse", "[readers][geometry]") {
  const Brush b = parseBrush(brushWithGeometry(), "brush.json");
  REQUIRE(b.surface.present());
  CHECK(b.surface.cage_mm.size() == 5);
  CHECK(b.surface.faces.size() == 4);
  CHECK(b.surface.skin[2].size() == 2);
  CHECK(b.surface.refinement_level == 1);
  REQUIRE(b.strips.present());
  CHECK(b.strips.count == 40);
  CHECK(b.strips.seed == 3);
  CHECK(b.strips.placement == "line");
}

TEST_CASE("bad surface and strips sections are 65 naming the field", "[readers][geometry]") {
  // Face indices out of range.
  CHECK_BRUSH_ERROR(geometryWith("/surface/faces/1/2", 5), "/surface/faces/1/2", "vertex index");
  // A face of 2 or 5 vertices, or one that repeats a vertex.
  CHECK_BRUSH_ERROR(geometryWith("/surface/faces/0", {0, 1}), "/surface/faces/0", "3 or 4");
  CHECK_BRUSH_ERROR(geometryWith("/surface/faces/0", {0, 1, 1}), "/surface/faces/0", "repeats");
  // Skin weights that do not sum to 1, or that name a missing spine or point.
  CHECK_BRUSH_ERROR(geometryWith("/surface/skin/2", {{1, 0, 0.5}, {0, 0, 0.4}}), "/surface/skin/2",
                    "sum to 1");
  CHECK_BRUSH_ERROR(geometryWith("/surface/skin/0", {{7, 0, 1.0}}), "/surface/skin/0/0/0",
                    "names no spine");
  CHECK_BRUSH_ERROR(geometryWith("/surface/skin/0", {{0, 3, 1.0}}), "/surface/skin/0/0/1",
                    "names no point");
  CHECK_BRUSH_ERROR(geometryWith("/surface/skin", {{{0, 0, 1.0}}}), "/surface/skin",
                    "one list");
  CHECK_BRUSH_ERROR(geometryWith("/surface/refinement_level", 5), "/surface/refinement_level",
                    "[0, 4]");
  CHECK_BRUSH_ERROR(geometryWith("/surface/creases", 1), "/surface/creases", "unknown key");
  // Strip counts above the documented limit, bad widths and placements.
  CHECK_BRUSH_ERROR(geometryWith("/strips/count", kMaxStrips + 1), "/strips/count", "1, 1000");
  CHECK_BRUSH_ERROR(geometryWith("/strips/count", 0), "/strips/count", "1, 1000");
  CHECK_BRUSH_ERROR(geometryWith("/strips/tip_width_mm", 1.0), "/strips/tip_width_mm",
                    "root_width_mm");
  CHECK_BRUSH_ERROR(geometryWith("/strips/placement", "grid"), "/strips/placement", "auto");
  // Clumps: at most one per strip (40 here), a strength in [0, 1], and no
  // strength without clumps to apply it to.
  CHECK_BRUSH_ERROR(geometryWith("/strips/clumps", 41), "/strips/clumps", "[0, count]");
  CHECK_BRUSH_ERROR(geometryWith("/strips/clumps", -1), "/strips/clumps", "[0, count]");
  CHECK_BRUSH_ERROR(geometryWith("/strips/clumping", 0.5), "/strips/clumping", "clumps >= 1");
  nlohmann::json clumped = nlohmann::json::parse(geometryWith("/strips/clumps", 4));
  clumped["strips"]["clumping"] = 1.5;
  CHECK_BRUSH_ERROR(clumped.dump(), "/strips/clumping", "[0, 1]");
  // A degenerate root layout: every root in one point.
  nlohmann::json doc = nlohmann::json::parse(brushWithGeometry());
  doc["spines"][1]["root_mm"] = {0, 0, 0};
  doc.erase("surface");
  CHECK_BRUSH_ERROR(doc.dump(), "/strips", "one point");
}

TEST_CASE("hair volume: read, and refused where it would be meaningless", "[readers][volume]") {
  const Brush off = parseBrush(kBrush, "brush.json");
  CHECK_FALSE(off.volume.present());  // absent: no volume term, as before
  nlohmann::json doc = nlohmann::json::parse(kBrush);
  doc["volume"] = {{"min_separation", 0.8}, {"stiffness_n_per_mm", 12}};
  const Brush on = parseBrush(doc.dump(), "brush.json");
  CHECK(on.volume.present());
  CHECK(on.volume.min_separation == 0.8);
  CHECK(on.volume.stiffness_n_per_mm == 12);
  // A separation of the rest spacing or more would push the hairs apart at rest.
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 1.2}}), "/volume/min_separation",
                    "spacing at rest");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 1.0}}), "/volume/min_separation",
                    "(0, 1)");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0}}), "/volume/min_separation",
                    "(0, 1)");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"stiffness_n_per_mm", -1}}),
                    "/volume/stiffness_n_per_mm", "(0, 1000]");
  CHECK_BRUSH_ERROR(brushWith("/volume", nlohmann::json::object()), "/volume/min_separation");
  // Cohesion at or below the rest spacing would pull the hairs together at rest.
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"max_separation", 0.9}}),
                    "/volume/max_separation", "(1, 100]");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"max_separation", 1.3},
                                          {"cohesion_n_per_mm", 0}}),
                    "/volume/cohesion_n_per_mm", "(0, 1000]");
  doc["volume"] = {{"min_separation", 0.8}, {"max_separation", 1.3}, {"cohesion_n_per_mm", 2}};
  const Brush cohesive = parseBrush(doc.dump(), "brush.json");
  CHECK(cohesive.volume.max_separation == 1.3);
  CHECK(cohesive.volume.cohesion_n_per_mm == 2);
  CHECK(cohesive.volume.tip_spread == 1);
  doc["volume"]["tip_spread"] = 0.25;
  CHECK(parseBrush(doc.dump(), "brush.json").volume.tip_spread == 0.25);
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"max_separation", 1.3},
                                          {"tip_spread", 1.5}}),
                    "/volume/tip_spread", "[0, 1]");
  // The squashed bundle's spread (docs/dynamics.md, "A squashed bundle
  // spreads"): off unless given, a stiffness in [0, 1000] N/mm.
  CHECK(cohesive.volume.spread_n_per_mm == 0);
  doc["volume"]["spread_n_per_mm"] = 40;
  CHECK(parseBrush(doc.dump(), "brush.json").volume.spread_n_per_mm == 40);
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"spread_n_per_mm", -1}}),
                    "/volume/spread_n_per_mm", "[0, 1000]");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"spread_n_per_mm", 1e4}}),
                    "/volume/spread_n_per_mm", "[0, 1000]");
  // The press the point takes up lying down before the belly squashes
  // (docs/dynamics.md, "The point lies down before the belly squashes"):
  // none unless given, mm of press in [0, 100].
  CHECK(cohesive.volume.squash_after_mm == 0);
  doc["volume"]["squash_after_mm"] = 5;
  CHECK(parseBrush(doc.dump(), "brush.json").volume.squash_after_mm == 5);
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"squash_after_mm", -1}}),
                    "/volume/squash_after_mm", "[0, 100]");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"squash_after_mm", 150}}),
                    "/volume/squash_after_mm", "[0, 100]");
  // An allowance as long as the hair (here 9.5 mm: the second spine hangs
  // 9 mm from a root 0.5 mm down) leaves nothing to squash, so a spread
  // given beside it would silently never act; without a spread it is harmless.
  doc["volume"]["squash_after_mm"] = 9.5;
  CHECK_BRUSH_ERROR(doc.dump(), "/volume/squash_after_mm", "below the hair's length");
  doc["volume"]["squash_after_mm"] = 9.4;
  CHECK(parseBrush(doc.dump(), "brush.json").volume.squash_after_mm == 9.4);
  doc["volume"]["squash_after_mm"] = 9.5;
  doc["volume"]["spread_n_per_mm"] = 0;
  CHECK(parseBrush(doc.dump(), "brush.json").volume.squash_after_mm == 9.5);
  doc["volume"]["spread_n_per_mm"] = 40;
  doc["volume"]["squash_after_mm"] = 5;
  // The squash over which the spread's push grows to its full stiffness
  // (docs/dynamics.md, "The spread ramps in"): none unless given, in [0, 10].
  CHECK(cohesive.volume.spread_ramp == 0);
  doc["volume"]["spread_ramp"] = 0.05;
  CHECK(parseBrush(doc.dump(), "brush.json").volume.spread_ramp == 0.05);
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"spread_ramp", -0.1}}),
                    "/volume/spread_ramp", "[0, 10]");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"spread_ramp", 11}}),
                    "/volume/spread_ramp", "[0, 10]");
  CHECK_BRUSH_ERROR(brushWith("/volume", {{"min_separation", 0.8}, {"spacing", 1}}),
                    "/volume/spacing", "unknown key");
}

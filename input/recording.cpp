#include "input/recording.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

#include "engine/base/error.h"
#include "input/text_fields.h"

namespace bristle::input {

using namespace detail;

const char* formatName(Format format) {
  switch (format) {
    case Format::kTrajectory: return "bristle-trajectory/1";
    case Format::kMyPaint: return "MyPaint events";
    case Format::kPointerCsv: return "Pointer Events CSV";
    case Format::kSvg: return "SVG";
  }
  return "?";
}

namespace {

constexpr const char* kExpected =
    "expected a bristle-trajectory/1 CSV (first line '# bristle-trajectory/1'), MyPaint events "
    "(lines 't x y pressure'), a Pointer Events CSV (a header naming timeStamp, x, y, "
    "pressure) or an SVG (<svg ...>)";

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// What the content looks like, from its first line that is neither blank nor
// (but for the trajectory's format line) a '#' comment; nullopt-like kTrajectory
// with *known false when it is none of them.
Format sniff(const std::string& text, bool* known, int* line_no) {
  *known = true;
  Lines lines(text);
  std::string_view line;
  int no = 0;
  while (lines.next(&line, &no)) {
    const std::string_view t = trim(line);
    if (t.empty()) continue;
    *line_no = no;
    if (t.rfind("# bristle-trajectory/", 0) == 0) return Format::kTrajectory;
    if (t[0] == '<' || t.rfind("\xEF\xBB\xBF<", 0) == 0) return Format::kSvg;
    if (t[0] == '#') continue;
    if (t.find(',') != std::string_view::npos) {
      for (std::string_view cell : csv::splitLine(t))
        if (cell == "timeStamp" || cell == "\"timeStamp\"") return Format::kPointerCsv;
    } else {
      const std::vector<std::string_view> f = splitBlanks(t);
      bool numbers = f.size() == 4;
      for (std::string_view s : f) {
        double v = 0;
        try {
          v = parseNumber(s, "", 0, 0, "");
        } catch (const Error&) {
          numbers = false;
        }
        (void)v;
      }
      if (numbers) return Format::kMyPaint;
    }
    break;
  }
  *known = false;
  return Format::kTrajectory;
}

}  // namespace

Format detectFormat(const std::string& text, const std::string& path) {
  bool known = false;
  int line_no = 1;
  const Format content = sniff(text, &known, &line_no);
  // An empty file is the trajectory reader's to report, as before recordings.
  if (!known && trim(text).empty()) return Format::kTrajectory;
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  const std::string where = "line " + std::to_string(line_no);
  if (!known)
    throw dataError(path, where, "not a format bristle reads: " + std::string(kExpected));
  auto mismatch = [&](const char* promised) {
    return dataError(path, where,
                     "ambiguous: the name ends in " + ext + ", which promises " + promised +
                         ", but the content is " + formatName(content) +
                         " (rename the file, or give bristle import --from); " + kExpected);
  };
  if (ext == ".svg" && content != Format::kSvg) throw mismatch("an SVG");
  if (ext == ".dat" && content != Format::kMyPaint) throw mismatch("MyPaint events");
  if (ext == ".csv" && content != Format::kTrajectory && content != Format::kPointerCsv)
    throw mismatch("a bristle-trajectory/1 or Pointer Events CSV");
  return content;
}

Recording readRecording(const std::string& text, const std::string& path, Format format,
                        const SvgOptions& svg, std::size_t max_samples) {
  Recording rec;
  switch (format) {
    case Format::kMyPaint: rec = readMyPaintEvents(text, path, max_samples); break;
    case Format::kPointerCsv: rec = readPointerCsv(text, path, max_samples); break;
    case Format::kSvg: rec = readSvg(text, path, svg, max_samples); break;
    case Format::kTrajectory:
      throw Error(ExitCode::kSoftware, "readRecording: a trajectory is not a recording");
  }
  // Samples at the same time: the later one stands (docs/input.md, "Time").
  std::vector<PenSample> kept;
  kept.reserve(rec.samples.size());
  for (const PenSample& s : rec.samples) {
    if (!kept.empty() && kept.back().t_s == s.t_s) {
      kept.back() = s;
      ++rec.merged_duplicates;
    } else {
      kept.push_back(s);
    }
  }
  rec.samples = std::move(kept);
  if (rec.merged_duplicates > 0)
    rec.warnings.push_back(path + ": merged " + std::to_string(rec.merged_duplicates) +
                           " sample(s) that repeat the time of the one before (the later "
                           "sample stands)");
  if (rec.samples.size() < 2)
    throw dataError(path, "size", "holds " + std::to_string(rec.samples.size()) +
                                      " sample(s) at distinct times: a recording needs 2 or more");
  if (std::none_of(rec.samples.begin(), rec.samples.end(),
                   [](const PenSample& s) { return s.down; }))
    throw dataError(path, "line " + std::to_string(rec.samples.front().line),
                    "the pen never touches (no sample with pressure > 0, or with buttons bit 0 "
                    "where a buttons column is given): nothing to paint");
  return rec;
}

}  // namespace bristle::input

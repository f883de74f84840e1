#include "cli/session_render.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "engine/base/error.h"

namespace bristle::cli {
namespace {

// The shortest %g text that reads back to the same double (at most 17
// digits), so that replay renders with the very values record did.
std::string exactNumber(double v) {
  char text[32];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::strtod(text, nullptr) == v) break;
  }
  return text;
}

std::vector<std::string> lines(const std::string& v) { return {v}; }
std::vector<std::string> lines(double v) { return {exactNumber(v)}; }
std::vector<std::string> lines(int v) { return {std::to_string(v)}; }
std::vector<std::string> lines(unsigned long long v) { return {std::to_string(v)}; }
std::vector<std::string> lines(bool v) { return {v ? "true" : "false"}; }
std::vector<std::string> lines(SolverKind v) { return {solverKindName(v)}; }
std::vector<std::string> lines(const std::vector<std::string>& v) { return v; }

template <auto Member>
std::vector<std::string> linesOf(const SessionRender& r) {
  return lines(r.*Member);
}

template <auto Member>
void copyOf(SessionRender& to, const SessionRender& from) {
  to.*Member = from.*Member;
}

// One option of SessionRender: its long name, its value's header lines, and
// how replay takes it from the header's options.
struct Field {
  const char* option;
  std::vector<std::string> (*text)(const SessionRender&);
  void (*copy)(SessionRender&, const SessionRender&);
};

template <auto Member>
constexpr Field field(const char* option) {
  return {option, &linesOf<Member>, &copyOf<Member>};
}

// Every option of SessionRender, in the header's order: a new option of the
// session's render is added here and in addSessionRenderOptions (cli/options.h).
const Field kFields[] = {
    field<&SessionRender::paint>("--paint"),
    field<&SessionRender::load>("--load"),
    field<&SessionRender::amount>("--amount"),
    field<&SessionRender::tip_length>("--tip-length"),
    field<&SessionRender::mix>("--mix"),
    field<&SessionRender::paper_tooth_mm>("--paper-tooth"),
    field<&SessionRender::paper_scale_mm>("--paper-scale"),
    field<&SessionRender::paper_seed>("--paper-seed"),
    field<&SessionRender::background>("--background"),
    field<&SessionRender::impasto>("--impasto"),
    field<&SessionRender::bits>("--bits"),
    field<&SessionRender::px_per_mm>("--px-per-mm"),
    field<&SessionRender::solver>("--solver"),
    field<&SessionRender::solver_max_iterations>("--solver-max-iterations"),
    field<&SessionRender::ipopt_options>("--ipopt-option"),
};

const Field* findField(const std::string& option) {
  for (const Field& f : kFields)
    if (option == f.option) return &f;
  return nullptr;
}

std::string knownOptions() {
  std::string list;
  for (const Field& f : kFields) list += (list.empty() ? "" : ", ") + std::string(f.option);
  return list;
}

// The values of a field as one text ("tol=1e-8 mu_strategy=monotone"), for messages.
std::string joined(const std::vector<std::string>& values) {
  std::string text;
  for (const std::string& v : values) text += (text.empty() ? "" : " ") + v;
  return values.empty() ? "(none)" : text;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> sessionRenderHeader(const SessionRender& r) {
  std::vector<std::pair<std::string, std::string>> header;
  for (const Field& f : kFields)
    for (const std::string& value : f.text(r)) {
      if (hasControlCharacter(value))
        throw Error(ExitCode::kUsage, std::string(f.option) + ": a value holding a control "
                                          "character cannot go into the session's header");
      header.emplace_back(f.option, value);
    }
  return header;
}

std::vector<std::string> sessionRenderWords(const haptics::Session& session,
                                            const std::string& session_path) {
  std::vector<std::string> words;
  for (const auto& [key, value] : session.comments) {
    if (key.rfind("--", 0) != 0) continue;  // the device, the brush, ...
    const std::string where = session_path + ": header: " + key;
    if (findField(key) == nullptr)
      throw Error(ExitCode::kDataError,
                  where + ": not an option of the render (known: " + knownOptions() + ")");
    if (key != "--impasto") {
      words.push_back(key + "=" + value);
    } else if (value == "true") {
      words.push_back(key);
    } else if (value != "false") {
      throw Error(ExitCode::kDataError, where + ": '" + value + "' must be true or false");
    }
  }
  return words;
}

SessionRender mergeSessionRender(const SessionRender& recorded, const haptics::Session& session,
                                 const SessionRender& args, const std::vector<std::string>& given,
                                 const std::string& session_path,
                                 std::vector<std::string>* warnings) {
  // record writes every option, so a header that records one records them
  // all: what it leaves out is the default (an --ipopt-option: none).
  const bool recorded_any =
      std::any_of(session.comments.begin(), session.comments.end(),
                  [](const auto& line) { return line.first.rfind("--", 0) == 0; });
  SessionRender merged = args;
  for (const Field& f : kFields) {
    if (std::find(given.begin(), given.end(), f.option) == given.end()) {
      f.copy(merged, recorded);
      continue;
    }
    const std::vector<std::string> header = f.text(recorded), mine = f.text(args);
    if (recorded_any && header != mine)
      warnings->push_back(session_path + ": " + f.option + " " + joined(mine) +
                          " overrides the header's " + joined(header));
  }
  return merged;
}

}  // namespace bristle::cli

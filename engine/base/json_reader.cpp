#include "engine/base/json_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "engine/base/spelling.h"
#include "engine/base/text_file.h"

namespace bristle {
namespace {

// A key as messages show it (oneLine, engine/base/error.h).
std::string printable(const std::string& key) { return oneLine(key); }

std::string escapePointerToken(const std::string& key) {
  std::string out;
  for (char c : printable(key)) {
    if (c == '~') out += "~0";
    else if (c == '/') out += "~1";
    else out += c;
  }
  return out;
}

// Walks `text` outside JSON strings, skipping a string's quotes and escapes
// as a JSON parser does, and calls visit(i) at each offset i there. visit
// returns the offset to go on from (i itself for the next character), or
// npos to stop: the scan then returns i. npos when it never stops.
template <typename Visit>
size_t scanOutsideStrings(const std::string& text, Visit visit) {
  bool in_string = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else {
      const size_t next = visit(i);
      if (next == std::string::npos) return i;
      i = next;
    }
  }
  return std::string::npos;
}

// Offset of the first number literal spelled exactly `token` outside JSON
// strings, or npos.
size_t findNumberLiteral(const std::string& text, const std::string& token) {
  auto numberChar = [](char c) {
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.' || c == 'e' || c == 'E';
  };
  return scanOutsideStrings(text, [&](size_t i) {
    if (!numberChar(text[i])) return i;
    size_t j = i;
    while (j < text.size() && numberChar(text[j])) ++j;
    return text.compare(i, j - i, token) == 0 ? std::string::npos : j - 1;
  });
}

// Thrown by the parser callback when arrays and objects nest too deep.
struct TooDeep {};

// Offset of the bracket that opens the (limit + 1)-th level of nesting, or npos.
// Only used after the parser stopped there, so the text before it is valid JSON
// and brackets inside strings are skipped as the parser skipped them.
size_t offsetBeyondDepth(const std::string& text, int limit) {
  int depth = 0;
  return scanOutsideStrings(text, [&](size_t i) {
    const char c = text[i];
    if ((c == '[' || c == '{') && ++depth > limit) return std::string::npos;
    if (c == ']' || c == '}') --depth;
    return i;
  });
}

// Thrown by the parser callback when a document holds too many values.
struct TooMany {};

// Thrown by the parser callback at a key its object already holds.
struct DuplicateKey {
  std::string pointer, key;
};

// The open containers while the parser reads, for the JSON pointer of a key:
// an object's keys so far and the last one, an array's index.
class OpenContainers {
 public:
  void start(bool object) { open_.push_back({object, {}, {}, -1}); }
  void end() {
    open_.pop_back();
    valueDone();
  }
  // A scalar value, or a container just closed: the next index of an array.
  void valueDone() {
    if (!open_.empty() && !open_.back().object) ++open_.back().index;
  }
  void key(const std::string& k) {
    Frame& f = open_.back();
    if (!f.keys.insert(k).second) throw DuplicateKey{pointer() + "/" + escapePointerToken(k), k};
    f.key = k;
  }

 private:
  struct Frame {
    bool object;
    std::set<std::string> keys;
    std::string key;  // an object's last key
    long index;       // an array's last finished element
  };
  // The pointer of the innermost open container.
  std::string pointer() const {
    std::string p;
    for (size_t i = 0; i + 1 < open_.size(); ++i)
      p += "/" + (open_[i].object ? escapePointerToken(open_[i].key)
                                  : std::to_string(open_[i].index + 1));
    return p;
  }
  std::vector<Frame> open_;
};

// nlohmann's parser is iterative, but what walks the document afterwards (copies,
// dump(), the readers) recurses: refuse the nesting before it is built. And
// each value costs 16 bytes and more in the document: refuse the count before
// 256 MiB of "0," becomes 6 GB of values. A key twice in one object is
// refused too: nlohmann keeps the last silently, and RFC 8259 leaves such an
// object's meaning to each reader, so one reader could see the other value.
nlohmann::json parseDepthLimited(const std::string& text) {
  long values = 0;
  OpenContainers open;
  return nlohmann::json::parse(
      text, [&values, &open](int depth, nlohmann::json::parse_event_t event,
                             nlohmann::json& parsed) {
        using Event = nlohmann::json::parse_event_t;
        const bool starts = event == Event::object_start || event == Event::array_start;
        // depth counts the containers around the one that starts here.
        if (starts && depth >= kMaxJsonDepth) throw TooDeep{};
        if ((starts || event == Event::value) && ++values > kMaxJsonValues) throw TooMany{};
        if (starts) open.start(event == Event::object_start);
        if (event == Event::object_end || event == Event::array_end) open.end();
        if (event == Event::value) open.valueDone();
        if (event == Event::key) open.key(parsed.get_ref<const std::string&>());
        return true;
      });
}

std::string shortDump(const nlohmann::json& value) {
  std::string s = value.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

}  // namespace

nlohmann::json parseJsonText(const std::string& text, const std::string& path) {
  try {
    return parseDepthLimited(text);
  } catch (const TooDeep&) {
    const size_t at = offsetBeyondDepth(text, kMaxJsonDepth);
    throw dataError(path, at == std::string::npos ? std::string("JSON") : lineColumnOf(text, at),
                    "arrays and objects nest deeper than the limit of " +
                        std::to_string(kMaxJsonDepth) + " levels");
  } catch (const DuplicateKey& e) {
    throw dataError(path, e.pointer,
                    "duplicate key \"" + printable(e.key) +
                        "\": the object already holds it (one of the two would be lost)");
  } catch (const TooMany&) {
    throw dataError(path, "JSON",
                    "holds more than " + std::to_string(kMaxJsonValues) +
                        " values (numbers, strings, arrays, objects ...), over the limit");
  } catch (const nlohmann::json::parse_error& e) {
    // e.byte is 1-based and points just past the offending character.
    const size_t offset = e.byte > 0 ? e.byte - 1 : 0;
    std::string what = e.what();
    const size_t pos = what.find("syntax error");
    throw dataError(path, lineColumnOf(text, offset),
                    "malformed JSON (" + (pos == std::string::npos ? what : what.substr(pos)) + ")");
  } catch (const nlohmann::json::out_of_range& e) {
    // 406 "number overflow parsing '1e999'": a literal beyond the range of a
    // double. nlohmann gives no position, so find the literal it names.
    const std::string what = e.what();
    const size_t open = what.find("parsing '");
    const size_t close = what.rfind('\'');
    const std::string token = open != std::string::npos && close > open + 9
                                  ? what.substr(open + 9, close - open - 9)
                                  : std::string();
    const size_t at = token.empty() ? std::string::npos : findNumberLiteral(text, token);
    if (at == std::string::npos) throw dataError(path, "JSON", what);
    throw dataError(path, lineColumnOf(text, at),
                    "number " + token + " is out of range (must be finite)");
  }
}

nlohmann::json parseJsonOrDiscarded(const std::string& text) {
  try {
    return parseDepthLimited(text);
  } catch (const TooDeep&) {
  } catch (const TooMany&) {
  } catch (const DuplicateKey&) {
  } catch (const nlohmann::json::exception&) {
  }
  return nlohmann::json(nlohmann::json::value_t::discarded);
}

JsonObject::JsonObject(const nlohmann::json& node, std::string pointer, std::string file)
    : node_(node), pointer_(std::move(pointer)), file_(std::move(file)) {
  if (!node_.is_object()) fail(pointer_.empty() ? "/" : pointer_, "must be a JSON object");
}

std::string JsonObject::childPointer(const std::string& key) const {
  return pointer_ + "/" + escapePointerToken(key);
}

void JsonObject::declareKeys(std::initializer_list<const char*> keys) const {
  for (const char* k : keys) declared_.emplace_back(k);
}

void JsonObject::checkDeclared(const std::string& key) const {
  if (!declared_.empty() && std::find(declared_.begin(), declared_.end(), key) == declared_.end())
    throw std::logic_error(file_ + ": " + childPointer(key) +
                           ": the reader asks for a key it did not declare");
}

bool JsonObject::has(const std::string& key) const {
  checkDeclared(key);
  return node_.contains(key);
}

void JsonObject::fail(const std::string& pointer, const std::string& rule) const {
  throw dataError(file_, pointer, rule);
}

const nlohmann::json& JsonObject::get(const std::string& key) const {
  checkDeclared(key);
  used_.insert(key);
  auto it = node_.find(key);
  if (it == node_.end()) {
    rejectMisspellingOf(key);
    fail(childPointer(key), "required key is missing");
  }
  return *it;
}

const nlohmann::json& JsonObject::raw(const std::string& key) const { return get(key); }

double JsonObject::number(const std::string& key) const {
  const nlohmann::json& v = get(key);
  if (!v.is_number()) fail(childPointer(key), shortDump(v) + " must be a number");
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(childPointer(key), "must be finite");
  return d;
}

double JsonObject::number(const std::string& key, double fallback) const {
  used_.insert(key);
  return has(key) ? number(key) : fallback;
}

bool JsonObject::boolean(const std::string& key, bool fallback) const {
  used_.insert(key);
  if (!has(key)) return fallback;
  const nlohmann::json& v = get(key);
  if (!v.is_boolean()) fail(childPointer(key) + " = " + shortDump(v), "must be true or false");
  return v.get<bool>();
}

int JsonObject::integer(const std::string& key) const {
  const nlohmann::json& v = get(key);
  if (!v.is_number_integer() && !(v.is_number_float() && v.get<double>() == std::floor(v.get<double>())))
    fail(childPointer(key), shortDump(v) + " must be an integer");
  const double d = v.get<double>();
  if (std::fabs(d) > 1e9) fail(childPointer(key), shortDump(v) + " is out of range");
  return static_cast<int>(d);
}

int JsonObject::integer(const std::string& key, int fallback) const {
  used_.insert(key);
  return has(key) ? integer(key) : fallback;
}

std::string JsonObject::string(const std::string& key) const {
  const nlohmann::json& v = get(key);
  if (!v.is_string()) fail(childPointer(key), shortDump(v) + " must be a string");
  return v.get<std::string>();
}

std::string JsonObject::string(const std::string& key, const std::string& fallback) const {
  used_.insert(key);
  return has(key) ? string(key) : fallback;
}

std::vector<double> JsonObject::numbers(const std::string& key) const {
  const nlohmann::json& v = get(key);
  if (!v.is_array()) fail(childPointer(key), shortDump(v) + " must be an array of numbers");
  std::vector<double> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string p = childPointer(key) + "/" + std::to_string(i);
    if (!v[i].is_number()) fail(p, shortDump(v[i]) + " must be a number");
    const double d = v[i].get<double>();
    if (!std::isfinite(d)) fail(p, "must be finite");
    out.push_back(d);
  }
  return out;
}

JsonObject JsonObject::object(const std::string& key) const {
  return JsonObject(get(key), childPointer(key), file_);
}

std::vector<JsonObject> JsonObject::objects(const std::string& key) const {
  const nlohmann::json& v = get(key);
  if (!v.is_array()) fail(childPointer(key), "must be an array of objects");
  std::vector<JsonObject> out;
  for (size_t i = 0; i < v.size(); ++i)
    out.emplace_back(v[i], childPointer(key) + "/" + std::to_string(i), file_);
  return out;
}

void JsonObject::require(bool ok, const std::string& key, const std::string& rule) const {
  if (ok) return;
  auto it = node_.find(key);
  fail(childPointer(key) + (it == node_.end() ? std::string() : " = " + shortDump(*it)), rule);
}

void JsonObject::requireAt(bool ok, const std::string& pointer, const nlohmann::json& value,
                           const std::string& rule) const {
  if (!ok) fail(pointer + " = " + shortDump(value), rule);
}

std::string JsonObject::unknownKeyRule(const std::string& key, const std::string& meant) const {
  return "unknown key '" + printable(key) + "'" +
         (meant.empty() ? std::string() : "; did you mean " + childPointer(meant) + "?");
}

void JsonObject::rejectUnknownKeys() const {
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    if (used_.count(it.key())) continue;
    // A key that is present is no misspelling of it ("Name" beside "name").
    std::vector<std::string> absent;
    if (declared_.empty()) {
      for (const std::string& k : used_) absent.push_back(k);
    } else {
      absent = declared_;
    }
    absent.erase(std::remove_if(absent.begin(), absent.end(),
                                [this](const std::string& k) { return node_.contains(k); }),
                 absent.end());
    fail(childPointer(it.key()),
         unknownKeyRule(it.key(), closestSpelling(it.key(), absent).value_or("")));
  }
}

void JsonObject::rejectMisspellingOf(const std::string& key) const {
  // Undeclared, a key not read yet may be a legitimate one: no guess.
  if (declared_.empty()) return;
  std::string typo;
  int nearest = 0;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string& k = it.key();
    if (used_.count(k) || std::find(declared_.begin(), declared_.end(), k) != declared_.end() ||
        !closestSpelling(k, {key}))
      continue;
    const int d = editDistance(k, key);
    if (typo.empty() || d < nearest) {
      typo = k;
      nearest = d;
    }
  }
  if (typo.empty()) return;
  used_.insert(typo);  // reported here; a reader that goes on does not report it again
  fail(childPointer(typo), unknownKeyRule(typo, key));
}

double checkedElement(const JsonObject& obj, const std::string& key, size_t index, double value,
                      bool ok, const std::string& rule) {
  if (!ok)
    obj.fail(obj.childPointer(key) + "/" + std::to_string(index) + " = " +
                 nlohmann::json(value).dump(),
             rule);
  return value;
}

}  // namespace bristle

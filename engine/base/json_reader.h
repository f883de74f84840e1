#pragma once
// Strict reading of JSON input files: every key is either used or reported as
// unknown, and every bad value is reported as `file: /json/pointer = value: rule`
// (docs/design.md, "Style habits", item 3). Readers throw bristle::Error with kDataError.
//
// The readers' own header, shared with batch/ (the manifest reader) and not
// installed: nlohmann-json stays out of the engine's installed API.

#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "engine/base/error.h"

namespace bristle {

// The deepest nesting of arrays and objects in a JSON input. The formats nest
// 5 levels at most (a brush's /surface/skin/0/0/0, a scene's
// /strokes/0/placement/offset_mm); 64 leaves room for any future format while
// every recursive walk of a document stays far inside the stack.
constexpr int kMaxJsonDepth = 64;
// The most values (numbers, strings, arrays, objects, ...) in a JSON input: the
// library's largest brush holds 1,749, and 1,000,000 take about 100 MB parsed,
// where a 256 MiB file of numbers would take 6 GB.
constexpr long kMaxJsonValues = 1000000;

// Parses text as JSON; malformed JSON, and arrays and objects nested deeper
// than kMaxJsonDepth, throw kDataError naming line and column.
nlohmann::json parseJsonText(const std::string& text, const std::string& path);

// As parseJsonText, but a document it would refuse is returned as discarded.
nlohmann::json parseJsonOrDiscarded(const std::string& text);

class JsonObject {
 public:
  JsonObject(const nlohmann::json& node, std::string pointer, std::string file);

  // Every key the object may hold, declared by its reader before it reads any.
  // They are what a misspelt key is matched against ("did you mean", at a
  // required key that is missing and at an unknown key): a key not yet read
  // may still be one of them, so without the list a legitimate key could be
  // taken for a typo (min_separation is missing, max_separation is not).
  // Asking for an undeclared key is a bug in the reader (std::logic_error).
  void declareKeys(std::initializer_list<const char*> keys) const;

  bool has(const std::string& key) const;
  const std::string& pointer() const { return pointer_; }
  const std::string& file() const { return file_; }
  std::string childPointer(const std::string& key) const;

  // Typed getters: mark the key used, check type and finiteness.
  double number(const std::string& key) const;
  double number(const std::string& key, double fallback) const;
  int integer(const std::string& key) const;
  int integer(const std::string& key, int fallback) const;
  bool boolean(const std::string& key, bool fallback) const;
  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& fallback) const;
  std::vector<double> numbers(const std::string& key) const;
  JsonObject object(const std::string& key) const;
  std::vector<JsonObject> objects(const std::string& key) const;
  const nlohmann::json& raw(const std::string& key) const;

  // Rule checks: throw naming the key's pointer and value.
  void require(bool ok, const std::string& key, const std::string& rule) const;
  void requireAt(bool ok, const std::string& pointer, const nlohmann::json& value,
                 const std::string& rule) const;
  // Throws for the first key that no getter asked for, suggesting the declared
  // key it most likely misspells (engine/base/spelling.h).
  void rejectUnknownKeys() const;
  // Throws for a present, undeclared key that misspells `key` (a required key
  // that is missing): "/spnies: unknown key 'spnies'; did you mean /spines?".
  // Nothing when there is none; the required getters call it themselves.
  void rejectMisspellingOf(const std::string& key) const;
  [[noreturn]] void fail(const std::string& pointer, const std::string& rule) const;

 private:
  const nlohmann::json& get(const std::string& key) const;
  void checkDeclared(const std::string& key) const;
  std::string unknownKeyRule(const std::string& key, const std::string& meant) const;

  const nlohmann::json& node_;
  std::string pointer_;
  std::string file_;
  mutable std::set<std::string> used_;
  mutable std::vector<std::string> declared_;  // in the reader's order
};

// Checks each element of a number array and names /pointer/index on failure.
double checkedElement(const JsonObject& obj, const std::string& key, size_t index,
                      double value, bool ok, const std::string& rule);

}  // namespace bristle

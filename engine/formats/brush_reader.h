#pragma once
// The reader of a brush file, JSON format `bristle-brush/1`
// (docs/brush-format.md): every field checked against its rule, each problem
// a one-line error naming the JSON pointer (docs/errors.md).

#include <string>
#include <vector>

#include "engine/model/brush.h"

namespace bristle {

// Parses and validates; throws bristle::Error (66 missing, 65 bad data naming the
// JSON pointer and the rule).
Brush loadBrush(const std::string& path);
// Reads a brush and lists every problem found (empty: the brush is sound);
// throws only for a missing file (66) or malformed JSON (65).
std::vector<std::string> checkBrush(const std::string& path);
// With `problems`, every problem is collected (the first of each spine and of
// each section) instead of thrown; the returned brush is then only partly read.
Brush parseBrush(const std::string& text, const std::string& path_for_messages,
                 std::vector<std::string>* problems = nullptr);

}  // namespace bristle

#pragma once
// Which known name a misspelt one most likely meant, for "did you mean"
// hints on unknown JSON keys (engine/base/json_reader.h). One definition of
// "close", so every reader suggests alike.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace bristle {

// Edits (insert, delete, replace a character, or swap two adjacent ones) that
// turn a into b: the optimal-string-alignment distance. Case counts.
int editDistance(std::string_view a, std::string_view b);

// The candidate nearest to `word` when it is close: at most 2 edits, and at
// most a third of the candidate's length (so "id" suggests nothing for "ix",
// while "segment_length_mm" finds "segment_lengths_mm"). Of equally near
// candidates the first; nullopt when none is close, or `word` is one of them.
std::optional<std::string> closestSpelling(std::string_view word,
                                           const std::vector<std::string>& candidates);

}  // namespace bristle

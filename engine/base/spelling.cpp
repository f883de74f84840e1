#include "engine/base/spelling.h"

#include <algorithm>

namespace bristle {

int editDistance(std::string_view a, std::string_view b) {
  const size_t n = a.size(), m = b.size();
  // Three rows of the dynamic programme: i - 2, i - 1 and i.
  std::vector<int> before(m + 1), previous(m + 1), row(m + 1);
  for (size_t j = 0; j <= m; ++j) previous[j] = static_cast<int>(j);
  for (size_t i = 1; i <= n; ++i) {
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= m; ++j) {
      const int replace = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({previous[j] + 1, row[j - 1] + 1, replace});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        row[j] = std::min(row[j], before[j - 2] + 1);
    }
    std::swap(before, previous);
    std::swap(previous, row);
  }
  return previous[m];
}

std::optional<std::string> closestSpelling(std::string_view word,
                                           const std::vector<std::string>& candidates) {
  constexpr int kMaxEdits = 2;
  std::optional<std::string> best;
  int best_distance = kMaxEdits + 1;
  for (const std::string& c : candidates) {
    const int d = editDistance(word, c);
    if (d == 0) return std::nullopt;
    if (d < best_distance && 3 * d <= static_cast<int>(c.size())) {
      best = c;
      best_distance = d;
    }
  }
  return best;
}

}  // namespace bristle

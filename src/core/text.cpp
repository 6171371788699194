#include "proxygrasp/core/text.h"

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <vector>

namespace pg {

int EditDistance(std::string_view a, std::string_view b) {
  // one row of the dynamic-programming table at a time
  std::vector<int> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    int diagonal = row[0];
    row[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int above = row[j];
      const int substitute = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({above + 1, row[j - 1] + 1, substitute});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string ClosestName(std::string_view name, std::span<const std::string> candidates) {
  const int limit = std::max(2, static_cast<int>(name.size()) / 3);
  std::string best;
  int bestDistance = limit + 1;
  for (const std::string& c : candidates) {
    const int d = EditDistance(name, c);
    if (d < bestDistance) {
      bestDistance = d;
      best = c;
    }
  }
  return best;
}

std::string DidYouMean(std::string_view name, std::span<const std::string> candidates) {
  const std::string best = ClosestName(name, candidates);
  return best.empty() ? std::string() : " (did you mean '" + best + "'?)";
}

std::string FormatDouble(double v) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), v);
  return std::string(buffer, result.ptr);
}

std::string FormatFixed(double v, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, v);
  return buffer;
}

}  // namespace pg

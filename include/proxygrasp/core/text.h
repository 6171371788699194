// String helpers for messages and traces: edit distance, "did you mean" hints, numbers.
#pragma once

#include <span>
#include <string>
#include <string_view>

namespace pg {

/// Levenshtein edit distance between a and b.
int EditDistance(std::string_view a, std::string_view b);

/// The candidate closest to name by edit distance, when it is close enough to be a likely typo
/// (distance <= max(2, name.size() / 3)); empty otherwise.
std::string ClosestName(std::string_view name, std::span<const std::string> candidates);

/// " (did you mean 'x'?)" for the closest candidate, or "" when none is close.
std::string DidYouMean(std::string_view name, std::span<const std::string> candidates);

/// Formats a double compactly: shortest text that reads back to the same value ("0.3", "1e-06").
std::string FormatDouble(double v);

/// Formats a double with a fixed number of decimals, as printf's "%.*f" ("0.050000").
std::string FormatFixed(double v, int decimals);

}  // namespace pg

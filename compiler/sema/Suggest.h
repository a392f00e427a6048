// "Did you mean ...?" for unknown names: the nearest candidate by edit distance.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace moire {

// Optimal-string-alignment distance (insertions, deletions, substitutions, transpositions).
int editDistance(std::string_view a, std::string_view b);

// The same distance when it is at most `limit`, else limit + 1. The work is bounded by
// min(|a|, |b|) * (2 * limit + 1) and is nothing when the lengths alone differ by more.
int editDistanceWithin(std::string_view a, std::string_view b, int limit);

// The candidate nearest to `name`, or "" when none is within `maxDistance` (by default a
// third of the name's length, at least 1, at most 3).
std::string nearestName(std::string_view name, const std::vector<std::string>& candidates,
                        int maxDistance = -1);

// "; did you mean 'x'?" or "".
std::string didYouMean(std::string_view name, const std::vector<std::string>& candidates);

} // namespace moire

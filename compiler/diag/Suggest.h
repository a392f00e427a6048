// "Did you mean ...?" for unknown names: the nearest candidate by edit distance.
#pragma once

#include "compiler/diag/Source.h"

#include <fmt/format.h>
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

// The tail of a message that proposes what to write instead, as "; did you mean 'x'?", with
// the replacement an editor can apply. Passed to DiagEngine::error as an argument of the
// message, it prints its text there and gives the diagnostic its Suggestion.
struct Hint {
    std::string text;        // as the message shows it; "" when nothing is proposed
    std::string replacement; // what to write instead; "" when the hint only explains
    SourceRange range;       // the text it replaces; not valid(): the diagnostic's own range

    Hint() = default;
    // A hint that only explains ("; to multiply, write 2 * x"): nothing to replace.
    Hint(std::string t) : text(std::move(t)) {}
    Hint(const char* t) : text(t) {}
};

// "; did you mean 'x'?" replacing the name, or an empty hint.
Hint didYouMean(std::string_view name, const std::vector<std::string>& candidates);
// The same for a known replacement: "; did you mean 'x'?".
Hint suggest(std::string replacement, SourceRange range = {});

} // namespace moire

template <>
struct fmt::formatter<moire::Hint> : fmt::formatter<std::string_view> {
    auto format(const moire::Hint& h, fmt::format_context& ctx) const {
        return fmt::formatter<std::string_view>::format(h.text, ctx);
    }
};

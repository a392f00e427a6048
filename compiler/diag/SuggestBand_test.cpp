// The banded edit distance behind "did you mean": the same answers as the full table, and
// the same suggestions, for any names (checked here on many random ones).
#include "compiler/diag/Suggest.h"

#include <algorithm>
#include <cctype>
#include <doctest/doctest.h>
#include <random>

using namespace moire;

namespace {

// The optimal-string-alignment distance by its full table, as the definition reads.
int fullDistance(const std::string& a, const std::string& b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
    for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
    for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
    for (size_t i = 1; i <= n; ++i)
        for (size_t j = 1; j <= m; ++j) {
            int cost = std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    return d[n][m];
}

// The nearest name by full distances to every candidate, with the same rules of choice.
std::string fullNearest(const std::string& name, const std::vector<std::string>& candidates) {
    int maxDistance = std::clamp(static_cast<int>(name.size()) / 3, 1, 3);
    std::string best;
    int bestDistance = maxDistance + 1;
    auto prefix = [&](const std::string& c) {
        size_t n = 0;
        while (n < c.size() && n < name.size() && c[n] == name[n]) ++n;
        return n;
    };
    for (const std::string& c : candidates) {
        int dist = fullDistance(name, c);
        if (dist >= static_cast<int>(std::max(name.size(), c.size()))) continue;
        if (dist < bestDistance ||
            (dist == bestDistance && !best.empty() &&
             (prefix(c) > prefix(best) || (prefix(c) == prefix(best) && c < best)))) {
            bestDistance = dist;
            best = c;
        }
    }
    return bestDistance <= maxDistance ? best : std::string();
}

std::string randomName(std::mt19937& rng, int maxLength) {
    // A small alphabet with both cases, so that near names (and transpositions) are common.
    static const char letters[] = "abcAB";
    std::string s(std::uniform_int_distribution<int>(0, maxLength)(rng), 'a');
    for (char& c : s) c = letters[std::uniform_int_distribution<int>(0, 4)(rng)];
    return s;
}

} // namespace

TEST_CASE("suggest: the banded distance is the full table's, or says it is past the limit") {
    std::mt19937 rng(12);
    for (int trial = 0; trial < 20000; ++trial) {
        std::string a = randomName(rng, 9), b = randomName(rng, 9);
        int limit = std::uniform_int_distribution<int>(0, 6)(rng);
        int full = fullDistance(a, b);
        CAPTURE(a);
        CAPTURE(b);
        CAPTURE(limit);
        CHECK(editDistanceWithin(a, b, limit) == std::min(full, limit + 1));
        CHECK(editDistance(a, b) == full);
    }
}

TEST_CASE("suggest: the nearest name is the one the full distances choose") {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<std::string> candidates;
        for (int k = 0; k < 8; ++k) candidates.push_back(randomName(rng, 8));
        std::string name = randomName(rng, 9);
        CAPTURE(name);
        CHECK(nearestName(name, candidates) == fullNearest(name, candidates));
    }
}

TEST_CASE("suggest: a name far longer than every candidate is rejected by its length alone") {
    // No table is filled when the lengths differ by more than the limit: a megabyte-long name
    // against the built-in names is as quick as a short one (not timed here; the answer is).
    std::string huge(1 << 20, 's');
    CHECK(editDistanceWithin(huge, "sin", 3) == 4);
    CHECK(nearestName(huge, {"sin", "spacing", "stroke"}).empty());
    CHECK(nearestName(std::string(5, 's') + "in", {"sin"}) == "");
    CHECK(nearestName("ssin", {"sin"}) == "sin");
}

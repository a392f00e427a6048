#include "compiler/diag/Suggest.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

namespace moire {

namespace {
bool sameLetter(char a, char b) {
    return std::tolower(static_cast<unsigned char>(a)) ==
           std::tolower(static_cast<unsigned char>(b));
}
} // namespace

int editDistance(std::string_view a, std::string_view b) {
    return editDistanceWithin(a, b, static_cast<int>(std::max(a.size(), b.size())));
}

// The optimal-string-alignment table, computed only in the diagonal band |i - j| <= limit:
// a cell outside it is more than `limit` edits away, and so is every path through it. Three
// rolling rows suffice (the transposition looks two rows back). Rows whose every cell in the
// band is past `limit` end the search, since distances never shrink along a path.
int editDistanceWithin(std::string_view a, std::string_view b, int limit) {
    const long n = static_cast<long>(a.size()), m = static_cast<long>(b.size());
    if (limit < 0) return 0 == n && 0 == m ? 0 : limit + 1;
    if (std::labs(n - m) > limit) return limit + 1;
    const int over = limit + 1;
    std::vector<int> prev2(m + 1, over), prev(m + 1, over), cur(m + 1, over);
    for (long j = 0; j <= std::min<long>(m, limit); ++j) prev[j] = static_cast<int>(j);
    for (long i = 1; i <= n; ++i) {
        const long lo = std::max<long>(1, i - limit), hi = std::min<long>(m, i + limit);
        // Cells just outside the band are read by the next row: they must read as too far,
        // whatever an older row left there.
        cur[0] = i <= limit ? static_cast<int>(i) : over;
        cur[lo - 1] = lo > 1 ? over : cur[0];
        if (hi < m) cur[hi + 1] = over;
        int rowBest = cur[0];
        for (long j = lo; j <= hi; ++j) {
            int cost = sameLetter(a[i - 1], b[j - 1]) ? 0 : 1;
            int d = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d = std::min(d, prev2[j - 2] + 1);
            cur[j] = std::min(d, over);
            rowBest = std::min(rowBest, cur[j]);
        }
        if (rowBest > limit) return over;
        std::swap(prev2, prev);
        std::swap(prev, cur);
    }
    return std::min(prev[m], over);
}

std::string nearestName(std::string_view name, const std::vector<std::string>& candidates,
                        int maxDistance) {
    if (maxDistance < 0) maxDistance = std::clamp(static_cast<int>(name.size()) / 3, 1, 3);
    std::string best;
    int bestDistance = maxDistance + 1;
    for (const std::string& c : candidates) {
        // Only a candidate at most as far as the best so far can win (ties are broken below),
        // so the distance need not be known past that: a name far longer or shorter than
        // every candidate costs nothing to reject.
        int dist = editDistanceWithin(name, c, bestDistance);
        if (dist > bestDistance) continue;
        // A suggestion must keep something of what was written: 'e' for 'a' replaces it
        // whole, which is no hint at all (every one-letter name is that near).
        if (dist >= static_cast<int>(std::max(name.size(), c.size()))) continue;
        // Between equally near names, the one that agrees longest with the start of what was
        // written wins ('sinn' reads as 'sin' rather than 'sign'), then the alphabetically first.
        auto prefix = [&](const std::string& cand) {
            size_t n = 0;
            while (n < cand.size() && n < name.size() && cand[n] == name[n]) ++n;
            return n;
        };
        bool better = dist < bestDistance ||
                      (dist == bestDistance && !best.empty() &&
                       (prefix(c) > prefix(best) || (prefix(c) == prefix(best) && c < best)));
        if (better) {
            bestDistance = dist;
            best = c;
        }
    }
    return bestDistance <= maxDistance ? best : std::string();
}

Hint didYouMean(std::string_view name, const std::vector<std::string>& candidates) {
    std::string near = nearestName(name, candidates);
    return near.empty() ? Hint() : suggest(std::move(near));
}

Hint suggest(std::string replacement, SourceRange range) {
    Hint h;
    h.text = "; did you mean '" + replacement + "'?";
    h.replacement = std::move(replacement);
    h.range = range;
    return h;
}

} // namespace moire

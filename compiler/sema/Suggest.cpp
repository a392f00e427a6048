#include "compiler/sema/Suggest.h"

#include <algorithm>
#include <cctype>

namespace moire {

int editDistance(std::string_view a, std::string_view b) {
    const size_t n = a.size(), m = b.size();
    std::vector<std::vector<int>> d(n + 1, std::vector<int>(m + 1));
    for (size_t i = 0; i <= n; ++i) d[i][0] = static_cast<int>(i);
    for (size_t j = 0; j <= m; ++j) d[0][j] = static_cast<int>(j);
    for (size_t i = 1; i <= n; ++i) {
        for (size_t j = 1; j <= m; ++j) {
            int cost = std::tolower(a[i - 1]) == std::tolower(b[j - 1]) ? 0 : 1;
            d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
        }
    }
    return d[n][m];
}

std::string nearestName(std::string_view name, const std::vector<std::string>& candidates,
                        int maxDistance) {
    if (maxDistance < 0) maxDistance = std::clamp(static_cast<int>(name.size()) / 3, 1, 3);
    std::string best;
    int bestDistance = maxDistance + 1;
    for (const std::string& c : candidates) {
        int dist = editDistance(name, c);
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

std::string didYouMean(std::string_view name, const std::vector<std::string>& candidates) {
    std::string near = nearestName(name, candidates);
    return near.empty() ? std::string() : "; did you mean '" + near + "'?";
}

} // namespace moire

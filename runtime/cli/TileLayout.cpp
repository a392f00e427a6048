#include "runtime/cli/TileLayout.h"

#include <algorithm>
#include <cstdint>
#include <fmt/format.h>
#include <numeric>
#include <set>

namespace moire::cli {

namespace {

std::string describe(const PlacedTile& t) {
    return fmt::format("'{}' ({}x{} at {},{})", t.name, t.width, t.height, t.x, t.y);
}

// The first pixel of row y, from the left, that no tile covers (the tiles overlap nowhere);
// -1 when the row is covered. `left` and `right` receive the tiles beside it (-1: none).
int firstGapInRow(const std::vector<PlacedTile>& tiles, int y, int width, int& left, int& right) {
    std::vector<int> row;
    for (int i = 0; i < static_cast<int>(tiles.size()); ++i)
        if (tiles[i].y <= y && y < tiles[i].y1()) row.push_back(i);
    std::sort(row.begin(), row.end(), [&](int a, int b) { return tiles[a].x < tiles[b].x; });
    int x = 0;
    left = right = -1;
    for (int i : row) {
        if (tiles[i].x > x) {
            right = i;
            return x;
        }
        x = tiles[i].x1();
        left = i;
    }
    return x < width ? x : -1;
}

} // namespace

std::string coverProblem(const std::vector<PlacedTile>& tiles, int width, int height) {
    if (tiles.empty()) return "there are no tiles";
    for (const PlacedTile& t : tiles)
        if (t.x < 0 || t.y < 0 || t.x1() > width || t.y1() > height)
            return fmt::format("{} reaches past the {}x{} frame", describe(t), width, height);
    // Overlaps: each tile against those that start above its bottom, in order of their tops.
    std::vector<int> order(tiles.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return tiles[a].y != tiles[b].y ? tiles[a].y < tiles[b].y : tiles[a].x < tiles[b].x;
    });
    for (size_t i = 0; i < order.size(); ++i) {
        const PlacedTile& a = tiles[order[i]];
        for (size_t j = i + 1; j < order.size() && tiles[order[j]].y < a.y1(); ++j) {
            const PlacedTile& b = tiles[order[j]];
            const int x0 = std::max(a.x, b.x), x1 = std::min(a.x1(), b.x1());
            if (x0 < x1)
                return fmt::format("{} and {} overlap: both cover the {}x{} pixels at {},{}",
                                   describe(a), describe(b), x1 - x0,
                                   std::min(a.y1(), b.y1()) - b.y, x0, b.y);
        }
    }
    // Inside the frame and overlapping nowhere: they cover it when their areas add up to it.
    uint64_t area = 0;
    for (const PlacedTile& t : tiles) area += uint64_t(t.width) * uint64_t(t.height);
    if (area == uint64_t(width) * uint64_t(height)) return "";
    // A gap starts on the frame's top row or on the row below some tile's bottom.
    std::set<int> rows{0};
    for (const PlacedTile& t : tiles)
        if (t.y1() < height) rows.insert(t.y1());
    for (int y : rows) {
        int left = -1, right = -1;
        const int x = firstGapInRow(tiles, y, width, left, right);
        if (x < 0) continue;
        std::string beside;
        if (left >= 0 && right >= 0)
            beside =
                fmt::format(", between {} and {}", describe(tiles[left]), describe(tiles[right]));
        else if (left >= 0 || right >= 0)
            beside = fmt::format(", beside {}", describe(tiles[left >= 0 ? left : right]));
        return fmt::format("no tile covers pixel {},{} of the {}x{} frame{}", x, y, width, height,
                           beside);
    }
    return fmt::format("the tiles do not cover the {}x{} frame", width, height); // not reached
}

std::vector<int> tilesCrossing(const std::vector<PlacedTile>& tiles, int y0, int y1) {
    std::vector<int> out;
    for (int i = 0; i < static_cast<int>(tiles.size()); ++i)
        if (tiles[i].y < y1 && y0 < tiles[i].y1()) out.push_back(i);
    return out;
}

} // namespace moire::cli

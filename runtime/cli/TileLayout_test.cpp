// coverProblem against a pixel count of the frame (the brute-force oracle), and its words for
// each way tiles can fail to cover a frame.
#include "runtime/cli/TileLayout.h"

#include <doctest/doctest.h>
#include <random>

namespace moire::cli {

namespace {

// Every pixel counted: inside and covered exactly once.
bool coversOnce(const std::vector<PlacedTile>& tiles, int width, int height) {
    std::vector<int> count(static_cast<size_t>(width) * height, 0);
    for (const PlacedTile& t : tiles)
        for (int y = t.y; y < t.y1(); ++y)
            for (int x = t.x; x < t.x1(); ++x) {
                if (x < 0 || y < 0 || x >= width || y >= height) return false;
                ++count[static_cast<size_t>(y) * width + x];
            }
    for (int c : count)
        if (c != 1) return false;
    return true;
}

// A grid split at random cuts, then maybe disturbed: a tile dropped, moved or grown.
std::vector<PlacedTile> randomLayout(std::mt19937& rng, int width, int height) {
    auto cuts = [&](int size) {
        std::vector<int> c{0};
        std::uniform_int_distribution<int> step(1, size);
        while (c.back() < size) c.push_back(std::min(size, c.back() + step(rng)));
        return c;
    };
    const std::vector<int> xs = cuts(width), ys = cuts(height);
    std::vector<PlacedTile> tiles;
    for (size_t j = 0; j + 1 < ys.size(); ++j)
        for (size_t i = 0; i + 1 < xs.size(); ++i)
            tiles.push_back({"t" + std::to_string(tiles.size()), xs[i], ys[j], xs[i + 1] - xs[i],
                             ys[j + 1] - ys[j]});
    std::uniform_int_distribution<size_t> pick(0, tiles.size() - 1);
    switch (rng() % 4) {
    case 1:
        if (tiles.size() > 1) tiles.erase(tiles.begin() + static_cast<long>(pick(rng)));
        break;
    case 2:
        tiles[pick(rng)].x += static_cast<int>(rng() % 3) - 1;
        break;
    case 3:
        tiles[pick(rng)].height += static_cast<int>(rng() % 2);
        break;
    default:
        break;
    }
    return tiles;
}

} // namespace

TEST_CASE("coverProblem agrees with a pixel count on random layouts") {
    std::mt19937 rng(7);
    int good = 0, bad = 0;
    for (int trial = 0; trial < 2000; ++trial) {
        const int w = 1 + static_cast<int>(rng() % 12), h = 1 + static_cast<int>(rng() % 12);
        const std::vector<PlacedTile> tiles = randomLayout(rng, w, h);
        const std::string problem = coverProblem(tiles, w, h);
        CAPTURE(problem);
        CHECK(problem.empty() == coversOnce(tiles, w, h));
        (problem.empty() ? good : bad)++;
    }
    CHECK(good > 100); // both kinds were tried
    CHECK(bad > 100);
}

TEST_CASE("coverProblem names the tiles at fault") {
    const PlacedTile a{"a.png", 0, 0, 100, 50}, b{"b.png", 100, 0, 60, 50},
        c{"c.png", 0, 50, 160, 30};
    CHECK(coverProblem({a, b, c}, 160, 80).empty());
    CHECK(coverProblem({}, 160, 80) == "there are no tiles");
    CHECK(coverProblem({a, b, c}, 150, 80) ==
          "'b.png' (60x50 at 100,0) reaches past the 150x80 frame");
    PlacedTile wide = b;
    wide.x = 90;
    CHECK(coverProblem({a, wide, c}, 160, 80) ==
          "'a.png' (100x50 at 0,0) and 'b.png' (60x50 at 90,0) overlap: both cover the 10x50 "
          "pixels at 90,0");
    PlacedTile narrow = b;
    narrow.x = 110;
    narrow.width = 50;
    CHECK(coverProblem({a, narrow, c}, 160, 80) ==
          "no tile covers pixel 100,0 of the 160x80 frame, between 'a.png' (100x50 at 0,0) and "
          "'b.png' (50x50 at 110,0)");
    CHECK(coverProblem({a, b}, 160, 80) == "no tile covers pixel 0,50 of the 160x80 frame");
    CHECK(coverProblem({b, c}, 160, 80) ==
          "no tile covers pixel 0,0 of the 160x80 frame, beside 'b.png' (60x50 at 100,0)");
}

TEST_CASE("tilesCrossing: the tiles that hold some of a band's rows") {
    const std::vector<PlacedTile> tiles{
        {"a", 0, 0, 10, 5}, {"b", 10, 0, 10, 7}, {"c", 0, 5, 10, 5}, {"d", 10, 7, 10, 3}};
    CHECK(tilesCrossing(tiles, 0, 5) == std::vector<int>{0, 1});
    CHECK(tilesCrossing(tiles, 4, 6) == std::vector<int>{0, 1, 2});
    CHECK(tilesCrossing(tiles, 7, 10) == std::vector<int>{2, 3});
}

} // namespace moire::cli

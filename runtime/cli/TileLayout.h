// Where `moire assemble`'s tiles go in their frame, and whether they cover it exactly once.
#pragma once

#include <string>
#include <vector>

namespace moire::cli {

// A tile's window of the frame, in the frame's pixels, and the name errors call it by.
struct PlacedTile {
    std::string name;
    int x = 0, y = 0, width = 0, height = 0;
    int x1() const { return x + width; }
    int y1() const { return y + height; }
};

// Why `tiles` do not cover the width x height frame exactly once, naming the tiles at fault
// (one past the frame's edge, two that overlap, the tiles beside a pixel none covers), or ""
// when they do.
std::string coverProblem(const std::vector<PlacedTile>& tiles, int width, int height);

// The tiles that hold some of rows [y0, y1), in the order given.
std::vector<int> tilesCrossing(const std::vector<PlacedTile>& tiles, int y0, int y1);

} // namespace moire::cli

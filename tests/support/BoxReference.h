// A brute-force box filter of an exact field, the independent expectation the mean filter's
// tests hold a frame to: each pixel's share of a rank-1 lattice of samples that a predicate on
// world points inks. Shared by the tests of members finer than a pixel
// (tests/distance_grid_test.cpp, tests/distance_dots_test.cpp, tests/fine_union_test.cpp).
#pragma once

#include "runtime/Image.h"

#include <functional>
#include <vector>

namespace moire::test {

// Sample j of n in the unit square: ((j + 1/2) / n, fract(j g + 1/2)), g the lattice's
// generator as a share of a turn (a Fibonacci lattice: F(k-1) / F(k); else the golden
// ratio's fraction).
struct RankOneLattice {
    int n;
    double g;
};
constexpr RankOneLattice kFibonacci10946{10946, 6765.0 / 10946.0};
constexpr RankOneLattice kGolden256{256, 0.6180339887498949};

// A width x height frame at `zoom` pixels a world unit, the origin at its middle and y up:
// per pixel (row by row), the share of the lattice's samples where `inked(x, y)`.
std::vector<double> boxReference(int width, int height, double zoom,
                                 const std::function<bool(double, double)>& inked,
                                 RankOneLattice lattice);

// A frame (paper white, ink black: its first channel's ink 1 - value) against a reference's
// per-pixel ink: the RMSE, and the frame's and the reference's mean ink.
struct InkError {
    double rmse, ink, exact;
};
InkError inkError(const Image& frame, const std::vector<double>& reference);

} // namespace moire::test

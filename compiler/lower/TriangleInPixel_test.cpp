// The paper a triangle lattice's strokes leave in the pixel (TriangleInPixel.h), against a
// brute-force count of the points of a fine grid over the pixel that lie in no stroke: each
// point's distance to its nearest line of each family, not the shrunk triangles the closed
// form takes.
#include "compiler/lower/LatticeSteps_test.h"
#include "compiler/lower/TriangleInPixel.h"

#include <array>
#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <random>

namespace moire::lower {
namespace {

constexpr int kGrid = 600;
// Two cells to either side of the centre's hold the pixel to 2 sqrt2 rows a pixel, less the
// spare kTriOneBlockRows keeps.
constexpr double kTwoBlocksRows = 2.8;

TEST_CASE(
    "the paper a triangle lattice's strokes leave in the pixel matches a count of its points") {
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> logSide(std::log(0.38), std::log(5.0)), turn(0.0, 6.283),
        index(-40.0, 40.0), stretch(1.0, 1.3), stroke(0.0, 0.3);
    int near = 0, oneBlock = 0, twoBlocks = 0, allInk = 0;
    for (int trial = 0; trial < 80; ++trial) {
        // A triangle lattice of side s pixels, stretched along a direction b and turned by a:
        // its points' steps are s at 0 and 60 degrees, so mapped.
        const double s = std::exp(logSide(rng)), a = turn(rng), b = turn(rng), k = stretch(rng);
        const auto [e1, e2, gu, gv] = latticeSteps(s, a, b, k);
        // The three families' rates, |grad u|, |grad v| and |grad (u + v)|, are their rows a
        // pixel.
        const double ru = std::hypot(gu[0], gu[1]), rv = std::hypot(gv[0], gv[1]);
        const double rw = std::hypot(gu[0] + gv[0], gu[1] + gv[1]);
        const double rows = std::max({ru, rv, rw});
        if (rows > kTwoBlocksRows) continue;
        const double h = stroke(rng) * s;
        const double u0 = index(rng), v0 = index(rng);
        long paper = 0;
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                const double x = (i + 0.5) / kGrid - 0.5, y = (j + 0.5) / kGrid - 0.5;
                const double u = u0 + gu[0] * x + gu[1] * y, v = v0 + gv[0] * x + gv[1] * y;
                auto clear = [&](double f, double rate) {
                    return std::abs(f - std::round(f)) > h * rate;
                };
                paper += clear(u, ru) && clear(v, rv) && clear(u + v, rw) ? 1 : 0;
            }
        const double want = double(paper) / (double(kGrid) * kGrid);
        allInk += paper == 0 ? 1 : 0;
        CAPTURE(trial);
        CAPTURE(s);
        CAPTURE(rows);
        CAPTURE(h);
        auto drawn = [&](int reach) {
            return trianglePaperInSquare(u0, v0, e1[0], e1[1], e2[0], e2[1], h * ru, h * rv, h * rw,
                                         reach);
        };
        CHECK(std::abs(drawn(2) - want) <= 4e-3);
        ++twoBlocks;
        if (rows <= kTriOneBlockRows) {
            CHECK(std::abs(drawn(1) - want) <= 4e-3);
            ++oneBlock;
        }
        if (rows <= kTriNearRows) {
            const TrianglesInSquare<double> cells =
                trianglesInSquare(u0, v0, e1[0], e1[1], e2[0], e2[1], h * ru, h * rv, h * rw);
            CHECK(std::abs(paperShare(paperOfNearCells(cells)) - want) <= 4e-3);
            ++near;
        }
        // With no stroke the triangles tile the plane: the whole pixel is paper.
        CHECK(trianglePaperInSquare(u0, v0, e1[0], e1[1], e2[0], e2[1], 0.0, 0.0, 0.0, 2) ==
              doctest::Approx(1.0).epsilon(1e-9));
    }
    CHECK(near >= 10);
    CHECK(oneBlock - near >= 10);
    CHECK(twoBlocks - oneBlock >= 10);
    CHECK(allInk >= 1); // strokes past the inradius leave no triangle
}

} // namespace
} // namespace moire::lower

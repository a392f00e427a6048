// Two dots' shared area (LatticeUnion.h, lensArea) against a brute-force count of the points that
// lie in both discs on a fine grid over the smaller one, and against the areas known in
// closed form: one disc within the other, discs apart, and equal discs through each other's
// centres.
#include "compiler/lower/LatticeUnion.h"

#include <array>
#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <optional>

namespace moire::lower {
namespace {

double bruteLens(double d, double r1, double r2) {
    constexpr int kSide = 800;
    const double r = std::min(r1, r2), cx = r1 <= r2 ? 0.0 : d, ox = r1 <= r2 ? d : 0.0;
    const double big = std::max(r1, r2), cell = 2.0 * r / kSide;
    long inked = 0;
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const double x = cx - r + (i + 0.5) * cell, y = -r + (j + 0.5) * cell;
            const bool inSmall = (x - cx) * (x - cx) + y * y < r * r;
            const bool inBig = (x - ox) * (x - ox) + y * y < big * big;
            if (inSmall && inBig) ++inked;
        }
    return double(inked) * cell * cell;
}

TEST_CASE("lattice union: two dots' shared area is the lens the brute count finds") {
    const double kRadii[][2] = {{0.1, 0.1}, {0.15, 0.3}, {0.4, 0.12}, {1.0, 1.0}};
    for (const auto& r : kRadii)
        for (double share : {0.0, 0.1, 0.35, 0.6, 0.9, 0.99, 1.2}) {
            const double d = share * (r[0] + r[1]);
            CAPTURE(r[0]);
            CAPTURE(r[1]);
            CAPTURE(d);
            const double want = bruteLens(d, r[0], r[1]);
            // The grid's own error: the smaller disc's rim over 800 cells of its diameter.
            const double small = std::min(r[0], r[1]);
            CHECK(std::abs(lensArea(d, r[0], r[1]) - want) <=
                  0.01 * std::numbers::pi * small * small);
        }
    // Closed forms: within, apart, and equal discs through each other's centres, whose lens
    // is 2 pi r^2 / 3 - sqrt3 r^2 / 2.
    CHECK(lensArea(0.05, 0.1, 0.4) == doctest::Approx(std::numbers::pi * 0.01).epsilon(1e-9));
    CHECK(lensArea(0.0, 0.2, 0.2) == doctest::Approx(std::numbers::pi * 0.04).epsilon(1e-6));
    CHECK(lensArea(0.51, 0.2, 0.3) == 0.0);
    const double r = 0.3;
    CHECK(lensArea(r, r, r) ==
          doctest::Approx(2.0 * std::numbers::pi * r * r / 3.0 - std::sqrt(3.0) * r * r / 2.0)
              .epsilon(1e-9));
}

// The share of a disc within a strip against the same brute count: the strip's edges across
// the disc, beside it, over it whole, and the disc wider than the strip.
double bruteStrip(double centre, double h, double r) {
    constexpr int kSide = 800;
    const double cell = 2.0 * r / kSide;
    long inked = 0;
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const double x = -r + (i + 0.5) * cell, y = -r + (j + 0.5) * cell;
            if (x * x + y * y < r * r && std::abs(centre + x) < h) ++inked;
        }
    return double(inked) * cell * cell;
}

TEST_CASE("lattice union: a dot's share within a strip is the brute count's") {
    for (double r : {0.1, 0.3})
        for (double h : {0.04, 0.15, 0.5})
            for (double centre : {0.0, 0.07, -0.2, 0.3, 0.61, -0.9}) {
                CAPTURE(r);
                CAPTURE(h);
                CAPTURE(centre);
                const double want = bruteStrip(centre, h, r);
                CHECK(std::abs(discInStrip(centre, h, r) - want) <=
                      0.01 * std::numbers::pi * r * r);
            }
    // Within the strip whole: the disc; out of it: nothing; the strip through the centre
    // and as wide as the disc: all but the two caps beyond |z| = r / 2.
    CHECK(discInStrip(0.1, 1.0, 0.3) == doctest::Approx(std::numbers::pi * 0.09).epsilon(1e-9));
    CHECK(discInStrip(1.0, 0.2, 0.3) == 0.0);
    const double r = 0.4, cap = r * r * (std::acos(0.5) - 0.5 * std::sqrt(0.75));
    CHECK(discInStrip(0.0, r / 2, r) == doctest::Approx(std::numbers::pi * r * r - 2 * cap));
}

// The region a lattice's cells make, and two of them laid on one another (LatticeUnion.h,
// cellArea), against a count of the grid points that satisfy every bound: the triangle
// lattice's triangle shrunk and moved, the honeycomb's hexagon, a hexagon and another moved
// half a cell, and a triangle cut by the lower bounds of the other way up.
double bruteCell(const std::array<std::array<double, 2>, 3>& m, const std::array<double, 3>& upper,
                 const std::optional<std::array<double, 3>>& lower) {
    constexpr int kSide = 1000;
    constexpr double kReach = 2.5; // the regions here lie within |u|, |v| < 2.5
    const double cell = 2.0 * kReach / kSide;
    long inside = 0;
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const double u = -kReach + (i + 0.5) * cell, v = -kReach + (j + 0.5) * cell;
            bool in = true;
            for (int k = 0; k < 3 && in; ++k) {
                const double along = m[k][0] * u + m[k][1] * v;
                in = along <= upper[k] && (!lower || -along <= (*lower)[k]);
            }
            if (in) ++inside;
        }
    return double(inside) * cell * cell;
}

TEST_CASE("lattice union: a cell's area, and two cells' overlap, are the brute count's") {
    const std::array<std::array<double, 2>, 3> kTriangle{{{0.0, -1.0}, {-1.0, 0.0}, {1.0, 1.0}}};
    const std::array<std::array<double, 2>, 3> kHexagon{{{1.0, 2.0}, {-2.0, -1.0}, {1.0, -1.0}}};
    struct Case {
        const std::array<std::array<double, 2>, 3>& normals;
        double kappa;
        std::array<double, 3> upper;
        std::optional<std::array<double, 3>> lower;
    };
    const Case kCases[] = {
        {kTriangle, 0.5, {0.0, 0.0, 1.0}, std::nullopt},           // the cell's triangle
        {kTriangle, 0.5, {-0.1, -0.15, 0.8}, std::nullopt},        // shrunk by a stroke
        {kTriangle, 0.5, {-0.2, -0.2, 0.3}, std::nullopt},         // none left
        {kTriangle, 0.5, {0.0, 0.0, 1.0}, {{0.7, 0.6, -0.5}}},     // cut by the other way up
        {kTriangle, 0.5, {0.3, 0.4, 1.0}, {{-0.2, 0.1, 0.9}}},     // corners cut, overlapping
        {kHexagon, 1.0 / 6.0, {1.0, 1.0, 1.0}, {{1.0, 1.0, 1.0}}}, // the honeycomb's cell
        {kHexagon, 1.0 / 6.0, {0.8, 0.85, 0.8}, {{0.8, 0.85, 0.8}}},
        {kHexagon, 1.0 / 6.0, {1.0, 0.4, 1.0}, {{-0.3, 1.0, 0.2}}},  // a hexagon on a moved one
        {kHexagon, 1.0 / 6.0, {1.0, 1.0, 1.0}, {{-1.2, 1.0, 1.0}}},  // apart
        {kHexagon, 1.0 / 6.0, {1.0, -2.0, 1.0}, {{-2.0, 1.0, 1.0}}}, // a step of (1, 1) apart
        {kHexagon, 1.0 / 6.0, {1.0, -1.0, 1.0}, {{0.0, 1.0, 0.0}}},  // neighbours: a side
    };
    for (const Case& c : kCases) {
        CAPTURE(c.upper[0]);
        CAPTURE(c.upper[1]);
        CAPTURE(c.upper[2]);
        const double want = bruteCell(c.normals, c.upper, c.lower);
        CHECK(std::abs(cellArea(c.upper, c.lower, c.kappa) - want) <= 0.003 + 0.002 * want);
    }
    // The cells' own areas: half the triangle lattice's cell, and the whole of the honeycomb's.
    using Bounds = std::optional<std::array<double, 3>>;
    CHECK(cellArea<double>({0.0, 0.0, 1.0}, Bounds{}, 0.5) == doctest::Approx(0.5));
    CHECK(cellArea<double>({1.0, 1.0, 1.0}, Bounds{{1.0, 1.0, 1.0}}, 1.0 / 6.0) ==
          doctest::Approx(1.0));
}

} // namespace
} // namespace moire::lower

// A polygon's area within the square pixel, and the paper a honeycomb's strokes leave there
// (HoneycombInPixel.h), against a brute-force count of the points of a fine grid over the
// pixel that lie in the polygon, or in no stroke of the honeycomb: each point's hexagon found
// by searching the centres about it, not by the four the closed form tries.
#include "compiler/lower/HoneycombInPixel.h"
#include "compiler/lower/LatticeSteps_test.h"

#include <array>
#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <random>

namespace moire::lower {
namespace {

constexpr int kGrid = 600;

// The share of a kGrid x kGrid grid of the square's points inside a convex polygon.
template <size_t N>
double brutePolygon(const std::array<std::array<double, 2>, N>& p) {
    long in = 0;
    for (int i = 0; i < kGrid; ++i)
        for (int j = 0; j < kGrid; ++j) {
            const double x = (i + 0.5) / kGrid - 0.5, y = (j + 0.5) / kGrid - 0.5;
            bool left = true, right = true;
            for (size_t k = 0; k < N; ++k) {
                const auto& a = p[k];
                const auto& z = p[(k + 1) % N];
                const double cross = (z[0] - a[0]) * (y - a[1]) - (z[1] - a[1]) * (x - a[0]);
                left = left && cross >= 0.0;
                right = right && cross <= 0.0;
            }
            in += (left || right) ? 1 : 0;
        }
    return double(in) / (double(kGrid) * kGrid);
}

TEST_CASE("a convex polygon's area within the square matches a count of its points") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> centre(-1.0, 1.0), size(0.05, 1.5), turn(0.0, 6.283);
    for (int trial = 0; trial < 60; ++trial) {
        // A hexagon of uneven radii, counterclockwise (convex: radii within a factor 1.15).
        std::array<std::array<double, 2>, 6> p;
        const double cx = centre(rng), cy = centre(rng), r = size(rng), a0 = turn(rng);
        for (int k = 0; k < 6; ++k) {
            const double a = a0 + k * std::numbers::pi / 3.0, rk = r * (1.0 + 0.15 * (k % 2));
            p[k] = {cx + rk * std::cos(a), cy + rk * std::sin(a)};
        }
        CAPTURE(trial);
        const double want = brutePolygon(p);
        CHECK(std::abs(polygonInSquare(p) - want) <= 4e-3);
        std::array<std::array<double, 2>, 6> reversed;
        for (int k = 0; k < 6; ++k) reversed[k] = p[5 - k];
        CHECK(std::abs(polygonInSquare(reversed) + want) <= 4e-3);
    }
    // Closed forms: a triangle inside, a square over the whole pixel, one far outside, and a
    // side along the pixel's own edge.
    const std::array<std::array<double, 2>, 3> small{{{0.0, 0.0}, {0.2, 0.0}, {0.0, 0.2}}};
    CHECK(polygonInSquare(small) == doctest::Approx(0.02).epsilon(1e-9));
    const std::array<std::array<double, 2>, 4> whole{
        {{-2.0, -2.0}, {2.0, -2.0}, {2.0, 2.0}, {-2.0, 2.0}}};
    CHECK(polygonInSquare(whole) == doctest::Approx(1.0).epsilon(1e-9));
    const std::array<std::array<double, 2>, 3> away{{{3.0, 3.0}, {4.0, 3.0}, {3.0, 4.0}}};
    CHECK(std::abs(polygonInSquare(away)) <= 1e-12);
    const std::array<std::array<double, 2>, 4> half{
        {{-0.5, -0.5}, {0.0, -0.5}, {0.0, 0.5}, {-0.5, 0.5}}};
    CHECK(polygonInSquare(half) == doctest::Approx(0.5).epsilon(1e-9));
}

// A polygon's area within a band of rows, against the same count over a tall grid: the
// hexagons above, cut by bands that miss them, cross them and hold them whole.
TEST_CASE("a convex polygon's area within a band of rows matches a count of its points") {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> centre(-0.3, 0.3), size(0.1, 0.45), turn(0.0, 6.283),
        edge(-0.6, 0.6), width(0.0, 0.5);
    constexpr int kSide = 800;
    for (int trial = 0; trial < 40; ++trial) {
        std::array<std::array<double, 2>, 6> p;
        const double cx = centre(rng), cy = centre(rng), r = size(rng), a0 = turn(rng);
        for (int k = 0; k < 6; ++k) {
            const double a = a0 + k * std::numbers::pi / 3.0, rk = r * (1.0 + 0.15 * (k % 2));
            p[k] = {cx + rk * std::cos(a), cy + rk * std::sin(a)};
        }
        const double y0 = edge(rng), y1 = y0 + width(rng);
        // Points of [-1, 1]^2 within the band and the polygon (it lies within the square).
        long in = 0;
        for (int i = 0; i < kSide; ++i)
            for (int j = 0; j < kSide; ++j) {
                const double x = 2.0 * (i + 0.5) / kSide - 1.0, y = 2.0 * (j + 0.5) / kSide - 1.0;
                if (y < y0 || y > y1) continue;
                bool inside = true;
                for (size_t k = 0; k < 6; ++k) {
                    const auto& a = p[k];
                    const auto& z = p[(k + 1) % 6];
                    inside =
                        inside && (z[0] - a[0]) * (y - a[1]) - (z[1] - a[1]) * (x - a[0]) >= 0.0;
                }
                in += inside ? 1 : 0;
            }
        const double want = 4.0 * double(in) / (double(kSide) * kSide);
        CAPTURE(trial);
        CHECK(std::abs(polygonInBand(p, y0, y1) - want) <= 3e-3);
        std::array<std::array<double, 2>, 6> reversed;
        for (int k = 0; k < 6; ++k) reversed[k] = p[5 - k];
        CHECK(std::abs(polygonInBand(reversed, y0, y1) + want) <= 3e-3);
    }
    // A band over the whole polygon holds its area; one beside it none.
    const std::array<std::array<double, 2>, 3> small{{{0.0, 0.0}, {0.2, 0.0}, {0.0, 0.2}}};
    CHECK(polygonInBand(small, -5.0, 5.0) == doctest::Approx(0.02).epsilon(1e-9));
    CHECK(std::abs(polygonInBand(small, 0.3, 0.5)) <= 1e-12);
}

// The honeycomb's paper at a grid point: its hexagon by the least max_k |m_k . q| over the
// centres within two of its rounded (u, v), and inside the shrunk one where every |m_k . q|
// is within its bound.
bool onPaper(double u, double v, const std::array<double, 3>& bounds) {
    double least = 1e30, qu = 0.0, qv = 0.0;
    for (int i = -2; i <= 2; ++i)
        for (int j = -2; j <= 2; ++j) {
            const double du = u - (std::round(u) + i), dv = v - (std::round(v) + j);
            double norm = 0.0;
            for (const auto& [m, n] : kHexNormals) norm = std::max(norm, std::abs(m * du + n * dv));
            if (norm < least) least = norm, qu = du, qv = dv;
        }
    for (size_t k = 0; k < 3; ++k)
        if (std::abs(kHexNormals[k][0] * qu + kHexNormals[k][1] * qv) > bounds[k]) return false;
    return true;
}

TEST_CASE("a disc's area within a convex polygon matches a count of its points") {
    // Random hexagons (a turned, stretched regular one) and discs that miss them, cut their
    // sides and corners, hold them and lie within them; counted over the square, which holds
    // every polygon and disc drawn.
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> centre(-0.3, 0.3), size(0.05, 0.3), turn(0.0, 6.283),
        stretch(0.6, 1.4), radius(0.0, 0.25);
    for (int trial = 0; trial < 40; ++trial) {
        const double cx = centre(rng) * 0.5, cy = centre(rng) * 0.5, s = size(rng), a = turn(rng),
                     k = stretch(rng);
        std::array<std::array<double, 2>, 6> hex;
        for (int i = 0; i < 6; ++i) {
            const double t = a + i * std::numbers::pi / 3.0;
            hex[i] = {cx + s * std::cos(t) * k, cy + s * std::sin(t)};
        }
        const double dx = centre(rng), dy = centre(rng), r = radius(rng);
        long in = 0;
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                const double x = (i + 0.5) / kGrid - 0.5, y = (j + 0.5) / kGrid - 0.5;
                if ((x - dx) * (x - dx) + (y - dy) * (y - dy) >= r * r) continue;
                bool inside = true;
                for (int q = 0; q < 6; ++q) {
                    const auto& p = hex[q];
                    const auto& z = hex[(q + 1) % 6];
                    inside = inside && (z[0] - p[0]) * (y - p[1]) - (z[1] - p[1]) * (x - p[0]) >= 0;
                }
                in += inside ? 1 : 0;
            }
        const double brute = double(in) / (double(kGrid) * kGrid);
        CAPTURE(trial);
        CHECK(std::abs(discInPolygon(hex, dx, dy, r) - brute) <= 1e-3);
        // Clockwise, the same area negated.
        std::array<std::array<double, 2>, 6> back;
        for (int i = 0; i < 6; ++i) back[i] = hex[5 - i];
        CHECK(std::abs(discInPolygon(back, dx, dy, r) + brute) <= 1e-3);
    }
    // Exact cases: a disc within the polygon, one holding it, one apart, a half disc.
    const std::array<std::array<double, 2>, 4> square{
        {{-1.0, -1.0}, {1.0, -1.0}, {1.0, 1.0}, {-1.0, 1.0}}};
    CHECK(discInPolygon(square, 0.2, -0.1, 0.5) == doctest::Approx(std::numbers::pi * 0.25));
    CHECK(discInPolygon(square, 0.1, 0.0, 3.0) == doctest::Approx(4.0));
    CHECK(std::abs(discInPolygon(square, 3.0, 0.0, 0.5)) <= 1e-12);
    CHECK(discInPolygon(square, 1.0, 0.0, 0.5) == doctest::Approx(std::numbers::pi * 0.125));
}

TEST_CASE("the paper a honeycomb's strokes leave in the pixel matches a count of its points") {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> logSide(std::log(0.35), std::log(5.0)), turn(0.0, 6.283),
        index(-40.0, 40.0), stretch(1.0, 1.3), stroke(0.0, 0.25);
    int oneRing = 0, twoRings = 0;
    for (int trial = 0; trial < 80; ++trial) {
        // A honeycomb of side s pixels, stretched along a direction b and turned by a: its
        // centres' steps are s sqrt3 at 0 and 60 degrees, so mapped.
        const double s = std::exp(logSide(rng)), a = turn(rng), b = turn(rng), k = stretch(rng);
        const auto [e1, e2, gu, gv] = latticeSteps(s * std::numbers::sqrt3, a, b, k);
        // The generators' gradients give each side's bound, 1 less the half-width times
        // |grad(m_k . (u, v))|, and the rows of edges a pixel, the greatest |grad(m_k . (u,
        // v))| (the sides lie on the lines m_k . (u, v) whole).
        const double h = stroke(rng) * s;
        std::array<double, 3> bounds{};
        double rows = 0.0;
        for (size_t k = 0; k < 3; ++k) {
            const auto [m, n] = kHexNormals[k];
            const double rate = std::hypot(m * gu[0] + n * gv[0], m * gu[1] + n * gv[1]);
            bounds[k] = 1.0 - h * rate;
            rows = std::max(rows, rate);
        }
        if (rows > kTwoRingsRows) continue;
        const double u0 = index(rng), v0 = index(rng);
        long paper = 0;
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                const double x = (i + 0.5) / kGrid - 0.5, y = (j + 0.5) / kGrid - 0.5;
                const double u = u0 + gu[0] * x + gu[1] * y, v = v0 + gv[0] * x + gv[1] * y;
                paper += onPaper(u, v, bounds) ? 1 : 0;
            }
        const double want = double(paper) / (double(kGrid) * kGrid);
        CAPTURE(trial);
        CAPTURE(s);
        CAPTURE(rows);
        CAPTURE(h);
        auto drawn = [&](int rings) {
            return honeycombPaperInSquare(u0, v0, e1[0], e1[1], e2[0], e2[1], bounds, rings);
        };
        CHECK(std::abs(drawn(2) - want) <= 4e-3);
        ++twoRings;
        if (rows <= kOneRingRows) {
            CHECK(std::abs(drawn(1) - want) <= 4e-3);
            ++oneRing;
        }
        // With no stroke the hexagons tile the plane: the whole pixel is paper.
        CHECK(honeycombPaperInSquare(u0, v0, e1[0], e1[1], e2[0], e2[1],
                                     std::array<double, 3>{1.0, 1.0, 1.0},
                                     2) == doctest::Approx(1.0).epsilon(1e-9));
    }
    CHECK(oneRing >= 20);
    CHECK(twoRings - oneRing >= 10);
}

// A bound past the other two's sum (a wide stroke on a stretched cell) leaves a parallelogram:
// held to the sum, the corners still bound the region the three bounds make.
TEST_CASE("a shrunk hexagon whose bounds leave a parallelogram keeps its area") {
    for (const std::array<double, 3>& bounds :
         {std::array<double, 3>{0.9, 0.2, 0.3}, std::array<double, 3>{0.1, 0.6, 0.3},
          std::array<double, 3>{0.2, 0.2, 0.7}}) {
        const double area = insetHexagonArea(bounds);
        // The region's area in (u, v), counted on a fine grid over [-1, 1]^2.
        long in = 0;
        constexpr int kSide = 1000;
        for (int i = 0; i < kSide; ++i)
            for (int j = 0; j < kSide; ++j) {
                const double u = 2.0 * (i + 0.5) / kSide - 1.0, v = 2.0 * (j + 0.5) / kSide - 1.0;
                bool inside = true;
                for (size_t k = 0; k < 3; ++k)
                    inside = inside &&
                             std::abs(kHexNormals[k][0] * u + kHexNormals[k][1] * v) <= bounds[k];
                in += inside ? 1 : 0;
            }
        CAPTURE(bounds[0]);
        CHECK(area == doctest::Approx(4.0 * double(in) / (double(kSide) * kSide)).epsilon(5e-3));
    }
}

} // namespace
} // namespace moire::lower

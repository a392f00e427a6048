// The folded members' mean (FoldMean.h) against a count of the points of a fine grid over a
// square beside the hyperbola's asymptote that the point rule inks: each point's own phase
// sqrt|x^2 - y^2|, its nearest member by the index, its first-order distance (the fold
// distance below the first member, as LayerPipeline.cpp measures it), not the linear P the
// closed form takes.
#include "compiler/lower/FoldMean.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <random>

namespace moire::lower {
namespace {

constexpr int kGrid = 300;
constexpr int kFirst = 1;

// The point rule's ink at (x, y): hyperbolas `s` apart, half-width h, the members' level l
// spacings.
bool inked(double x, double y, double s, double h, double l) {
    const double q = x * x - y * y, gq = 2.0 * std::hypot(x, y); // |grad q|
    const double phi = std::sqrt(std::abs(q));
    const double index = phi / s - l;
    if (index < kFirst) {
        const double c = (kFirst + l) * s;
        return (c * c - phi * phi) / gq <= h;
    }
    const double grad = gq / (2.0 * phi * s); // |grad index|
    return std::abs(index - std::round(index)) / grad <= h;
}

TEST_CASE("the folded members' mean over a square matches a count of its points") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    auto logUniform = [&](double lo, double hi) {
        return std::exp(std::log(lo) + (std::log(hi) - std::log(lo)) * unit(rng));
    };
    double sum = 0;
    int straddling = 0, merged = 0, trials = 0;
    for (int trial = 0; trial < 120; ++trial) {
        const double s = logUniform(0.02, 2.0), h = s * (0.05 + 0.4 * unit(rng));
        const double l = 0.9 * unit(rng);
        const double side = s * logUniform(0.1, 6.0), turn = 6.283 * unit(rng);
        // A point on the asymptote x = y, u from the centre, moved across it by up to a side.
        const double u = 3.0 + 27.0 * unit(rng), across = side * (2.0 * unit(rng) - 1.0);
        const double cx = u / std::sqrt(2.0) + across / std::sqrt(2.0);
        const double cy = u / std::sqrt(2.0) - across / std::sqrt(2.0);
        const double e1x = std::cos(turn), e1y = std::sin(turn), e2x = -e1y, e2y = e1x;
        long ink = 0;
        for (int i = 0; i < kGrid; ++i)
            for (int j = 0; j < kGrid; ++j) {
                const double a = ((i + 0.5) / kGrid - 0.5) * side;
                const double b = ((j + 0.5) / kGrid - 0.5) * side;
                ink += inked(cx + a * e1x + b * e2x, cy + a * e1y + b * e2y, s, h, l) ? 1 : 0;
            }
        const double want = double(ink) / (double(kGrid) * kGrid);
        // P = |q| / s^2 at the centre, its gradient on the centre's side.
        const double q = cx * cx - cy * cy, sign = q < 0 ? -1.0 : 1.0;
        const double gx = sign * 2.0 * cx / (s * s), gy = -sign * 2.0 * cy / (s * s);
        const double got =
            foldMeanInk(std::abs(q) / (s * s), (gx * e1x + gy * e1y) * side,
                        (gx * e2x + gy * e2y) * side, h * std::hypot(gx, gy), l + kFirst);
        const double err = std::abs(got - want);
        sum += err;
        ++trials;
        straddling += std::abs(across) < side * 0.7 ? 1 : 0;
        // The strokes about the centre overlap, a member or more merged into one ink.
        merged += h * std::hypot(gx, gy) > std::sqrt(std::abs(q)) / s ? 1 : 0;
        CAPTURE(trial);
        CAPTURE(s);
        CAPTURE(h);
        CAPTURE(side);
        CAPTURE(across);
        CHECK(err <= 0.02);
    }
    // Parts several members wide over a bending Q are off by up to 0.017; the mean is 0.0007.
    CHECK(sum / trials <= 0.002);
    CHECK(straddling >= 40);
    CHECK(merged >= 20);
}

} // namespace
} // namespace moire::lower

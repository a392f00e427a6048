// The excess of three families of lines over independent inks (DistanceGrid.h, tripleExcess)
// against brute force: the share of the plane the three strokes cover where their indices'
// sum is constant, sampled over the unit torus of two of the indices; and a square pixel
// crossed by three families of lines whose gradients nearly cancel, sampled over the pixel,
// against the three closed-form means laid as independent inks plus the excess.
#include "compiler/lower/DistanceGrid.h"
#include "compiler/lower/Prefilter.h"

#include <cmath>
#include <doctest/doctest.h>

namespace moire::lower {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool within(double index, double w) {
    return std::abs(index - std::round(index)) < 0.5 * w;
}

// The share of the plane where index a, b or c - a - b is within its stroke (w1, w2, w3 wide),
// over an n x n grid of midpoints of the torus of (a, b).
double torusShare(double c, double w1, double w2, double w3) {
    constexpr int n = 1024;
    long inked = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double a = (i + 0.5) / n, b = (j + 0.5) / n;
            inked += within(a, w1) || within(b, w2) || within(c - a - b, w3);
        }
    return double(inked) / (double(n) * n);
}

} // namespace

TEST_CASE("tripleExcess: three strokes whose indices sum to a constant, against their share") {
    struct Case {
        double c, w1, w2, w3;
    };
    const Case kCases[] = {{0.0, 0.2, 0.2, 0.2},  {0.5, 0.2, 0.2, 0.2},  {0.25, 0.2, 0.2, 0.2},
                           {0.0, 0.1, 0.3, 0.15}, {0.4, 0.35, 0.1, 0.2}, {0.1, 0.45, 0.45, 0.45}};
    for (const Case& k : kCases) {
        CAPTURE(k.c);
        CAPTURE(k.w1);
        const double independent = 1.0 - (1.0 - k.w1) * (1.0 - k.w2) * (1.0 - k.w3);
        const double share = torusShare(k.c, k.w1, k.w2, k.w3);
        const double excess = tripleExcess(k.c, k.w1, k.w2, k.w3, 0.0, 0.0);
        CHECK(std::abs(independent + excess - share) < 1.5e-3);
    }
    // Three lines through every crossing of the other two, each a fifth of their spacing wide:
    // the paper left is each triangle shrunk by the stroke, (1 - 3 w / 2)^2 of the plane.
    const double lattice = 1.0 - std::pow(1.0 - 1.5 * 0.2, 2);
    CHECK(std::abs(1.0 - std::pow(0.8, 3) + tripleExcess(0.0, 0.2, 0.2, 0.2, 0.0, 0.0) - lattice) <
          1e-3);
}

TEST_CASE("tripleExcess: a pixel crossed by three families of lines, against brute force") {
    // Family k's index runs 6 lines a pixel along its normal at a + 60 k degrees (the third
    // 6 + d3), from c_k at the pixel's centre; the signs (+, -, +) make the three gradients
    // nearly cancel. Off the brute force by 0.0002, 0.0006, 0.0003, 0.0001 and 0.00003, where
    // the independent inks alone are off by 0.022, 0.015, 0.015, 0.0017 and 0.0002. (A third
    // family of 9 lines a pixel is off by 0.004: three of its lines beat with two of each
    // other's, a resonance of higher harmonics the excess leaves out.)
    struct Case {
        double a, d3, c1, c2, c3, w;
    };
    const Case kCases[] = {{0.2, 0.0, 0.1, 0.3, 0.2, 0.2},
                           {0.5, 0.0, 0.4, 0.1, 0.2, 0.25},
                           {0.2, 0.3, 0.0, 0.0, 0.0, 0.2},
                           {1.0, 0.8, 0.3, 0.6, 0.1, 0.2},
                           {0.7, 2.3, 0.0, 0.0, 0.0, 0.2}};
    for (const Case& k : kCases) {
        CAPTURE(k.a);
        CAPTURE(k.d3);
        const double sign[3] = {1.0, -1.0, 1.0};
        double gu[3], gv[3], c[3] = {k.c1, k.c2, k.c3};
        for (int f = 0; f < 3; ++f) {
            const double lines = f == 2 ? 6.0 + k.d3 : 6.0;
            gu[f] = lines * std::cos(k.a + f * kPi / 3.0);
            gv[f] = lines * std::sin(k.a + f * kPi / 3.0);
        }
        constexpr int n = 1024;
        long inked = 0;
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                const double x = (i + 0.5) / n - 0.5, y = (j + 0.5) / n - 0.5;
                bool any = false;
                for (int f = 0; f < 3; ++f) any = any || within(c[f] + gu[f] * x + gv[f] * y, k.w);
                inked += any;
            }
        const double brute = double(inked) / (double(n) * n);
        double paper = 1.0, su = 0.0, sv = 0.0, sum = 0.0;
        for (int f = 0; f < 3; ++f) {
            paper *= 1.0 - squareMeanInk(c[f], std::abs(gu[f]), std::abs(gv[f]), 0.5 * k.w);
            su += sign[f] * gu[f];
            sv += sign[f] * gv[f];
            sum += sign[f] * c[f];
        }
        const double independent = 1.0 - paper;
        const double closed = independent + tripleExcess(sum, k.w, k.w, k.w, su, sv);
        CAPTURE(brute);
        CAPTURE(independent);
        CAPTURE(closed);
        CHECK(std::abs(closed - brute) < 1e-3);
    }
}

} // namespace moire::lower

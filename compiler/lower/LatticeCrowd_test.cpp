// A lattice's nearest dot over the pixel (LatticeCrowd.h, discInSquare) against the area of
// the disc inside the unit square counted by brute force on a 512 x 512 grid of sample points:
// dots much smaller than the pixel, about its size and larger, inside it, across its sides and
// corners, and out of it.
#include "compiler/lower/LatticeCrowd.h"

#include <cmath>
#include <doctest/doctest.h>

namespace moire::lower {
namespace {

double bruteDisc(double cu, double cv, double r) {
    constexpr int kSide = 512;
    int inked = 0;
    for (int i = 0; i < kSide; ++i)
        for (int j = 0; j < kSide; ++j) {
            const double u = (i + 0.5) / kSide - 0.5, v = (j + 0.5) / kSide - 0.5;
            if ((u - cu) * (u - cu) + (v - cv) * (v - cv) < r * r) ++inked;
        }
    return double(inked) / (double(kSide) * kSide);
}

TEST_CASE("lattice crowd: the nearest dot's share of the pixel is the disc's area within it") {
    const double kRadii[] = {0.05, 0.2, 0.42, 0.7, 1.3, 3.0};
    const double kCentres[][2] = {{0.0, 0.0},  {0.3, -0.1}, {0.5, 0.5},   {-0.62, 0.1},
                                  {0.9, -0.8}, {1.4, 0.0},  {-0.2, 0.45}, {0.05, -1.1}};
    for (double r : kRadii)
        for (const auto& c : kCentres) {
            CAPTURE(r);
            CAPTURE(c[0]);
            CAPTURE(c[1]);
            const double want = bruteDisc(c[0], c[1], r);
            const double got = discInSquare(c[0], c[1], r);
            // The grid's own error is about the disc's perimeter within the pixel over 512.
            CHECK(std::abs(got - want) <= 0.004 + 0.01 * want);
        }
    // A whole disc inside the pixel: pi r^2 exactly (the midpoint rule over the half turn).
    CHECK(discInSquare(0.1, -0.05, 0.3) == doctest::Approx(M_PI * 0.09).epsilon(1e-9));
    // No disc out of reach.
    CHECK(discInSquare(2.0, 0.0, 0.4) == 0.0);
}

// The disc's transform, 2 J1(z) / z, against its integral over the disc's chords taken
// directly: (4 / pi) times the integral over [0, pi / 2] of cos^2 t cos(z sin t), by 20000
// midpoints. Either side of the hand-over from the series to Hankel's form at z = 8, at the
// first zero of J1 (3.8317), and far out.
TEST_CASE("lattice crowd: a disc's Fourier transform is 2 J1(z) / z") {
    for (double z :
         {0.0, 0.3, 1.0, 2.5, 3.8317, 5.0, 7.2, 7.99, 8.0, 8.01, 9.3, 12.0, 20.0, 41.0}) {
        CAPTURE(z);
        constexpr int kSteps = 20000;
        double sum = 0.0;
        for (int i = 0; i < kSteps; ++i) {
            const double t = (i + 0.5) * (M_PI / 2) / kSteps;
            sum += std::cos(t) * std::cos(t) * std::cos(z * std::sin(t));
        }
        const double want = 4.0 / M_PI * sum * (M_PI / 2) / kSteps;
        CHECK(std::abs(discTransform(z) - want) <= 2e-5);
    }
}

} // namespace
} // namespace moire::lower

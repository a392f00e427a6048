// Exact fractions: approximate() against a scan of every denominator, and sums and least
// common multiples against counting.
#include "compiler/lower/Rational.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numeric>
#include <random>

using namespace moire;

namespace {

constexpr int64_t kDen = 1000; // the denominators a clip reads its cycles with

// The nearest fraction with a denominator up to maxDen by trying every denominator; ties go
// to the smaller denominator. Independent of the continued fraction in approximate().
Rational nearestByScan(double v, int64_t maxDen) {
    Rational best{0, 1};
    long double bestErr = INFINITY;
    for (int64_t q = 1; q <= maxDen; ++q) {
        int64_t p = std::llround(v * static_cast<double>(q));
        long double err = std::fabs(static_cast<long double>(v) - static_cast<long double>(p) / q);
        if (err < bestErr) {
            bestErr = err;
            int64_t g = std::gcd(p, q);
            best = {p / g, q / g};
        }
    }
    return best;
}

} // namespace

TEST_CASE("decimals are read as the nearest fraction with a denominator up to 1000") {
    CHECK(approximate(1.5, kDen) == Rational{3, 2});
    CHECK(approximate(2.5, kDen) == Rational{5, 2});
    CHECK(approximate(0.1, kDen) == Rational{1, 10});
    CHECK(approximate(0.3333, kDen) == Rational{1, 3});
    CHECK(approximate(1.0 / 3.0, kDen) == Rational{1, 3});
    CHECK(approximate(0.6667, kDen) == Rational{2, 3});
    CHECK(approximate(0.333, kDen) == Rational{333, 1000}); // exactly representable: kept
    CHECK(approximate(10.0 / 7.0, kDen) == Rational{10, 7});
    CHECK(approximate(-2.25, kDen) == Rational{-9, 4});
    CHECK(approximate(0.0, kDen) == Rational{0, 1});
    CHECK(approximate(6.0, kDen) == Rational{6, 1});
    CHECK(approximate(30000.0 / 1001.0, 1001) == Rational{30000, 1001});

    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> dist(0.0, 20.0);
    for (int i = 0; i < 200; ++i) {
        double v = dist(rng);
        CAPTURE(v);
        for (int64_t maxDen : {7, 100, 1000}) {
            CAPTURE(maxDen);
            CHECK(approximate(v, maxDen) == nearestByScan(v, maxDen));
        }
    }
}

TEST_CASE("exact sums and least common multiples of fractions") {
    CHECK(add({1, 3}, {1, 6}) == Rational{1, 2});
    CHECK(lcm({3, 2}, {5, 2}) == Rational{15, 2});
    CHECK(lcm({1, 3}, {3, 2}) == Rational{3, 1});
    CHECK(lcm({4, 3}, {1, 1}) == Rational{4, 1});
    CHECK_FALSE(lcm({0, 1}, {1, 1}).has_value());
    CHECK_FALSE(lcm({INT64_MAX - 1, 1}, {INT64_MAX - 2, 1}).has_value()); // overflow
    // Against the smallest k for which k a is a whole multiple of b, found by counting.
    for (int64_t an = 1; an <= 9; ++an)
        for (int64_t ad = 1; ad <= 6; ++ad)
            for (int64_t bn = 1; bn <= 9; ++bn)
                for (int64_t bd = 1; bd <= 6; ++bd) {
                    Rational a = approximate(static_cast<double>(an) / ad, kDen);
                    Rational b = approximate(static_cast<double>(bn) / bd, kDen);
                    int64_t k = 1;
                    while ((k * a.num * b.den) % (a.den * b.num) != 0) ++k;
                    int64_t g = std::gcd(k * a.num, a.den);
                    INFO(an, "/", ad, " and ", bn, "/", bd);
                    CHECK(lcm(a, b) == Rational{k * a.num / g, a.den / g});
                }
}

TEST_CASE("products of fractions, and fractions as text") {
    CHECK(multiply({3, 2}, {2, 9}) == Rational{1, 3});
    CHECK(multiply({-3, 4}, {4, 3}) == Rational{-1, 1});
    CHECK_FALSE(multiply({INT64_MAX, 1}, {2, 1}).has_value()); // overflow
    CHECK(fractionText({3, 2}) == "3/2");
    CHECK(fractionText({7, 1}) == "7");
}

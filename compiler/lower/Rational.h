// Exact fractions for the clock: a clip's loop is the least common multiple of its timings'
// cycles, and a frame rate such as 30000 / 1001 is a fraction too. Decimals written in a
// scene (1.5, 0.3333) become fractions through approximate(); the arithmetic on them is
// exact, in 128 bits, and says when a result would not fit 64.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace moire {

// A fraction num / den in lowest terms with den > 0.
struct Rational {
    int64_t num = 0, den = 1;
    double value() const { return static_cast<double>(num) / static_cast<double>(den); }
    bool operator==(const Rational&) const = default;
};

// The fraction nearest to `v` among those with a denominator at most `maxDen`, from the
// convergents and semiconvergents of v's continued fraction. Requires |v| < 2^53; 0 for a
// value that is not finite or a `maxDen` below 1.
Rational approximate(double v, int64_t maxDen);
// Exact sum, product and least common multiple (of positive fractions: the smallest value
// that is a whole multiple of both); nullopt when a numerator or denominator would overflow.
std::optional<Rational> add(Rational a, Rational b);
std::optional<Rational> multiply(Rational a, Rational b);
std::optional<Rational> lcm(Rational a, Rational b);

// "3/2", or "7" for a whole number.
std::string fractionText(Rational r);

} // namespace moire

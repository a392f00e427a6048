#include "compiler/lower/Rational.h"

#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>

namespace moire {

namespace {

using i128 = __int128;

i128 gcd128(i128 a, i128 b) {
    if (a < 0) a = -a;
    if (b < 0) b = -b;
    while (b != 0) {
        i128 r = a % b;
        a = b;
        b = r;
    }
    return a;
}

// num / den reduced, or nullopt when it does not fit 64 bits.
std::optional<Rational> reduce(i128 num, i128 den) {
    if (den == 0) return std::nullopt;
    if (den < 0) num = -num, den = -den;
    i128 g = gcd128(num, den);
    if (g > 1) num /= g, den /= g;
    constexpr i128 kMax = std::numeric_limits<int64_t>::max();
    if (num > kMax || num < -kMax || den > kMax) return std::nullopt;
    return Rational{static_cast<int64_t>(num), static_cast<int64_t>(den)};
}

i128 abs128(i128 v) {
    return v < 0 ? -v : v;
}

} // namespace

Rational approximate(double v, int64_t maxDen) {
    if (!std::isfinite(v) || maxDen < 1) return {};
    const bool negative = v < 0;
    const double x = std::fabs(v);
    // Below 2^-60 the nearest fraction with a small denominator is 0 anyway; stopping there
    // keeps x's exact binary fraction p / 2^k within 128 bits.
    if (x < std::ldexp(1.0, -60)) return {};
    // x = p / q exactly: a 53-bit mantissa over a power of two (or an integer).
    int exp = 0;
    const double mant = std::frexp(x, &exp); // x = mant * 2^exp, mant in [0.5, 1)
    i128 p = static_cast<i128>(std::ldexp(mant, 53));
    i128 q = 1;
    if (exp >= 53)
        p <<= (exp - 53);
    else
        q <<= (53 - exp);
    // Euclid on p / q gives the continued fraction [a0; a1, ...]; h / k are its convergents.
    i128 h0 = 0, h1 = 1, k0 = 1, k1 = 0;
    i128 num = p, den = q;
    while (den != 0) {
        i128 a = num / den;
        i128 h2 = a * h1 + h0, k2 = a * k1 + k0;
        if (k2 > maxDen) {
            // The best fraction with a bounded denominator is the last convergent or the
            // largest semiconvergent under the bound, whichever is nearer.
            i128 m = (maxDen - k0) / k1;
            i128 hs = m * h1 + h0, ks = m * k1 + k0;
            // |p/q - hs/ks| < |p/q - h1/k1|  <=>  |p ks - hs q| k1 < |p k1 - h1 q| ks
            if (m > 0 && abs128(p * ks - hs * q) * k1 < abs128(p * k1 - h1 * q) * ks)
                h1 = hs, k1 = ks;
            break;
        }
        h0 = h1, h1 = h2, k0 = k1, k1 = k2;
        i128 r = num - a * den;
        num = den;
        den = r;
    }
    Rational out = reduce(h1, k1).value_or(Rational{});
    if (negative) out.num = -out.num;
    return out;
}

std::optional<Rational> add(Rational a, Rational b) {
    return reduce(static_cast<i128>(a.num) * b.den + static_cast<i128>(b.num) * a.den,
                  static_cast<i128>(a.den) * b.den);
}

std::optional<Rational> lcm(Rational a, Rational b) {
    if (a.num <= 0 || b.num <= 0) return std::nullopt;
    // For fractions in lowest terms, the common multiples of p1/q1 and p2/q2 are the
    // multiples of lcm(p1, p2) / gcd(q1, q2).
    i128 g = gcd128(a.num, b.num);
    i128 num = static_cast<i128>(a.num) / g * b.num;
    return reduce(num, std::gcd(a.den, b.den));
}

std::optional<Rational> multiply(Rational a, Rational b) {
    return reduce(static_cast<i128>(a.num) * b.num, static_cast<i128>(a.den) * b.den);
}

std::string fractionText(Rational r) {
    if (r.den == 1) return fmt::format("{}", r.num);
    return fmt::format("{}/{}", r.num, r.den);
}

} // namespace moire

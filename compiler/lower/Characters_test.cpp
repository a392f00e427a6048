// The character search (Characters.h) on every backend that runs here, against independent
// expectations: a hand-computed heterodyne ratio, a brute-force loop over integer pairs, an
// exact ternary beat.
#include "compiler/lower/Characters.h"
#include "compiler/lower/KernelProbe_test.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <random>

using namespace moire;
using lower::Grad;

namespace {

// The brute-force oracle: Eq. 11-12 written out again, minimised by a plain loop over every
// integer pair with 1 <= |k_i| <= maxOrder (independent of the code under test on purpose).
struct Brute {
    double mu;
    int k1, k2;
};
double bruteMerit(int k1, int k2, Grad<double> g1, Grad<double> g2) {
    const double bx = k1 * g1.x + k2 * g2.x, by = k1 * g1.y + k2 * g2.y;
    const double cx = k1 * g1.x - k2 * g2.x, cy = k1 * g1.y - k2 * g2.y;
    const double eta = std::sqrt(bx * bx + by * by) / (0.5 * std::sqrt(cx * cx + cy * cy));
    return std::abs(k1 * k2) * std::max(eta, 1e-3); // the merit's floor (kEtaFloor), restated
}
Brute bruteMinimum(Grad<double> g1, Grad<double> g2, int maxOrder) {
    Brute best{INFINITY, 0, 0};
    for (int k1 = 1; k1 <= maxOrder; ++k1)
        for (int k2 = -maxOrder; k2 <= maxOrder; ++k2)
            if (k2 != 0) {
                const double mu = bruteMerit(k1, k2, g1, g2);
                if (mu < best.mu) best = {mu, k1, k2};
            }
    return best;
}

Grad<double> gradientOf(double pitch, double angle) {
    return {std::cos(angle) / pitch, std::sin(angle) / pitch};
}

// The kernel: uniforms 0-5 are three gradients, bottom to top (the first `layers` of them
// used); outputs the winner's merit and coefficients.
test::KernelProbe stackProbe(int layers) {
    return test::KernelProbe(4, [layers](ir::Builder& b) {
        std::vector<lower::LayerFields> fields;
        for (int i = 0; i < layers; ++i) {
            lower::LayerFields f;
            f.index = b.constF(0.0);
            f.distance = b.constF(0.0);
            f.gradX = b.uniform(2 * i);
            f.gradY = b.uniform(2 * i + 1);
            fields.push_back(f);
        }
        lower::Character c = lower::stackCharacter(b, fields);
        b.output(0, c.mu);
        for (int i = 0; i < 3; ++i)
            b.output(1 + i, i < c.count ? c.k[static_cast<size_t>(i)] : b.constF(0.0));
    });
}

} // namespace

TEST_CASE("characters: eta of two parallel line families is the hand-computed ratio") {
    // Line families of pitches s1, s2 along one direction: g_i = u / s_i, so
    // eta_(1,-1) = |1/s1 - 1/s2| / ((1/s1 + 1/s2) / 2), and the pair's winner is (1, -1) when
    // the pitches are close.
    test::KernelProbe probe(1, [](ir::Builder& b) {
        using ir::BuiltValue;
        Grad<BuiltValue> g1{BuiltValue(b, b.uniform(0)), BuiltValue(b, b.uniform(1))};
        Grad<BuiltValue> g2{BuiltValue(b, b.uniform(2)), BuiltValue(b, b.uniform(3))};
        BuiltValue one(b, b.constF(1.0)), minusOne(b, b.constF(-1.0));
        b.output(0, lower::heterodyneRatio(one, minusOne, g1, g2).id);
    });
    test::KernelProbe pair = stackProbe(2);
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend) || !pair.use(backend)) continue;
        INFO(backend);
        for (double s1 : {4.0, 10.0, 25.0})
            for (double ratio : {1.02, 1.1, 0.93})
                for (double angle : {0.0, 0.7, 2.9}) {
                    const double s2 = s1 * ratio;
                    const Grad<double> g1 = gradientOf(s1, angle), g2 = gradientOf(s2, angle);
                    const double want =
                        2.0 * std::abs(1 / s1 - 1 / s2) / (1 / s1 + 1 / s2); // by hand
                    const std::vector<double> u = {g1.x, g1.y, g2.x, g2.y};
                    CHECK(probe.run(u)[0] == doctest::Approx(want).epsilon(1e-4));
                    const std::vector<double> w = pair.run(u);
                    CHECK(w[0] == doctest::Approx(want).epsilon(1e-4));
                    CHECK(std::abs(w[1]) == 1.0);
                    CHECK(w[2] == -w[1]);
                }
    }
}

TEST_CASE("characters: the reduction finds the shortest beat that brute force finds") {
    // Random non-collinear pairs: the reduced basis's first vector is as short as the shortest
    // nonzero k1 g1 + k2 g2 over every |k_i| <= 60 (the double instantiation, exactly).
    std::mt19937_64 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    for (int t = 0; t < 300; ++t) {
        const Grad<double> g1 = gradientOf(2 + 20 * unit(rng), 6.3 * unit(rng));
        const Grad<double> g2 = gradientOf(2 + 20 * unit(rng), 6.3 * unit(rng));
        auto basis = lower::reduceBeats(g1, g2, [](const auto&, const auto&) {});
        double shortest = INFINITY;
        for (int k1 = -60; k1 <= 60; ++k1)
            for (int k2 = -60; k2 <= 60; ++k2)
                if (k1 || k2)
                    shortest = std::min(shortest,
                                        std::hypot(k1 * g1.x + k2 * g2.x, k1 * g1.y + k2 * g2.y));
        CHECK(std::hypot(basis[0].x, basis[0].y) == doctest::Approx(shortest).epsilon(1e-9));
        // The carried coordinates name the vector.
        CHECK(basis[0].k1 * g1.x + basis[0].k2 * g2.x == doctest::Approx(basis[0].x).epsilon(1e-9));
    }
}

TEST_CASE("characters: the shipped search names the brute-force winner on random pairs") {
    // Pairs near alignment (twist within 10 degrees, half of them counted the other way, so
    // sums win as often as differences), pitches within a factor four: the kernel's winner
    // must be as good as the exhaustive minimum over orders <= 48, and its merit must be the
    // merit of the character it names.
    test::KernelProbe probe = stackProbe(2);
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend)) continue;
        INFO(backend);
        const double tol = 2e-4; // single precision on the JIT
        std::mt19937_64 rng(5);
        std::uniform_real_distribution<double> unit(0.0, 1.0);
        int visible = 0, beyondFloor = 0;
        for (int t = 0; t < 400; ++t) {
            const double s1 = 4 * std::pow(10.0, unit(rng));
            const double s2 = s1 * std::pow(4.0, 2 * unit(rng) - 1);
            const double a = 6.3 * unit(rng);
            const double twist = (2 * unit(rng) - 1) * 10 * std::numbers::pi / 180 +
                                 (unit(rng) < 0.5 ? std::numbers::pi : 0.0);
            const Grad<double> g1 = gradientOf(s1, a), g2 = gradientOf(s2, a + twist);
            const std::vector<double> got = probe.run({g1.x, g1.y, g2.x, g2.y});
            const Brute want = bruteMinimum(g1, g2, 48);
            const int k1 = static_cast<int>(std::lround(got[1]));
            const int k2 = static_cast<int>(std::lround(got[2]));
            INFO("s1 ", s1, " s2 ", s2, " twist ", twist, " brute (", want.k1, ",", want.k2, ") ",
                 want.mu, " got (", k1, ",", k2, ") ", got[0]);
            REQUIRE(k1 != 0);
            REQUIRE(k2 != 0);
            CHECK(got[0] == doctest::Approx(bruteMerit(k1, k2, g1, g2)).epsilon(tol));
            CHECK(got[0] <= want.mu * (1 + tol) + 1e-6);
            if (want.mu < lower::kFringeMerit) {
                ++visible;
                if (std::max(want.k1, std::abs(want.k2)) > 2) ++beyondFloor;
            }
        }
        // The sample exercises what the floor cannot see.
        CHECK(visible > 100);
        CHECK(beyondFloor > 20);
    }
}

TEST_CASE("characters: the ternary (1, 1, -2) beat wins where g1 + g2 = 2 g3") {
    // Three gradients with g3 the mean of g1 and g2, spread so that no pair beats slowly:
    // the zero-sum ternary character's beat is exactly zero there.
    test::KernelProbe probe = stackProbe(3);
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend)) continue;
        INFO(backend);
        for (double turn : {0.0, 1.1, 4.0}) {
            const Grad<double> g1 = gradientOf(6.0, turn + 0.15), g2 = gradientOf(10.0, turn - 0.2);
            const Grad<double> g3 = {(g1.x + g2.x) / 2, (g1.y + g2.y) / 2};
            const std::vector<double> got = probe.run({g1.x, g1.y, g2.x, g2.y, g3.x, g3.y});
            CHECK(got[0] == doctest::Approx(2 * lower::kEtaFloor)); // weight 2, eta floored
            const double sign = got[1] > 0 ? 1.0 : -1.0;
            CHECK(sign * got[1] == 1.0);
            CHECK(sign * got[2] == 1.0);
            CHECK(sign * got[3] == -2.0);
            // Perturbed off the harmonic mean, a pair wins back the frame only if slower.
            const Grad<double> off = {g3.x * 1.2, g3.y * 1.2};
            const std::vector<double> moved = probe.run({g1.x, g1.y, g2.x, g2.y, off.x, off.y});
            CHECK(moved[0] > 0.05);
        }
    }
}

TEST_CASE("characters: a sole layer and a zero gradient have no character") {
    test::KernelProbe one = stackProbe(1), two = stackProbe(2);
    for (const std::string& backend : test::probeBackends()) {
        if (!one.use(backend) || !two.use(backend)) continue;
        CHECK(one.run({0.1, 0.0})[0] >= 1e29);
        CHECK(two.run({0.1, 0.0, 0.0, 0.0})[0] >= 1.0); // a beat with nothing is no fringe
    }
}

TEST_CASE("characters: exactly commensurate parallel families keep their low-order fringe") {
    // Parallel line families at rational pitch ratios beat exactly (eta = 0) in characters
    // of every multiple order; the visible fringe is the lowest of them, which the merit's
    // floor on eta keeps ahead of the high orders (10 : 10.5 is 20 : 21, whose (21, -20)
    // also has eta 0). The expected winners are solved by hand.
    struct Case {
        double s1, s2;
        int k1, k2; // up to sign
    };
    test::KernelProbe probe = stackProbe(2);
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend)) continue;
        INFO(backend);
        for (const Case& c : {Case{10, 10.5, 1, -1}, Case{15, 5, 3, -1}, Case{10, 20, 1, -2},
                              Case{12, 8, 3, -2}, Case{7, 7, 1, -1}})
            for (double angle : {0.0, 0.4, 2.2}) {
                INFO(c.s1, " : ", c.s2, " at ", angle);
                const Grad<double> g1 = gradientOf(c.s1, angle), g2 = gradientOf(c.s2, angle);
                const std::vector<double> got = probe.run({g1.x, g1.y, g2.x, g2.y});
                const double sign = got[1] * c.k1 > 0 ? 1.0 : -1.0;
                CHECK(sign * got[1] == c.k1);
                CHECK(sign * got[2] == c.k2);
                CHECK(got[0] < lower::kFringeMerit);
            }
    }
}

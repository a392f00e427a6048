// The mean filter's closed form (Prefilter.h) against an independent expectation: the exact
// point rule of the stroke (ink where the index is within w of a whole number) averaged by
// brute force over 256 evenly spread samples of the footprint, on every backend.
#include "compiler/lower/KernelProbe_test.h"
#include "compiler/lower/Prefilter.h"

#include <cmath>
#include <doctest/doctest.h>

namespace moire::lower {
namespace {

// The oracle: the stroke sampled at 256 midpoints across [index - nu/2, index + nu/2].
double bruteMean(double index, double nu, double w) {
    constexpr int kSamples = 256;
    int inked = 0;
    for (int i = 0; i < kSamples; ++i) {
        double x = index + nu * ((i + 0.5) / kSamples - 0.5);
        if (std::abs(x - std::round(x)) < w) ++inked;
    }
    return static_cast<double>(inked) / kSamples;
}

// How far 256 samples can be from the integral: each stroke edge inside the box can flip
// at most one sample, and a box of nu periods holds at most 2 (nu + 1) edges; plus the
// float kernels' rounding.
double sampleTolerance(double nu) {
    return (2.0 * (std::ceil(nu) + 1.0)) / 256.0 + 1e-4;
}

struct Setting {
    double index, nu, w;
};

std::vector<Setting> settings() {
    std::vector<Setting> out;
    for (double nu : {0.01, 0.1, 0.3, 0.5, 0.9, 1.0, 1.43, 2.5, 3.7, 8.0})
        for (double w : {0.0, 0.02, 0.0714, 0.2, 0.45, 0.5, 0.8})
            for (double index : {0.0, 0.13, 0.5, -0.37, 3.99, 17.25, -120.6})
                out.push_back({index, nu, w});
    return out;
}

TEST_CASE("prefilter: the box mean's closed form is the brute-force mean of the stroke") {
    int checked = 0;
    for (const Setting& s : settings()) {
        CAPTURE(s.index);
        CAPTURE(s.nu);
        CAPTURE(s.w);
        CHECK(std::abs(boxMeanInk(s.index, s.nu, s.w) - bruteMean(s.index, s.nu, s.w)) <=
              sampleTolerance(s.nu));
        ++checked;
    }
    CHECK(checked == 490);
}

TEST_CASE("prefilter: the box mean's limits: the point rule, the mean ink 2w, solid ink") {
    // A narrow footprint reads the stroke's exact step at its centre.
    CHECK(boxMeanInk(3.04, 1e-3, 0.05) == doctest::Approx(1.0));
    CHECK(boxMeanInk(3.06, 1e-3, 0.05) == doctest::Approx(0.0));
    // A wide one reads the stroke's share of a period, 2w, ...
    for (double w : {0.01, 0.0714, 0.3})
        CHECK(boxMeanInk(0.37, 4096.0, w) == doctest::Approx(2.0 * w).epsilon(1e-3));
    // ... which is solid ink once the strokes touch.
    CHECK(boxMeanInk(0.37, 2.3, 0.5) == doctest::Approx(1.0));
    CHECK(boxMeanInk(0.37, 2.3, 0.9) == doctest::Approx(1.0));
    // A whole number of periods holds exactly one stroke each, wherever the box sits.
    for (double index : {0.0, 0.21, 0.5, 7.77})
        CHECK(boxMeanInk(index, 3.0, 0.1) == doctest::Approx(0.2));
}

TEST_CASE("prefilter: every backend computes the box mean the double form computes") {
    test::KernelProbe probe(1, [](ir::Builder& b) {
        ir::BuiltValue index(b, b.uniform(0)), nu(b, b.uniform(1)), w(b, b.uniform(2));
        b.output(0, boxMeanInk(index, nu, w).id);
    });
    for (const std::string& backend : test::probeBackends()) {
        CAPTURE(backend);
        if (!probe.use(backend)) continue;
        for (const Setting& s : settings()) {
            CAPTURE(s.index);
            CAPTURE(s.nu);
            CAPTURE(s.w);
            const double got = probe.run({s.index, s.nu, s.w})[0];
            CHECK(std::abs(got - bruteMean(s.index, s.nu, s.w)) <= sampleTolerance(s.nu));
            // Float kernels: within a few float steps of the footprint's inverse.
            CHECK(got == doctest::Approx(boxMeanInk(s.index, s.nu, s.w)).epsilon(1e-3));
        }
    }
}

TEST_CASE("prefilter: the hand-over keeps the point rule where members are resolved") {
    // Uniforms: index, |grad index|, point ink, half-width, pixel; first member 1 or none.
    auto kernel = [](std::optional<int> first) {
        return test::KernelProbe(1, [first](ir::Builder& b) {
            Footprint fp{b.uniform(0), b.uniform(1), first};
            b.output(0, meanInk(b, fp, b.uniform(2), b.uniform(3), b.uniform(4)));
        });
    };
    test::KernelProbe plain = kernel(std::nullopt);
    test::KernelProbe folded = kernel(1);
    for (const std::string& backend : test::probeBackends()) {
        CAPTURE(backend);
        if (!plain.use(backend) || !folded.use(backend)) continue;
        const double point = 0.8125, h = 0.05;
        // |grad index| 1 / spacing; pixel 1: nu = 1 / spacing members per pixel.
        for (double nu : {kMeanFrom, 0.9 * kMeanFrom, 0.1, 0.025}) // the point rule, exactly
            CHECK(plain.run({2.3, nu, point, h, 1.0})[0] == doctest::Approx(point));
        for (double nu : {kMeanFull, 1.1 * kMeanFull, 1.43, 100.0}) { // the box mean
            CAPTURE(nu);
            CHECK(plain.run({2.3, nu, point, h, 1.0})[0] ==
                  doctest::Approx(boxMeanInk(2.3, nu, h * nu)).epsilon(1e-4));
        }
        // Between, a mix of the two.
        const double nu = 0.5 * (kMeanFrom + kMeanFull), mean = boxMeanInk(2.3, nu, h * nu);
        const double got = plain.run({2.3, nu, point, h, 1.0})[0];
        CHECK(got > std::min(point, mean));
        CHECK(got < std::max(point, mean));
        // A family that starts at member 1 keeps the point rule where the footprint reaches
        // below it, and takes the mean above.
        CHECK(folded.run({0.9, 1.0 / 0.7, point, h, 1.0})[0] == doctest::Approx(point));
        CHECK(folded.run({5.1, 1.0 / 0.7, point, h, 1.0})[0] ==
              doctest::Approx(boxMeanInk(5.1, 1.0 / 0.7, h / 0.7)).epsilon(1e-4));
    }
}

} // namespace
} // namespace moire::lower

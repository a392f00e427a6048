// The mean filter's closed forms (Prefilter.h) against an independent expectation: the exact
// point rule of the stroke (ink where the index is within w of a whole number) averaged by
// brute force over 256 evenly spread samples of the footprint (a box, or a square pixel
// crossed by the gradient at an angle), on every backend.
#include "compiler/lower/KernelProbe_test.h"
#include "compiler/lower/Prefilter.h"

#include <cmath>
#include <doctest/doctest.h>
#include <functional>
#include <string>
#include <vector>

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

// The oracle over a square pixel whose sides span `along` and `across` units of index: 256
// samples on a rank-1 lattice (sample j at ((j + 1/2) / 256, frac(j / phi + 1/2))), so that
// both sides see 256 distinct positions.
double bruteSquareMean(double index, double along, double across, double w) {
    constexpr int kSamples = 256;
    int inked = 0;
    for (int j = 0; j < kSamples; ++j) {
        double u = (j + 0.5) / kSamples, v = j * 0.6180339887498949 + 0.5;
        v -= std::floor(v);
        double x = index + along * (u - 0.5) + across * (v - 0.5);
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

// A setting of a closed form: its inputs (the kernel's uniforms), and what it must give: the
// brute-force oracle's value within `tolerance`, and the double form's.
struct FormCase {
    std::vector<double> uniforms;
    double brute, tolerance, exact;
};

// The setting's inputs, for a failure's message.
std::string named(const FormCase& c) {
    std::string out;
    for (double u : c.uniforms) out += std::to_string(u) + " ";
    return out;
}

// Each setting's double form against the oracle; returns how many were checked.
int checkDoubleForm(const std::vector<FormCase>& cases) {
    for (const FormCase& c : cases) {
        const std::string uniforms = named(c);
        CAPTURE(uniforms);
        CHECK(std::abs(c.exact - c.brute) <= c.tolerance);
    }
    return static_cast<int>(cases.size());
}

std::vector<FormCase> boxCases() {
    std::vector<FormCase> cases;
    for (const Setting& s : settings())
        cases.push_back({{s.index, s.nu, s.w},
                         bruteMean(s.index, s.nu, s.w),
                         sampleTolerance(s.nu),
                         boxMeanInk(s.index, s.nu, s.w)});
    return cases;
}

TEST_CASE("prefilter: the box mean's closed form is the brute-force mean of the stroke") {
    CHECK(checkDoubleForm(boxCases()) == 490);
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

struct SquareSetting {
    double index, along, across, w;
};

std::vector<SquareSetting> squareSettings() {
    std::vector<SquareSetting> out;
    for (double nu : {0.3, 0.7, 1.0, 1.43, 3.7, 9.0})
        for (double angle : {0.0, 0.2, 0.7854, 1.2, 1.5708})
            for (double w : {0.0, 0.0714, 0.2, 0.5})
                for (double index : {0.0, 0.37, -4.81, 17.5})
                    out.push_back(
                        {index, nu * std::abs(std::cos(angle)), nu * std::abs(std::sin(angle)), w});
    return out;
}

// The square's sampling error as the box's, plus the blur of a side held at 1/32 of the other
// where the gradient runs along a side (each edge moved by at most that share of the pixel).
double squareTolerance(const SquareSetting& s) {
    const double wide = std::max(s.along, s.across), narrow = std::min(s.along, s.across);
    return sampleTolerance(s.along + s.across) + (narrow < wide * kLeastSideShare ? 1.0 / 16 : 0);
}

std::vector<FormCase> squareCases() {
    std::vector<FormCase> cases;
    for (const SquareSetting& s : squareSettings())
        cases.push_back({{s.index, s.along, s.across, s.w},
                         bruteSquareMean(s.index, s.along, s.across, s.w),
                         squareTolerance(s),
                         squareMeanInk(s.index, s.along, s.across, s.w)});
    return cases;
}

TEST_CASE("prefilter: the square pixel's closed form is the brute-force mean over the square") {
    CHECK(checkDoubleForm(squareCases()) == 480);
    // Along a side it is the box; wide, the stroke's share 2w; solid where strokes touch.
    CHECK(squareMeanInk(0.37, 1.43, 0.0, 0.0714) ==
          doctest::Approx(boxMeanInk(0.37, 1.43 * (1 + kLeastSideShare), 0.0714)).epsilon(0.01));
    CHECK(squareMeanInk(0.37, 300.0, 200.0, 0.0714) == doctest::Approx(0.1428).epsilon(1e-3));
    CHECK(squareMeanInk(0.37, 0.8, 0.6, 0.5) == doctest::Approx(1.0));
}

// Runs `form` (built over uniforms 0, 1, ...) on every backend for every case. The float
// kernels stay within `epsilon` of the double form (a few float steps of the footprint's
// inverse).
void checkOnBackends(const std::function<ir::ValueId(ir::Builder&)>& form,
                     const std::vector<FormCase>& cases, double epsilon) {
    test::KernelProbe probe(1, [&](ir::Builder& b) { b.output(0, form(b)); });
    for (const std::string& backend : test::probeBackends()) {
        CAPTURE(backend);
        if (!probe.use(backend)) continue;
        for (const FormCase& c : cases) {
            const std::string uniforms = named(c);
            CAPTURE(uniforms);
            const double got = probe.run(c.uniforms)[0];
            CHECK(std::abs(got - c.brute) <= c.tolerance);
            CHECK(got == doctest::Approx(c.exact).epsilon(epsilon));
        }
    }
}

TEST_CASE("prefilter: every backend computes the box mean the double form computes") {
    checkOnBackends(
        [](ir::Builder& b) {
            ir::BuiltValue index(b, b.uniform(0)), nu(b, b.uniform(1)), w(b, b.uniform(2));
            return boxMeanInk(index, nu, w).id;
        },
        boxCases(), 1e-3);
}

TEST_CASE("prefilter: every backend computes the square's mean the double form computes") {
    checkOnBackends(
        [](ir::Builder& b) {
            ir::BuiltValue index(b, b.uniform(0)), along(b, b.uniform(1)), across(b, b.uniform(2)),
                w(b, b.uniform(3));
            return squareMeanInk(index, along, across, w).id;
        },
        squareCases(), 2e-3);
}

TEST_CASE("prefilter: the hand-over keeps the point rule where members are resolved") {
    // Uniforms: index, |grad index|, point ink, half-width, pixel, and the gradient's
    // components (0.3 radians off the pixel's first side); first member 1 or none.
    auto kernel = [](std::optional<int> first) {
        return test::KernelProbe(1, [first](ir::Builder& b) {
            ir::ValueId grad = b.uniform(1);
            Footprint fp{b.uniform(0), grad, b.mul(grad, b.constF(std::cos(0.3))),
                         b.mul(grad, b.constF(std::sin(0.3))), first};
            b.output(0, meanInk(b, fp, b.uniform(2), b.uniform(3), PixelFootprint{b.uniform(4)}));
        });
    };
    auto mean = [](double index, double nu, double w) {
        return squareMeanInk(index, nu * std::cos(0.3), nu * std::sin(0.3), w);
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
                  doctest::Approx(mean(2.3, nu, h * nu)).epsilon(1e-4));
        }
        // Between, a mix of the two.
        const double nu = 0.5 * (kMeanFrom + kMeanFull), between = mean(2.3, nu, h * nu);
        const double got = plain.run({2.3, nu, point, h, 1.0})[0];
        CHECK(got > std::min(point, between));
        CHECK(got < std::max(point, between));
        // A family that starts at member 1 keeps the point rule where the footprint reaches
        // below it, and takes the mean above.
        CHECK(folded.run({0.9, 1.0 / 0.7, point, h, 1.0})[0] == doctest::Approx(point));
        CHECK(folded.run({5.1, 1.0 / 0.7, point, h, 1.0})[0] ==
              doctest::Approx(mean(5.1, 1.0 / 0.7, h / 0.7)).epsilon(1e-4));
    }
}

} // namespace
} // namespace moire::lower

// The mean filter's closed forms (Prefilter.h) against an independent expectation: the exact
// point rule of the stroke (ink where the index is within w of a whole number) averaged by
// brute force over 256 evenly spread samples of the footprint (a box, or a square pixel
// crossed by the gradient at an angle), and a single stroke seen from its distance averaged over
// the square pixel, on every backend.
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

// The oracle of one stroke seen from its distance: the pixel's centre `d` from the member's
// centre line, ink within h of it, the pixel's sides spanning `along` and `across` world units
// of the normal; 256 samples over the square on the same rank-1 lattice.
double bruteDistanceMean(double d, double h, double along, double across) {
    constexpr int kSamples = 256;
    int inked = 0;
    for (int j = 0; j < kSamples; ++j) {
        double u = (j + 0.5) / kSamples, v = j * 0.6180339887498949 + 0.5;
        v -= std::floor(v);
        if (std::abs(d + along * (u - 0.5) + across * (v - 0.5)) < h) ++inked;
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

struct DistanceSetting {
    double d, h, along, across;
};

std::vector<DistanceSetting> distanceSettings() {
    std::vector<DistanceSetting> out;
    for (double pixel : {0.4, 1.0, 3.0})
        for (double angle : {0.0, 0.3, 0.7854, 1.5708})
            for (double h : {0.0, 0.05, 0.25, 0.6, 2.0})
                for (double d : {0.0, 0.3, 0.9, 1.7, 5.0, 1e30})
                    out.push_back({d, h, pixel * std::abs(std::cos(angle)),
                                   pixel * std::abs(std::sin(angle))});
    return out;
}

std::vector<FormCase> distanceCases() {
    std::vector<FormCase> cases;
    for (const DistanceSetting& s : distanceSettings()) {
        // Two stroke edges, each flipping a sample or two of the lattice; where the footprint is a
        // box (across 0) the narrower side is held at 1/32 of the wider, moving an edge by as much.
        const double wide = std::max(s.along, s.across), narrow = std::min(s.along, s.across);
        const double tolerance =
            4.0 / 256 + 1e-4 + (narrow < wide * kLeastSideShare ? 1.0 / 16 : 0);
        cases.push_back({{s.d, s.h, s.along, s.across},
                         bruteDistanceMean(s.d, s.h, s.along, s.across),
                         tolerance,
                         distanceMeanInk(s.d, s.h, s.along, s.across)});
    }
    return cases;
}

TEST_CASE("prefilter: the distance mean's closed form is the brute-force mean over the square") {
    CHECK(checkDoubleForm(distanceCases()) == 360);
    // Its limits: a hairline's share of a wide pixel, 2h / pixel, wherever it crosses; nothing
    // past the footprint's reach; solid within a stroke wider than the pixel.
    CHECK(distanceMeanInk(0.1, 0.05, 10.0, 0.0) == doctest::Approx(0.01).epsilon(1e-3));
    // (a trapezoid 14 wide, 1/8 high over its middle 2)
    CHECK(distanceMeanInk(0.1, 0.05, 6.0, 8.0) == doctest::Approx(0.1 / 8.0));
    CHECK(distanceMeanInk(3.0, 0.5, 0.8, 0.6) == doctest::Approx(0.0));
    CHECK(distanceMeanInk(0.2, 3.0, 0.8, 0.6) == doctest::Approx(1.0));
}

TEST_CASE("prefilter: every backend computes the distance mean the double form computes") {
    checkOnBackends(
        [](ir::Builder& b) {
            ir::BuiltValue d(b, b.uniform(0)), h(b, b.uniform(1)), along(b, b.uniform(2)),
                across(b, b.uniform(3));
            return distanceMeanInk(d, h, along, across).id;
        },
        distanceCases(), 2e-3);
}

TEST_CASE("prefilter: a family without an index draws its nearest member's mean over the pixel") {
    // A straight member through the origin with its normal at `angle` (uniforms 4, 5: its
    // cosine and sine): the distance |x cos + y sin| of the world point (uniforms 0, 1, the
    // kernel's independents), whose gradient (AD) is the normal; half-width and pixel in
    // uniforms 2 and 3. A distance that does not vary (the second kernel) has no normal to
    // read, and the footprint is a box of the pixel's side.
    test::KernelProbe normal(
        1,
        [](ir::Builder& b) {
            ir::ValueId x = b.emit(ir::Op::Indep, {b.uniform(0)}, 0.0, 0);
            ir::ValueId y = b.emit(ir::Op::Indep, {b.uniform(1)}, 0.0, 1);
            ir::ValueId d = b.abs(b.add(b.mul(x, b.uniform(4)), b.mul(y, b.uniform(5))));
            b.output(0, distanceInk(b, d, b.uniform(2), ir::kNoValue, ir::kNoValue,
                                    PixelFootprint{b.uniform(3)}));
        },
        true);
    test::KernelProbe box(
        1,
        [](ir::Builder& b) {
            b.output(0, distanceInk(b, b.uniform(0), b.uniform(1), ir::kNoValue, ir::kNoValue,
                                    PixelFootprint{b.uniform(2)}));
        },
        true);
    // A distance computed from a derivative (here the same line's, |x cos + y sin| times the
    // x-derivative of x) reads the normal from the gradient the family gives (uniforms 4, 5).
    test::KernelProbe given(
        1,
        [](ir::Builder& b) {
            ir::ValueId x = b.emit(ir::Op::Indep, {b.uniform(0)}, 0.0, 0);
            ir::ValueId y = b.emit(ir::Op::Indep, {b.uniform(1)}, 0.0, 1);
            ir::ValueId one = b.emit(ir::Op::DerivX, {x});
            ir::ValueId d =
                b.mul(b.abs(b.add(b.mul(x, b.uniform(4)), b.mul(y, b.uniform(5)))), one);
            b.output(0, distanceInk(b, d, b.uniform(2), b.uniform(4), b.uniform(5),
                                    PixelFootprint{b.uniform(3)}));
        },
        true);
    for (const std::string& backend : test::probeBackends()) {
        CAPTURE(backend);
        if (!normal.use(backend) || !box.use(backend) || !given.use(backend)) continue;
        for (double pixel : {0.5, 1.0, 4.0})
            for (double angle : {0.0, 0.4, 1.1, 2.5})
                for (double d : {0.01, 0.35, 1.2})
                    for (double h : {0.05, 0.6}) {
                        CAPTURE(pixel);
                        CAPTURE(angle);
                        CAPTURE(d);
                        CAPTURE(h);
                        const double c = std::cos(angle), s = std::sin(angle);
                        const double blur = angle == 0.0 ? 1.0 / 16 : 0.0;
                        CHECK(std::abs(normal.run({d * c, d * s, h, pixel, c, s})[0] -
                                       bruteDistanceMean(d, h, pixel * std::abs(c),
                                                         pixel * std::abs(s))) <=
                              4.0 / 256 + 1e-3 + blur);
                        CHECK(given.run({d * c, d * s, h, pixel, c, s})[0] ==
                              doctest::Approx(normal.run({d * c, d * s, h, pixel, c, s})[0]));
                        CHECK(std::abs(box.run({d, h, pixel})[0] -
                                       bruteDistanceMean(d, h, pixel, 0.0)) <=
                              2.0 / 256 + 1.0 / 16);
                    }
    }
}

TEST_CASE("prefilter: a phase family draws the square pixel's mean of its stroke at every nu") {
    // Uniforms: index, |grad index|, distance, half-width, pixel; the gradient 0.3 radians off
    // the pixel's first side; first member 1 or none.
    auto kernel = [](std::optional<int> first) {
        return test::KernelProbe(
            1,
            [first](ir::Builder& b) {
                ir::ValueId grad = b.uniform(1);
                Footprint fp{b.uniform(0), grad, b.mul(grad, b.constF(std::cos(0.3))),
                             b.mul(grad, b.constF(std::sin(0.3))), first};
                b.output(0,
                         meanInk(b, fp, b.uniform(2), b.uniform(3), PixelFootprint{b.uniform(4)}));
            },
            true);
    };
    test::KernelProbe plain = kernel(std::nullopt);
    test::KernelProbe folded = kernel(1);
    for (const std::string& backend : test::probeBackends()) {
        CAPTURE(backend);
        if (!plain.use(backend) || !folded.use(backend)) continue;
        const double h = 0.05;
        // |grad index| nu, pixel 1: nu members a pixel, from resolved (40 pixels a member) to
        // a hundred a pixel. The expectation: the unfloored stroke averaged over the square by
        // brute force, whatever nu (no hand-over to the point rule any more).
        for (double nu : {0.025, 0.1, 0.25, 0.4, 1.43, 100.0})
            for (double index : {2.3, 2.02, -7.49}) {
                CAPTURE(nu);
                CAPTURE(index);
                const double along = nu * std::cos(0.3), across = nu * std::sin(0.3);
                const double distance = std::abs(index - std::round(index)) / nu;
                CHECK(std::abs(plain.run({index, nu, distance, h, 1.0})[0] -
                               bruteSquareMean(index, along, across, h * nu)) <=
                      sampleTolerance(along + across) + 1e-3);
            }
        // A family that starts at member 1 takes its nearest member's distance mean where the
        // footprint reaches below it (here member 1, 0.1 / 1.43 world units away; a distance
        // given as a number has no normal to read, so the footprint is the pixel's box), and
        // the periodic mean above.
        const double nu = 1.0 / 0.7, d = 0.1 * 0.7;
        CHECK(std::abs(folded.run({0.9, nu, d, h, 1.0})[0] - bruteDistanceMean(d, h, 1.0, 0.0)) <=
              2.0 / 256 + 1.0 / 16);
        CHECK(std::abs(folded.run({5.1, nu, d, h, 1.0})[0] -
                       bruteSquareMean(5.1, nu * std::cos(0.3), nu * std::sin(0.3), h * nu)) <=
              sampleTolerance(nu * 1.25) + 1e-3);
    }
}

} // namespace
} // namespace moire::lower

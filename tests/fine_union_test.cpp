// The union of fine layers under the mean filter (compiler/lower/FineUnion.h,
// docs/filtering.md "Fine layers together"): two fine line families drawn at one sample a
// pixel against a brute-force 256-sample box filter of the exact pair field, where their
// members are finer than the pixels and their beat is not (the pixel holds the pair's
// correlated mean, and the fringe shows) and where the beat is finer too (the layers are
// independent, and the union of their means is right); the envelope view unmoved by the
// filter; the JIT and Vulkan against the interpreter. A pair's correlation is in closed form
// (sweptOverlap): checked in double against the brute-force mean of the two periodic strokes'
// composite, and drawn against the 24-tap sweep a longer run still takes.
#include "compiler/lower/FineUnion.h"
#include "runtime/output/Render.h"
#include "tests/support/BoxReference.h"
#include "tests/support/Support.h"

#include <cmath>
#include <complex>
#include <cstdio>
#include <doctest/doctest.h>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr int kW = 96, kH = 64; // the frame
constexpr double kStroke = 0.3; // every layer's stroke

// Upright-or-turned lines: members where (x cos a + y sin a) / spacing is whole.
struct Lines {
    double spacing, degrees;
    double index(double x, double y) const {
        const double a = degrees * M_PI / 180.0;
        return (x * std::cos(a) + y * std::sin(a)) / spacing;
    }
};

struct Pair {
    Lines a, b;
    double zoom;
    std::string scene() const {
        char buf[512];
        std::snprintf(
            buf, sizeof buf,
            "scene { size = (%d, %d) }\ncamera { zoom = %.17g }\n"
            "layer a { family = lines; spacing = %.17g; angle = %.17gdeg; stroke = %g }\n"
            "layer b { family = lines; spacing = %.17g; angle = %.17gdeg; stroke = %g }\n",
            kW, kH, zoom, a.spacing, a.degrees, kStroke, b.spacing, b.degrees, kStroke);
        return buf;
    }
    // The pair with a third layer that inks nothing (layer a again, at opacity 0): a run of
    // three, which the union sweeps (FineUnion.cpp), with the pair's beat and weight.
    std::string sweptScene() const {
        char buf[256];
        std::snprintf(buf, sizeof buf,
                      "layer c { family = lines; spacing = %.17g; angle = %.17gdeg; stroke = %g; "
                      "opacity = 0 }\n",
                      a.spacing, a.degrees, kStroke);
        return scene() + buf;
    }
    // The world point of a position in the frame: the origin at the middle, y up.
    void world(double px, double py, double& x, double& y) const {
        x = (px - 0.5 * kW) / zoom;
        y = (0.5 * kH - py) / zoom;
    }
    bool inked(double x, double y) const {
        auto on = [&](const Lines& l) {
            const double f = l.index(x, y);
            return std::abs(f - std::round(f)) * l.spacing < 0.5 * kStroke;
        };
        return on(a) || on(b);
    }
    // Each pixel's share of 256 samples (a rank-1 lattice) that either stroke inks.
    std::vector<double> bruteForce() const {
        return test::boxReference(
            kW, kH, zoom, [&](double x, double y) { return inked(x, y); }, test::kGolden256);
    }
    // The amplitude of the beat's fundamental in a picture: 2 |mean of ink exp(-2 pi i D)|,
    // D = f_a - f_b at the pixel's centre.
    double fringe(const std::vector<double>& ink) const {
        std::complex<double> sum = 0.0;
        for (int py = 0; py < kH; ++py)
            for (int px = 0; px < kW; ++px) {
                double x, y;
                world(px + 0.5, py + 0.5, x, y);
                const double d = a.index(x, y) - b.index(x, y);
                sum += ink[size_t(py) * kW + px] * std::polar(1.0, -2.0 * M_PI * d);
            }
        return 2.0 * std::abs(sum) / (double(kW) * kH);
    }
};

std::vector<double> inkOf(const Image& img) {
    std::vector<double> out(size_t(kW) * kH);
    for (int py = 0; py < kH; ++py)
        for (int px = 0; px < kW; ++px) out[size_t(py) * kW + px] = 1.0 - img.at(px, py, 0);
    return out;
}

double meanAbs(const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
    return sum / double(a.size());
}

CompileOptions pointFilter() {
    CompileOptions o;
    o.filter = sema::FilterMode::Point;
    return o;
}

// Lines 1 and 1.05 apart at 2 members a pixel: the beat is 21 units, 10.5 pixels.
const Pair kParallel{{1.0, 0.0}, {1.05, 0.0}, 0.5};
// Lines 1 apart turned 4 degrees from each other, 2.5 members a pixel: the beat,
// 1 / (2 sin 2deg) = 14.3 units, is 5.7 pixels, across both of the pixel's sides.
const Pair kTurned{{1.0, 0.0}, {1.0, 4.0}, 0.4};
// Lines 1 and 1.37 apart at 5 members a pixel: the beat, 3.7 units, is 0.74 pixels (and the
// pitches are far from a small ratio, which would lock the two into a higher character).
const Pair kFineBeat{{1.0, 0.0}, {1.37, 0.0}, 0.2};
// Lines 15 and 5.1 apart at 0.1 pixels a unit (0.67 and 2 members a pixel): the nominal
// pitches 15 and 5 license the (3, -1) beat, swept along w = (1, 3), whose fringe is 25 pixels.
const Pair kLicensed{{15.0, 0.0}, {5.1, 0.0}, 0.1};
// Crossed lines, 4 members a pixel: no beat at all.
const Pair kCrossed{{1.0, 0.0}, {1.0, 90.0}, 0.25};

} // namespace

TEST_CASE("fine union: the square pixel's transfer of a fundamental is the product of sincs") {
    // The mean over the pixel of cos(2 pi (along u + across v)), u, v in [-1/2, 1/2], brute
    // forced on a 512 x 512 grid, against footprintTransfer where neither side spans a period.
    for (double along : {0.05, 0.3, 0.7, 0.95})
        for (double across : {0.0, 0.2, 0.6}) {
            CAPTURE(along);
            CAPTURE(across);
            double sum = 0.0;
            const int n = 512;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) {
                    double u = (i + 0.5) / n - 0.5, v = (j + 0.5) / n - 0.5;
                    sum += std::cos(2.0 * M_PI * (along * u + across * v));
                }
            CHECK(lower::footprintTransfer(along, across) ==
                  doctest::Approx(sum / (double(n) * n)).epsilon(1e-3));
        }
    // Past a period of either side it is held at 0.
    CHECK(std::abs(lower::footprintTransfer(1.3, 0.1)) < 1e-12);
}

namespace {

// The periodic stroke: 1 within h of a whole number (in index units).
double box(double x, double h) {
    return std::abs(x - std::round(x)) <= h ? 1.0 : 0.0;
}

// The mean over u in [0, 1) of A(f1 + p u) B(f2 + q u), on a grid of n points (midpoints).
double bruteOverlap(double f1, double f2, int p, int q, double h1, double h2, int n = 200000) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
        const double u = (i + 0.5) / n;
        sum += box(f1 + p * u, h1) * box(f2 + q * u, h2);
    }
    return sum / n;
}

} // namespace

TEST_CASE("fine union: the pair's overlap in closed form is the strokes' mean product") {
    // Against the brute force, over offsets, widths up to touching and both directions of the
    // sweep, the diagonal (1, 1), the sum beat (1, -1) and licensed deviations (1, 3), (2, -3).
    const double widths[][2] = {{0.15, 0.15}, {0.05, 0.3}, {0.3, 0.45}, {0.5, 0.2}, {0.0, 0.2}};
    const int dirs[][2] = {{1, 1}, {1, -1}, {1, 3}, {2, -3}};
    for (const auto& w : widths)
        for (const auto& d : dirs)
            for (double f1 : {0.0, 0.13, 3.37, -7.71})
                for (double f2 : {0.0, 0.41, 12.9}) {
                    CAPTURE(w[0]);
                    CAPTURE(w[1]);
                    CAPTURE(d[0]);
                    CAPTURE(d[1]);
                    CAPTURE(f1);
                    CAPTURE(f2);
                    const double want = bruteOverlap(f1, f2, d[0], d[1], w[0], w[1]);
                    // The footprint held at its least (1e-3 of an index a side) blurs the
                    // trapezoid's corners by as much.
                    const double got =
                        lower::sweptOverlap<double>(f1, f2, d[0], d[1], w[0], w[1], 0.0, 0.0);
                    CHECK(std::abs(got - want) <= 2e-3);
                    if (d[0] == 1 && std::abs(d[1]) == 1)
                        CHECK(std::abs(lower::periodicBoxOverlap(d[1] > 0 ? f1 - f2 : f1 + f2, w[0],
                                                                 w[1]) -
                                       want) <= 1e-4);
                }
}

TEST_CASE("fine union: the pair's overlap averaged over the pixel is the brute-force mean") {
    // periodicBoxOverlapMean against periodicBoxOverlap averaged over the square pixel's
    // offsets, D + along u + across v, u and v on a 400 x 400 grid.
    for (double along : {0.02, 0.3, 0.9, 2.5})
        for (double across : {0.0, 0.1, 0.6})
            for (double offset : {0.0, 0.21, 0.5, 5.8}) {
                CAPTURE(along);
                CAPTURE(across);
                CAPTURE(offset);
                const double h1 = 0.15, h2 = 0.22;
                const int n = 400;
                double sum = 0.0;
                for (int i = 0; i < n; ++i)
                    for (int j = 0; j < n; ++j) {
                        const double u = (i + 0.5) / n - 0.5, v = (j + 0.5) / n - 0.5;
                        sum += lower::periodicBoxOverlap(offset + along * u + across * v, h1, h2);
                    }
                const double want = sum / (double(n) * n);
                CHECK(std::abs(lower::periodicBoxOverlapMean(offset, h1, h2, along, across) -
                               want) <= 2e-3);
            }
}

TEST_CASE("fine union: the correlation is the composite's mean less the means composited") {
    // Two layers of strengths k1, k2 and inks c1, c2 over `under`, their strokes at offset D:
    // the brute-force mean over the sweep of the over-composite, less the composite of the
    // layers' own means, is k1 k2 (E - a b) (under - c1) (FineUnion.cpp, pairCorrelation).
    const double k1 = 0.8, k2 = 0.6, h1 = 0.2, h2 = 0.12;
    const double under[4] = {0.9, 0.85, 0.7, 1.0}, c1[4] = {0.1, 0.3, 0.5, 1.0},
                 c2[4] = {0.6, 0.2, 0.1, 1.0};
    for (double offset : {0.0, 0.1, 0.3, 0.47}) {
        CAPTURE(offset);
        const int n = 100000;
        double mean[4] = {0, 0, 0, 0}, a = 0, bb = 0;
        for (int i = 0; i < n; ++i) {
            const double u = (i + 0.5) / n;
            const double cov1 = k1 * box(offset + u, h1), cov2 = k2 * box(u, h2);
            a += cov1 / n;
            bb += cov2 / n;
            for (int ch = 0; ch < 4; ++ch) {
                const double one = under[ch] * (1 - cov1) + c1[ch] * cov1;
                mean[ch] += (one * (1 - cov2) + c2[ch] * cov2) / n;
            }
        }
        const double e = lower::periodicBoxOverlap(offset, h1, h2);
        for (int ch = 0; ch < 4; ++ch) {
            CAPTURE(ch);
            const double one = under[ch] * (1 - a) + c1[ch] * a;
            const double pivot = one * (1 - bb) + c2[ch] * bb;
            const double want = mean[ch] - pivot;
            const double got = k1 * k2 * (e - 4 * h1 * h2) * (under[ch] - c1[ch]);
            CHECK(std::abs(got - want) <= 1e-4);
        }
    }
}

TEST_CASE("fine union: unresolved members with a resolved beat draw the pair's fringe") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (const Pair* pair : {&kParallel, &kTurned}) {
        CAPTURE(pair->scene());
        const std::vector<double> want = pair->bruteForce();
        auto program = test::compileOk(pair->scene()); // the default filter: mean
        const std::vector<double> got = inkOf(test::renderScene(*program, *interp));
        const double error = meanAbs(got, want);
        const double fringe = pair->fringe(want), shown = pair->fringe(got);
        INFO("error ", error, ", fringe ", shown, " against ", fringe);
        CHECK(fringe > 0.1); // the brute force holds a fringe
        CHECK(error <= 0.02);
        CHECK(shown == doctest::Approx(fringe).epsilon(0.1));
        // Point-sampled, the floored strokes fill the pixel and the fringe is gone.
        auto point = test::compileOk(pair->scene(), pointFilter());
        const std::vector<double> flat = inkOf(test::renderScene(*point, *interp));
        CHECK(meanAbs(flat, want) > 10.0 * error);
        CHECK(pair->fringe(flat) < 0.5 * fringe);
    }
}

TEST_CASE("fine union: the pair's closed form draws what the sweep draws, a little sharper") {
    // The closed form against the 24-tap sweep (the same pair in a run of three whose third
    // layer inks nothing), both against the brute force: the two agree to within the sweep's
    // own error (its taps' antialias band softens the strokes' overlap, and it weights every
    // harmonic of the beat by the fundamental's transfer), and the closed form is no further
    // from the brute force.
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (const Pair* pair : {&kParallel, &kTurned, &kFineBeat}) {
        CAPTURE(pair->scene());
        const std::vector<double> want = pair->bruteForce();
        const std::vector<double> closed =
            inkOf(test::renderScene(*test::compileOk(pair->scene()), *interp));
        const std::vector<double> swept =
            inkOf(test::renderScene(*test::compileOk(pair->sweptScene()), *interp));
        const double apart = meanAbs(closed, swept);
        const double errClosed = meanAbs(closed, want), errSwept = meanAbs(swept, want);
        INFO("closed against swept ", apart, ", error closed ", errClosed, ", swept ", errSwept);
        CHECK(apart <= 0.02);
        CHECK(apart <= errSwept);
        CHECK(errClosed <= errSwept + 1e-3);
    }
    // A licensed direction (w = (1, 3)) in closed form, against the brute force: its fringe is
    // the (3, -1) beat's, which the pixel's mean of the strokes' union shows as it is.
    const std::vector<double> want = kLicensed.bruteForce();
    const std::vector<double> got =
        inkOf(test::renderScene(*test::compileOk(kLicensed.scene()), *interp));
    const std::vector<double> flat =
        inkOf(test::renderScene(*test::compileOk(kLicensed.scene(), pointFilter()), *interp));
    INFO("licensed: error ", meanAbs(got, want), ", point sampled ", meanAbs(flat, want));
    CHECK(meanAbs(got, want) <= 0.02);
}

TEST_CASE("fine union: where the beat is finer than the pixels too, the layers are independent") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (const Pair* pair : {&kFineBeat, &kCrossed}) {
        CAPTURE(pair->scene());
        const std::vector<double> want = pair->bruteForce();
        auto program = test::compileOk(pair->scene());
        const std::vector<double> got = inkOf(test::renderScene(*program, *interp));
        double mean = 0.0;
        for (double v : want) mean += v / double(want.size());
        // The union of the two means, 1 - (1 - 0.3 / s_a)(1 - 0.3 / s_b), is the field's tone.
        const double independent =
            1.0 - (1.0 - kStroke / pair->a.spacing) * (1.0 - kStroke / pair->b.spacing);
        CHECK(mean == doctest::Approx(independent).epsilon(0.03));
        CHECK(meanAbs(got, want) <= 0.02);
    }
}

TEST_CASE("fine union: the envelope view is the filter's to leave alone") {
    // The filter acts on the pattern: the envelope view draws the same under either filter, and
    // so does the right half of the split view.
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (sema::ViewMode view : {sema::ViewMode::Envelope, sema::ViewMode::Split}) {
        CompileOptions mean, point = pointFilter();
        mean.view = point.view = view;
        const Image a = test::renderScene(*test::compileOk(kParallel.scene(), mean), *interp);
        const Image b = test::renderScene(*test::compileOk(kParallel.scene(), point), *interp);
        Image right = a, rightPoint = b;
        if (view == sema::ViewMode::Split) {
            right = test::renderWindow(*test::compileOk(kParallel.scene(), mean), *interp,
                                       kW / 2 + 2, 0, kW / 2 - 2, kH);
            rightPoint = test::renderWindow(*test::compileOk(kParallel.scene(), point), *interp,
                                            kW / 2 + 2, 0, kW / 2 - 2, kH);
        }
        CHECK(test::compareImages(right, rightPoint, 0.0).maxAbs == 0.0);
    }
}

TEST_CASE("fine union: the JIT and the GPU draw the union the interpreter draws") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (const Pair* pair : {&kParallel, &kTurned, &kFineBeat, &kLicensed}) {
        auto program = test::compileOk(pair->scene());
        const Image ref = test::renderScene(*program, *interp);
        for (const char* name : {"jit", "vulkan"}) {
            CAPTURE(name);
            CAPTURE(pair->scene());
            auto backend = test::makeBackendOrSkip(name);
            if (!backend) continue;
            test::ImageDiff d =
                test::compareImages(ref, test::renderScene(*program, *backend), 2.0 / 255);
            CHECK(d.fractionWithin() >= 0.999);
            CHECK(d.meanAbs <= 0.5 / 255.0);
        }
    }
}

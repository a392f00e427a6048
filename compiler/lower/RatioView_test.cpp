// The ratio view's colours and the overlay's fringe curves (RatioView.h) on every backend that
// runs here: the curves against the level sets of two line families solved by hand, the
// colours against the palette.
#include "compiler/lower/KernelProbe_test.h"
#include "compiler/lower/RatioView.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>

using namespace moire;

namespace {

constexpr double kDeg = std::numbers::pi / 180;

// Two line families: idx1 = x / s1, idx2 = (x cos t + y sin t) / s2. The kernel's uniforms
// are the world point (0, 1) and the world size of a pixel (2); its outputs the overlay's
// coverage, min mu, the ratio view's straight RGB, and the overlay laid over white paper.
test::KernelProbe linesProbe(double s1, double s2, double turn) {
    return test::KernelProbe(8, [=](ir::Builder& b) {
        ir::ValueId x = b.uniform(0), y = b.uniform(1), pixel = b.uniform(2);
        lower::LayerFields f1, f2;
        f1.index = b.mul(x, b.constF(1 / s1));
        f1.gradX = b.constF(1 / s1);
        f1.gradY = b.constF(0.0);
        f2.index =
            b.add(b.mul(x, b.constF(std::cos(turn) / s2)), b.mul(y, b.constF(std::sin(turn) / s2)));
        f2.gradX = b.constF(std::cos(turn) / s2);
        f2.gradY = b.constF(std::sin(turn) / s2);
        f1.distance = f2.distance = b.constF(0.0);
        const std::vector<lower::LayerFields> layers = {f1, f2};
        lower::Character c = lower::stackCharacter(b, layers);
        b.output(0, lower::overlayCoverage(b, c, layers, pixel));
        b.output(1, c.mu);
        lower::Ink ratio = lower::ratioViewInk(b, c);
        b.output(2, ratio.r);
        b.output(3, ratio.g);
        b.output(4, ratio.b);
        ir::ValueId one = b.constF(1.0);
        lower::Ink over =
            lower::overlayFringes(b, lower::paper(b, one, one, one, one), c, layers, pixel);
        b.output(5, over.r);
        b.output(6, over.g);
        b.output(7, over.b);
    });
}

// The antialiased line of the overlay at `d` pixels from its centre line.
double lineCoverage(double d) {
    const double h = lower::kOverlayHalfWidthPixels, a = lower::kAntialiasPixels;
    const double u = std::clamp((d - (h - a)) / (2 * a), 0.0, 1.0);
    return 1 - u * u * (3 - 2 * u);
}

} // namespace

TEST_CASE("ratio view: the overlay draws the fringe lines of two line families where they are") {
    // Pitches 10 and 10.4, 1 degree apart: the (1, -1) fringes are the lines
    // x / s1 - (x cos t + y sin t) / s2 = n. Solved by hand for x at two heights, each gives a
    // line through two points; the overlay's coverage at a point is the antialiased line at
    // the point's distance (in pixels) from the nearest of them.
    const double s1 = 10, s2 = 10.4, t = 1 * kDeg;
    test::KernelProbe probe = linesProbe(s1, s2, t);
    const double slope = 1 / s1 - std::cos(t) / s2; // d(D)/dx
    auto xOn = [&](int n, double y) { return (n + y * std::sin(t) / s2) / slope; };
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend)) continue;
        INFO(backend);
        // Single precision: D ~ 3 is the difference of indices ~ 80, so the JIT's and the
        // GPU's D are off by about 1e-5, a hundredth of a pixel at these pitches; the
        // interpreter computes in double.
        const double tol = backend == "interp" ? 1e-5 : 0.02;
        for (double pixel : {0.5, 2.0})
            for (double y : {-300.0, 40.0, 900.0})
                for (double off : {0.0, 0.3, 0.6, 0.9, 1.2, 1.6, 3.0, -0.45, -1.1}) {
                    // A point `off` pixels (horizontally) from fringe n = 3 at height y.
                    const double x = xOn(3, y) + off * pixel;
                    double nearest = INFINITY;
                    for (int n = 1; n <= 5; ++n) {
                        const double x0 = xOn(n, 0), x1 = xOn(n, 1000); // two points of it
                        const double dx = x1 - x0, dy = 1000;
                        const double dist =
                            std::abs(dx * (y - 0) - dy * (x - x0)) / std::hypot(dx, dy);
                        nearest = std::min(nearest, dist / pixel);
                    }
                    const std::vector<double> got = probe.run({x, y, pixel});
                    INFO("pixel ", pixel, " y ", y, " off ", off, " distance ", nearest);
                    CHECK(got[1] <= lower::kFringeMerit);
                    CHECK(std::abs(got[0] - lineCoverage(nearest)) <= tol);
                }
        // On a fringe line the overlay is crimson over the paper.
        const std::vector<double> on = probe.run({xOn(2, 5.0), 5.0, 1.0});
        CHECK(on[5] == doctest::Approx(lower::kOverlayCrimson[0]).epsilon(1e-4));
        CHECK(on[6] == doctest::Approx(lower::kOverlayCrimson[1]).epsilon(1e-4));
        CHECK(on[7] == doctest::Approx(lower::kOverlayCrimson[2]).epsilon(1e-4));
    }
}

TEST_CASE("ratio view: no overlay where no fringe exists") {
    // 40 degrees apart, pitches 10 and 10.4: no character is slow (min mu > 1/4), so nothing
    // is drawn even on the level sets of the character that wins.
    const double s1 = 10, s2 = 10.4, t = 40 * kDeg;
    test::KernelProbe probe = linesProbe(s1, s2, t);
    for (const std::string& backend : test::probeBackends()) {
        if (!probe.use(backend)) continue;
        INFO(backend);
        for (double x : {0.0, 3.3, 17.0, 101.5})
            for (double y : {0.0, 7.25, -50.0}) {
                const std::vector<double> got = probe.run({x, y, 1.0});
                CHECK(got[1] > lower::kFringeMerit);
                CHECK(got[0] == 0.0);
                CHECK(got[5] == 1.0);
            }
    }
}

TEST_CASE("ratio view: grey is min mu, hued by the winner's order") {
    struct Case {
        double s1, s2, turnDeg;
        int order; // |k1| + |k2| of the winner, by hand
    };
    // (1, -1) at close pitches; (3, -1) at 15 and 5 twisted 2 degrees (Fig. 7); (2, -1) at
    // 10 and 5.1; and far apart, where every order reads white.
    for (const Case& cs : {Case{10, 10.4, 1, 2}, Case{15, 5, 2, 4}, Case{10, 5.1, 0.5, 3}}) {
        test::KernelProbe probe = linesProbe(cs.s1, cs.s2, cs.turnDeg * kDeg);
        const auto& colour = lower::kOrderColours[cs.order == 2 ? 0 : (cs.order == 3 ? 1 : 2)];
        for (const std::string& backend : test::probeBackends()) {
            if (!probe.use(backend)) continue;
            INFO(backend, " ", cs.s1, " ", cs.s2);
            const std::vector<double> got = probe.run({1.5, 2.5, 1.0});
            const double grey = std::clamp(got[1] / lower::kRatioScale, 0.0, 1.0);
            CHECK(got[1] < lower::kFringeMerit);
            for (int ch = 0; ch < 3; ++ch)
                CHECK(got[2 + ch] ==
                      doctest::Approx(colour[ch] + (1 - colour[ch]) * grey).epsilon(1e-4));
        }
    }
}

// A grid given by its distance alone, its lines crowding (compiler/lower/DistanceGrid.h,
// docs/filtering.md "A grid given by its distance"): the parts' normals run two ways, each
// way's spacing is read by probes, and the pixel's mean is the two families' closed forms laid
// as independent inks. Drawn at one sample a pixel against a brute-force box filter of the
// exact field (10946 samples a pixel, a rank-1 lattice), for square grids at several turns
// and densities, a grid whose two spacings differ, and one whose lines cross at 60 degrees;
// and the window's mean ink against the share of the plane the strokes cover.
#include "runtime/output/Render.h"
#include "tests/support/BoxReference.h"
#include "tests/support/Support.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <doctest/doctest.h>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr int kW = 48, kH = 32;
// Lines along two directions, (cos a, sin a) and (cos b, sin b) their normals, `first` and
// `second` apart, each stroke `stroke` wide; drawn at `zoom` pixels a world unit.
struct Grid {
    double first, second, a, b, stroke, zoom;
    double rmse; // the most RMSE against the brute force
    std::string scene() const {
        char buf[1024];
        std::snprintf(buf, sizeof buf,
                      "scene { size = (%d, %d) }\ncamera { zoom = %.17g }\n"
                      "family grid {\n let u = x * %.17g + y * %.17g\n"
                      " let v = x * %.17g + y * %.17g\n"
                      " distance = min(abs(u - %.17g * round(u / %.17g)), abs(v - %.17g * "
                      "round(v / %.17g)))\n}\n"
                      "layer a { family = grid; stroke = %.17g }\n",
                      kW, kH, zoom, std::cos(a), std::sin(a), std::cos(b), std::sin(b), first,
                      first, second, second, stroke);
        return buf;
    }
    bool inked(double x, double y) const {
        auto near = [&](double angle, double spacing) {
            const double u = x * std::cos(angle) + y * std::sin(angle);
            return std::abs(u - spacing * std::round(u / spacing)) < 0.5 * stroke;
        };
        return near(a, first) || near(b, second);
    }
    std::vector<double> bruteForce() const {
        return test::boxReference(
            kW, kH, zoom, [&](double x, double y) { return inked(x, y); }, test::kFibonacci10946);
    }
    // The share of the plane within half a stroke of a line: the two families' strokes
    // cross at every offset alike, each covering stroke / spacing of the plane.
    double share() const { return 1.0 - (1.0 - stroke / first) * (1.0 - stroke / second); }
};

constexpr double kDeg = M_PI / 180.0;

} // namespace

TEST_CASE("distance grid: a crowded grid's mean against the box filter of its exact field") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    // RMSE read by the tubes before (DistanceTubes.h), and now:
    const Grid kGrids[] = {
        // A square grid, six lines a pixel each way, square to the pixels (every pixel's
        // centre on a crossing, and every part where two lines are as near: the parts all
        // read one way, and the centre's ray runs along a line), 0.64 (solid ink) -> 0.0030;
        // turned 10 degrees, 0.0058 -> 0.0003; 30 degrees, 0.162 (ink 0.393) -> 0.0005.
        {1, 1, 0, 90 * kDeg, 0.2, 1.0 / 6, 0.006},
        {1, 1, 10 * kDeg, 100 * kDeg, 0.2, 1.0 / 6, 0.001},
        {1, 1, 30 * kDeg, 120 * kDeg, 0.2, 1.0 / 6, 0.001},
        // 3.3 a pixel, 0.0022 -> 0.0005; 20 a pixel, where the parts stand five lines apart
        // and many read one way alone, 0.037 -> 0.0043 with the looks for a crossing line a
        // lattice (aliasing with the grid as the parts do), 0.0022 with them an R2 sequence.
        {1, 1, 10 * kDeg, 100 * kDeg, 0.2, 0.3, 0.0015},
        {1, 1, 10 * kDeg, 100 * kDeg, 0.2, 0.05, 0.0032},
        // Spacings 1 and 1.6: 0.0095 -> 0.0020.
        {1, 1.6, 10 * kDeg, 100 * kDeg, 0.2, 1.0 / 6, 0.004},
        // Lines crossing at 60 degrees: 0.018 -> 0.0004.
        {1, 1, 10 * kDeg, 70 * kDeg, 0.2, 1.0 / 6, 0.001},
    };
    for (const Grid& g : kGrids) {
        const std::string text = g.scene();
        CAPTURE(text);
        auto drawn = test::compileOk(text);
        const Image img = test::renderScene(*drawn, *backend);
        REQUIRE(img.width == kW);
        const std::vector<double> want = g.bruteForce();
        const test::InkError e = test::inkError(img, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE("RMSE ", e.rmse, " ink ", e.ink, " brute force ", e.exact, " share ",
                    g.share());
        CHECK(e.rmse <= g.rmse);
        CHECK(std::abs(e.ink - g.share()) <= 0.01 * g.share());
    }
}

namespace {

// Lines along three directions whose normals stand 60 degrees apart from `a` on, each
// family `spacing[k]` apart and moved `offset[k]` of a spacing along its normal: the triangle
// lattice's lines where no family is moved (every third line through each crossing of the
// other two), a trihexagonal pattern where one is moved half a spacing.
struct ThreeWays {
    double spacing[3], offset[3], a, stroke, zoom;
    double rmse;
    double step = M_PI / 3.0; // between the families' normals
    double normal(int k) const { return a + k * step; }
    std::string scene() const {
        std::string d;
        char buf[512];
        for (int k = 0; k < 3; ++k) {
            std::snprintf(buf, sizeof buf, " let u%d = x * %.17g + y * %.17g - %.17g\n", k,
                          std::cos(normal(k)), std::sin(normal(k)), offset[k] * spacing[k]);
            d += buf;
        }
        auto term = [&](int k) {
            std::snprintf(buf, sizeof buf, "abs(u%d - %.17g * round(u%d / %.17g))", k, spacing[k],
                          k, spacing[k]);
            return std::string(buf);
        };
        const std::string t0 = term(0), t1 = term(1), t2 = term(2);
        std::snprintf(buf, sizeof buf, "scene { size = (%d, %d) }\ncamera { zoom = %.17g }\n", kW,
                      kH, zoom);
        return std::string(buf) + "family lines3 {\n" + d + " distance = min(" + t0 + ", min(" +
               t1 + ", " + t2 +
               "))\n}\nlayer a { family = lines3; stroke = " + std::to_string(stroke) + " }\n";
    }
    bool inked(double x, double y) const {
        for (int k = 0; k < 3; ++k) {
            const double u =
                x * std::cos(normal(k)) + y * std::sin(normal(k)) - offset[k] * spacing[k];
            if (std::abs(u - spacing[k] * std::round(u / spacing[k])) < 0.5 * stroke) return true;
        }
        return false;
    }
};

} // namespace

TEST_CASE("distance grid: three ways of lines crowding against the box filter of their exact "
          "field") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    // RMSE read by the tubes before (DistanceTubes.h), and now:
    const ThreeWays kCases[] = {
        // The triangle lattice's lines, six a pixel each way, turned 10 degrees: 0.034 ->
        // 0.00095; one family moved half a spacing (trihexagonal), 0.033 -> 0.0035; the third
        // family's spacing 2% wider (the three indices' sum beating across the frame), 0.040
        // -> 0.0012.
        {{1, 1, 1}, {0, 0, 0}, 10 * kDeg, 0.2, 1.0 / 6, 0.002},
        {{1, 1, 1}, {0, 0, 0.5}, 10 * kDeg, 0.2, 1.0 / 6, 0.005},
        {{1, 1, 1.02}, {0, 0, 0}, 10 * kDeg, 0.2, 1.0 / 6, 0.002},
        // 3.3 and 20 a pixel: 0.012 -> 0.0016, 0.029 -> 0.0015.
        {{1, 1, 1}, {0, 0, 0}, 10 * kDeg, 0.2, 0.3, 0.003},
        {{1, 1, 1}, {0, 0, 0}, 10 * kDeg, 0.2, 0.05, 0.003},
        // Turned 37 degrees, 0.00066; spacings 1, 1.3 and 1.6 moved apart, 0.0033; normals 50
        // degrees apart, 0.0014 (0.026 before the check for a line half-way, which the probes
        // stepped over where the third family's line passed by it); 65 degrees apart, a
        // narrower stroke, 0.0010.
        {{1, 1, 1}, {0, 0, 0}, 37 * kDeg, 0.2, 1.0 / 6, 0.0015},
        {{1, 1.3, 1.6}, {0, 0.2, 0.1}, 10 * kDeg, 0.2, 1.0 / 6, 0.005},
        {{1, 1, 1}, {0, 0, 0}, 10 * kDeg, 0.2, 1.0 / 6, 0.0025, 50 * kDeg},
        {{1, 1, 1}, {0, 0.3, 0.6}, 25 * kDeg, 0.15, 1.0 / 6, 0.002, 65 * kDeg},
    };
    for (const ThreeWays& g : kCases) {
        const std::string text = g.scene();
        CAPTURE(text);
        auto drawn = test::compileOk(text);
        const Image img = test::renderScene(*drawn, *backend);
        REQUIRE(img.width == kW);
        const std::vector<double> want = test::boxReference(
            kW, kH, g.zoom, [&](double x, double y) { return g.inked(x, y); },
            test::kFibonacci10946);
        const test::InkError e = test::inkError(img, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE("RMSE ", e.rmse, " ink ", e.ink, " brute force ", e.exact);
        CHECK(e.rmse <= g.rmse);
        CHECK(std::abs(e.ink - e.exact) <= 0.01 * e.exact);
    }
}

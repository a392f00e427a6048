// The stdlib families' special cases and identities, the AD gradient against Table 1's
// |grad phi| column, and the JIT against the exact interpreter. The distance checks against
// true Euclidean distance are in families_test.cpp.
#include "runtime/Probe.h"
#include "tests/support/NearestMember.h"
#include "tests/support/Support.h"

#include <cfloat>
#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace moire;
using test::RefLayer;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

struct Fields {
    double index, distance, gx, gy;
};

Fields fieldsAt(Prober& probe, const SceneProgram& program, int layer, double x, double y) {
    std::vector<double> v = probe.at(x, y);
    const auto& l = program.layout;
    return {v[l.indexSlot(layer)], v[l.distanceSlot(layer)], v[l.gradXSlot(layer)],
            v[l.gradYSlot(layer)]};
}

// Seeded points, uniform in the square [-half, half]^2 about (cx, cy).
std::vector<std::pair<double, double>> points(int n, double half, uint64_t seed, double cx = 0.0,
                                              double cy = 0.0) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-half, half);
    std::vector<std::pair<double, double>> out;
    for (int i = 0; i < n; ++i) {
        double x = u(rng), y = u(rng);
        out.push_back({cx + x, cy + y});
    }
    return out;
}

// Two layers that must draw the same thing: equal index and distance at random points.
// Returns how many points differed by more than `tol` (relative), so a caller can also
// check that two layers that should differ do.
int differingPoints(const std::string& a, const std::string& b, double tol, uint64_t seed) {
    auto program =
        test::compileOk(a + "\n" + b, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    int differ = 0;
    for (auto [x, y] : points(100, 40.0, seed)) {
        Fields fa = fieldsAt(probe, *program, 0, x, y), fb = fieldsAt(probe, *program, 1, x, y);
        bool same = std::fabs(fa.index - fb.index) <= tol * (1.0 + std::fabs(fa.index)) &&
                    std::fabs(fa.distance - fb.distance) <= tol * (1.0 + fa.distance);
        differ += same ? 0 : 1;
    }
    return differ;
}

} // namespace

TEST_CASE("families: the hyperbola never inks its excluded member 0, the asymptote pair") {
    // Member 0 would be the asymptote pair x = +-y, where |grad phi| = |p| / phi is infinite,
    // so the family starts at n = 1. Near the asymptotes and close to the centre, member 1
    // is far away (x^2 - y^2 = +-s^2 passes at about s^2 / 2|p| from the asymptotes), and
    // the distance must say so. Dividing the clamped residual by the local gradient, as
    // plain Eq. 5 does, made it shrink to zero on the asymptotes (0.34 at (5, 5.01) with
    // s = 8, where the truth is 4.01), so a black stroke showed member 0 after all.
    for (double phase : {0.0, -2.0, 3.0}) {
        RefLayer ref{test::refHyperbola(), 8.0, phase, 0.0, 0.0, 0.0};
        std::string layer = test::layerSource("hyperbola", "stroke = 1; color = #000000", ref);
        auto program = test::compileOk("scene { background = #ffffff }\n" + layer,
                                       {.mode = CompileOptions::Mode::Probe, .layerFields = true});
        Prober probe(*program, nullptr);
        CAPTURE(layer);
        int white = 0;
        for (double t : {0.5, 1.0, 2.0, 3.5, 5.0, 7.0, 9.0}) {
            for (double off : {0.0, 1e-6, 1e-3, 1e-2, 0.1}) {
                for (auto [x, y] :
                     {std::pair{t, t + off}, {-t - off, t}, {t + off, -t}, {-t, -t - off}}) {
                    CAPTURE(x);
                    CAPTURE(y);
                    std::vector<double> v = probe.at(x, y);
                    double d = v[program->layout.distanceSlot(0)];
                    test::Nearest truth = test::nearestMember(ref, x, y, 3.0 * ref.spacing);
                    REQUIRE(truth.found);
                    CHECK(truth.member >= 1);
                    // Rounding the index alone would pick member 0 (or below) here: the
                    // clamp to the first member is what these points exercise.
                    CHECK(v[program->layout.indexSlot(0)] < 0.5);
                    // The renderer never puts member 1 nearer than it is...
                    CHECK(d >= 0.97 * truth.distance);
                    // ...so where it is beyond the stroke (half-width 1.15 + band 0.7 at a
                    // pixel per world unit), the asymptote stays paper-white.
                    if (truth.distance > 2.5) {
                        CHECK(v[0] == 1.0); // red of the final colour
                        ++white;
                    }
                }
            }
        }
        CHECK(white >= 80); // of the 140 points, most are far from member 1
    }
}

TEST_CASE("families: a spiral's arm count is rounded, half away from zero, and 0 arms is circles") {
    // The phase r - M s theta / tau closes across atan2's cut only for whole M, so `arms` is
    // rounded; the two layers of each pair must then draw the same thing.
    auto spiral = [](const std::string& arms) {
        return "layer { family = spiral; spacing = 7; arms = " + arms + " }";
    };
    const std::vector<std::pair<std::string, std::string>> same = {
        {"1.4", "1"},   {"2.6", "3"}, {"2.5", "3"}, {"-2.5", "-3"},
        {"-1.4", "-1"}, {"0.4", "0"}, {"-0.3", "0"}};
    uint64_t seed = 1;
    for (const auto& [a, b] : same) {
        CAPTURE(a);
        CHECK(differingPoints(spiral(a), spiral(b), 1e-12, seed++) == 0);
    }
    CHECK(differingPoints(spiral("0"), "layer { family = circles; spacing = 7 }", 1e-12, seed++) ==
          0);
    // The comparison can see a difference: one arm is not two, nor turned the other way.
    CHECK(differingPoints(spiral("1"), spiral("2"), 1e-6, seed++) > 50);
    CHECK(differingPoints(spiral("1"), spiral("-1"), 1e-6, seed++) > 50);
}

TEST_CASE("families: a wave of amplitude 0 is vertical lines, and ngon is squares, hexagons and "
          "triangles") {
    CHECK(differingPoints(
              "layer { family = wave; spacing = 6; amplitude = 0; frequency = 1.7; shift = 20deg }",
              "layer { family = lines; spacing = 6 }", 1e-12, 11) == 0);
    CHECK(differingPoints("layer { family = wave; spacing = 6; amplitude = 2; frequency = 1.7 }",
                          "layer { family = lines; spacing = 6 }", 1e-6, 12) > 50);
    // The N-gon row, r cos(wrap(theta, 2 pi / N)), puts a facet normal at theta = 0 as the
    // square, hexagon and triangle rows do (a flat side facing +x), so no turn relates
    // them: sides = 4 is squares as they stand. (Squares turned by 45 degrees, which a
    // vertex-first convention would need, are a different pattern, as the last check shows.)
    const double tol = 1e-12; // the trigonometric and the abs/max forms agree to rounding
    CHECK(differingPoints("layer { family = ngon; sides = 4; spacing = 8; phase = 1 }",
                          "layer { family = squares; spacing = 8; phase = 1 }", tol, 13) == 0);
    CHECK(differingPoints(
              "layer { family = ngon; sides = 6; spacing = 8; origin = (3, -2); rotation = 17deg }",
              "layer { family = hexagons; spacing = 8; origin = (3, -2); rotation = 17deg }", tol,
              14) == 0);
    CHECK(differingPoints("layer { family = ngon; sides = 3; spacing = 5 }",
                          "layer { family = triangles; spacing = 5 }", tol, 15) == 0);
    CHECK(differingPoints("layer { family = ngon; sides = 4; spacing = 8 }",
                          "layer { family = squares; spacing = 8; rotation = 45deg }", 1e-6,
                          16) > 50);
}

TEST_CASE("families: the AD index gradient is Table 1's gradient, for every family") {
    // The gradient is not optional (spec 3.3): Eq. 5 divides by it. Here the kernel's index
    // gradient (forward-mode AD of the stdlib phase) must have the length |grad phi| / s of
    // Table 1's formula column, and point where central differences of Table 1's phase
    // say, in world coordinates (through each layer's origin and rotation).
    struct Case {
        std::string family, args;
        RefLayer ref;
    };
    auto layer = [](test::RefFamily f, double s, double phase, double ox, double oy,
                    double rotDeg) {
        return RefLayer{std::move(f), s, phase, ox, oy, rotDeg * kDeg};
    };
    const std::vector<Case> cases = {
        {"lines", "angle = 30deg", layer(test::refLines(30 * kDeg), 8, 1, 2, 3, 20)},
        {"circles", "", layer(test::refCircles(), 8, 0, -3, 1, 0)},
        {"squares", "", layer(test::refSquares(), 6, 2, 1, 1, 33)},
        {"triangles", "", layer(test::refTriangles(), 7, 0, 0, 0, -20)},
        {"hexagons", "", layer(test::refHexagons(), 9, 0, 4, -4, 10)},
        {"ngon", "sides = 7", layer(test::refNgon(7), 8, 0, 0, 0, 5)},
        {"wave", "amplitude = 12; frequency = 2; shift = 30deg",
         layer(test::refWave(12, 2, 30 * kDeg), 8, 0, 1, 2, 15)},
        {"parabola", "bend = 4", layer(test::refParabola(4), 8, 0, 0, -5, -40)},
        {"hyperbola", "", layer(test::refHyperbola(), 8, -2, 3, 3, 25)},
        {"spiral", "arms = -3", layer(test::refSpiral(-3, 6), 6, 0, -2, 2, 60)},
    };
    uint64_t seed = 40;
    for (const Case& c : cases) {
        std::string src = test::layerSource(c.family, c.args, c.ref);
        CAPTURE(src);
        auto program =
            test::compileOk(src, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
        Prober probe(*program, nullptr);
        const RefLayer& L = c.ref;
        int compared = 0;
        for (auto [x, y] : points(60, 40.0, seed++, L.originX, L.originY)) {
            CAPTURE(x);
            CAPTURE(y);
            Fields f = fieldsAt(probe, *program, 0, x, y);
            double lx, ly;
            L.toLocal(x, y, lx, ly);
            double want = L.family.gradNorm(lx, ly) / L.spacing;
            CHECK(std::hypot(f.gx, f.gy) == doctest::Approx(want).epsilon(1e-9));
            // Central differences of the index in world coordinates, on the branch of theta
            // at the point; skipped across a kink (a polygon's corner line, the hyperbola's
            // asymptotes), where the one-sided differences disagree.
            const double h = 1e-6 * L.spacing;
            auto u = [&](double wx, double wy) {
                double qx, qy;
                L.toLocal(wx, wy, qx, qy);
                return (L.family.phi(qx, qy, std::atan2(ly, lx)) - L.phase) / L.spacing;
            };
            double u0 = u(x, y);
            double fx = (u(x + h, y) - u0) / h, bx = (u0 - u(x - h, y)) / h;
            double fy = (u(x, y + h) - u0) / h, by = (u0 - u(x, y - h)) / h;
            if (std::hypot(fx - bx, fy - by) > 1e-4 * want) continue;
            CHECK(f.gx == doctest::Approx((fx + bx) / 2).epsilon(1e-5).scale(want));
            CHECK(f.gy == doctest::Approx((fy + by) / 2).epsilon(1e-5).scale(want));
            ++compared;
        }
        CHECK(compared >= 50);
    }
}

TEST_CASE("families: the JIT's fields agree with the exact interpreter's to single precision") {
    auto jit = test::makeBackendOrSkip("jit");
    if (!jit) return;
    const std::vector<std::string> layers = {
        "layer { family = circles; spacing = 5; phase = 1.5; origin = (3, -7) }",
        "layer { family = hexagons; spacing = 9; phase = 3; origin = (5, 1); rotation = 10deg }",
        "layer { family = ngon; sides = 7; spacing = 8; phase = 2 }",
        "layer { family = wave; spacing = 8; amplitude = 4; frequency = 2; shift = 45deg }",
        "layer { family = parabola; spacing = 6; bend = -2; origin = (-5, 3); rotation = 60deg }",
        "layer { family = hyperbola; spacing = 6; phase = -2; origin = (2, -3); rotation = 30deg }",
        "layer { family = spiral; spacing = 6; arms = -3; phase = 1.5; origin = (-4, 2); rotation "
        "= 45deg }",
    };
    uint64_t seed = 70;
    for (const std::string& src : layers) {
        CAPTURE(src);
        auto program =
            test::compileOk(src, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
        Prober exact(*program, nullptr), single(*program, jit.get());
        for (auto [x, y] : points(100, 40.0, seed++)) {
            CAPTURE(x);
            CAPTURE(y);
            Fields a = fieldsAt(exact, *program, 0, x, y), b = fieldsAt(single, *program, 0, x, y);
            // The JIT's kernel runs in float: the world point (up to ~45 units from the
            // origin here) and the phase are rounded to 24 bits, so the index is good to a
            // few ulps of |index| + |p| |grad index|, and the distance to that over the
            // gradient plus a few ulps of its own. Measured worst: 0.7 of one ulp of that
            // scale; 4 allow for the odd sin or atan2 that rounds the other way.
            double g = std::max(std::hypot(a.gx, a.gy), 1e-30);
            double indexTol = 4 * FLT_EPSILON * (1.0 + std::fabs(a.index) + std::hypot(x, y) * g);
            CHECK(std::fabs(a.index - b.index) <= indexTol);
            CHECK(std::fabs(a.distance - b.distance) <=
                  indexTol / g + 4 * FLT_EPSILON * a.distance);
        }
    }
}

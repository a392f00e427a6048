// Morphs between families (spec §8.3): `family = morph(timing, f0, f1, ...)`. The timing's
// raw progress is cut into one equal share per family; family k holds through its share and,
// in the share's last morph_time seconds, travels to the next with weight
// w = cubic_in_out(u), u the fraction of the change elapsed. What travels is the geometry:
// the phases are interpolated, phi = (1 - w) phi_k + w phi_next, and the blend drawn by
// Eq. 5. Held to independent expectations:
//  - the concentric families in closed form: the support functions rho and their gradients
//    (the active facet's unit normal), so the blend's distance is
//    |phi - s round(phi / s)| / |(1 - w) grad rho_k + w grad rho_next|;
//  - points placed on a blended member by solving along a ray, which must be inked: one
//    stroke travels, it does not break up or cross-fade;
//  - the timeline worked out here from the definition: which family when, the weight, the
//    wrap of a loop, the hold of once and pingpong, morph_time;
//  - walking morphs against an exhaustive scan of the blended members;
//  - mixed kinds (walking with non-walking) interpolate the two distances.
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr double kSpacing = 10.0;
const double kRoot3 = std::sqrt(3.0);

// A concentric shape: its support function and that function's gradient at a point.
struct Shape {
    std::function<double(double, double)> rho;
    std::function<std::pair<double, double>(double, double)> grad;
};

double sgn(double v) {
    return v < 0 ? -1.0 : 1.0;
}

const Shape kCircle{[](double x, double y) { return std::hypot(x, y); },
                    [](double x, double y) {
                        double r = std::hypot(x, y);
                        return std::pair{x / r, y / r};
                    }};
const Shape kHexagon{[](double x, double y) {
                         return std::max(std::fabs(x),
                                         std::fabs(x) / 2 + kRoot3 / 2 * std::fabs(y));
                     },
                     [](double x, double y) {
                         if (std::fabs(x) >= std::fabs(x) / 2 + kRoot3 / 2 * std::fabs(y))
                             return std::pair{sgn(x), 0.0};
                         return std::pair{sgn(x) / 2, kRoot3 / 2 * sgn(y)};
                     }};
const Shape kSquare{[](double x, double y) { return std::max(std::fabs(x), std::fabs(y)); },
                    [](double x, double y) {
                        if (std::fabs(x) >= std::fabs(y)) return std::pair{sgn(x), 0.0};
                        return std::pair{0.0, sgn(y)};
                    }};

// The distance to the nearest member of a family of spacing kSpacing with unit gradient.
double memberDistance(double phi) {
    return std::fabs(phi - kSpacing * std::round(phi / kSpacing));
}

// The blend of two shapes at weight w, by Eq. 5.
double blendDistance(const Shape& a, const Shape& b, double w, double x, double y) {
    const double phi = (1 - w) * a.rho(x, y) + w * b.rho(x, y);
    auto [ax, ay] = a.grad(x, y);
    auto [bx, by] = b.grad(x, y);
    return memberDistance(phi) / std::hypot((1 - w) * ax + w * bx, (1 - w) * ay + w * by);
}

double cubicInOut(double u) {
    return u < 0.5 ? 4 * u * u * u : 1 - std::pow(2 - 2 * u, 3) / 2;
}

CompileOptions probing() {
    CompileOptions o;
    o.layerFields = true;
    o.mode = CompileOptions::Mode::Probe;
    return o;
}

// Seeded points in the disc of radius 60 (six spacings), away from the centre (the
// families' common singular point) and from the shapes' corners, where a support function
// has no gradient and Eq. 5 differs from the true distance.
std::vector<std::pair<double, double>> points(uint64_t seed, int n = 60) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<std::pair<double, double>> out;
    auto nearCorner = [](double x, double y) {
        const double hexGap = std::fabs(std::fabs(x) / 2 - kRoot3 / 2 * std::fabs(y));
        return hexGap < 1e-3 * std::hypot(x, y) ||
               std::fabs(std::fabs(x) - std::fabs(y)) < 1e-3 * std::hypot(x, y);
    };
    while (static_cast<int>(out.size()) < n) {
        double r = 60 * std::sqrt(unit(rng)), a = 2 * std::numbers::pi * unit(rng);
        double x = r * std::cos(a), y = r * std::sin(a);
        if (r > 1 && !nearCorner(x, y)) out.emplace_back(x, y);
    }
    return out;
}

void near(double got, double want, double tolerance = 1e-9) {
    CAPTURE(got);
    CAPTURE(want);
    CHECK(std::fabs(got - want) <= tolerance);
}

// A morph of circles, hexagons and squares (layer 0) beside each family drawn alone
// (layers 1 to 3), on the timing `cycle`, whose declaration is given.
struct MorphScene {
    std::unique_ptr<SceneProgram> program;
    std::unique_ptr<Prober> probe;

    explicit MorphScene(const std::string& timing, const std::string& morphExtra = "") {
        const std::string s = "spacing = 10";
        std::string text = timing + "\n" +
                           "layer m { family = morph(cycle, circles, hexagons, squares); " + s +
                           morphExtra +
                           " }\n"
                           "layer c { family = circles; " +
                           s +
                           " }\n"
                           "layer h { family = hexagons; " +
                           s +
                           " }\n"
                           "layer q { family = squares; " +
                           s + " }\n";
        program = test::compileOk(text, probing());
        probe = std::make_unique<Prober>(*program, nullptr);
    }
    // The four layers' distances at (x, y), time t: morph, circles, hexagons, squares.
    std::vector<double> at(double x, double y, double t) {
        std::vector<double> v = probe->at(x, y, t);
        std::vector<double> d;
        for (int i = 0; i < 4; ++i) d.push_back(v[program->layout.distanceSlot(i)]);
        return d;
    }
    double morph(double x, double y, double t) { return at(x, y, t)[0]; }
};

// Every layer of a one-layer scene at (x, y): (distance, red channel of the pixel).
struct OneLayer {
    std::unique_ptr<SceneProgram> program;
    std::unique_ptr<Prober> probe;
    explicit OneLayer(const std::string& text) {
        program = test::compileOk(text, probing());
        probe = std::make_unique<Prober>(*program, nullptr);
    }
    std::pair<double, double> at(double x, double y, double t) {
        std::vector<double> v = probe->at(x, y, t);
        return {v[program->layout.distanceSlot(0)], v[0]};
    }
};

} // namespace

// A loop of 3 s over three families, shares of one second; each change takes the default
// 0.28 s at the end of its share: circles -> hexagons over [0.72, 1], hexagons -> squares
// over [1.72, 2], squares -> circles over [2.72, 3].
const char* const kLoop = "timing cycle { period = 3; mode = loop }";

TEST_CASE("morph: the families drawn alone are their closed forms") {
    // The baseline the other cases compare the morph with, checked against the geometry.
    MorphScene scene(kLoop);
    for (auto [x, y] : points(1)) {
        CAPTURE(x);
        CAPTURE(y);
        std::vector<double> d = scene.at(x, y, 0.5);
        near(d[1], memberDistance(kCircle.rho(x, y)));
        near(d[2], memberDistance(kHexagon.rho(x, y)));
        near(d[3], memberDistance(kSquare.rho(x, y)));
    }
}

TEST_CASE("morph: a change blends the two phases, half way at morph_time / 2") {
    MorphScene scene(kLoop);
    for (auto [x, y] : points(2)) {
        CAPTURE(x);
        CAPTURE(y);
        const std::vector<double> d = scene.at(x, y, 0.0);
        const double c = d[1], h = d[2], q = d[3];
        // Each family holds through its share up to the change, exactly.
        for (double t : {0.0, 0.5, 0.72}) near(scene.morph(x, y, t), c, 1e-12);
        // cubic_in_out(1/2) = 1/2: half way in time is half way between the phases.
        near(scene.morph(x, y, 0.86), blendDistance(kCircle, kHexagon, 0.5, x, y));
        // A quarter of the way in time: cubic_in_out(1/4) = 1/16 of the way.
        near(scene.morph(x, y, 0.79), blendDistance(kCircle, kHexagon, 1.0 / 16, x, y));
        for (double t : {1.0, 1.5, 1.72}) near(scene.morph(x, y, t), h, 1e-12);
        near(scene.morph(x, y, 1.86), blendDistance(kHexagon, kSquare, 0.5, x, y));
        near(scene.morph(x, y, 2.5), q, 1e-12);
        // The loop closes: squares travel back to circles at the end of the pass.
        near(scene.morph(x, y, 2.86), blendDistance(kSquare, kCircle, 0.5, x, y));
        near(scene.morph(x, y, 3.0), c, 1e-12);
    }
    // The shares cut the raw progress: the timing's easing (for its ramps) moves no change.
    MorphScene eased("timing cycle { period = 3; mode = loop; easing = quad_in }");
    for (auto [x, y] : points(8, 20)) {
        near(eased.morph(x, y, 0.86), blendDistance(kCircle, kHexagon, 0.5, x, y));
        near(eased.morph(x, y, 1.86), blendDistance(kHexagon, kSquare, 0.5, x, y));
    }
}

TEST_CASE("morph: one stroke travels between the shapes, it neither breaks nor cross-fades") {
    // Half way from circles to hexagons. Zoom 4: the stroke's half width is 0.5 world units,
    // with 0.175 of antialiasing beyond it.
    OneLayer scene(
        "timing cycle { period = 2; mode = once }\ncamera { zoom = 4 }\n"
        "layer { family = morph(cycle, circles, hexagons); spacing = 10; stroke = 1 }\n");
    const double t = 0.72 + 0.14, w = 0.5; // the first share's change, half way
    int onStroke = 0, offStroke = 0;
    for (double a = 0.025; a < 2 * std::numbers::pi; a += 0.05) {
        const double ux = std::cos(a), uy = std::sin(a);
        for (int n = 2; n <= 5; ++n) {
            CAPTURE(a);
            CAPTURE(n);
            // Member n of the blend along this ray: (1 - w) R + w R hex(u) = n s. Every such
            // point is inked, at every angle: the member is one unbroken stroke.
            const double R = n * kSpacing / ((1 - w) + w * kHexagon.rho(ux, uy));
            auto [d, red] = scene.at(R * ux, R * uy, t);
            CHECK(d < 1e-9);
            CHECK(red < 1e-6);
            ++onStroke;
            // On the circle of member n, well away from every hexagon, the point is not on
            // the blend either: a cross-fade would lay half the circle's ink there.
            const double x = n * kSpacing * ux, y = n * kSpacing * uy;
            if (memberDistance(kHexagon.rho(x, y)) < 2.5) continue;
            auto [d2, red2] = scene.at(x, y, t);
            near(d2, blendDistance(kCircle, kHexagon, w, x, y));
            CHECK(d2 > 1.0);
            CHECK(red2 == 1.0); // white paper
            ++offStroke;
        }
    }
    CHECK(onStroke > 400);
    CHECK(offStroke > 40);
}

TEST_CASE("morph: a loop comes back from its last family to its first") {
    MorphScene scene("timing cycle { period = 3; delay = 0.5; mode = loop }");
    // Cycles of 3.5 s: 0.5 s held at progress 0 (circles), then a second each for circles,
    // hexagons and squares; the squares' share ends with the change back to circles.
    for (auto [x, y] : points(3, 30)) {
        CAPTURE(x);
        CAPTURE(y);
        const std::vector<double> d = scene.at(x, y, 0.0);
        const double c = d[1], q = d[3];
        near(scene.morph(x, y, 0.0), c, 1e-12);
        near(scene.morph(x, y, 1.0), c, 1e-12);
        near(scene.morph(x, y, 3.0), q, 1e-12);
        near(scene.morph(x, y, 3.22 + 0.14), blendDistance(kSquare, kCircle, 0.5, x, y));
        near(scene.morph(x, y, 3.5 + 0.3), c, 1e-12); // the next cycle's delay: circles
        // The same before the clock's 0: the cycles tile the line.
        near(scene.morph(x, y, 3.36 - 7.0), blendDistance(kSquare, kCircle, 0.5, x, y));
    }
}

TEST_CASE("morph: once and pingpong start from the first family and hold at the ends") {
    MorphScene once("timing cycle { period = 3; delay = 0.5; mode = once }");
    MorphScene pingpong("timing cycle { period = 3; mode = pingpong }");
    for (auto [x, y] : points(4, 30)) {
        CAPTURE(x);
        CAPTURE(y);
        const std::vector<double> d = once.at(x, y, 0.0);
        const double c = d[1], q = d[3];
        // once: circles until the delay and through their share, then hexagons and squares,
        // and squares for ever after (the last share has no change).
        for (double t : {-5.0, 0.0, 0.5, 1.2}) near(once.morph(x, y, t), c, 1e-12);
        near(once.morph(x, y, 1.36), blendDistance(kCircle, kHexagon, 0.5, x, y));
        near(once.morph(x, y, 2.36), blendDistance(kHexagon, kSquare, 0.5, x, y));
        for (double t : {3.3, 3.49, 3.5, 4.0, 100.0}) near(once.morph(x, y, t), q, 1e-12);
        // pingpong: the same way up, and back down in mirror image (progress is symmetric
        // about the top, so is everything drawn from it).
        near(pingpong.morph(x, y, 0.86), blendDistance(kCircle, kHexagon, 0.5, x, y));
        for (double u : {0.1, 0.75, 0.86, 1.2, 1.9, 2.8})
            near(pingpong.morph(x, y, 3 + u), pingpong.morph(x, y, 3 - u));
        near(pingpong.morph(x, y, 6.0), c, 1e-12);
    }
}

TEST_CASE("morph: morph_time sets how long a change takes, at most a share") {
    MorphScene slow(kLoop, "; morph_time = 0.6");
    MorphScene whole(kLoop, "; morph_time = 5"); // longer than a share: the whole share
    for (auto [x, y] : points(5, 30)) {
        CAPTURE(x);
        CAPTURE(y);
        const std::vector<double> d = slow.at(x, y, 0.0);
        const double c = d[1], h = d[2];
        near(slow.morph(x, y, 0.4), c, 1e-12);
        near(slow.morph(x, y, 0.7), blendDistance(kCircle, kHexagon, 0.5, x, y));
        near(slow.morph(x, y, 0.4 + 0.28),
             blendDistance(kCircle, kHexagon, cubicInOut(0.28 / 0.6), x, y));
        near(slow.morph(x, y, 1.0), h, 1e-12);
        near(whole.morph(x, y, 0.5), blendDistance(kCircle, kHexagon, 0.5, x, y));
        // No jump where one share ends and the next begins.
        near(whole.morph(x, y, 1.0 - 1e-9), h, 1e-6);
        near(whole.morph(x, y, 1.0), h, 1e-12);
    }
}

// h_p(n) for a blend of walking circles and hexagons: every member scanned, none skipped.
double walkingBlend(double w, double s, double dx, double dy, double turn, double px, double py,
                    double guard) {
    double best = guard;
    for (int n = 0; n < 400; ++n) {
        const double c = std::cos(n * turn), sn = std::sin(n * turn);
        const double qx = c * px + sn * py - n * dx, qy = c * py - sn * px - n * dy;
        const double rho = (1 - w) * kCircle.rho(qx, qy) + w * kHexagon.rho(qx, qy);
        best = std::min(best, std::fabs(rho - n * s));
    }
    return best;
}

TEST_CASE("morph: walking families blend their radii inside the search") {
    const std::string walk = "offset = (2.5, 1); turn = 3deg";
    const std::string text = "timing cycle { period = 2; mode = loop }\n"
                             "layer { family = morph(cycle, circles, hexagons); spacing = 10; " +
                             walk +
                             " }\n"
                             "layer { family = circles; spacing = 10; " +
                             walk +
                             " }\n"
                             "layer { family = hexagons; spacing = 10; " +
                             walk + " }\n";
    auto program = test::compileOk(text, probing());
    Prober probe(*program, nullptr);
    const lower::OutputLayout& layout = program->layout;
    // The guard (Eq. 26) at zoom 1 with the default stroke: max(h + a, 3/4 s) = 7.5.
    const double guard = 7.5, turn = 3 * std::numbers::pi / 180;
    int compared = 0;
    for (auto [x, y] : points(6, 80)) {
        CAPTURE(x);
        CAPTURE(y);
        std::vector<double> held = probe.at(x, y, 0.5), back = probe.at(x, y, 1.5);
        near(held[layout.distanceSlot(0)], held[layout.distanceSlot(1)], 1e-12);
        near(back[layout.distanceSlot(0)], back[layout.distanceSlot(2)], 1e-12);
        for (auto [t, w] :
             {std::pair{0.86, 0.5}, std::pair{0.79, 1.0 / 16}, std::pair{1.86, 0.5}}) {
            CAPTURE(t);
            // From hexagons back to circles in the second share: the blend's weight is on
            // the circles' side.
            const double weight = t > 1 ? 1 - w : w;
            const double want = walkingBlend(weight, 10, 2.5, 1, turn, x, y, guard);
            const double got = probe.at(x, y, t)[layout.distanceSlot(0)];
            if (want < guard - 1e-6) {
                near(got, want);
                ++compared;
            } else {
                CHECK(got >= guard - 1e-9);
            }
        }
    }
    CHECK(compared > 100);
}

TEST_CASE("morph: a walking family and one that cannot walk interpolate their distances") {
    // lines cannot walk, circles can: the morph's lines share is plain lines, its circles
    // share the walking circles, and a change between them blends the two distances.
    const std::string walk = "offset = (2.5, 1); turn = 3deg";
    const std::string text = "timing cycle { period = 2; mode = loop }\n"
                             "layer { family = morph(cycle, lines, circles); spacing = 10; " +
                             walk +
                             " }\n"
                             "layer { family = lines; spacing = 10 }\n"
                             "layer { family = circles; spacing = 10; " +
                             walk +
                             " }\n"
                             "layer { family = circles; spacing = 10 }\n";
    auto program = test::compileOk(text, probing());
    Prober probe(*program, nullptr);
    const lower::OutputLayout& layout = program->layout;
    int differ = 0;
    for (auto [x, y] : points(7, 40)) {
        CAPTURE(x);
        CAPTURE(y);
        std::vector<double> lines = probe.at(x, y, 0.5), circles = probe.at(x, y, 1.5);
        near(lines[layout.distanceSlot(0)], lines[layout.distanceSlot(1)], 1e-12);
        near(circles[layout.distanceSlot(0)], circles[layout.distanceSlot(2)], 1e-12);
        std::vector<double> half = probe.at(x, y, 0.86);
        near(half[layout.distanceSlot(0)],
             (half[layout.distanceSlot(1)] + half[layout.distanceSlot(2)]) / 2);
        // The walk is visible: the walking circles are not the concentric ones.
        differ +=
            std::fabs(circles[layout.distanceSlot(2)] - circles[layout.distanceSlot(3)]) > 0.1;
    }
    CHECK(differ > 20);
}

TEST_CASE("morph: the change is the library's cubic even where a scene has its own") {
    // §8.3 fixes the change's easing; a scene's `easing cubic_in_out = u` is for its own
    // timings, and must not reshape its morphs.
    MorphScene shadowed(std::string("easing cubic_in_out = u\n") + kLoop);
    for (auto [x, y] : points(9, 20)) {
        CAPTURE(x);
        CAPTURE(y);
        near(shadowed.morph(x, y, 0.79), blendDistance(kCircle, kHexagon, 1.0 / 16, x, y));
    }
}

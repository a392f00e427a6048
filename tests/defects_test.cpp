// Defects (spec §5): a circle-valued field A theta / tau encoded into a line family makes a
// fork grating. Against its unmodulated twin the index difference D = idx_b - idx_a = A f is
// multivalued, but {D in Z} is a well-defined fringe set whose signed crossings on any loop
// are the gain times the enclosed winding; and near the defect the heterodyne ratio against
// the twin crosses 1/4 at the core radius, 2 A s / pi to first order. Everything here is read
// from the renderer's own index and AD-gradient outputs through the probe.
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <doctest/doctest.h>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTau = 2.0 * kPi;

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

struct Fields {
    double index, distance, gx, gy;
};

// A compiled scene and its probe, kept together because the probe refers to the program.
struct Scene {
    std::unique_ptr<SceneProgram> program;
    Prober probe;
    explicit Scene(const std::string& src, Backend* backend = nullptr)
        : program(test::compileOk(src, {.mode = CompileOptions::Mode::Probe, .layerFields = true})),
          probe(*program, backend) {}

    std::vector<double> at(double x, double y) { return probe.at(x, y); }
    Fields layer(const std::vector<double>& v, int i) const {
        const auto& l = program->layout;
        return {v[l.indexSlot(i)], v[l.distanceSlot(i)], v[l.gradXSlot(i)], v[l.gradYSlot(i)]};
    }
};

// Layer a (slot 0) carries the field; layer b (slot 1) is its unmodulated twin, so
// D = idx_b - idx_a = gain * f (§10.1: idx_a = idx_b - gain f).
std::string twinScene(const std::string& field, double gain, double spacing = 6.0,
                      const std::string& angle = "0deg") {
    std::string lines = "family = lines; angle = " + angle + "; spacing = " + num(spacing);
    return "layer a { " + lines + "; field = " + field + "; gain = " + num(gain) + " }\n" +
           "layer b { " + lines + " }\n";
}

struct DSample {
    double d, gx, gy; // D and its gradient
};
DSample sampleD(Scene& sc, double x, double y) {
    std::vector<double> v = sc.at(x, y);
    Fields a = sc.layer(v, 0), b = sc.layer(v, 1);
    return {b.index - a.index, b.gx - a.gx, b.gy - a.gy};
}

// Signed crossings of {D in Z} along the circle about (cx, cy) of radius R, walked
// counterclockwise. Between samples D moves continuously (by under 0.1, checked against the
// AD gradient times the step), except across a branch cut, where it also jumps by the
// cut's winding. Each step's jump is what the gradient does not explain: the raw change
// minus the trapezoid of grad D along the step. The walk removes the nearest integer to it
// (unwrapping the cut) and counts every integer the unwrapped D passes; `tear` keeps the
// largest part of a jump that was not an integer.
struct Walk {
    int up = 0, down = 0; // crossings with D increasing, decreasing
    double lift = 0.0;    // net change of the unwrapped D around the loop
    double tear = 0.0;    // largest distance of a step's jump from an integer
    int cuts = 0;         // steps with a nonzero integer jump
    int samples = 0;
    int count() const { return up - down; }
};
Walk walkLoop(Scene& sc, double cx, double cy, double R) {
    const double t0 = 0.3217; // start off the cut and off the axes
    int n = 2048;
    for (;;) {
        std::vector<DSample> d(n);
        std::vector<double> px(n), py(n);
        double worst = 0.0; // largest |grad D| times the step, in index units
        const double step = kTau * R / n;
        for (int k = 0; k < n; ++k) {
            double t = t0 + kTau * k / n;
            px[k] = cx + R * std::cos(t);
            py[k] = cy + R * std::sin(t);
            d[k] = sampleD(sc, px[k], py[k]);
            worst = std::max(worst, std::hypot(d[k].gx, d[k].gy) * step);
        }
        if (worst > 0.1) {
            REQUIRE(n < (1 << 17)); // only a loop through a core would refine without end
            n = static_cast<int>(n * std::ceil(worst / 0.05));
            continue;
        }
        Walk w;
        w.samples = n;
        // A start on an integer would make floor() ambiguous at the loop's two ends.
        REQUIRE(std::fabs(d[0].d - std::round(d[0].d)) > 1e-6);
        double lifted = d[0].d;
        for (int k = 1; k <= n; ++k) {
            const DSample &p = d[k - 1], &q = d[k % n];
            double along = 0.5 * ((p.gx + q.gx) * (px[k % n] - px[k - 1]) +
                                  (p.gy + q.gy) * (py[k % n] - py[k - 1]));
            double jump = (q.d - p.d) - along;
            double whole = std::round(jump);
            w.tear = std::max(w.tear, std::fabs(jump - whole));
            if (whole != 0.0) ++w.cuts;
            double next = lifted + (q.d - p.d) - whole;
            int c = static_cast<int>(std::floor(next) - std::floor(lifted));
            (c > 0 ? w.up : w.down) += std::abs(c);
            lifted = next;
        }
        w.lift = lifted - d[0].d;
        return w;
    }
}

struct Charge {
    double x, y, q;
};
// Independent expectation: a counterclockwise circle winds once about each point inside it.
double enclosedCharge(const std::vector<Charge>& charges, double cx, double cy, double R) {
    double total = 0.0;
    for (const Charge& c : charges) {
        double dist = std::hypot(c.x - cx, c.y - cy);
        REQUIRE(std::fabs(dist - R) > 3.0); // loops keep clear of the cores
        if (dist < R) total += c.q;
    }
    return total;
}

std::string angleAbout(double x, double y) {
    return "atan2(y - " + num(y) + ", x - " + num(x) + ")";
}

} // namespace

TEST_CASE("defects: the signed fringe count on a loop is the gain times the enclosed winding") {
    struct Probe {
        std::string what, field;
        double gain;
        std::vector<Charge> charges; // where f winds, and by how much
        double cx, cy, R;
    };
    const std::vector<Charge> origin = {{0, 0, 1}};
    const std::vector<Charge> displaced = {{-25, 40, 1}};
    // An opposite-charge pair: f = (atan2 about p1 - atan2 about p2) / tau.
    const std::vector<Charge> pair = {{-30, 0, 1}, {30, 5, -1}};
    const std::string pairField = "(" + angleAbout(-30, 0) + " - " + angleAbout(30, 5) + ") / tau";
    std::vector<Probe> probes;
    for (int gain = 1; gain <= 10; ++gain)
        probes.push_back({"gains 1 to 10 about the origin", "theta / tau", double(gain), origin,
                          gain % 3 - 1.0, 0.5 * gain - 2.0, 9.0 + 4.0 * gain});
    probes.push_back({"a loop beside the defect", "theta / tau", 7, origin, 30, 10, 12});
    probes.push_back({"a negative gain", "theta / tau", -4, origin, 2, -3, 25});
    probes.push_back(
        {"displaced defect", angleAbout(-25, 40) + " / tau", 3, displaced, -25, 40, 15});
    probes.push_back({"displaced defect", angleAbout(-25, 40) + " / tau", 3, displaced, 0, 0, 20});
    probes.push_back({"displaced defect", angleAbout(-25, 40) + " / tau", 3, displaced, 0, 0, 100});
    probes.push_back(
        {"displaced defect", angleAbout(-25, 40) + " / tau", -6, displaced, -40, 30, 30});
    probes.push_back({"pair: around the positive", pairField, 2, pair, -30, 0, 20});
    probes.push_back({"pair: around the negative", pairField, 2, pair, 30, 5, 20});
    probes.push_back({"pair: around both", pairField, 2, pair, 0, 0, 60});
    probes.push_back({"pair: around neither", pairField, 2, pair, 0, 60, 30});
    probes.push_back({"pair: around the negative", pairField, 5, pair, 40, 0, 15});
    probes.push_back({"pair: around both", pairField, 5, pair, 5, -10, 150});
    // A single-valued field on top adds crossings both ways but no net count: the saddle
    // alone is crossed dozens of times round a loop of radius 200.
    probes.push_back({"defect + saddle", "theta / tau + saddle", 4, origin, 0, 0, 200});
    probes.push_back({"defect + saddle", "theta / tau + saddle", 4, origin, 180, 40, 120});
    probes.push_back({"defect + x^2 / K", "theta / tau + x^2 / 900", 3, origin, 50, 20, 60});
    probes.push_back({"defect + x^2 / K", "theta / tau + x^2 / 900", 3, origin, 50, 20, 40});
    probes.push_back({"pair + terrain", pairField + " + terrain", 3, pair, 0, 0, 120});
    probes.push_back({"pair + terrain", pairField + " + terrain", 3, pair, -30, 0, 200});

    REQUIRE(probes.size() >= 22);
    int crossedBothWays = 0;
    for (const Probe& p : probes) {
        CAPTURE(p.what);
        CAPTURE(p.field);
        CAPTURE(p.gain);
        CAPTURE(p.cx);
        CAPTURE(p.cy);
        CAPTURE(p.R);
        Scene sc(twinScene(p.field, p.gain));
        Walk w = walkLoop(sc, p.cx, p.cy, p.R);
        CAPTURE(w.up);
        CAPTURE(w.down);
        CAPTURE(w.samples);
        const double expected = p.gain * enclosedCharge(p.charges, p.cx, p.cy, p.R);
        CHECK(w.count() == expected);
        // At integer gain every jump the gradient does not explain is a whole number (at
        // 2.5 it would be a half; see the next case), so the unwrapping is unambiguous.
        CHECK(w.tear < 1e-3);
        if (w.up > 0 && w.down > 0) ++crossedBothWays;
    }
    // The exact fields really were crossed in both directions, so cancellation was tested.
    CHECK(crossedBothWays >= 6);
}

TEST_CASE("defects: an integer gain leaves the members continuous across the branch cut, and 2.5 "
          "tears") {
    // theta = atan2(y, x) is pi just above the negative x axis and -pi just below it, so
    // idx_a = x / s - A theta / tau is larger by A below the cut than above it. At whole A
    // the nearest member and its distance do not notice; at A = 2.5 the jump is half a
    // member, and the residual r becomes 1/2 - r.
    const double s = 6.0, eps = 1e-9;
    for (double gain : {1.0, 2.0, 5.0, 10.0, -3.0, 2.5, -0.5}) {
        CAPTURE(gain);
        Scene sc(twinScene("theta / tau", gain, s));
        const bool whole = gain == std::round(gain);
        int torn = 0;
        for (double rho : {3.7, 11.2, 25.3, 48.9, 97.1, 150.6, 233.3}) {
            CAPTURE(rho);
            std::vector<double> above = sc.at(-rho, eps), below = sc.at(-rho, -eps);
            Fields a = sc.layer(above, 0), b = sc.layer(below, 0);
            CHECK(b.index - a.index == doctest::Approx(gain).epsilon(1e-9));
            // The AD gradient has no cut: atan2's derivative is single-valued.
            CHECK(a.gx == doctest::Approx(b.gx).epsilon(1e-9));
            CHECK(a.gy == doctest::Approx(b.gy).epsilon(1e-9));
            if (whole) {
                CHECK(a.distance == doctest::Approx(b.distance).epsilon(1e-7));
            } else {
                const double grad = std::hypot(b.gx, b.gy);
                const double rBelow = std::fabs(b.index - std::round(b.index));
                CHECK(a.distance * grad == doctest::Approx(0.5 - rBelow).epsilon(1e-7));
                if (std::fabs(a.distance - b.distance) > 0.1 * s) ++torn;
            }
            // The same across the twin's difference D: whole jumps, or a half.
            double jump = sampleD(sc, -rho, eps).d - sampleD(sc, -rho, -eps).d;
            double frac = std::fabs(jump - std::round(jump));
            CHECK(frac == doctest::Approx(whole ? 0.0 : 0.5).scale(1).epsilon(1e-9));
        }
        if (!whole) CHECK(torn >= 3); // the tear shows at most radii, not by chance at one
        // Round a loop about the defect, the one jump the gradient does not explain is at
        // the cut: a whole A, or at 2.5 a half that no unwrapping can remove (the loop has
        // no closed fringe set to count).
        Walk w = walkLoop(sc, 1.0, -2.0, 40.0);
        CHECK(w.tear == doctest::Approx(whole ? 0.0 : 0.5).scale(1).epsilon(1e-3));
        if (whole) {
            CHECK(std::fabs(w.lift - gain) < 1e-9);
            // A loop that crosses the cut twice without enclosing the defect: two whole
            // jumps that cancel, and no net fringe.
            Walk beside = walkLoop(sc, -60.0, 3.0, 20.0);
            CHECK(beside.cuts == 2);
            CHECK(beside.tear < 1e-3);
            CHECK(beside.count() == 0);
        }
    }
}

namespace {

// The heterodyne ratio (Eq. 10) between layers 0 and 1 at (x, y), from their AD gradients.
double het(Scene& sc, double x, double y) {
    std::vector<double> v = sc.at(x, y);
    Fields a = sc.layer(v, 0), b = sc.layer(v, 1);
    double dx = a.gx - b.gx, dy = a.gy - b.gy;
    double gx = 0.5 * (a.gx + b.gx), gy = 0.5 * (a.gy + b.gy);
    return std::hypot(dx, dy) / std::hypot(gx, gy);
}

// Where het crosses 1/4 on the ray from (cx, cy) in direction phi, by bisection in
// [lo, hi]; het falls monotonically along these rays (see below), which the bracket checks.
double coreCrossing(Scene& sc, double cx, double cy, double phi, double lo, double hi) {
    auto h = [&](double r) { return het(sc, cx + r * std::cos(phi), cy + r * std::sin(phi)); };
    REQUIRE(h(lo) > 0.25);
    REQUIRE(h(hi) < 0.25);
    for (int i = 0; i < 60 && hi - lo > 1e-13 * hi; ++i) {
        double mid = 0.5 * (lo + hi);
        (h(mid) > 0.25 ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
}

struct CoreCase {
    double gain, spacing, psiDeg; // carrier: lines at angle psi (their normal), spacing s
    double x0, y0;                // the defect
};
const std::vector<CoreCase> kCoreCases = {
    {1, 6, 0, 0, 0},     {3, 6, 0, 0, 0},      {5, 4, 0, 0, 0},     {8, 9.5, 0, 0, 0},
    {2, 6, 30, -25, 40}, {-2, 5, -70, 10, -5}, {4, 7.5, 115, 0, 0},
};

// Ray directions: the extremes of sigma below (phi - psi = +-90 degrees), sigma = 0, and
// directions between, none special.
std::vector<double> rayAngles(double psi) {
    std::vector<double> out;
    for (double off : {0.0, 90.0, -90.0, 180.0, 37.0, 128.0, -151.0, -12.5})
        out.push_back(psi + off * kPi / 180.0);
    return out;
}

} // namespace

TEST_CASE(
    "defects: against the twin, het crosses 1/4 at the exact root, within 1/8 of 2 A s / pi") {
    // Layer a is lines (unit normal n, spacing s) carrying A theta / tau about p0; layer b
    // is the bare twin. At p = p0 + r (cos phi, sin phi), with e the unit vector along
    // increasing theta there, grad theta = e / r, so
    //     grad idx_b = n / s,   grad idx_a = n / s - k e,   k = A / (tau r),
    //     grad D = k e,         g = (grad idx_a + grad idx_b) / 2 = n / s - k e / 2.
    // With u = |k| s and sigma = sign(A) sin(phi - psi) (so that -sign(A) e.n = sigma):
    //     het^2 = u^2 / (1 + sigma u + u^2 / 4).
    // The first-order picture (§5) drops g's own term and takes het = u, crossing 1/4 at
    // u = 1/4: r0 = 4 |A| s / tau = 2 |A| s / pi. Setting het = 1/4 exactly instead gives
    // 63/4 u^2 - sigma u - 1 = 0, whose positive root is u = 2 (sigma + sqrt(sigma^2 + 63)) / 63:
    //     r* = r0 (sqrt(63 + sigma^2) - sigma) / 8.
    // So the crossing moves by -sigma/8 at first order in het (g's cross term is of order het
    // itself): 7/8 r0 on the ray where sigma = 1, 9/8 r0 where sigma = -1, and
    // sqrt(63)/8 r0 = 0.99216 r0 where the ray runs along n. |r*/r0 - 1| <= 1/8 always, and
    // the second-order remainder |r*/r0 - (1 - sigma/8)| <= 1 - sqrt(63)/8 < 0.0079.
    // (het is increasing in u for u < 2, so it falls along every ray through the bracket.)
    double lowest = 2.0, highest = 0.0;
    for (const CoreCase& c : kCoreCases) {
        CAPTURE(c.gain);
        CAPTURE(c.spacing);
        CAPTURE(c.psiDeg);
        const std::string field = "atan2(y - " + num(c.y0) + ", x - " + num(c.x0) + ") / tau";
        Scene sc(twinScene(field, c.gain, c.spacing, num(c.psiDeg) + "deg"));
        const double psi = c.psiDeg * kPi / 180.0;
        const double r0 = 2.0 * std::fabs(c.gain) * c.spacing / kPi;
        for (double phi : rayAngles(psi)) {
            CAPTURE(phi);
            const double sigma = (c.gain > 0 ? 1.0 : -1.0) * std::sin(phi - psi);
            const double exact = r0 * (std::sqrt(63.0 + sigma * sigma) - sigma) / 8.0;
            const double measured = coreCrossing(sc, c.x0, c.y0, phi, 0.5 * r0, 2.0 * r0);
            CHECK(measured == doctest::Approx(exact).epsilon(1e-6));
            CHECK(std::fabs(measured / r0 - 1.0) <= 0.125 + 1e-9);
            CHECK(std::fabs(measured / r0 - (1.0 - sigma / 8.0)) <=
                  1.0 - std::sqrt(63.0) / 8.0 + 1e-9);
            lowest = std::min(lowest, measured / r0);
            highest = std::max(highest, measured / r0);
        }
    }
    // The rays at +-90 degrees from n reach the bound's two ends: the first-order radius is
    // 12.5% off there, not a fraction of a percent. (Measured against the exact root: 5e-14
    // at worst; docs/families.md.)
    CHECK(lowest == doctest::Approx(0.875).epsilon(1e-6));
    CHECK(highest == doctest::Approx(1.125).epsilon(1e-6));
}

TEST_CASE(
    "defects: with the field split +A/2, -A/2 between the layers, het crosses 1/4 at 2 A s / pi") {
    // Layer a carries gain A/2 and layer b gain -A/2 of the same theta / tau about p0: then
    // D = idx_b - idx_a = A theta / tau as before, but g = n / s exactly (the two field terms
    // cancel in the mean), so het = |A| s / (tau r) and the first-order core radius
    // r* = 2 |A| s / pi is exact. The issue asks for 1e-3; the double interpreter does far
    // better, and the single-precision JIT must meet it too.
    std::vector<std::unique_ptr<Backend>> owned;
    std::vector<Backend*> backends = {nullptr};
    if (auto jit = test::makeBackendOrSkip("jit")) {
        backends.push_back(jit.get());
        owned.push_back(std::move(jit));
    }
    for (size_t bi = 0; bi < backends.size(); ++bi) {
        CAPTURE(bi);
        for (const CoreCase& c : kCoreCases) {
            CAPTURE(c.gain);
            CAPTURE(c.spacing);
            CAPTURE(c.psiDeg);
            const std::string field = "atan2(y - " + num(c.y0) + ", x - " + num(c.x0) + ") / tau";
            const std::string lines = "family = lines; angle = " + num(c.psiDeg) +
                                      "deg; spacing = " + num(c.spacing) + "; field = " + field;
            Scene sc("layer a { " + lines + "; gain = " + num(c.gain / 2) + " }\n" + "layer b { " +
                         lines + "; gain = " + num(-c.gain / 2) + " }\n",
                     backends[bi]);
            const double r0 = 2.0 * std::fabs(c.gain) * c.spacing / kPi;
            for (double phi : rayAngles(c.psiDeg * kPi / 180.0)) {
                CAPTURE(phi);
                double measured = coreCrossing(sc, c.x0, c.y0, phi, 0.5 * r0, 2.0 * r0);
                CHECK(measured == doctest::Approx(r0).epsilon(1e-3));
                if (bi == 0) CHECK(measured == doctest::Approx(r0).epsilon(1e-9));
            }
        }
    }
    // Measured at worst: 1.5e-14 on the interpreter, 4.3e-7 on the JIT (docs/families.md).
}

// The six field presets of stdlib/fields.moire, as a layer uses them (`field = name`):
// each value against an independent C++ transcription of the formula its comment states,
// the forward-mode AD gradient against finite differences, the properties the comments
// claim, and the poles (dipole charges, vortex centres), where the exact interpreter and the
// single-precision JIT must give the same finite numbers (spec §10.2: shared clamps).
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <functional>
#include <memory>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr double kTau = 2.0 * std::numbers::pi;

// The presets as their comments describe them, written out again in C++.
struct Preset {
    std::string name;
    std::function<double(double, double)> f;
    std::vector<std::pair<double, double>> poles; // where f is singular
};

double sq(double v) {
    return v * v;
}

const std::vector<Preset>& presets() {
    static const std::vector<Preset> all = {
        {"saddle", [](double x, double y) { return (x * x - y * y) / sq(150); }, {}},
        {"dipole",
         [](double x, double y) {
             return 3 * std::log(std::hypot(x + 120, y) / std::hypot(x - 120, y));
         },
         {{-120, 0}, {120, 0}}},
        {"bumps",
         [](double x, double y) {
             return 6 * std::exp(-(sq(x - 160) + sq(y - 90)) / sq(110)) +
                    4 * std::exp(-(sq(x + 190) + sq(y + 60)) / sq(80)) -
                    5 * std::exp(-(sq(x + 20) + sq(y - 170)) / sq(95)) +
                    3 * std::exp(-(sq(x - 60) + sq(y + 190)) / sq(70));
         },
         {}},
        {"swirl",
         [](double x, double y) {
             return 2 * (std::log(std::hypot(x - 150, y - 110)) -
                         std::log(std::hypot(x + 150, y - 110)) +
                         std::log(std::hypot(x + 150, y + 110)) -
                         std::log(std::hypot(x - 150, y + 110)));
         },
         {{150, 110}, {-150, 110}, {-150, -110}, {150, -110}}},
        {"ripple",
         [](double x, double y) { return 3 * std::cos(kTau * std::hypot(x, y) / 120); },
         {{0, 0}}}, // not singular (cos is even in r), but r's own derivative is there
        {"terrain",
         [](double x, double y) {
             return 2.2 * std::sin(x / 97 + 0.3) + 1.7 * std::sin((0.6 * x + 0.8 * y) / 71 + 1.1) +
                    1.3 * std::sin((-0.7 * x + 0.71 * y) / 53 + 2.3) +
                    0.9 * std::sin((0.25 * x - 0.97 * y) / 37 + 0.7) +
                    0.6 * std::sin((0.94 * x + 0.34 * y) / 23 + 4.1);
         },
         {}},
    };
    return all;
}

// One layer per preset, in order: lines of spacing 1 carrying the preset at gain -1, so the
// layer's index is x + f and its index gradient (1, 0) + grad f (§10.1: idx - gain f).
std::string presetScene() {
    std::string src;
    for (const Preset& p : presets())
        src += "layer { family = lines; spacing = 1; field = " + p.name + "; gain = -1 }\n";
    return src;
}

struct Value {
    double f, fx, fy, distance;
};

struct Probed {
    std::unique_ptr<SceneProgram> program;
    Prober probe;
    explicit Probed(Backend* backend = nullptr)
        : program(test::compileOk(presetScene(),
                                  {.mode = CompileOptions::Mode::Probe, .layerFields = true})),
          probe(*program, backend) {}
    // Every output at (x, y), and preset i's value and gradient read off its layer.
    std::vector<double> all(double x, double y) { return probe.at(x, y); }
    Value preset(const std::vector<double>& v, int i, double x) const {
        const auto& l = program->layout;
        return {v[l.indexSlot(i)] - x, v[l.gradXSlot(i)] - 1.0, v[l.gradYSlot(i)],
                v[l.distanceSlot(i)]};
    }
    Value at(int i, double x, double y) { return preset(all(x, y), i, x); }
};

double nearestPole(const Preset& p, double x, double y) {
    double d = INFINITY;
    for (auto [px, py] : p.poles) d = std::min(d, std::hypot(x - px, y - py));
    return d;
}

// Seeded points over a 1200 x 800 frame about the origin (the default image at zoom 1),
// kept `clear` world units from the preset's singular points.
std::vector<std::pair<double, double>> framePoints(const Preset& p, int n, uint64_t seed,
                                                   double clear) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> ux(-600, 600), uy(-400, 400);
    std::vector<std::pair<double, double>> out;
    while (static_cast<int>(out.size()) < n) {
        double x = ux(rng), y = uy(rng);
        if (nearestPole(p, x, y) >= clear) out.push_back({x, y});
    }
    return out;
}

} // namespace

TEST_CASE("field presets: each value is the formula its comment states") {
    Probed probe;
    uint64_t seed = 100;
    for (size_t i = 0; i < presets().size(); ++i) {
        const Preset& p = presets()[i];
        CAPTURE(p.name);
        for (auto [x, y] : framePoints(p, 200, seed++, 1.0)) {
            CAPTURE(x);
            CAPTURE(y);
            Value v = probe.at(static_cast<int>(i), x, y);
            // The layer's index is x + f, so f carries the rounding of a sum of size |x|.
            CHECK(std::fabs(v.f - p.f(x, y)) <= 1e-13 * (1 + std::fabs(x) + std::fabs(v.f)));
        }
    }
}

TEST_CASE("field presets: the AD gradient is the finite-difference gradient") {
    // Fourth-order central differences of the probed value, h = 0.01: truncation is far below
    // the tolerance for every preset's length scales (the shortest is terrain's 23 units),
    // and the 1e-13 rounding of x + f becomes about 1e-11 in the derivative.
    Probed probe;
    const double h = 0.01;
    uint64_t seed = 200;
    for (size_t i = 0; i < presets().size(); ++i) {
        const Preset& p = presets()[i];
        CAPTURE(p.name);
        auto f = [&](double x, double y) { return probe.at(static_cast<int>(i), x, y).f; };
        int compared = 0;
        for (auto [x, y] : framePoints(p, 150, seed++, 8.0)) {
            CAPTURE(x);
            CAPTURE(y);
            Value v = probe.at(static_cast<int>(i), x, y);
            double fx =
                (-f(x + 2 * h, y) + 8 * f(x + h, y) - 8 * f(x - h, y) + f(x - 2 * h, y)) / (12 * h);
            double fy =
                (-f(x, y + 2 * h) + 8 * f(x, y + h) - 8 * f(x, y - h) + f(x, y - 2 * h)) / (12 * h);
            const double tol = 1e-6 * std::hypot(v.fx, v.fy) + 1e-9;
            CHECK(std::fabs(v.fx - fx) <= tol);
            CHECK(std::fabs(v.fy - fy) <= tol);
            ++compared;
        }
        CHECK(compared == 150);
    }
}

TEST_CASE("field presets: the properties their comments claim") {
    Probed probe;
    std::mt19937_64 rng(300);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    // saddle: the level through the origin is the pair of diagonals.
    for (int k = 0; k < 40; ++k) {
        double t = 500 * u(rng);
        CHECK(std::fabs(probe.at(0, t, t).f) < 1e-12);
        CHECK(std::fabs(probe.at(0, t, -t).f) < 1e-12);
    }
    // dipole: its contours are circles about each charge. The level f = c is where
    // |p - (-120, 0)| = k |p - (120, 0)| with k = exp(c / 3): the Apollonius circle with
    // centre (120 (k^2 + 1) / (k^2 - 1), 0) and radius 240 k / |k^2 - 1|.
    for (double c : {-6.0, -2.5, -0.7, 0.4, 1.9, 5.0}) {
        CAPTURE(c);
        const double k = std::exp(c / 3), centre = 120 * (k * k + 1) / (k * k - 1),
                     radius = 240 * k / std::fabs(k * k - 1);
        for (int j = 0; j < 24; ++j) {
            double t = kTau * (j + 0.37) / 24;
            CHECK(probe.at(1, centre + radius * std::cos(t), radius * std::sin(t)).f ==
                  doctest::Approx(c).epsilon(1e-10));
        }
    }
    // swirl: the vortices turn alternately, so f is odd under each mirror of the rectangle.
    for (int k = 0; k < 40; ++k) {
        double x = 500 * u(rng), y = 350 * u(rng), f = probe.at(3, x, y).f;
        CHECK(probe.at(3, -x, y).f == doctest::Approx(-f).epsilon(1e-9).scale(1e-9));
        CHECK(probe.at(3, x, -y).f == doctest::Approx(-f).epsilon(1e-9).scale(1e-9));
    }
    // ripple: one wave every 120 units, the same in every direction.
    for (int k = 0; k < 40; ++k) {
        double a = kTau * (u(rng) + 1) / 2, r = 200 * (u(rng) + 1), b = kTau * (u(rng) + 1) / 2;
        double f = probe.at(4, r * std::cos(a), r * std::sin(a)).f;
        CHECK(probe.at(4, (r + 120) * std::cos(a), (r + 120) * std::sin(a)).f ==
              doctest::Approx(f).epsilon(1e-9).scale(1e-9));
        CHECK(probe.at(4, r * std::cos(b), r * std::sin(b)).f ==
              doctest::Approx(f).epsilon(1e-9).scale(1e-9));
    }
}

namespace {

// Probes the points at and near the singular point (px, py) of preset i: every output of the
// interpreter is finite, and where the JIT runs (`single` not null) it gives the same numbers
// to single precision. Returns how many points were probed.
int checkPole(Probed& exact, Probed* single, int i, double px, double py) {
    // Offsets from the singular point, down to one float ulp there (the JIT receives the
    // probe point as floats): 2^-17 at 120 and 110, 2^-16 at 150. Off the charges' axis
    // y = 0 any float works, down to under the log floor (1e-30), where the clamp and its
    // flat slope take over.
    const double u17 = std::ldexp(1.0, -17), u16 = std::ldexp(1.0, -16);
    std::vector<std::pair<double, double>> near = {{0, 0},
                                                   {u16, 0},
                                                   {-u16, 0},
                                                   {0, u17},
                                                   {0, -u17},
                                                   {u16, u17},
                                                   {std::ldexp(1.0, -10), 0},
                                                   {0, 1e-3},
                                                   {0.5, -0.25}};
    if (py == 0)
        for (double dy : {1e-9, -1e-20, 1e-29, 1e-31, 1e-33}) near.push_back({0, dy});
    for (auto [dx, dy] : near) {
        // Rounded to floats, so that both evaluators see the same point.
        const double x = static_cast<float>(px + dx), y = static_cast<float>(py + dy);
        CAPTURE(presets()[i].name);
        CAPTURE(x);
        CAPTURE(y);
        std::vector<double> ve = exact.all(x, y), vs = single ? single->all(x, y) : ve;
        for (size_t k = 0; k < ve.size(); ++k) {
            CAPTURE(k);
            CHECK(std::isfinite(ve[k]));
            CHECK(std::isfinite(vs[k]));
        }
        Value e = exact.preset(ve, i, x), s = exact.preset(vs, i, x); // one layout for both
        // The index is x + f: single precision holds it to a few ulps of its size.
        const double idxTol = 1e-6 * (1 + std::fabs(x) + std::fabs(e.f));
        CHECK(std::fabs(s.f - e.f) <= idxTol);
        const double g = std::hypot(e.fx + 1, e.fy);
        CHECK(std::fabs(s.fx - e.fx) <= 1e-5 * g);
        CHECK(std::fabs(s.fy - e.fy) <= 1e-5 * g);
        // The distance is the index residual over |grad index|, so it inherits the index's
        // absolute error, divided by that length.
        CHECK(std::fabs(s.distance - e.distance) <= idxTol / g + 1e-5 * e.distance);
    }
    return static_cast<int>(near.size());
}

} // namespace

TEST_CASE("field presets: at and near the poles the interpreter and the JIT agree, finitely") {
    auto jit = test::makeBackendOrSkip("jit");
    Probed exact;
    std::unique_ptr<Probed> single = jit ? std::make_unique<Probed>(jit.get()) : nullptr;
    int checked = 0;
    for (size_t i = 0; i < presets().size(); ++i)
        for (auto [px, py] : presets()[i].poles)
            checked += checkPole(exact, single.get(), static_cast<int>(i), px, py);
    CHECK(checked == 2 * 14 + 4 * 9 + 14); // dipole's two charges, swirl, ripple
}

// The dipole is written as a difference of logarithms, not the log of a quotient: at a
// charge the quotient would be 240 / 0 = inf before log's floor could act.
TEST_CASE("field presets: the dipole's charge at (120, 0) is finite and agrees") {
    Probed exact;
    std::vector<double> at = exact.all(120, 0);
    CHECK(std::all_of(at.begin(), at.end(), [](double v) { return std::isfinite(v); }));
    if (auto jit = test::makeBackendOrSkip("jit")) {
        Probed single(jit.get());
        CHECK(std::isfinite(single.at(1, 120, 1e-20).fy));
    }
}

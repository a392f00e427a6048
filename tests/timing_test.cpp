// Timings and easings (spec §8.5) against closed forms written out here, independently of
// the lowering (compiler/lower/Timings.cpp) and of stdlib/easings.moire:
//  - every standard easing at many u, the ends and the turning point, to 1e-12;
//  - the three modes with delays and non-integer periods, at the boundaries and before 0;
//  - ramp of numbers, angles, vectors and colours is mix(a, b, eased progress), and a dozen
//    parameters on one timing are at the same progress at every t;
//  - a frame is a function of the clock: rendering other frames first changes nothing.
// Values are read on the double-precision interpreter: a number through the camera zoom
// (evaluateFrame gives it exactly), the rest through the prober's layer distances.
#include "runtime/FrameEval.h"
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <cmath>
#include <cstring>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <functional>
#include <numbers>
#include <random>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kExact = 1e-12;

// The standard easings, as the usual closed forms (easings.net's, u in [0, 1]).
struct EasingForm {
    const char* name;
    std::function<double(double)> f;
};
const std::vector<EasingForm>& easingForms() {
    static const std::vector<EasingForm> forms = {
        {"linear", [](double u) { return u; }},
        {"sine", [](double u) { return (1 - std::cos(kPi * u)) / 2; }},
        {"sine_in", [](double u) { return 1 - std::cos(kPi * u / 2); }},
        {"sine_out", [](double u) { return std::sin(kPi * u / 2); }},
        {"quad_in", [](double u) { return u * u; }},
        {"quad_out", [](double u) { return 1 - (1 - u) * (1 - u); }},
        {"quad_in_out",
         [](double u) { return u < 0.5 ? 2 * u * u : 1 - std::pow(-2 * u + 2, 2) / 2; }},
        {"cubic_in", [](double u) { return u * u * u; }},
        {"cubic_out", [](double u) { return 1 - std::pow(1 - u, 3); }},
        {"cubic_in_out",
         [](double u) { return u < 0.5 ? 4 * u * u * u : 1 - std::pow(-2 * u + 2, 3) / 2; }},
    };
    return forms;
}

double ease(const std::string& name, double u) {
    for (const EasingForm& e : easingForms())
        if (name == e.name) return e.f(u);
    FAIL("no closed form for easing ", name);
    return 0;
}

enum class Mode { Once, Loop, PingPong };
const char* modeWord(Mode m) {
    return m == Mode::Once ? "once" : m == Mode::Loop ? "loop" : "pingpong";
}

// The raw progress, from the definition: 0 to 1 over `period` seconds after `delay`; once
// holds at 0 before and at 1 after; loop repeats every delay + period, pingpong every
// delay + 2 period (hold, up, down). Negative time: the clock before 0 is the same clock,
// so a repeating timing repeats backwards too (its cycles tile the whole line), and a `once`
// timing has not started.
double rawProgress(Mode m, double delay, double period, double t) {
    if (m == Mode::Once) return t <= delay ? 0.0 : t >= delay + period ? 1.0 : (t - delay) / period;
    const double cycle = delay + (m == Mode::Loop ? 1.0 : 2.0) * period;
    double into = std::fmod(t, cycle);
    if (into < 0) into += cycle;
    if (into < delay) return 0.0;
    const double a = (into - delay) / period;
    return m == Mode::Loop || a <= 1.0 ? a : 2.0 - a;
}

std::string timingSource(Mode m, double delay, double period, const std::string& easing) {
    return fmt::format("timing tm {{ period = {}; delay = {}; mode = {}{} }}\n", period, delay,
                       modeWord(m), easing.empty() ? "" : "; easing = " + easing);
}

// The camera zoom of frame t: evaluateFrame computes it in double precision, so a scene
// whose zoom is `1 + <expression>` shows that expression's value at any instant.
double zoomAt(const SceneProgram& program, double t, FrameValues* values = nullptr) {
    FrameValues fv;
    std::string diags;
    INFO(diags);
    REQUIRE(evaluateFrame(program, FrameRequest{t}, fv, diags));
    if (values) *values = fv;
    return fv.zoom;
}

void near(double got, double want, double tolerance = kExact) {
    CAPTURE(got);
    CAPTURE(want);
    CHECK(std::fabs(got - want) <= tolerance);
}

} // namespace

TEST_CASE("timing: every standard easing is its closed form, ends and turning point included") {
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> us = {0.0, 1.0, 0.5, 0.5 - 1e-9, 0.5 + 1e-9, 0.25, 0.75, 1e-9, 1 - 1e-9};
    for (int i = 0; i <= 64; ++i) us.push_back(i / 64.0);
    for (int i = 0; i < 100; ++i) us.push_back(unit(rng));
    for (const EasingForm& e : easingForms()) {
        CAPTURE(e.name);
        // Period 1 and no delay: at t = u the raw progress is u exactly.
        auto program = test::compileOk(timingSource(Mode::Once, 0, 1, e.name) +
                                       "camera { zoom = 1 + progress(tm) }");
        for (double u : us) {
            CAPTURE(u);
            near(zoomAt(*program, u) - 1, e.f(u));
        }
        near(zoomAt(*program, 0) - 1, 0.0);
        near(zoomAt(*program, 1) - 1, 1.0);
    }
}

TEST_CASE("timing: the easings keep their shapes: monotone, in-out symmetric, out mirrors in") {
    // Properties that do not depend on the formulas above: each easing rises from 0 to 1,
    // an in-out easing is point-symmetric about (1/2, 1/2), and an out is its in reflected.
    for (const EasingForm& e : easingForms()) {
        CAPTURE(e.name);
        auto p = test::compileOk(timingSource(Mode::Once, 0, 1, e.name) +
                                 "camera { zoom = 1 + progress(tm) }");
        double before = -1;
        for (int i = 0; i <= 200; ++i) {
            double v = zoomAt(*p, i / 200.0) - 1;
            CHECK(v >= before);
            before = v;
        }
        std::string name = e.name;
        if (name.ends_with("_in_out") || name == "sine")
            for (double u : {0.1, 0.3, 0.45}) near(zoomAt(*p, u) - 1 + zoomAt(*p, 1 - u) - 1, 1.0);
        if (name.ends_with("_out") && !name.ends_with("_in_out")) {
            std::string in = name.substr(0, name.size() - 4) + "_in";
            for (double u : {0.1, 0.3, 0.7}) near(zoomAt(*p, u) - 1, 1 - ease(in, 1 - u));
        }
    }
}

TEST_CASE("timing: a scene's own easing, and step") {
    // smoothstep's polynomial, declared by the scene; a scene easing of a library name hides
    // the library's for the scene's timings.
    auto own = test::compileOk("easing smooth = u * u * (3 - 2 * u)\n" +
                               timingSource(Mode::Once, 0, 1, "smooth") +
                               "camera { zoom = 1 + progress(tm) }");
    auto hidden = test::compileOk("easing sine = u ^ 2\n" + timingSource(Mode::Once, 0, 1, "sine") +
                                  "camera { zoom = 1 + progress(tm) }");
    for (double u : {0.0, 0.2, 0.5, 0.9, 1.0}) {
        near(zoomAt(*own, u) - 1, u * u * (3 - 2 * u));
        near(zoomAt(*hidden, u) - 1, u * u);
    }
    // step(edge, v): 0 below the edge, 1 from it on (the edge itself included).
    auto step = test::compileOk("camera { zoom = 1 + step(0.25, t) }");
    CHECK(zoomAt(*step, -1) == 1);
    CHECK(zoomAt(*step, 0.2499999) == 1);
    CHECK(zoomAt(*step, 0.25) == 2);
    CHECK(zoomAt(*step, 7) == 2);
    // A hard cut as an easing: the timing's progress jumps half way through.
    auto snap =
        test::compileOk("easing snap = step(0.5, u)\n" + timingSource(Mode::Once, 1, 2, "snap") +
                        "camera { zoom = 1 + progress(tm) }");
    CHECK(zoomAt(*snap, 1.9) == 1);
    CHECK(zoomAt(*snap, 2.0) == 2);
}

TEST_CASE("timing: once, loop and pingpong against their closed forms, before 0 too") {
    struct Case {
        Mode mode;
        double delay, period;
        std::string easing;
        bool dyadic; // boundaries exact in binary: the discontinuities can be hit exactly
    };
    const std::vector<Case> cases = {
        {Mode::Once, 0.5, 1.25, "", true},           {Mode::Once, 0.1, 2.7, "cubic_in_out", false},
        {Mode::Loop, 0.5, 1.25, "", true},           {Mode::Loop, 0, 0.75, "", true},
        {Mode::Loop, 0.3, 0.7, "sine", false},       {Mode::PingPong, 0.25, 1.5, "", true},
        {Mode::PingPong, 0, 0.3, "quad_out", false},
    };
    for (const Case& c : cases) {
        CAPTURE(modeWord(c.mode));
        CAPTURE(c.delay);
        CAPTURE(c.period);
        CAPTURE(c.easing);
        auto program = test::compileOk(timingSource(c.mode, c.delay, c.period, c.easing) +
                                       "camera { zoom = 1 + progress(tm) }");
        auto expected = [&](double t) {
            double raw = rawProgress(c.mode, c.delay, c.period, t);
            return c.easing.empty() ? raw : ease(c.easing, raw);
        };
        // The settings reach the frame as written.
        FrameValues fv;
        zoomAt(*program, 0, &fv);
        REQUIRE(fv.timings.size() == 1);
        CHECK(fv.timings[0].name == "tm");
        CHECK(fv.timings[0].period == c.period);
        CHECK(fv.timings[0].delay == c.delay);
        CHECK(fv.timings[0].mode == static_cast<TimingValues::Mode>(static_cast<int>(c.mode)));
        const double cycle = c.delay + (c.mode == Mode::PingPong ? 2 : 1) * c.period;
        near(fv.timings[0].cycle(), cycle);

        std::vector<double> ts;
        for (int i = -120; i <= 160; ++i) ts.push_back(cycle * i / 40.0 + 1e-7);
        for (double b : {c.delay, c.delay + c.period, c.delay + 2 * c.period})
            for (double d : {-1e-6, 1e-6}) ts.push_back(b + d);
        if (c.dyadic) {
            // The boundaries themselves: the end of the delay, the top, the cycle's ends.
            for (double b : {c.delay, c.delay + c.period, c.delay + 2 * c.period, cycle, 2 * cycle,
                             -cycle, -2 * cycle, -cycle + c.delay})
                ts.push_back(b);
        }
        for (double t : ts) {
            CAPTURE(t);
            near(zoomAt(*program, t) - 1, expected(t));
        }
        // Spot values that need no formula at all.
        near(zoomAt(*program, c.delay) - 1, 0.0);
        if (c.easing.empty()) {
            near(zoomAt(*program, c.delay + c.period / 2) - 1, 0.5);
            near(zoomAt(*program, c.delay + c.period * (1 - 1e-9)) - 1, 1.0, 1e-8);
        }
        if (c.mode == Mode::Once) {
            CHECK(zoomAt(*program, -50) == 1); // not started
            CHECK(zoomAt(*program, 1e4) == 2); // at rest at the end
        } else {
            // Periodic both ways: the clock before 0 repeats the same cycles.
            for (double t : {0.37, 1.1, 2.9})
                for (int k : {-3, -1, 2})
                    near(zoomAt(*program, t + k * cycle), zoomAt(*program, t), 1e-9);
        }
        if (c.mode == Mode::PingPong) // symmetric about the top
            for (double x : {0.1, 0.4, 0.9})
                near(zoomAt(*program, c.delay + c.period + x * c.period),
                     zoomAt(*program, c.delay + c.period - x * c.period));
        if (c.mode == Mode::Loop && c.dyadic) {
            // The loop's seam: just before the cycle's end the progress is about to reach 1;
            // at the end it starts again from 0 (after the next delay, if any).
            CHECK(zoomAt(*program, cycle - 1e-9) - 1 > 0.999);
            CHECK(zoomAt(*program, cycle) == 1);
        }
    }
}

namespace {

// The colour channel `hex` (two hex digits) as the language reads it.
double channel(const char* hex) {
    return std::stoi(hex, nullptr, 16) / 255.0;
}

CompileOptions probing() {
    CompileOptions o;
    o.layerFields = true;
    o.mode = CompileOptions::Mode::Probe;
    // Point-sampled: the paper's colour must reach the probe untouched, and a probe's pixel is
    // not a pixel of any frame for the mean filter to average over.
    o.filter = sema::FilterMode::Point;
    return o;
}

} // namespace

TEST_CASE("timing: ramp is mix of its ends at the eased progress, for every type") {
    // Observed without going through ramp's own lowering: the colour is the paper (no ink
    // reaches the probe point), the angle is the zoom (angle / 1deg is a number), and a
    // vector's components are the distances from the probe point (0, 0) to two `lines`
    // layers at angle 0 and 90deg whose single near member sits at the ramped origin; a
    // number is a third such layer's phase.
    const std::string text =
        "timing tm { period = 2; delay = 0.5; mode = pingpong; easing = sine }\n"
        "scene { background = ramp(tm, #204060ff, #c0801040) }\n"
        "camera { zoom = 1 + ramp(tm, 10deg, 70deg) / 1deg }\n"
        "layer { family = lines; spacing = 1000; origin = ramp(tm, (1, 2), (4, 6)) }\n"
        "layer { family = lines; angle = 90deg; spacing = 1000; origin = ramp(tm, (1, 2), (4, 6)) "
        "}\n"
        "layer { family = lines; spacing = 1000; phase = ramp(tm, 3, 7) }\n";
    auto program = test::compileOk(text, probing());
    Prober probe(*program, nullptr);
    const lower::OutputLayout& layout = program->layout;
    const double from[4] = {channel("20"), channel("40"), channel("60"), 1.0};
    const double to[4] = {channel("c0"), channel("80"), channel("10"), channel("40")};
    auto mix = [](double a, double b, double u) { return a + (b - a) * u; };
    for (int i = -10; i <= 60; ++i) {
        const double t = i * 0.077;
        CAPTURE(t);
        const double p = ease("sine", rawProgress(Mode::PingPong, 0.5, 2, t));
        near(zoomAt(*program, t) - 1, mix(10, 70, p), 1e-11);
        std::vector<double> v = probe.at(0, 0, t);
        for (int c = 0; c < 4; ++c) near(v[c], mix(from[c], to[c], p));
        near(v[layout.distanceSlot(0)], mix(1, 4, p));
        near(v[layout.distanceSlot(1)], mix(2, 6, p));
        near(v[layout.distanceSlot(2)], mix(3, 7, p));
    }
}

TEST_CASE("timing: a dozen parameters on one timing move as one") {
    // Twelve parameters of different kinds (origins, phases, a family's angle, a vector's
    // two components), each ramped between its own ends on one eased, delayed loop: at every
    // t each must be at the same fraction of its way, and that fraction must be the timing's
    // progress (the zoom shows progress(tm)).
    struct Param {
        std::string layer;                   // the layer, with %A and %B for the ends
        double a, b;                         // the ends
        std::function<double(double)> value; // the ramped value, from the layer's distance
    };
    auto direct = [](double d) { return d; };
    // angle layers: origin (-100, 0), so the probe point is at x = 100 in the layer and the
    // near member's distance is 100 cos(angle).
    auto angle = [](double d) { return std::acos(d / 100) * 180 / kPi; };
    const std::vector<Param> params = {
        {"origin = (ramp(tm, %A, %B), 0)", 1, 5, direct},
        {"origin = (ramp(tm, %A, %B), 0)", 9, 2, direct},
        {"origin = (ramp(tm, %A, %B), 0)", 0.5, 30, direct},
        {"origin = (ramp(tm, %A, %B), 0)", 100, 40, direct},
        {"phase = ramp(tm, %A, %B)", 3, 7, direct},
        {"phase = ramp(tm, %A, %B)", 50, 10, direct},
        {"phase = ramp(tm, %A, %B)", 0.25, 0.75, direct},
        {"phase = ramp(tm, %A, %B)", 400, 1, direct},
        {"origin = (-100, 0); angle = ramp(tm, %Adeg, %Bdeg)", 20, 70, angle},
        {"origin = (-100, 0); angle = ramp(tm, %Adeg, %Bdeg)", 80, 10, angle},
        {"origin = ramp(tm, (%A, 1), (%B, 2))", 3, 8, direct},
        {"angle = 90deg; origin = ramp(tm, (1, %A), (2, %B))", 9, 1, direct},
    };
    std::string text =
        "timing tm { period = 2.5; delay = 0.75; mode = loop; easing = cubic_in_out }\n"
        "camera { zoom = 1 + progress(tm) }\n";
    for (const Param& p : params) {
        std::string body = p.layer;
        body.replace(body.find("%A"), 2, fmt::format("{}", p.a));
        body.replace(body.find("%B"), 2, fmt::format("{}", p.b));
        text += "layer { family = lines; spacing = 1000; " + body + " }\n";
    }
    auto program = test::compileOk(text, probing());
    Prober probe(*program, nullptr);
    for (int i = -20; i <= 70; ++i) {
        const double t = i * 0.0813;
        CAPTURE(t);
        const double progress = zoomAt(*program, t) - 1;
        near(progress, ease("cubic_in_out", rawProgress(Mode::Loop, 0.75, 2.5, t)));
        std::vector<double> v = probe.at(0, 0, t);
        for (size_t k = 0; k < params.size(); ++k) {
            CAPTURE(k);
            const Param& p = params[k];
            const double fraction =
                (p.value(v[program->layout.distanceSlot(static_cast<int>(k))]) - p.a) / (p.b - p.a);
            near(fraction, progress, 1e-10);
        }
    }
}

TEST_CASE("timing: a frame is a function of the clock, and nothing carries over") {
    // §8.5: the frame at t is computed, not replayed. Rendering t, then another frame, then t
    // again, or t from a freshly compiled program, must give the same image bit for bit, on
    // every backend; and the probe (which keeps its registers between calls) the same values.
    const std::string text =
        "scene { size = (64, 48); background = ramp(tm, #ffffff, #f0e8d0) }\n"
        "timing tm { period = 2; delay = 0.25; mode = pingpong; easing = sine_in }\n"
        "timing cycle { period = 3; mode = loop }\n"
        "camera { zoom = 1.5; rotation = ramp(tm, 0deg, 30deg) }\n"
        "layer { family = morph(cycle, circles, hexagons, squares); spacing = 6;\n"
        "        origin = ramp(tm, (0, 0), (5, -3)); offset = ramp(tm, (0, 0), (0.5, 0.2)) }\n"
        "layer { family = lines; spacing = 4; angle = ramp(tm, 10deg, 80deg);\n"
        "        color = ramp(tm, #202060, #a02020) }\n";
    auto same = [](const Image& a, const Image& b) {
        return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
               std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
    };
    const double t = 1.3, other = 2.9;
    for (const std::string& name : test::availableBackends()) {
        CAPTURE(name);
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        auto program = test::compileOk(text);
        Image first = test::renderScene(*program, *backend, 0, 0, t);
        Image between = test::renderScene(*program, *backend, 0, 0, other);
        Image again = test::renderScene(*program, *backend, 0, 0, t);
        auto fresh = test::compileOk(text);
        Image alone = test::renderScene(*fresh, *backend, 0, 0, t);
        CHECK_FALSE(same(first, between)); // the scene moves: the check below is not vacuous
        CHECK(same(first, again));
        CHECK(same(first, alone));
    }
    auto program = test::compileOk(text, probing());
    Prober probe(*program, nullptr);
    for (auto [x, y] : {std::pair{3.0, 4.0}, std::pair{-11.5, 7.25}}) {
        std::vector<double> a = probe.at(x, y, t);
        std::vector<double> b = probe.at(x, y, other);
        std::vector<double> c = probe.at(x, y, t);
        CHECK(a != b);
        CHECK(a == c);
    }
}

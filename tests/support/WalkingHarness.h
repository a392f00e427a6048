// Shared by the walking-family tests (walking_test.cpp, walking_index_test.cpp): one
// compiled walking layer whose numbers are re-set per setting, evaluated on the exact
// interpreter with its radius evaluations counted, and helpers to place points.
#pragma once

#include "compiler/backend/interp/Interpreter.h"
#include "runtime/Probe.h"
#include "tests/reference/WalkingReference.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <doctest/doctest.h>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace moire::walktest {

using reference::Walking;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

// Names and values for failure messages: SHOW(x, y) reports "x, y = 1.5, -2". INFO is lazy,
// so nothing is formatted unless a check fails.
template <class... T>
inline std::string show(const T&... v) {
    std::ostringstream o;
    o.precision(17);
    const char* sep = "";
    ((o << sep << v, sep = ", "), ...);
    return o.str();
}
#define SHOW(...) INFO(#__VA_ARGS__ " = ", show(__VA_ARGS__))
// Measured figures (docs/families.md quotes them), printed with MOIRE_WALKING_REPORT=1.
#define REPORT(...)                                                                                \
    do {                                                                                           \
        if (std::getenv("MOIRE_WALKING_REPORT")) MESSAGE(__VA_ARGS__);                             \
    } while (false)

// One compiled walking layer (double interpreter, counting radius evaluations) whose numbers
// are re-set per setting: the scene is written with sentinel numbers, each found by value
// among the literal slots.
struct Walker {
    std::unique_ptr<SceneProgram> program;
    std::unique_ptr<Prober> probe;
    int zoom, spacing, phase, ox, oy, turn, stroke, sides = -1;

    explicit Walker(const std::string& fam, const lower::WalkingVariant& variant = {}) {
        std::string text =
            "camera { zoom = 1.0101 }\nlayer { family = " + fam +
            "; spacing = 10.0202; phase = 0.0303; offset = (0.0404, 0.0505); turn = 0.0606rad;"
            " stroke = 1.0707" +
            (fam == "ngon" ? "; sides = 5.0808" : "") + " }\n";
        program = test::compileOk(text, CompileOptions{.mode = CompileOptions::Mode::Probe,
                                                       .layerFields = true,
                                                       .tally = true,
                                                       .walking = variant});
        probe = std::make_unique<Prober>(*program, nullptr);
        auto slot = [&](double v) {
            for (size_t i = 0; i < program->literals.size(); ++i)
                if (program->literals[i] == v) return static_cast<int>(i);
            FAIL("no literal slot holds ", v);
            return -1;
        };
        zoom = slot(1.0101), spacing = slot(10.0202), phase = slot(0.0303), ox = slot(0.0404);
        oy = slot(0.0505), turn = slot(0.0606), stroke = slot(1.0707);
        if (fam == "ngon") sides = slot(5.0808);
    }
};

// The stroke band and guard are written again here on purpose, from the spec (Eqs. 26, 35):
// an oracle independent of compiler/lower's (LayerPipeline.h, WalkingFamily.h).
struct Setting {
    Walking w;
    double zoom = 1.0, stroke = 1.5;
    double sides = -1.0; // >= 0: an ngon layer with this side count (may be fractional)
    double h() const { return std::max(stroke / 2.0, 1.15 / zoom); }
    double a() const { return 0.7 / zoom; }
    double guard() const { return std::max(h() + a(), 0.75 * w.spacing); }
    double accept() const { return h() - a(); }
    double coverage(double d) const { // Eq. 4 without opacity
        double t = std::clamp((d - (h() - a())) / (2.0 * a()), 0.0, 1.0);
        return 1.0 - t * t * (3.0 - 2.0 * t);
    }
};

// A setting, as the scene would say it (the turn in radians).
inline std::string describe(const Setting& st) {
    return show("facets", st.w.facets, "sides", st.sides, "spacing", st.w.spacing, "phase",
                st.w.phase, "offset", st.w.offsetX, st.w.offsetY, "turn", st.w.turn, "zoom",
                st.zoom, "stroke", st.stroke);
}

struct Out {
    double distance, index, lo, hi;
    uint64_t evaluations; // radius evaluations the pixel took (the interpreter's tally)
};

inline std::string familyOf(int facets) {
    return facets == 0   ? "circles"
           : facets == 3 ? "triangles"
           : facets == 4 ? "squares"
           : facets == 6 ? "hexagons"
                         : "ngon";
}

// The family a setting is drawn with.
inline std::string familyOf(const Setting& st) {
    return st.sides >= 0 ? "ngon" : familyOf(st.w.facets);
}

// The compiled layer `k` (of familyOf(st)) at (x, y) for a setting, probed by `p` (the
// walker's own interpreter, or another backend's prober over the same program). The tally
// is left at 0: only the interpreter counts.
inline Out probeOn(Prober& p, const Walker& k, const Setting& st, double x, double y) {
    p.setLiteral(k.zoom, st.zoom);
    p.setLiteral(k.spacing, st.w.spacing);
    p.setLiteral(k.phase, st.w.phase);
    p.setLiteral(k.ox, st.w.offsetX);
    p.setLiteral(k.oy, st.w.offsetY);
    p.setLiteral(k.turn, st.w.turn);
    p.setLiteral(k.stroke, st.stroke);
    if (k.sides >= 0) p.setLiteral(k.sides, st.sides >= 0 ? st.sides : st.w.facets);
    std::vector<double> v = p.at(x, y);
    const auto& L = k.program->layout;
    return {v[L.distanceSlot(0)], v[L.indexSlot(0)], v[L.aux0Slot(0)], v[L.aux1Slot(0)], 0};
}

// The same on the walker's double interpreter, with its count of radius evaluations.
inline Out solveOn(Walker& k, const Setting& st, double x, double y) {
    Out o = probeOn(*k.probe, k, st, x, y);
    o.evaluations = Interpreter::lastTally(0);
    return o;
}

// The solver at (x, y) for a setting, on the double interpreter.
inline Out solve(const Setting& st, double x, double y) {
    static std::map<std::string, std::unique_ptr<Walker>> compiled; // one program per shape
    std::unique_ptr<Walker>& k = compiled[familyOf(st)];
    if (!k) k = std::make_unique<Walker>(familyOf(st));
    return solveOn(*k, st, x, y);
}

// The angle of facet normal k of an N-gon (facet 0 faces +x; vertices lie half way between).
inline double facetAngle(int n, int k) {
    return 2.0 * kPi * k / n;
}

// An offset whose drift constant m = rho(-delta) is f s, with -delta pointing at `angle`.
inline void setDrift(Walking& w, double f, double angle) {
    double t = f * w.spacing / reference::radius(w.facets, std::cos(angle), std::sin(angle));
    w.offsetX = -t * std::cos(angle);
    w.offsetY = -t * std::sin(angle);
}

// A point on member n of the family, in direction `angle` of that member's own frame, moved
// by `jitter` along that direction (world units, approximately).
inline void onMember(const Walking& w, int64_t n, double angle, double jitter, double& x,
                     double& y) {
    double dx = std::cos(angle), dy = std::sin(angle);
    double rad =
        std::max(0.0, n * w.spacing + w.phase) / reference::radius(w.facets, dx, dy) + jitter;
    double qx = rad * dx + n * w.offsetX, qy = rad * dy + n * w.offsetY; // q_n + n delta
    double c = std::cos(n * w.turn), s = std::sin(n * w.turn);
    x = c * qx - s * qy;
    y = s * qx + c * qy;
}

// A point uniform in the disc of radius `extent` about the origin.
inline void inDisc(double extent, std::mt19937_64& rng, double& x, double& y) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    double r = extent * std::sqrt(unit(rng)), a = 2 * kPi * unit(rng);
    x = r * std::cos(a), y = r * std::sin(a);
}

// A point on or near a random member reaching `extent`: the member, the direction and a
// jitter within the setting's guard band drawn from `rng`.
inline void nearMember(const Setting& st, double extent, std::mt19937_64& rng, double& x,
                       double& y) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double jitter = (unit(rng) - 0.5) * st.guard();
    const double angle = 2 * kPi * unit(rng);
    const auto n = static_cast<int64_t>(unit(rng) * extent / st.w.spacing);
    onMember(st.w, n, angle, jitter, x, y);
}

// The solver's clamped distance agrees with an expected one: equal to rounding, or both
// inside the band that is inked solid (the solver may stop early there, §7.1).
inline bool agrees(const Setting& st, double got, double want, double x, double y) {
    double tol = 1e-10 * (1.0 + std::hypot(x, y) + st.w.spacing);
    return std::fabs(got - want) <= tol || (got <= st.accept() && want <= st.accept());
}

// Renders each (name, scene body) at w x h on the exact interpreter and the single-precision
// JIT: the picture must have ink (precision loses ink) and the JIT must draw it within 2/255
// at 99.9% of samples. Rendered coverage, not raw distances: f32 moves a residual by about an
// ulp of the member's radius, which matters to the picture only where it moves a pixel
// across the antialias band.
inline void
checkJitDrawsLikeInterpreter(const std::vector<std::pair<std::string, std::string>>& scenes, int w,
                             int h) {
    auto interp = test::makeBackendOrSkip("interp");
    auto jit = test::makeBackendOrSkip("jit");
    if (!interp || !jit) return;
    for (const auto& [name, body] : scenes) {
        SHOW(name);
        auto program = test::compileOk("scene { size = (" + std::to_string(w) + ", " +
                                       std::to_string(h) + ") }\n" + body + "\n");
        Image exact = test::renderScene(*program, *interp);
        Image fast = test::renderScene(*program, *jit);
        test::ImageDiff d = test::compareImages(exact, fast, 2.0 / 255.0);
        double ink = 0.0; // the picture is not blank (precision loses ink, as above)
        for (float v : exact.pixels) ink += 1.0 - v;
        ink /= exact.pixels.size() * 3.0 / 4.0; // black ink on white; alpha stays 1
        REPORT(name, ": ink ", ink, ", max difference ", d.maxAbs,
               ", within 2/255: ", d.fractionWithin());
        CHECK(ink > 0.05);
        CHECK(d.fractionWithin() >= 0.999);
    }
}

} // namespace moire::walktest

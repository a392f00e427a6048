// The index gradient of walking families (spec §4.1), held to independent expectations.
//
// A walking family's index field is found by search: the nearest member n* plus the
// fractional residual h(n*) / (h(n*) - h(n* +- 1)). Its gradient comes from forward-mode AD
// through the solver's result, n* held fixed. Here it is checked
//  - against central finite differences of the index field itself, on the reference
//    interpreter in double, at seeded points of every walking example, the default scene and
//    one scene for each branch of the solver (concentric, translated circle, translated
//    polygon, the scan, an encoded field). A difference means nothing where the index is not
//    smooth within its step: across a member (the index is piecewise linear between members,
//    with a kink on each), across a corner of a polygon's radius, or where n* jumps to a
//    member that is not a neighbour or the fraction switches to its fallback. Such points
//    are skipped, and what says so is the differences alone (the stencil crosses a whole
//    index, or its two step sizes disagree), never the gradient under test;
//  - against the closed form inside member 0, where the fraction falls back to the residual
//    in spacings: for circles the gradient is p / (|p| s);
//  - on the JIT (single precision) against the interpreter;
//  - and structurally: AD leaves the solver's search loops as they are (n* is held fixed, so
//    no tangent is carried through the search that found it).
#include "compiler/passes/AutoDiff.h"
#include "runtime/output/Render.h"
#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <doctest/doctest.h>
#include <random>

using namespace moire;

namespace {

constexpr double kTime = 4.0; // a clock for the animated scenes

struct Sample {
    double index, gx, gy;
};

struct Scene {
    const char* name;
    std::string text;
    double halfX, halfY; // the world box the points are drawn from, about the origin
};

std::string layerScene(const std::string& body) {
    return "layer walk {\n" + body + "\n}\n";
}

std::vector<Scene> scenes() {
    return {
        {"walking_squares", test::readFile(test::sourcePath("examples/walking_squares.moire")), 480,
         320},
        {"walking_triangles", test::readFile(test::sourcePath("examples/walking_triangles.moire")),
         560, 380},
        {"unwinding_walk", test::readFile(test::sourcePath("examples/unwinding_walk.moire")), 500,
         330},
        {"drifting_walks", test::readFile(test::sourcePath("examples/drifting_walks.moire")), 520,
         350},
        // One scene per branch of the solver.
        {"concentric (turn only)",
         layerScene("family = squares\nspacing = 8\nturn = 1.5deg\nphase = 3"), 300, 300},
        {"translated circle", layerScene("family = circles\nspacing = 8\noffset = (1.0, 0.4)"), 300,
         300},
        {"translated polygon", layerScene("family = hexagons\nspacing = 8\noffset = (1.3, -0.6)"),
         300, 300},
        {"scan (heptagons)",
         layerScene("family = ngon\nsides = 7\nspacing = 8\noffset = (0.8, 0.5)\n"
                    "turn = 0.7deg"),
         300, 300},
        {"encoded field",
         layerScene("family = circles\nspacing = 8\noffset = (1.0, 0.4)\nturn = 0.5deg\n"
                    "field = 0.002 * x * x + 0.01 * y\ngain = 1"),
         300, 300},
    };
}

// A scene compiled with its layers' fields as outputs, read on a backend (null: the reference
// interpreter, in double).
class Fields {
  public:
    Fields(const SceneProgram& program, Backend* backend)
        : program_(program), probe_(program, backend) {}
    Sample at(int layer, double x, double y) {
        const std::vector<double> o = probe_.at(x, y, kTime);
        const auto& l = program_.layout;
        return {o[l.indexSlot(layer)], o[l.gradXSlot(layer)], o[l.gradYSlot(layer)]};
    }

  private:
    const SceneProgram& program_;
    Prober probe_;
};

// The central difference of the index along (dx, dy) with step h, and the values it read.
struct Difference {
    double slope, lo, hi;
};
Difference difference(Fields& f, int layer, double x, double y, double dx, double dy, double h) {
    const double hi = f.at(layer, x + h * dx, y + h * dy).index;
    const double lo = f.at(layer, x - h * dx, y - h * dy).index;
    return {(hi - lo) / (2 * h), lo, hi};
}

// True when the index is smooth across both stencils: no whole index (a member) between
// their values, and the steps h and 2h agreeing (their difference is O(h^2) where the index
// is smooth, O(1) across a kink or a jump).
bool smooth(const Difference& d1, const Difference& d2, double centre) {
    const double lo = std::min({d1.lo, d1.hi, d2.lo, d2.hi, centre});
    const double hi = std::max({d1.lo, d1.hi, d2.lo, d2.hi, centre});
    if (std::floor(lo) != std::floor(hi)) return false;
    return std::abs(d1.slope - d2.slope) <= 1e-7 * std::max(std::abs(d1.slope), 1e-3);
}

struct Stats {
    int compared = 0, skipped = 0;
    double worst = 0; // the largest relative error of the gradient's length
};

// The number of values each loop carries, in program order (regions in place).
void loopWidths(const ir::Function& f, ir::BlockId block, std::vector<size_t>& out) {
    for (const ir::Inst& inst : f.blocks[block].insts) {
        if (inst.op == ir::Op::Loop) out.push_back(inst.results.size());
        for (ir::BlockId r : inst.regions) loopWidths(f, r, out);
    }
}

// A scene compiled with its layers' fields as outputs.
std::unique_ptr<SceneProgram> compileFields(const std::string& text) {
    return test::compileOk(text, {.mode = CompileOptions::Mode::Probe, .layerFields = true});
}

// Calls fn(layer, x, y) at `count` seeded points of the scene's box for each of its layers.
template <class Fn>
void forEachPoint(const Scene& s, const SceneProgram& program, std::mt19937& rng, int count,
                  Fn&& fn) {
    std::uniform_real_distribution<double> ux(-s.halfX, s.halfX), uy(-s.halfY, s.halfY);
    for (int layer = 0; layer < program.layout.numLayers; ++layer)
        for (int i = 0; i < count; ++i) {
            const double x = ux(rng), y = uy(rng);
            CAPTURE(layer);
            CAPTURE(x);
            CAPTURE(y);
            fn(layer, x, y);
        }
}

} // namespace

TEST_CASE("walking gradient: the exact index gradient matches finite differences of the index") {
    // Step 1e-4 world units at pitches 8 to 9: the difference's truncation error is far below
    // 1e-8 of the gradient and its rounding (1e-16 of an index of order 100, over 2e-4) about
    // 1e-10 of it.
    const double h = 1e-4;
    std::mt19937 rng(1515);
    for (const Scene& s : scenes()) {
        const std::string name = s.name;
        CAPTURE(name);
        auto program = compileFields(s.text);
        Fields exact(*program, nullptr);
        Stats st;
        forEachPoint(s, *program, rng, 400, [&](int layer, double x, double y) {
            const Sample g = exact.at(layer, x, y);
            REQUIRE(std::isfinite(g.index));
            REQUIRE(std::isfinite(g.gx));
            REQUIRE(std::isfinite(g.gy));
            const Difference dx = difference(exact, layer, x, y, 1, 0, h);
            const Difference dy = difference(exact, layer, x, y, 0, 1, h);
            const Difference dx2 = difference(exact, layer, x, y, 1, 0, 2 * h);
            const Difference dy2 = difference(exact, layer, x, y, 0, 1, 2 * h);
            if (!smooth(dx, dx2, g.index) || !smooth(dy, dy2, g.index)) {
                ++st.skipped;
                return;
            }
            ++st.compared;
            const double len = std::hypot(dx.slope, dy.slope);
            const double err = std::hypot(g.gx - dx.slope, g.gy - dy.slope) / len;
            st.worst = std::max(st.worst, err);
            CHECK(err < 1e-7);
        });
        MESSAGE(name << ": " << st.compared << " points compared, " << st.skipped
                     << " skipped, worst relative error " << st.worst);
        // The skips are the rare points near a kink, not the rule.
        CHECK(st.skipped * 10 < st.compared);
    }
}

TEST_CASE("walking gradient: inside member 0 the fallback's own gradient, p / (|p| s)") {
    // Member 0 is the circle of radius `phase` about the origin; inside it the fraction falls
    // back to the residual in spacings, (|p| - phase) / s.
    auto program =
        compileFields(layerScene("family = circles\nspacing = 8\nphase = 20\noffset = (1.0, 0.4)"));
    Fields exact(*program, nullptr);
    for (int i = 0; i < 24; ++i) {
        const double a = 0.37 + 0.26 * i, r = 4.0 + 0.55 * i; // |p| from 4 to 16.7
        const double x = r * std::cos(a), y = r * std::sin(a);
        CAPTURE(x);
        CAPTURE(y);
        const Sample g = exact.at(0, x, y);
        CHECK(g.index == doctest::Approx((r - 20.0) / 8.0).epsilon(1e-12));
        CHECK(g.gx == doctest::Approx(x / (r * 8.0)).epsilon(1e-12));
        CHECK(g.gy == doctest::Approx(y / (r * 8.0)).epsilon(1e-12));
    }
}

TEST_CASE("walking gradient: the JIT's gradient agrees with the interpreter's") {
    std::unique_ptr<Backend> jit = makeBackend("jit");
    REQUIRE(jit);
    std::mt19937 rng(2024);
    for (const Scene& s : scenes()) {
        const std::string name = s.name;
        CAPTURE(name);
        auto program = compileFields(s.text);
        Fields exact(*program, nullptr), single(*program, jit.get());
        int compared = 0, nearMember = 0;
        double worst = 0;
        forEachPoint(s, *program, rng, 600, [&](int layer, double x, double y) {
            const Sample want = exact.at(layer, x, y), got = single.at(layer, x, y);
            // The same index to single precision (of an index of order 100)...
            CHECK(got.index == doctest::Approx(want.index).epsilon(1e-5).scale(100));
            // ...and the same gradient, but on a member: the index has a kink there, and
            // which side of it single precision lands on is a matter of rounding.
            if (std::abs(want.index - std::round(want.index)) < 1e-3) {
                ++nearMember;
                return;
            }
            ++compared;
            const double err =
                std::hypot(got.gx - want.gx, got.gy - want.gy) / std::hypot(want.gx, want.gy);
            worst = std::max(worst, err);
            CHECK(err < 1e-3);
        });
        MESSAGE(name << ": " << compared << " points compared (" << nearMember
                     << " on a member), worst relative difference " << worst);
    }
}

TEST_CASE("walking gradient: AD carries no tangent through the solver's loops") {
    size_t loops = 0;
    for (const Scene& s : scenes()) {
        const std::string name = s.name;
        CAPTURE(name);
        auto program = compileFields(s.text);
        std::vector<size_t> before, after;
        loopWidths(program->lowered, 0, before);
        loopWidths(passes::autoDiff(program->lowered), 0, after);
        CHECK(after == before);
        loops += before.size();
    }
    // The scan's stride and walk, the polygon's two passes: there are loops to leave alone
    // (a scene whose parameters fold to the concentric or the circle's branch has none).
    CHECK(loops >= 8);
}

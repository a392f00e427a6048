// The walking scan's carried rotation (compiler/lower/WalkingFamily, scan()): a skip of 2 to
// 7 strides turns the carried point by Rot(k sigma theta) built from the powers
// Rot(2^j sigma theta) of k's binary digits, where it used to take a fresh cosine and sine
// of n theta. Held to independent expectations: the brute-force reference (double, every
// member turned afresh) on the interpreter, and the interpreter on the single-precision JIT,
// at turns large enough that k theta wraps the circle, so that a wrong digit or power would
// turn the point somewhere else entirely.
#include "tests/support/WalkingHarness.h"

using namespace moire;
using namespace moire::walktest;

TEST_CASE("walking: skips of several members keep the carried turn exact") {
    // Points far from every member skip the most (the Lipschitz bound grows with the
    // residual), and the turns here make Rot(k theta) differ from Rot(theta) by up to a
    // half turn and more within one 7-member jump.
    std::mt19937_64 rng(23);
    long checked = 0;
    for (int n : {0, 3, 4, 6})
        for (double turnDeg : {5.0, -13.0, 37.0, 171.0})
            for (double f : {0.4, 1.3}) {
                Setting st;
                st.w.facets = n;
                st.w.spacing = 6.0;
                st.w.phase = 1.5;
                st.w.turn = turnDeg * kDeg;
                setDrift(st.w, f, 0.7);
                st.stroke = 1.2;
                for (int j = 0; j < 40; ++j) {
                    double x, y;
                    if (j % 4 == 0)
                        nearMember(st, 350.0, rng, x, y);
                    else
                        inDisc(350.0, rng, x, y);
                    reference::Nearest ref = reference::nearest(st.w, x, y, st.guard(), 200000);
                    if (!ref.complete) continue;
                    Out o = solve(st, x, y);
                    INFO(describe(st));
                    SHOW(x, y, o.distance, ref.distance, ref.argmin, o.evaluations);
                    CHECK(agrees(st, o.distance, ref.distance, x, y));
                    ++checked;
                }
            }
    REPORT("points checked against the reference: ", checked);
    CHECK(checked >= 1000);
}

TEST_CASE("walking: the JIT's carried turn draws what the interpreter draws at large turns") {
    // Coverage within 2/255 (checkJitDrawsLikeInterpreter), as in walking_index_test.cpp; the
    // second scene is zoomed out until the scan strides, so the powers there come from
    // Rot(sigma theta) by squaring.
    const std::vector<std::pair<std::string, std::string>> scenes = {
        {"squares, turn 23deg",
         "camera { zoom = 1 }\nlayer { family = squares; spacing = 7; offset = (1.5, 0.5); "
         "turn = 23deg; stroke = 1.5 }"},
        {"strided hexagons, turn 1.1deg",
         "camera { zoom = 0.5; center = (3000, 0) }\nlayer { family = hexagons; spacing = 10; "
         "offset = (9.5, 0); turn = 1.1deg; stroke = 1 }"},
        {"circles, turn -61deg",
         "camera { zoom = 0.6 }\nlayer { family = circles; spacing = 9; offset = (2, -3); "
         "turn = -61deg; stroke = 2 }"},
    };
    checkJitDrawsLikeInterpreter(scenes, 200, 140);
}

// The render fuzz target's rule for interpreter (double) against JIT (float) renders of two
// 8 x 8 windows (fuzz/RenderCompare.h): real JIT renders of every example pass, a picture that
// is wrong as a whole fails, and a scene that single precision cannot draw gets no verdict.
#include "fuzz/RenderCompare.h"
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <limits>

using namespace moire;

namespace {
// The windows of frame t = 0.5 rendered on `backend`, with the frame's uniforms replaced by
// `edit` of them.
template <class Edit>
std::vector<float> render(const SceneProgram& program, const std::string& backend, Edit edit) {
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateFrame(program, FrameRequest{0.5}, fv, diags));
    auto b = makeBackend(backend); // a JIT's kernel lives as long as its backend
    auto kernel = b->compile(program.kernel);
    return fuzz::renderWindows(*kernel, edit(fv.uniforms), fv.width, fv.height);
}
std::vector<double> same(const std::vector<double>& u) {
    return u;
}
std::vector<float> renderInterp(const SceneProgram& program, auto edit) {
    return render(program, "interp", edit);
}
} // namespace

TEST_CASE("fuzz render rule: the JIT's renders of the examples agree with the interpreter") {
    for (const std::string& rel : test::exampleScenes()) {
        CAPTURE(rel);
        auto program = test::compileOk(test::readFile(test::sourcePath(rel)), {}, rel);
        std::vector<float> want = renderInterp(*program, same);
        std::vector<float> got = render(*program, "jit", same);
        CHECK(fuzz::offFraction(want, got, 4, 4) <= fuzz::kOffFraction);
        // Most of the samples are within 1/255, as the backend tests ask of whole images.
        CHECK(fuzz::offFraction(want, got, 4, 4) <= 0.05);
    }
}

TEST_CASE("fuzz render rule: a few edge pixels pass, a whole image off fails") {
    auto program = test::compileOk(test::readFile(test::sourcePath("examples/two_rings.moire")));
    std::vector<float> want = renderInterp(*program, same);
    std::vector<float> rounded =
        renderInterp(*program, [](auto& u) { return fuzz::floatUniforms(u, 0); });
    std::vector<float> nudged =
        renderInterp(*program, [](auto& u) { return fuzz::floatUniforms(u, 4); });
    REQUIRE(fuzz::judge(want, want, rounded, nudged, 4, 4) == fuzz::Verdict::Agree);

    // Three pixels turned from ink to paper or back: what float does at edges.
    std::vector<float> edges = want;
    for (int p : {3, 17, 40})
        for (int c = 0; c < 3; ++c) edges[p * 4 + c] = 1.0f - edges[p * 4 + c];
    CHECK(fuzz::judge(want, edges, rounded, nudged, 4, 4) == fuzz::Verdict::Agree);

    // Every uniform changed (camera, colours, spacing): another picture.
    std::vector<float> moved = renderInterp(*program, [](std::vector<double> u) {
        for (double& v : u) v = v * 1.5 + 0.25;
        return u;
    });
    CHECK(fuzz::offFraction(want, moved, 4, 4) > fuzz::kOffFraction);
    CHECK(fuzz::judge(want, moved, rounded, nudged, 4, 4) == fuzz::Verdict::Differ);

    // Every colour inverted.
    std::vector<float> inverted = want;
    for (float& v : inverted) v = 1.0f - v;
    CHECK(fuzz::judge(want, inverted, rounded, nudged, 4, 4) == fuzz::Verdict::Differ);
}

TEST_CASE("fuzz render rule: a scene single precision cannot draw gets no verdict") {
    // Lines 0.0137 apart (14 pixels), seen from 1e6 units away: float keeps 0.06 of a unit
    // there, a few lines, so uniforms nudged by a few float ulps alone give another picture.
    auto program =
        test::compileOk("camera { center = (1000000, 3) zoom = 1000 }\n"
                        "layer a { family = lines; spacing = 0.0137; stroke = 0.005 }\n");
    std::vector<float> want = renderInterp(*program, same);
    std::vector<float> rounded =
        renderInterp(*program, [](auto& u) { return fuzz::floatUniforms(u, 0); });
    std::vector<float> nudged =
        renderInterp(*program, [](auto& u) { return fuzz::floatUniforms(u, 4); });
    // The JIT's own render is such another picture, and is not held to the interpreter's.
    std::vector<float> jit = render(*program, "jit", same);
    CHECK(fuzz::offFraction(want, jit, 4, 4) > fuzz::kOffFraction);
    CHECK(fuzz::judge(want, jit, rounded, nudged, 4, 4) == fuzz::Verdict::IllConditioned);
}

TEST_CASE("fuzz render rule: float's range is not excused, only its precision") {
    // A stroke of 1e308 is finite for the interpreter; a JIT that makes it infinite draws
    // another picture, and the rounded re-render must not excuse that by overflowing too.
    std::vector<double> u = fuzz::floatUniforms({1e308, -1e308, 1e-50, -1e-50, 0.0, 0.1}, 0);
    CHECK(u[0] == std::numeric_limits<float>::max());
    CHECK(u[1] == -std::numeric_limits<float>::max());
    CHECK(u[2] == std::numeric_limits<float>::denorm_min());
    CHECK(u[3] == -std::numeric_limits<float>::denorm_min());
    CHECK(u[4] == 0.0);
    CHECK(u[5] == static_cast<double>(0.1f));
    std::vector<double> n = fuzz::floatUniforms({0.1, -1e308}, 2);
    CHECK(n[0] == std::nextafter(std::nextafter(0.1f, 1.0f), 1.0f));
    CHECK(n[1] == -std::numeric_limits<float>::max());
}

TEST_CASE("fuzz render rule: a uniform beyond float's range is never excused") {
    CHECK_FALSE(fuzz::beyondFloat({0.0, -3.4e38, 1e30, INFINITY, NAN}));
    CHECK(fuzz::beyondFloat({1.0, 3.5e38}));
    CHECK(fuzz::beyondFloat({-1e308}));
    // Another picture whose interpreter re-renders also differ: ill-conditioned, unless a
    // uniform was beyond float.
    std::vector<float> want(64, 0.0f), other(64, 1.0f);
    CHECK(fuzz::judge(want, other, other, other, 4, 4) == fuzz::Verdict::IllConditioned);
    CHECK(fuzz::judge(want, other, other, other, 4, 4, true) == fuzz::Verdict::Differ);
    CHECK(fuzz::judge(want, want, other, other, 4, 4, true) == fuzz::Verdict::Agree);
}

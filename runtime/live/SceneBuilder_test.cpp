// The live rebuild: a change of numbers keeps the compiled kernel (counted at the builder and
// at the backend's own compile counter), a change of structure compiles a new one, and what
// a reused kernel draws is what a fresh compilation of the new text draws.
#include "compiler/backend/llvm/LlvmJit.h"
#include "runtime/FrameEval.h"
#include "runtime/live/SceneBuilder.h"
#include "runtime/TileExecutor.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>

namespace moire {
namespace {

const char* kScene = R"(scene { size = (48, 32); background = #f0ece4 }
camera { zoom = 1.5 }
layer a { family = circles; spacing = 5; stroke = 1.2; color = #202028; origin = (-3, 0) }
layer b { family = lines; spacing = 4; rotation = 12deg; stroke = 1; color = #802020 }
)";

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    size_t at = text.find(from);
    REQUIRE(at != std::string::npos);
    return text.replace(at, from.size(), to);
}

Image draw(const LiveProgram& build) {
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(*build.program, {}, frame, diags));
    KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
    return runKernel(*build.kernel, kf);
}

} // namespace

TEST_CASE("SceneBuilder: number edits reuse the kernel, structural edits compile one") {
    LlvmJitBackend jit;
    SceneBuilder builder(jit);
    BuildResult first = builder.build("live.moire", kScene);
    REQUIRE(first.kind == BuildResult::Kind::Structure);
    CHECK(builder.kernelBuilds() == 1);
    CHECK(jit.compileCount() == 1);

    // Numbers, colours, angles and vectors: uniforms only.
    const std::pair<const char*, const char*> numberEdits[] = {
        {"spacing = 5", "spacing = 6.5"}, {"zoom = 1.5", "zoom = 0.8"},
        {"#802020", "#2040a0"},           {"12deg", "-40deg"},
        {"(-3, 0)", "(2.5, -7)"},         {"stroke = 1;", "stroke = 2.25;"},
    };
    std::string text = kScene;
    for (auto [from, to] : numberEdits) {
        CAPTURE(std::string(to));
        text = replaced(text, from, to);
        BuildResult r = builder.build("live.moire", text);
        REQUIRE(r.kind == BuildResult::Kind::Numbers);
        CHECK(r.build->kernel == first.build->kernel);
        // What the reused kernel draws is what a fresh compile of the text draws.
        std::unique_ptr<SceneProgram> fresh = test::compileOk(text);
        LlvmJitBackend other;
        Image expect = test::renderScene(*fresh, other);
        test::ImageDiff d = test::compareImages(draw(*r.build), expect, 0.0);
        CHECK(d.maxAbs == 0.0);
    }
    CHECK(builder.kernelBuilds() == 1);
    CHECK(jit.compileCount() == 1);
    CHECK(builder.frontEndCompiles() == 1 + static_cast<int>(std::size(numberEdits)));

    // Structure: another family, another layer, a property that was absent, an expression.
    const std::pair<const char*, const char*> structuralEdits[] = {
        {"family = lines", "family = wave"},
        {"layer b", "layer c { family = circles; spacing = 3 }\nlayer b"},
        {"stroke = 1.2;", "stroke = 1.2; phase = 0.25;"},
        {"spacing = 6.5", "spacing = 6.5 + x / 40"},
    };
    int before = builder.kernelBuilds();
    for (auto [from, to] : structuralEdits) {
        CAPTURE(std::string(to));
        text = replaced(text, from, to);
        BuildResult r = builder.build("live.moire", text);
        CAPTURE(r.diagnostics);
        REQUIRE(r.kind == BuildResult::Kind::Structure);
        CHECK(builder.kernelBuilds() == ++before);
        std::unique_ptr<SceneProgram> fresh = test::compileOk(text);
        LlvmJitBackend other;
        CHECK(test::compareImages(draw(*r.build), test::renderScene(*fresh, other), 0.0).maxAbs ==
              0.0);
    }
    CHECK(jit.compileCount() == 1 + static_cast<int>(std::size(structuralEdits)));
}

TEST_CASE("SceneBuilder: same bytes are skipped, bad text keeps the current build") {
    LlvmJitBackend jit;
    SceneBuilder builder(jit);
    BuildResult good = builder.build("live.moire", kScene);
    REQUIRE(good.good());
    CHECK(builder.build("live.moire", kScene).kind == BuildResult::Kind::Unchanged);
    CHECK(builder.frontEndCompiles() == 1);

    std::string broken = std::string(kScene).substr(0, 95);
    BuildResult bad = builder.build("live.moire", broken);
    CHECK(bad.kind == BuildResult::Kind::Failed);
    CHECK(bad.diagnostics.find("live.moire:") == 0);
    CHECK(bad.diagnostics.find("error:") != std::string::npos);
    CHECK(builder.current() == good.build);
    // The same broken bytes again: nothing new to say.
    CHECK(builder.build("live.moire", broken).kind == BuildResult::Kind::Unchanged);
    // Back to the good text: a new build of it, and its kernel is the one already compiled.
    BuildResult again = builder.build("live.moire", kScene);
    CHECK(again.kind == BuildResult::Kind::Numbers);
    CHECK(again.build->kernel == good.build->kernel);

    // A file that vanished, then came back with the same bytes: reported twice, not skipped.
    CHECK(builder.unreadable("live.moire: error: gone\n").kind == BuildResult::Kind::Failed);
    CHECK(builder.build("live.moire", kScene).good());
    CHECK(builder.kernelBuilds() == 1);
}

TEST_CASE("SceneBuilder: an interactive program keeps its kernel across view edits") {
    // The viewer's pan, zoom and layer motions are literal slots: any values, one kernel.
    LlvmJitBackend jit;
    SceneBuilder builder(jit, CompileOptions{.mode = CompileOptions::Mode::Interactive});
    BuildResult r = builder.build("live.moire", kScene);
    REQUIRE(r.good());
    const SceneProgram& p = *r.build->program;
    REQUIRE(p.viewSlot >= 0);
    CHECK(p.literals.size() == static_cast<size_t>(p.viewSlot + lower::ViewSlots::count(2)));
    // The identity view draws what the plain program draws.
    std::unique_ptr<SceneProgram> plain = test::compileOk(kScene);
    LlvmJitBackend other;
    Image expect = test::renderScene(*plain, other);
    CHECK(test::compareImages(draw(*r.build), expect, 1e-6).maxAbs < 1e-5);

    // Each view slot against the scene written with the same placement.
    using VS = lower::ViewSlots;
    auto viewed = [&](std::vector<std::pair<int, double>> slots) {
        std::vector<double> literals = p.literals;
        for (auto [slot, v] : slots) literals[p.viewSlot + slot] = v;
        FrameRequest req;
        req.literals = &literals;
        FrameValues frame;
        std::string diags;
        REQUIRE(evaluateFrame(p, req, frame, diags));
        KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
        return runKernel(*r.build->kernel, kf);
    };
    auto written = [&](std::string text) {
        std::unique_ptr<SceneProgram> q = test::compileOk(text);
        return test::renderScene(*q, other);
    };
    const double deg = 3.14159265358979323846 / 180.0;
    std::string s = kScene;
    CHECK(test::compareImages(viewed({{VS::kPanX, 5}, {VS::kPanY, -3}, {VS::kZoomFactor, 2}}),
                              written(replaced(s, "zoom = 1.5", "zoom = 3; center = (5, -3)")),
                              0.02)
              .fractionWithin() > 0.999);
    CHECK(test::compareImages(
              viewed({{VS::layer(0, VS::kLayerDx), 2}, {VS::layer(0, VS::kLayerDy), 1}}),
              written(replaced(s, "(-3, 0)", "(-1, 1)")), 0.02)
              .fractionWithin() > 0.999);
    // A turn about the world origin carries the origin round with it and adds to rotation.
    CHECK(test::compareImages(
              viewed({{VS::layer(0, VS::kLayerTurn), 90 * deg},
                      {VS::layer(1, VS::kLayerTurn), 30 * deg}}),
              written(replaced(replaced(s, "(-3, 0)", "(0, -3)"), "12deg", "42deg")), 0.02)
              .fractionWithin() > 0.999);
}

} // namespace moire

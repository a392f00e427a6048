// Every example scene (the embedded default among them, as examples/drifting_walks.moire)
// against the two independent expectations an example can have: the reference interpreter
// (backend parity) and a reviewed golden image (regressions).
#include "runtime/output/ImageIO.h"
#include "runtime/output/Render.h"
#include "tests/support/Support.h"

#include <cmath>
#include <cstdlib>
#include <doctest/doctest.h>
#include <filesystem>

using namespace moire;

namespace {

struct Scene {
    std::string name, path, text;
};

std::vector<Scene> allScenes() {
    std::vector<Scene> out;
    for (const std::string& rel : test::exampleScenes())
        out.push_back({std::filesystem::path(rel).stem().string(), rel,
                       test::readFile(test::sourcePath(rel))});
    return out;
}

// Parity size: large enough that every example shows its strokes at a few pixels a member.
constexpr int kParityW = 480, kParityH = 320;
// Golden window: the middle 400 x 300 pixels of each scene at its own size, so the strokes
// are compared at the resolution they were designed for.
constexpr int kGoldenW = 400, kGoldenH = 300;
// Both checks render this instant, not t = 0, so that the animated examples are compared in
// motion: halfway through a morph, part way along a ramp. Still scenes ignore it.
constexpr double kFrameTime = 3.6;

} // namespace

TEST_CASE("there are examples, and each says what it shows") {
    std::vector<std::string> examples = test::exampleScenes();
    CHECK(examples.size() >= 4);
    for (const std::string& rel : examples) {
        CAPTURE(rel);
        std::string text = test::readFile(test::sourcePath(rel));
        CHECK(text.rfind("//", 0) == 0); // opens with a comment
    }
}

// `moire render` with no scene draws the teaser's eighth panel, embedded from its example file,
// so the checks below cover it there.
TEST_CASE("the embedded default scene is examples/drifting_walks.moire") {
    CHECK(defaultScene().text == test::readFile(test::sourcePath("examples/drifting_walks.moire")));
}

// Every backend against the interpreter, which computes in double. The JIT computes in
// single precision with libm: coverage within 1/255 on at least 99.9% of the samples (RGBA).
// Vulkan computes in single precision too, but with the GPU's own sin, cos, atan, exp, pow,
// which the Vulkan spec lets be far less exact than libm's (atan to 4096 ulp; sin and cos to
// 2^-11 absolute): within 2/255 on at least 99.9% of the samples, and a mean difference
// under 0.5/255, so that a systematic shift (a wrong op, a half-pixel slip) fails even where
// it stays under 2/255. MOIRE_PARITY_REPORT=1 prints the figures.
TEST_CASE("every backend agrees with the interpreter on every example") {
    auto oracle = makeBackend("interp");
    for (const Scene& s : allScenes()) {
        CAPTURE(s.name);
        auto program = test::compileOk(s.text, {}, s.path);
        Image expected = test::renderScene(*program, *oracle, kParityW, kParityH, kFrameTime);
        for (const std::string& name : test::availableBackends()) {
            if (name == "interp") continue;
            CAPTURE(name);
            auto backend = test::makeBackendOrSkip(name);
            if (!backend) continue;
            Image got = test::renderScene(*program, *backend, kParityW, kParityH, kFrameTime);
            const bool gpu = name == "vulkan";
            test::ImageDiff d = test::compareImages(expected, got, (gpu ? 2.0 : 1.0) / 255.0);
            INFO("max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255, "/255, within ",
                 d.fractionWithin());
            if (std::getenv("MOIRE_PARITY_REPORT"))
                MESSAGE(s.name, " on ", name, ": max ", d.maxAbs * 255, "/255, mean ",
                        d.meanAbs * 255, "/255, within ", (gpu ? 2 : 1),
                        "/255: ", d.fractionWithin());
            CHECK(d.fractionWithin() >= 0.999);
            if (gpu) CHECK(d.meanAbs < 0.5 / 255.0);
        }
    }
}

// Golden images: the interpreter's render of the middle window, quantised to 8 bits, against
// a reviewed PNG in tests/golden/. Tolerance: at most 0.5% of samples off by more than 2/255 and a
// mean difference under 0.5/255 (room for libm differences between machines, none for a change in
// what is drawn). MOIRE_UPDATE_GOLDEN=1 rewrites the references. Drawn point-sampled, as the
// references were made: tests/filter_test.cpp holds the default mean filter to them where
// members are resolved (docs/filtering.md).
TEST_CASE("examples match their golden images") {
    const bool update = std::getenv("MOIRE_UPDATE_GOLDEN") != nullptr;
    auto interp = makeBackend("interp");
    CompileOptions point;
    point.filter = sema::FilterMode::Point;
    for (const Scene& s : allScenes()) {
        CAPTURE(s.name);
        auto program = test::compileOk(s.text, point, s.path);
        FrameValues fv;
        std::string diags;
        REQUIRE(evaluateFrame(*program, FrameRequest{kFrameTime}, fv, diags));
        Image img = test::renderWindow(*program, *interp, (fv.width - kGoldenW) / 2,
                                       (fv.height - kGoldenH) / 2, kGoldenW, kGoldenH, kFrameTime);
        std::string golden = test::sourcePath("tests/golden/" + s.name + ".png");
        if (update) {
            writeImage(golden, img);
            MESSAGE("wrote ", golden);
            continue;
        }
        REQUIRE_MESSAGE(std::filesystem::exists(golden),
                        "no golden image; run with MOIRE_UPDATE_GOLDEN=1 and review it");
        Image ref = readImage(golden);
        // Quantise the render as the PNG writer does.
        for (float& v : img.pixels) v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
        test::ImageDiff d = test::compareImages(ref, img, 2.0 / 255.0);
        INFO("max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255, "/255, within ",
             d.fractionWithin());
        CHECK(d.fractionWithin() >= 0.995);
        CHECK(d.meanAbs <= 0.5 / 255.0);
    }
}

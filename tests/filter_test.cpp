// The stroke filter (docs/filtering.md): the mean over the pixel where a phase family's members
// are finer than pixels, the point rule where they are resolved, and the switch between them
// in the scene and on the command line.
#include "runtime/output/ImageIO.h"
#include "runtime/output/Render.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <filesystem>

using namespace moire;

namespace {

// Circles 0.7 apart, 0.1 wide, at the default zoom (1 pixel a world unit): 1.43 members a
// pixel, each inking 0.1 / 0.7 of its period.
const char* kFineCircles = "layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n";
constexpr double kFineCirclesInk = 0.1 / 0.7;

// The mean ink (1 - red, on white paper) of an image.
double meanInk(const Image& img) {
    double sum = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) sum += 1.0 - img.at(x, y, 0);
    return sum / (static_cast<double>(img.width) * img.height);
}

// A window of the scene at its own size away from the centre, where the circles' index runs
// evenly (at the centre it folds: r = |p|).
Image fineWindow(const SceneProgram& program, Backend& backend) {
    return test::renderWindow(program, backend, 800, 560, 160, 120);
}

CompileOptions withFilter(sema::FilterMode mode) {
    CompileOptions options;
    options.filter = mode;
    return options;
}

} // namespace

TEST_CASE("filter: circles finer than the pixels read their mean ink, not solid black") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    auto mean = test::compileOk(kFineCircles); // the default filter
    Image img = fineWindow(*mean, *interp);
    CHECK(meanInk(img) == doctest::Approx(kFineCirclesInk).epsilon(0.05));
    // Point-sampled, the floored strokes (2.3 pixels wide every 0.7) merge into solid ink.
    auto point = test::compileOk(kFineCircles, withFilter(sema::FilterMode::Point));
    CHECK(meanInk(fineWindow(*point, *interp)) > 0.95);
    // The scene's switch does the same as the option.
    auto written = test::compileOk(std::string("scene { filter = point }\n") + kFineCircles);
    test::ImageDiff same =
        test::compareImages(fineWindow(*written, *interp), fineWindow(*point, *interp), 0.0);
    CHECK(same.maxAbs == 0.0);
}

TEST_CASE("filter: a turned camera turns the pixel's footprint with it") {
    // Fine lines at 30 degrees seen straight, and lines at 0 degrees under a camera turned by
    // -30 degrees: the same picture, so the footprint must follow the pixel's sides (a
    // footprint that kept to the world's axes would read the second one's lines as crossing
    // the pixel at 30 degrees).
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    const char* kLines = "layer a { family = lines; spacing = 0.8; stroke = 0.15; angle = ";
    auto straight = test::compileOk(std::string(kLines) + "30deg }\n");
    auto turned =
        test::compileOk(std::string("camera { rotation = -30deg }\n") + kLines + "0deg }\n");
    auto unturned = test::compileOk(std::string(kLines) + "0deg }\n");
    const Image want = fineWindow(*straight, *interp);
    test::ImageDiff same = test::compareImages(want, fineWindow(*turned, *interp), 2.0 / 255.0);
    CHECK(same.fractionWithin() >= 0.999);
    // And the angle matters: upright lines fill the square pixel's footprint otherwise.
    test::ImageDiff other = test::compareImages(want, fineWindow(*unturned, *interp), 2.0 / 255.0);
    CHECK(other.fractionWithin() < 0.9);
}

TEST_CASE("filter: the JIT and the GPU draw the mean the interpreter draws") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    // Lines at a slant over two scales, some resolved, some not, and the fine circles.
    const std::string scenes[] = {
        kFineCircles,
        "camera { zoom = 0.3 }\nlayer a { family = lines; spacing = 4; stroke = 0.5; "
        "rotation = 17deg }\nlayer b { family = circles; spacing = 9; stroke = 2 }\n",
    };
    for (const std::string& text : scenes) {
        auto program = test::compileOk(text);
        Image ref = fineWindow(*program, *interp);
        for (const char* name : {"jit", "vulkan"}) {
            CAPTURE(name);
            CAPTURE(text);
            auto backend = test::makeBackendOrSkip(name);
            if (!backend) continue;
            test::ImageDiff d = test::compareImages(ref, fineWindow(*program, *backend), 2.0 / 255);
            CHECK(d.fractionWithin() >= 0.999);
            CHECK(d.meanAbs <= 0.5 / 255.0);
        }
    }
}

TEST_CASE("filter: --filter on render, and a bad value named") {
    test::TempDir dir("filter");
    dir.write("fine.moire", std::string("scene { size = (160, 120) }\n") + kFineCircles);
    auto render = [&](const std::string& args, const std::string& out) {
        return test::runCommand(test::moireBinary() + " render " + dir.file("fine.moire") +
                                " --backend interp -o " + dir.file(out) + " " + args);
    };
    REQUIRE(render("", "mean.png").status == 0);
    REQUIRE(render("--filter point", "point.png").status == 0);
    REQUIRE(render("--filter mean", "asked.png").status == 0);
    const double meanShown = meanInk(readImage(dir.file("mean.png")));
    CHECK(meanShown < 0.3); // the centre's fold and 8-bit quantising aside, ~0.14
    CHECK(meanInk(readImage(dir.file("point.png"))) > 0.9);
    CHECK(meanInk(readImage(dir.file("asked.png"))) == doctest::Approx(meanShown));
    test::CommandResult bad = render("--filter blur", "bad.png");
    CHECK(bad.status != 0);
    CHECK(bad.err.find("--filter must be point or mean, not 'blur'") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("bad.png")));
}

// The examples under the default filter against their golden images (made point-sampled), with
// the golden test's tolerance: the mean leaves a scene whose members stand 4 pixels apart or
// more as it was. Three examples hold members finer than that in places, and there the mean
// draws their grey: the hyperbolae where they crowd toward the asymptotes, and the encoded
// carriers of two_fields and vortex_streamlines where their fields compress them (measured
// against point sampling on the golden window: 1.0%, 6.3% and 0.6% of samples off by more than
// 2/255; docs/filtering.md).
TEST_CASE("filter: the mean keeps the golden images of the examples whose members are resolved") {
    const std::vector<std::string> unresolved = {"hyperbolae", "two_fields", "vortex_streamlines"};
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    constexpr int kW = 400, kH = 300; // the golden window and frame (examples_test.cpp)
    constexpr double kFrameTime = 3.6;
    int compared = 0;
    for (const std::string& rel : test::exampleScenes()) {
        const std::string name = std::filesystem::path(rel).stem().string();
        if (std::find(unresolved.begin(), unresolved.end(), name) != unresolved.end()) continue;
        CAPTURE(name);
        auto program = test::compileOk(test::readFile(test::sourcePath(rel)), {}, rel);
        FrameValues fv;
        std::string diags;
        REQUIRE(evaluateFrame(*program, FrameRequest{kFrameTime}, fv, diags));
        Image img = test::renderWindow(*program, *interp, (fv.width - kW) / 2, (fv.height - kH) / 2,
                                       kW, kH, kFrameTime);
        for (float& v : img.pixels) v = std::round(std::clamp(v, 0.0f, 1.0f) * 255.0f) / 255.0f;
        Image ref = readImage(test::sourcePath("tests/golden/" + name + ".png"));
        test::ImageDiff d = test::compareImages(ref, img, 2.0 / 255.0);
        INFO("max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255, "/255");
        CHECK(d.fractionWithin() >= 0.995);
        CHECK(d.meanAbs <= 0.5 / 255.0);
        ++compared;
    }
    CHECK(compared + unresolved.size() == test::exampleScenes().size());
}

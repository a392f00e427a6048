// The views (sema/Views.h) end to end: the envelope and the split drawn alike by every
// backend (the interpreter is the reference; a backend missing here is skipped), the split's
// halves equal to the pattern and the envelope drawn apart, and `moire render --view` (with
// --envelope-gain and --envelope-taps) drawing what the scene's own settings draw.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>

using namespace moire;

namespace {

const char* const kScenes[] = {
    "scene { size = (64, 40) }\n"
    "layer { family = circles; spacing = 6; stroke = 2.4; origin = (-12, 0) }\n"
    "layer { family = circles; spacing = 6.3; stroke = 2.4; origin = (12, 2) }\n",
    "scene { size = (64, 40); background = #f4f0e8 }\n"
    "layer { family = lines; spacing = 5; stroke = 2; color = #2040a0 }\n"
    "layer { family = wave; spacing = 5.2; stroke = 2; rotation = 4deg; color = #a02010 }\n"
    "layer { family = spiral; spacing = 7; stroke = 1; opacity = 0.5 }\n",
    "scene { size = (64, 40) }\n"
    "layer { family = hyperbola; spacing = 8; stroke = 3; field = x / 20 }\n",
    // A lattice (swept over its unit cell) under a radial pencil (swept by rotation).
    "scene { size = (64, 40) }\n"
    "layer { family = hex_lattice; spacing = 5; stroke = 2.4; rotation = 3deg }\n"
    "layer { family = pencil; lines = 40; start = 4; stroke = 1.5; origin = (6, 2) }\n",
};

Image render(const std::string& text, sema::ViewMode view, Backend& backend) {
    auto program = test::compileOk(text, {.view = view});
    return test::renderScene(*program, backend);
}

} // namespace

TEST_CASE("views: the envelope and the split draw alike on the interpreter, the JIT and Vulkan") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    int compared = 0;
    for (const char* name : {"jit", "vulkan"}) {
        auto backend = test::makeBackendOrSkip(name); // null, with a message, when missing
        if (!backend) continue;
        for (const char* text : kScenes)
            for (sema::ViewMode view : {sema::ViewMode::Envelope, sema::ViewMode::Split}) {
                CAPTURE(text);
                INFO("backend ", name, ", view ", sema::viewName(view));
                const Image want = render(text, view, *interp);
                const Image got = render(text, view, *backend);
                test::ImageDiff d = test::compareImages(want, got, 2.0 / 255);
                INFO("max ", d.maxAbs * 255, "/255, within 2/255: ", d.fractionWithin());
                CHECK(d.fractionWithin() >= 0.99);
                CHECK(d.meanAbs < 1.0 / 255);
                ++compared;
            }
    }
    CHECK(compared >= 6);
}

TEST_CASE("views: the split is the pattern left of the middle and the envelope right of it") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    for (const char* text : kScenes) {
        CAPTURE(text);
        const Image pattern = render(text, sema::ViewMode::Pattern, *interp);
        const Image envelope = render(text, sema::ViewMode::Envelope, *interp);
        const Image split = render(text, sema::ViewMode::Split, *interp);
        const int w = split.width, mid = w / 2;
        int ruled = 0;
        for (int y = 0; y < split.height; ++y)
            for (int x = 0; x < w; ++x) {
                const size_t at = (static_cast<size_t>(y) * w + x) * 4;
                const Image& side = x < mid ? pattern : envelope;
                const bool onRule = x >= mid - 2 && x <= mid + 1;
                bool same = true;
                for (int c = 0; c < 4; ++c) same &= split.pixels[at + c] == side.pixels[at + c];
                if (onRule)
                    ruled += !same;
                else
                    CHECK(same);
            }
        // The dashed rule: ink on about half the rows, in the two columns about the middle.
        CHECK(ruled >= split.height / 2);
    }
}

TEST_CASE("views: render --view and the envelope options draw what the scene's settings draw") {
    test::TempDir dir("views");
    const std::string layers = "layer { family = circles; spacing = 6; stroke = 2.4; origin = "
                               "(-12, 0) }\nlayer { family = lines; spacing = 6; stroke = 2.4; "
                               "rotation = 10deg }\n";
    dir.write("plain.moire", "scene { size = (48, 32) }\n" + layers);
    dir.write("set.moire", "scene { size = (48, 32); view = envelope; envelope_gain = 1.5; "
                           "envelope_taps = 12 }\n" +
                               layers);
    auto moire = [&](const std::string& args) {
        return test::runCommand(test::moireBinary() + " render -q --backend interp " + args);
    };
    REQUIRE(moire(dir.file("set.moire") + " -o " + dir.file("set.png")).status == 0);
    REQUIRE(moire(dir.file("plain.moire") +
                  " --view envelope --envelope-gain 1.5 "
                  "--envelope-taps 12 -o " +
                  dir.file("flag.png"))
                .status == 0);
    REQUIRE(moire(dir.file("plain.moire") + " -o " + dir.file("pattern.png")).status == 0);
    REQUIRE(moire(dir.file("set.moire") + " --view pattern -o " + dir.file("back.png")).status ==
            0);
    const Image set = readImage(dir.file("set.png")), flag = readImage(dir.file("flag.png"));
    CHECK(test::compareImages(set, flag, 0.0).maxAbs == 0.0);
    // --view pattern overrides the scene's envelope, and the envelope is not the pattern.
    const Image pattern = readImage(dir.file("pattern.png")),
                back = readImage(dir.file("back.png"));
    CHECK(test::compareImages(pattern, back, 0.0).maxAbs == 0.0);
    CHECK(test::compareImages(pattern, set, 0.0).maxAbs > 0.1);
    // A view that does not exist, or taps that are not a whole number: the command line is wrong.
    test::CommandResult bad =
        moire(dir.file("plain.moire") + " --view ratios -o " + dir.file("x.png"));
    CHECK(bad.status == 2);
    CHECK(bad.err ==
          "moire: error: --view must be pattern, envelope, split or ratio, not 'ratios'\n");
    CHECK(moire(dir.file("plain.moire") + " --envelope-taps 0 -o " + dir.file("x.png")).status ==
          2);
}

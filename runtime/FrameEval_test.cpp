// FrameRequest::pixelSize: a program compiled with CompileOptions::pixelSize draws the pixel
// size it is given on a canvas of its own size, and without one the frame fitted as always.
#include "runtime/FrameEval.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <string>

using namespace moire;

namespace {

// Renders `program` at w x h with `request`'s pixel size on the named backend.
Image renderAt(const SceneProgram& program, Backend& backend, int w, int h, double pixel) {
    FrameRequest req;
    req.width = w;
    req.height = h;
    req.pixelSize = pixel;
    FrameValues fv;
    std::string diags;
    REQUIRE_MESSAGE(evaluateFrame(program, req, fv, diags), diags);
    auto kernel = backend.compile(program.kernel);
    Image img(fv.width, fv.height, kernel->numOutputs());
    kernel->runTile(KernelFrame{fv.uniforms.data(), fv.width, fv.height}, TileRect{0, 0, w, h},
                    img.pixels.data(), static_cast<size_t>(w) * kernel->numOutputs());
    return img;
}

const char* const kLayers =
    "layer a { family = circles; spacing = 3; stroke = 1; origin = (-4, 1) }\n"
    "layer b { family = lines; spacing = 2.5; stroke = 0.8; angle = 20deg }\n";

} // namespace

TEST_CASE("a pixel size from the request draws what a scene framed to that size draws") {
    // The oracle: a scene whose own frame, fitted to 64 x 40 pixels, makes each pixel 0.375
    // world units (24 / 64 = 15 / 40). The program under test frames another size with a
    // zoom, both of which the request's pixel size replaces.
    const int w = 64, h = 40;
    auto framed = test::compileOk(std::string("scene { size = (24, 15) }\n") + kLayers);
    CompileOptions options;
    options.pixelSize = true;
    auto scaled = test::compileOk(
        std::string("scene { size = (100, 50) }\ncamera { zoom = 2 }\n") + kLayers, options);
    REQUIRE(scaled->pixelSlot >= 0);
    for (const std::string& name : {std::string("interp"), std::string("jit")}) {
        CAPTURE(name);
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        const Image want = renderAt(*framed, *backend, w, h, 0.0);
        const Image got = renderAt(*scaled, *backend, w, h, 0.375);
        // The interpreter, in double, gives the same pixels; the JIT's single-precision
        // kernel reaches the same pixel size by other operations (a uniform, not a fit of the
        // image's size), a float rounding apart, which the mean filter's quotient of differences
        // (lower/Prefilter.h, divided by the footprint's area) magnifies to some tens of float
        // steps: far below an 8-bit step.
        const test::ImageDiff d = test::compareImages(got, want, 0.0);
        CHECK(d.maxAbs <= (name == "interp" ? 0.0 : 1e-5));
    }
}

TEST_CASE("without a pixel size, a program with the slot draws the fitted frame") {
    const std::string text =
        std::string("scene { size = (100, 50) }\ncamera { zoom = 1.5 }\n") + kLayers;
    CompileOptions options;
    options.pixelSize = true;
    auto plain = test::compileOk(text);
    auto slotted = test::compileOk(text, options);
    auto backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    FrameValues fv;
    std::string diags;
    FrameRequest req;
    req.width = 70;
    req.height = 30;
    REQUIRE(evaluateFrame(*slotted, req, fv, diags));
    // max(100 / 70, 50 / 30) / 1.5
    CHECK(fv.pixelSize == doctest::Approx(50.0 / 30.0 / 1.5).epsilon(1e-15));
    const Image want = renderAt(*plain, *backend, 70, 30, 0.0);
    const Image got = renderAt(*slotted, *backend, 70, 30, 0.0);
    CHECK(test::compareImages(got, want, 0.0).maxAbs == 0.0);
}

// Random valid scenes drawn alike by the interpreter (double), the JIT (float) and Vulkan
// (float, lavapipe where there is no GPU). The values are drawn over wide log-uniform ranges,
// up to the limits the frame checks enforce (docs/language.md, "Values the renderers draw"):
// within them, nothing the kernel computes may overflow float, so the float backends must
// draw the interpreter's picture. Before those limits, a stroke of 1e308 or a zoom of 1e-30
// passed and the float backends drew another picture altogether (value_limits_test.cpp has
// the errors for values past them).
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <random>
#include <string>

using namespace moire;

namespace {

class SceneGenerator {
  public:
    explicit SceneGenerator(uint64_t seed) : rng_(seed) {}

    // A scene of one or two layers, framed at w x h pixels.
    std::string scene(int w, int h) {
        // Zoom over its whole range; the lengths are drawn relative to the pixel it gives,
        // so that extreme zooms bring extreme (but allowed) lengths with them.
        const double zoom = logUniform(1e-6, 1e6);
        const double pixel = 1.0 / zoom;
        std::string text = fmt::format("scene {{ size = ({}, {}); background = #f4f0e8 }}\n", w, h);
        text += fmt::format("camera {{ zoom = {:.17g}; center = ({:.17g}, {:.17g}); rotation = "
                            "{:.17g}rad }}\n",
                            zoom, length(pixel, 1e-2, 1e2), length(pixel, 1e-2, 1e2),
                            signedLog(1e-3, 9.9e11));
        const int layers = 1 + static_cast<int>(uniform(0, 2));
        for (int i = 0; i < layers; ++i) text += layer(pixel);
        return text;
    }

  private:
    std::string layer(double pixel) {
        static const char* families[] = {
            "lines",    "circles",   "squares", "triangles", "hexagons",       "ngon",       "wave",
            "parabola", "hyperbola", "spiral",  "pencil",    "square_lattice", "hex_lattice"};
        const std::string family = families[static_cast<int>(uniform(0, 13)) % 13];
        std::string props = "family = " + family;
        // Spacing from far below a pixel (solid ink) to far above the view (one member),
        // held inside the allowed range.
        const double spacing =
            std::clamp(pixel * logUniform(1e-4, 1e4), lower::kMinSpacing, lower::kMaxMagnitude);
        props += fmt::format("; spacing = {:.17g}", spacing);
        props += fmt::format("; stroke = {:.17g}", std::clamp(pixel * logUniform(1e-3, 1e3), 1e-12,
                                                              lower::kMaxMagnitude));
        props += fmt::format("; origin = ({:.17g}, {:.17g})", length(pixel, 1e-2, 1e2),
                             length(pixel, 1e-2, 1e2));
        props += fmt::format("; rotation = {:.17g}rad", signedLog(1e-3, 9.9e11));
        props += fmt::format("; phase = {:.17g}", spacing * uniform(-1, 1));
        props += fmt::format("; opacity = {:.3f}", uniform(0.3, 1.0));
        props += fmt::format("; color = #{:02x}{:02x}{:02x}", byte(), byte(), byte());
        if (family == "ngon")
            props += fmt::format("; sides = {}", 3 + static_cast<int>(uniform(0, 8)));
        if (family == "wave")
            props += fmt::format("; amplitude = {:.17g}", spacing * logUniform(1e-2, 1e1));
        if (family == "spiral")
            props += fmt::format("; arms = {}", static_cast<int>(uniform(-3, 4)));
        // Walking, with a turn up to the limit: it is reduced modulo a full turn per frame.
        const bool walks =
            family == "circles" || family == "squares" || family == "hexagons" || family == "ngon";
        if (walks && uniform(0, 1) < 0.5) {
            props += fmt::format("; offset = ({:.17g}, {:.17g})", spacing * uniform(-0.3, 0.3),
                                 spacing * uniform(-0.3, 0.3));
            props += fmt::format("; turn = {:.17g}rad", signedLog(1e-3, 9.9e11));
        }
        return "layer { " + props + " }\n";
    }

    double uniform(double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng_);
    }
    double logUniform(double lo, double hi) {
        return std::exp(uniform(std::log(lo), std::log(hi)));
    }
    double signedLog(double lo, double hi) {
        return (uniform(0, 1) < 0.5 ? -1 : 1) * logUniform(lo, hi);
    }
    // A signed length of `pixel` times [lo, hi], log-uniform, within the allowed magnitude.
    double length(double pixel, double lo, double hi) {
        return std::clamp((uniform(0, 1) < 0.5 ? -1 : 1) * pixel * logUniform(lo, hi),
                          -lower::kMaxMagnitude, lower::kMaxMagnitude);
    }
    int byte() { return static_cast<int>(uniform(0, 255.99)); }

    std::mt19937_64 rng_;
};

} // namespace

TEST_CASE("backend agreement: random valid scenes, up to the value limits, draw alike on the "
          "interpreter, the JIT and Vulkan") {
    auto interp = makeBackend("interp");
    auto jit = makeBackend("jit");
    auto vulkan = test::makeBackendOrSkip("vulkan"); // null, with a message, without a device
    REQUIRE(interp);
    REQUIRE(jit);
    const int w = 40, h = 28;
    SceneGenerator gen(20240612);
    int compared = 0;
    for (int i = 0; i < 14; ++i) {
        const std::string text = gen.scene(w, h);
        CAPTURE(text);
        auto program = test::compileOk(text);
        const Image want = test::renderScene(*program, *interp);
        for (Backend* b : {jit.get(), vulkan.get()}) {
            if (!b) continue;
            const Image got = test::renderScene(*program, *b);
            test::ImageDiff d = test::compareImages(want, got, 2.0 / 255);
            INFO("backend ", b->name(), ": max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255,
                 "/255, within 2/255: ", d.fractionWithin());
            CHECK(d.fractionWithin() >= 0.99);
            CHECK(d.meanAbs < 1.0 / 255);
            ++compared;
        }
    }
    CHECK(compared >= 14);
}

// The envelope of walking families (§4.4, Eq. 14-15), against an independent path: every
// pixel's members found by the exhaustive reference scan (tests/reference), not by the
// certified solver the kernel runs, then swept by Eq. 15 at 1,024 taps in double. For a
// walking family Eq. 15 is the definition (first order per tap, one local gap per period:
// re-rendering with the phase moved would grow radii while the poses stay put, which is no
// period of the family at all), so the formula is restated here as the oracle's; what is
// tested independently is the search for the nearest member and its two neighbours, the
// guard widened to a full pitch, the floor of a saturated solve, and the 24-tap average.
#include "tests/reference/WalkingReference.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;
namespace ref = moire::reference;

namespace {

constexpr int kW = 64, kH = 48;

struct Layer {
    ref::Walking walk;
    double stroke;
};

std::string layerText(const Layer& l) {
    const char* family = l.walk.facets == 0   ? "circles"
                         : l.walk.facets == 4 ? "squares"
                                              : "hexagons";
    return fmt::format("layer {{ family = {}; spacing = {}; phase = {}; offset = ({}, {}); "
                       "turn = {}rad; stroke = {} }}\n",
                       family, l.walk.spacing, l.walk.phase, l.walk.offsetX, l.walk.offsetY,
                       l.walk.turn, l.stroke);
}

// The oracle's mean ink of black strokes on white paper at the world point (x, y), one
// world unit a pixel.
double oracle(const std::vector<Layer>& layers, double x, double y) {
    constexpr int kTaps = 1024;
    constexpr double kPixel = 1.0, kAntialias = 0.7 * kPixel, kNone = 1e30;
    struct Sample {
        double z, up, down, floor, h, a, gap;
    };
    std::vector<Sample> samples;
    for (const Layer& l : layers) {
        const double h = l.stroke / 2, guard = std::max(h + kAntialias, l.walk.spacing);
        ref::Nearest near = ref::nearest(l.walk, x, y, guard);
        REQUIRE(near.complete);
        Sample s{kNone, kNone, kNone, guard, h, 0, 0};
        if (near.argmin >= 0 && near.distance < guard) {
            const int64_t n = near.argmin;
            s.z = -ref::residual(l.walk, x, y, n);
            s.up = -ref::residual(l.walk, x, y, n + 1);
            s.down = n >= 1 ? -ref::residual(l.walk, x, y, n - 1) : kNone;
            s.floor = 0;
        }
        // The local period: the gap of the two members that bracket the point (Envelope.h).
        const double gap =
            s.z >= 0 && s.down < kNone / 2 && s.z > s.down ? s.z - s.down : std::abs(s.up - s.z);
        s.gap = gap;
        // The band: the pattern's, widened to two of the view's 24 taps (Envelope.h).
        s.a = std::min(std::max(kAntialias, 2.0 * gap / 24.0), h);
        samples.push_back(s);
    }
    double sum = 0;
    for (int j = 0; j < kTaps; ++j) {
        const double u = (j + 0.5) / kTaps;
        double paper = 1;
        for (const Sample& s : samples) {
            const double shift = u * s.gap;
            double d =
                std::min({std::abs(s.z - shift), std::abs(s.up - shift), std::abs(s.down - shift)});
            d = std::max(d, s.floor);
            const double t = std::clamp((d - (s.h - s.a)) / (2 * s.a), 0.0, 1.0);
            paper *= t * t * (3 - 2 * t); // 1 - coverage
        }
        sum += paper;
    }
    return sum / kTaps;
}

} // namespace

TEST_CASE("envelope: walking families swept by Eq. 15 over the reference scan's members") {
    const std::vector<std::vector<Layer>> scenes = {
        // Two walking circle families drifting against each other (the default preset's kind).
        {{{0, 7, 0, 1.4, 0.4, 0.012}, 2.4}, {{0, 7, 0, -1.2, 0.3, -0.01}, 2.4}},
        // Walking squares, turning, over walking hexagons.
        {{{4, 6, 0, 0.5, 0.2, 0.03}, 2.4}, {{6, 6.5, 0, -0.3, 0.6, -0.02}, 2.6}},
        // One walking family alone, graded here at gain 1 (its mean).
        {{{0, 6, 0, 2.0, 0.0, 0.02}, 2.4}},
    };
    for (const auto& layers : scenes) {
        std::string text = fmt::format("scene {{ size = ({}, {}) }}\n", kW, kH);
        for (const Layer& l : layers) text += layerText(l);
        CAPTURE(text);
        auto program =
            test::compileOk(text, {.view = sema::ViewMode::Envelope, .envelopeGain = 1.0});
        auto interp = test::makeBackendOrSkip("interp");
        const Image got = test::renderScene(*program, *interp);
        size_t within = 0;
        double worst = 0, lightest = 0, darkest = 1;
        for (int py = 0; py < kH; ++py)
            for (int px = 0; px < kW; ++px) {
                const double x = px + 0.5 - kW / 2.0, y = kH / 2.0 - (py + 0.5);
                const double want = oracle(layers, x, y);
                lightest = std::max(lightest, want), darkest = std::min(darkest, want);
                const double d =
                    std::abs(got.pixels[(static_cast<size_t>(py) * kW + px) * 4] - want);
                worst = std::max(worst, d);
                within += d <= 1.0 / 255;
            }
        INFO("largest difference ", worst * 255, " colour steps");
        CHECK(static_cast<double>(within) / (kW * kH) >= 0.999);
        CHECK(lightest - darkest > 0.1); // there is a fringe (or a bunching) to get right
    }
}

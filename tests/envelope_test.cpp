// The envelope view (§4.4) against independent expectations:
//  - a brute-force mean of the pattern itself, re-rendered at 1,024 index advances (each
//    layer's `phase` literal moved by u w s, through the pattern's own distance code, then the
//    images averaged), which the view's 24 taps of Eq. 15 must match within one colour step
//    at 99.9% of pixels; the sweep direction of the oracle is chosen per pixel here from the
//    layers' own index gradients (the pattern's layer-field outputs), by Eq. 11 worked out
//    anew: the second layer runs backwards where its gradient points against the first's;
//  - the pivot: with a gain, the view is the composite of the layers' own means (each layer
//    swept alone, the other's opacity set to 0) plus the gain times the departure from it;
//  - zoom invariance: the same world points at zoom 1 and zoom 4 give the same value.
// The strokes are wider than the hairline floor at these zooms, so the pattern the oracle
// averages draws them at their true width, as the view does; and two taps are narrower than
// the pattern's 0.7 px antialias band, so the view ramps the edges as the pattern does.
#include "tests/support/BruteMean.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;

namespace {

constexpr int kW = 64, kH = 48;
constexpr int kBruteTaps = 1024;
// Sentinel values written as each layer's phase and opacity, to find their literal slots.
constexpr double kPhase[2] = {0.000123, 0.000456};
constexpr double kOpacity[2] = {0.999, 0.998};

struct Example {
    const char* name;
    std::string scene; // two layers (or one), each with `phase = {p}; opacity = {o}`
    double spacing[2];
};

std::string twoLayers(const std::string& a, const std::string& b,
                      const std::string& paper = "#f4f0e8") {
    return fmt::format("scene {{ size = ({}, {}); background = {} }}\n", kW, kH, paper) +
           fmt::format("layer {{ {}; phase = {}; opacity = {} }}\n", a, kPhase[0], kOpacity[0]) +
           fmt::format("layer {{ {}; phase = {}; opacity = {} }}\n", b, kPhase[1], kOpacity[1]);
}

std::vector<Example> examples() {
    return {
        {"lines 6 degrees apart",
         twoLayers("family = lines; spacing = 6; stroke = 2.4",
                   "family = lines; spacing = 6; stroke = 2.4; rotation = 6deg"),
         {6, 6}},
        {"circles with displaced centres (sum beat between them)",
         twoLayers("family = circles; spacing = 6; stroke = 2.6; origin = (-14, 0)",
                   "family = circles; spacing = 6.24; stroke = 2.4; origin = (14, 3)"),
         {6, 6.24}},
        {"spiral over circles, coloured",
         twoLayers("family = spiral; spacing = 5; stroke = 2.4; color = #1a3a8a",
                   "family = circles; spacing = 5.3; stroke = 2.8; color = #aa2200; origin = (4, "
                   "-2)"),
         {5, 5.3}},
        {"wave over lines",
         twoLayers("family = wave; amplitude = 6; spacing = 7; stroke = 3",
                   "family = lines; spacing = 7.4; stroke = 2.4; rotation = 3deg"),
         {7, 7.4}},
        {"hyperbolae (first member 1; pixel centres on the asymptotes, the fold itself)",
         twoLayers("family = hyperbola; spacing = 6; stroke = 2.4",
                   "family = hyperbola; spacing = 6.3; stroke = 2.4; origin = (3, 1)"),
         {6, 6.3}},
        {"one parabola family",
         fmt::format("scene {{ size = ({}, {}) }}\nlayer {{ family = parabola; bend = 3; "
                     "spacing = 6; stroke = 2.4; phase = {}; opacity = {} }}\n",
                     kW, kH, kPhase[0], kOpacity[0]),
         {6, 0}},
    };
}

// The brute-force mean of the pattern's RGB over kBruteTaps advances of every layer's
// index, swept as Eq. 11 says per pixel; `alone` >= 0 sweeps only that layer (the other's
// opacity 0). Returns kW x kH x 3. The pattern point-sampled, as the envelope's taps read it
// (the mean filter, docs/filtering.md, averages where these fine pitches meet the pixels).
std::vector<double> bruteMean(const Example& ex, int alone = -1) {
    auto p = test::compileOk(ex.scene, {.layerFields = true, .filter = sema::FilterMode::Point});
    auto jit = test::makeBackendOrSkip("jit");
    auto kernel = jit->compile(p->kernel);
    const int layers = p->layout.numLayers;
    std::vector<int> phase, opacity;
    for (int i = 0; i < layers; ++i) {
        phase.push_back(test::literalSlot(*p, kPhase[i]));
        opacity.push_back(test::literalSlot(*p, kOpacity[i]));
    }
    std::vector<double> lits = p->literals;
    if (alone >= 0)
        for (int i = 0; i < layers; ++i)
            if (i != alone) lits[opacity[i]] = 0.0;
    // Which way the second layer runs: backwards where g1 . g2 < 0 (the sum is slower), both
    // ways mixed across the hand-over.
    std::vector<double> backwards;
    if (layers == 2) backwards = test::sumSweepShares(*p, *kernel, lits);
    std::vector<double> sums[2];
    for (int dir = 0; dir < (layers == 2 ? 2 : 1); ++dir)
        for (int j = 0; j < kBruteTaps; ++j) {
            const double u = (j + 0.5) / kBruteTaps;
            std::vector<double> l = lits;
            // index = (phi - phase) / s: the index advances by u w when phase falls by u w s.
            for (int i = 0; i < layers; ++i) {
                const double w = i == 1 && dir == 1 ? -1.0 : 1.0;
                l[phase[i]] = kPhase[i] - u * w * ex.spacing[i];
            }
            test::addFrameRGB(*p, *kernel, l, sums[dir]);
        }
    return test::fadedMean(sums, backwards, kBruteTaps);
}

Image envelope(const Example& ex, double gain, const std::string& backend = "interp") {
    auto p = test::compileOk(ex.scene, {.view = sema::ViewMode::Envelope, .envelopeGain = gain});
    auto b = test::makeBackendOrSkip(backend);
    return test::renderScene(*p, *b);
}

} // namespace

TEST_CASE("envelope: 24 taps of Eq. 15 match the pattern re-rendered at 1,024 index advances") {
    for (const Example& ex : examples()) {
        INFO(ex.name);
        CHECK(test::shareWithinOneStep(envelope(ex, 1.0), bruteMean(ex)) >= 0.999);
    }
}

TEST_CASE("envelope: the gain grades about the composite of the layers' own means") {
    // Black ink on white paper: a layer alone over the paper averages to m_i = 1 - c_i (its
    // mean coverage), so the composite of the two means is m_1 m_2; a sole layer is graded
    // about its nominal ink instead, 1 - opacity * stroke / spacing.
    const double gain = 2.5;
    const std::vector<Example> cases = {
        {"lines 6 degrees apart",
         twoLayers("family = lines; spacing = 6; stroke = 2.4",
                   "family = lines; spacing = 6; stroke = 2.4; rotation = 6deg", "#ffffff"),
         {6, 6}},
        {"circles with displaced centres",
         twoLayers("family = circles; spacing = 6; stroke = 2.6; origin = (-14, 0)",
                   "family = circles; spacing = 6.24; stroke = 2.4; origin = (14, 3)", "#ffffff"),
         {6, 6.24}},
        examples().back(), // the sole parabola family, stroke 2.4 over spacing 6
    };
    for (const Example& ex : cases) {
        INFO(ex.name);
        auto p = test::compileOk(ex.scene);
        const bool sole = p->layout.numLayers == 1;
        const std::vector<double> mean = bruteMean(ex);
        std::vector<double> pivot(kW * kH * 3, 1.0 - kOpacity[0] * 2.4 / 6.0);
        if (!sole) {
            const std::vector<double> a = bruteMean(ex, 0), b = bruteMean(ex, 1);
            for (size_t k = 0; k < pivot.size(); ++k) pivot[k] = a[k] * b[k];
        }
        std::vector<double> want(pivot.size());
        for (size_t k = 0; k < want.size(); ++k)
            want[k] = std::clamp(pivot[k] + gain * (mean[k] - pivot[k]), 0.0, 1.0);
        CHECK(test::shareWithinOneStep(envelope(ex, gain), want) >= 0.999);
    }
}

TEST_CASE("envelope: the same world points give the same value at zoom 1 and zoom 4") {
    // Pitches at which two of the 24 taps are wider than the pattern's 0.7 px band already at
    // zoom 1 (Envelope.h): from there on the view does not depend on the pixel's size.
    const std::vector<Example> cases = {
        {"lines 6 degrees apart",
         twoLayers("family = lines; spacing = 12; stroke = 4",
                   "family = lines; spacing = 12; stroke = 4; rotation = 6deg"),
         {12, 12}},
        {"circles with displaced centres",
         twoLayers("family = circles; spacing = 10; stroke = 4; origin = (-14, 0)",
                   "family = circles; spacing = 10.4; stroke = 3.6; origin = (14, 3)"),
         {10, 10.4}},
        {"wave over lines",
         twoLayers("family = wave; amplitude = 6; spacing = 12; stroke = 5",
                   "family = lines; spacing = 12.5; stroke = 4; rotation = 3deg"),
         {12, 12.5}},
    };
    for (const Example& ex : cases) {
        INFO(ex.name);
        // World points spread over the frame.
        CHECK(test::zoomDifference(ex.scene, 56.0, 40.0, "interp") <= 1.0);
    }
}

// The ratio view and the fringe overlay (docs/views.md) end to end, against independent
// expectations:
//  - every view, with and without the overlay, drawn alike by the interpreter, the JIT and
//    Vulkan on every example and the default scene (a backend missing here is skipped; a
//    view a scene's families cannot take is reported by the compiler and left out);
//  - the overlay's curves land on the envelope's light fringes: from each pixel the overlay
//    inks most, the nearest local maximum of the envelope's lightness along the normal of
//    the curve (the gradient of D = idx1 - idx2, from the pattern's own layer fields) is
//    under a pixel away on average (Fig. 5d);
//  - Fig. 7 (two line families at pitches 15 and 5, turned 2 degrees): the ratio view hues
//    the frame by the (3, -1) beat's order, and the envelope keeps the broad fringe, as the
//    pattern averaged by brute force along w = (1, 3) does, where the diagonal's average
//    loses it.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <doctest/doctest.h>
#include <filesystem>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;
using sema::ViewMode;

namespace {

double lightness(const Image& img, int x, int y) {
    const float* p = img.row(y) + static_cast<size_t>(x) * img.channels;
    return (p[0] + p[1] + p[2]) / 3.0;
}

// Lightness at a fractional pixel position (pixel centres at integer + 1/2), bilinear.
double lightnessAt(const Image& img, double x, double y) {
    x = std::clamp(x - 0.5, 0.0, img.width - 1.0001);
    y = std::clamp(y - 0.5, 0.0, img.height - 1.0001);
    const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
    const double fx = x - x0, fy = y - y0;
    return (1 - fy) * ((1 - fx) * lightness(img, x0, y0) + fx * lightness(img, x0 + 1, y0)) +
           fy * ((1 - fx) * lightness(img, x0, y0 + 1) + fx * lightness(img, x0 + 1, y0 + 1));
}

// The mean lightness of each row: a fringe running along the rows survives it, structure at
// the carriers' scale across them averages away.
std::vector<double> rowMeans(const Image& img) {
    std::vector<double> out;
    for (int y = 0; y < img.height; ++y) {
        double sum = 0;
        for (int x = 0; x < img.width; ++x) sum += lightness(img, x, y);
        out.push_back(sum / img.width);
    }
    return out;
}

double range(const std::vector<double>& v) {
    auto [lo, hi] = std::minmax_element(v.begin(), v.end());
    return *hi - *lo;
}

} // namespace

TEST_CASE("ratio view and overlay: every view draws alike on every backend, on every example") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    std::vector<std::pair<std::string, std::string>> scenes = {{"default", defaultScene().text}};
    for (const std::string& rel : test::exampleScenes())
        scenes.push_back({rel, test::readFile(test::sourcePath(rel))});
    int compared = 0, leftOut = 0;
    for (const char* name : {"jit", "vulkan"}) {
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        for (const auto& [path, text] : scenes)
            for (const sema::ViewName& v : sema::viewNames())
                for (bool overlay : {false, true}) {
                    if (!overlay && v.mode == ViewMode::Pattern) continue; // examples_test's
                    CompileResult r =
                        compileScene(path, text, {.view = v.mode, .overlay = overlay});
                    if (!r.program) { // a family the view cannot sweep: said, not drawn
                        CHECK(r.diagnostics.find("cannot yet do") != std::string::npos);
                        ++leftOut;
                        continue;
                    }
                    INFO(path, ", ", name, ", ", v.name, overlay ? " with the overlay" : "");
                    const Image want = test::renderScene(*r.program, *interp, 40, 28, 3.6);
                    const Image got = test::renderScene(*r.program, *backend, 40, 28, 3.6);
                    test::ImageDiff d = test::compareImages(want, got, 2.0 / 255);
                    INFO("max ", d.maxAbs * 255, "/255, within 2/255: ", d.fractionWithin());
                    CHECK(d.fractionWithin() >= 0.98);
                    ++compared;
                }
    }
    MESSAGE(compared, " renders compared; ", leftOut, " views a scene cannot take left out");
    CHECK(compared >= 40);
    // Every example's families sweep (the lattices and the pencil included): none is left out.
    CHECK(leftOut == 0);
}

TEST_CASE("the overlay's curves lie on the envelope's light fringes (Fig. 5d)") {
    // Two circle families 34 units apart whose pitches differ by 4 percent (Fig. 5).
    const std::string layers = "layer { family = circles; spacing = 6; stroke = 2.2; origin = "
                               "(-17, 0) }\n"
                               "layer { family = circles; spacing = 6.24; stroke = 2.2; origin = "
                               "(17, 0) }\n";
    const std::string scene = "scene { size = (240, 160) }\ncamera { zoom = 0.5 }\n" + layers;
    auto jit = test::makeBackendOrSkip("jit");
    REQUIRE(jit);
    auto plain = test::compileOk(scene, {.view = ViewMode::Envelope});
    auto inked = test::compileOk(scene, {.view = ViewMode::Envelope, .overlay = true});
    auto fields = test::compileOk(scene, {.layerFields = true});
    const Image envelope = test::renderScene(*plain, *jit);
    const Image overlaid = test::renderScene(*inked, *jit);
    const Image f = test::renderScene(*fields, *jit);
    const auto& L = fields->layout;
    // The overlay's own ink: how far each pixel moved toward crimson (red up, green down).
    auto overlayInk = [&](int x, int y) {
        const float* a = envelope.row(y) + static_cast<size_t>(x) * envelope.channels;
        const float* b = overlaid.row(y) + static_cast<size_t>(x) * overlaid.channels;
        return (b[0] - a[0]) - (b[1] - a[1]);
    };
    double sum = 0;
    int n = 0;
    for (int y = 4; y < envelope.height - 4; ++y)
        for (int x = 4; x < envelope.width - 4; ++x) {
            // The pixels on a curve: those inked most, more than either neighbour across it.
            const double ink = overlayInk(x, y);
            if (ink < 0.5) continue;
            const float* o = f.row(y) + static_cast<size_t>(x) * f.channels;
            double nx = o[L.gradXSlot(0)] - o[L.gradXSlot(1)];
            double ny = o[L.gradYSlot(0)] - o[L.gradYSlot(1)];
            const double len = std::hypot(nx, ny);
            if (!(len > 0)) continue;
            nx /= len;
            ny /= len;
            // The fringe's period along the normal, in pixels (world units at zoom 0.5: 2 px
            // a unit... read off the image: 1 / |grad D| units): look a third of it either way.
            const double periodPx = 0.5 / len;
            if (periodPx < 12) continue; // too close to the carriers for a fringe to read
            // Screen y runs down: the field's y gradient turns to -y on screen.
            const double sx = nx, sy = -ny;
            double bestT = 1e9, bestL = -1;
            const double reach = periodPx / 3;
            for (double t = -reach; t <= reach; t += 0.05) {
                const double l = lightnessAt(envelope, x + 0.5 + t * sx, y + 0.5 + t * sy);
                if (l > bestL) bestL = l, bestT = t;
            }
            if (std::abs(bestT) >= reach - 0.1) continue; // no maximum inside: a dark flank
            sum += std::abs(bestT);
            ++n;
        }
    MESSAGE(n, " overlay pixels; mean distance to the envelope's light fringe ", sum / n, " px");
    REQUIRE(n >= 50);
    CHECK(sum / n < 1.0);
}

TEST_CASE("Fig. 7: the ratio view names the (3, -1) beat and the envelope keeps its fringe") {
    // Sentinel phases, to find the two layers' phase literals for the brute force below. The
    // strokes are wider than the hairline floor (2.3 px), so the pattern the brute force
    // averages draws them at their true width, as the view does.
    const double phase[2] = {0.000123, 0.000456}, spacing[2] = {15, 5};
    const std::string scene = fmt::format(
        "scene {{ size = (120, 160); envelope_taps = 48; envelope_gain = 1 }}\n"
        "layer {{ family = lines; spacing = 15; stroke = 4; phase = {} }}\n"
        "layer {{ family = lines; spacing = 5; stroke = 2.5; rotation = 2deg; phase = {} }}\n",
        phase[0], phase[1]);
    auto jit = test::makeBackendOrSkip("jit");
    REQUIRE(jit);
    // The ratio view: every pixel in the fringe regime (dark) and hued by order 4, orange.
    const Image ratio = test::renderScene(*test::compileOk(scene, {.view = ViewMode::Ratio}), *jit);
    for (int y = 0; y < ratio.height; y += 7)
        for (int x = 0; x < ratio.width; x += 7) {
            const float* p = ratio.row(y) + static_cast<size_t>(x) * ratio.channels;
            CHECK(p[0] - p[2] > 0.5f); // orange: the (3, -1) beat's order, not black (order 2)
        }
    // The brute force: the pattern re-rendered at 240 advances u of the two indices along w,
    // through the pattern's own code (each layer's phase literal moved by u w_i s_i), averaged.
    // (Each stroke as written, point-sampled: what the sweep's taps draw. The mean filter's
    // pattern would also count where the two layers' strokes meet within a pixel.)
    auto pattern =
        test::compileOk(scene, {.filter = sema::FilterMode::Point, .strokeFloor = false});
    int slot[2] = {-1, -1};
    for (size_t i = 0; i < pattern->literals.size(); ++i)
        for (int l = 0; l < 2; ++l)
            if (pattern->literals[i] == phase[l]) slot[l] = static_cast<int>(i);
    REQUIRE((slot[0] >= 0 && slot[1] >= 0));
    auto averaged = [&](double w0, double w1) {
        const int taps = 240;
        Image mean(120, 160, 4);
        std::fill(mean.pixels.begin(), mean.pixels.end(), 0.0f);
        for (int j = 0; j < taps; ++j) {
            const double u = (j + 0.5) / taps;
            pattern->literals[slot[0]] = phase[0] - u * w0 * spacing[0];
            pattern->literals[slot[1]] = phase[1] - u * w1 * spacing[1];
            const Image img = test::renderScene(*pattern, *jit);
            for (size_t i = 0; i < mean.pixels.size(); ++i)
                mean.pixels[i] += img.pixels[i / 4 * img.channels + i % 4] / taps;
        }
        return mean;
    };
    const Image kept = averaged(1, 3), diagonal = averaged(1, 1);
    const Image envelope =
        test::renderScene(*test::compileOk(scene, {.view = ViewMode::Envelope}), *jit);
    // The view is that average (gain 1), and its rows carry the broad fringe.
    test::ImageDiff d = test::compareImages(kept, envelope, 2.0 / 255, 3);
    INFO("view against the brute force along (1, 3): max ", d.maxAbs * 255, "/255");
    CHECK(d.fractionWithin() >= 0.99);
    const double keptContrast = range(rowMeans(kept)), lostContrast = range(rowMeans(diagonal));
    const double viewContrast = range(rowMeans(envelope));
    MESSAGE("fringe contrast across the rows: the view ", viewContrast, ", along (1, 3) ",
            keptContrast, ", along the diagonal ", lostContrast);
    CHECK(viewContrast > 0.05);
    CHECK(lostContrast < viewContrast / 5);
}

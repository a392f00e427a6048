// The Vulkan backend (runtime/vulkan) held to independent expectations: the interpreter's
// pictures, its own single-dispatch render (for the chunked and windowed paths), the
// structural cache's compile counter, and the walking families' brute-force reference
// (tests/reference). Every case is skipped (tests/support/Skip.h) where no Vulkan device is
// available (no driver, no device); CI runs them on lavapipe, so the images stay small.
// The command line (`moire devices`, --device, no driver) is in cli_test.cpp; per-example
// parity in examples_test.cpp.
#include "runtime/output/Render.h"
#include "runtime/TileExecutor.h"
#include "runtime/vulkan/VulkanBackend.h"
#include "tests/support/Skip.h"
#include "tests/support/WalkingHarness.h"

#include <algorithm>
#include <cstdlib>
#include <map>
#include <thread>

using namespace moire;
using namespace moire::walktest;

namespace {

// The Vulkan backend, or null (the case skipped) where this machine has none.
std::unique_ptr<VulkanBackend> vulkanOrSkip(const VulkanOptions& options = {}) {
    try {
        return std::make_unique<VulkanBackend>(options);
    } catch (const BackendError& e) {
        test::skip(std::string("no Vulkan backend: ") + e.what());
        return nullptr;
    }
}

// Two layers, one turned walking family (a loop per pixel) and one plain: enough structure
// that a misplaced chunk or a swapped row shows.
const char* kScene = "scene { size = (150, 94) }\ncamera { zoom = 1.3 }\n"
                     "layer { family = triangles; spacing = 6; offset = (1.5, 0.5); "
                     "turn = 2deg; stroke = 1.2 }\n"
                     "layer { family = lines; spacing = 5; rotation = 20deg }\n";

// Frame 0 at the scene's own size.
FrameValues frameOf(const SceneProgram& program) {
    FrameValues fv;
    std::string diags;
    INFO(diags);
    REQUIRE(evaluateFrame(program, FrameRequest{}, fv, diags));
    return fv;
}

bool identical(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.channels == b.channels &&
           a.pixels == b.pixels;
}

} // namespace

TEST_CASE("vulkan: a device that is not there is a BackendError, not a crash") {
    // Whether or not this machine has Vulkan, asking for device 99 must throw BackendError
    // with a message naming what is missing; so must makeBackend, which tests and the command
    // line go through.
    try {
        VulkanBackend b(VulkanOptions{.device = 99});
        FAIL("device 99 opened");
    } catch (const BackendError& e) {
        std::string what = e.what();
        CHECK(what.find('\n') == std::string::npos);
        CHECK(
            (what.find("99") != std::string::npos || what.find("no Vulkan") != std::string::npos));
    }
    CHECK_THROWS_AS(makeBackend("vulkan", BackendOptions{.device = 99}), BackendError);
}

TEST_CASE("vulkan: chunked, windowed and concurrent runs give the single dispatch's pixels") {
    auto whole = vulkanOrSkip();
    if (!whole) return;
    // 37 pixels of 4 floats (RGBA) a chunk: 150-pixel rows split into 5 chunks each
    // (4 x 37 + 2), 470 chunks in all, taking turns in the executor's two slots. The whole
    // frame (225 KB of output) is one chunk on any device.
    auto chunked = vulkanOrSkip(VulkanOptions{.maxChunkBytes = 37 * 4 * sizeof(float)});
    REQUIRE(chunked);
    auto program = test::compileOk(kScene);
    const FrameValues fv = frameOf(*program);
    const KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    auto kw = whole->compile(program->kernel), kc = chunked->compile(program->kernel);
    REQUIRE(kw->wholeFrame());
    const Image a = runKernel(*kw, frame), b = runKernel(*kc, frame);
    CHECK(identical(a, b));

    // The same pixels are the same computation wherever they sit in the dispatch: a window
    // written into a larger buffer (rowStride past its width) holds the frame's pixels.
    const int n = kw->numOutputs(), wx = 41, wy = 17, ww = 53, wh = 29, pad = 7;
    std::vector<float> buf(static_cast<size_t>(ww + pad) * n * wh, -1.0f);
    kc->runTile(frame, TileRect{wx, wy, wx + ww, wy + wh}, buf.data(),
                static_cast<size_t>(ww + pad) * n);
    size_t mismatches = 0, padTouched = 0;
    for (int y = 0; y < wh; ++y)
        for (int x = 0; x < ww + pad; ++x)
            for (int k = 0; k < n; ++k) {
                float v = buf[(static_cast<size_t>(y) * (ww + pad) + x) * n + k];
                if (x >= ww)
                    padTouched += v != -1.0f;
                else
                    mismatches += v != a.at(wx + x, wy + y, k);
            }
    CHECK(mismatches == 0);
    CHECK(padTouched == 0);

    // runTile is callable from several threads at once (the CPU executor's contract): four
    // threads, each its own horizontal quarter, into one image.
    Image c(fv.width, fv.height, n);
    std::vector<std::thread> pool;
    for (int t = 0; t < 4; ++t)
        pool.emplace_back([&, t] {
            int y0 = fv.height * t / 4, y1 = fv.height * (t + 1) / 4;
            kc->runTile(frame, TileRect{0, y0, fv.width, y1}, c.row(y0),
                        static_cast<size_t>(fv.width) * n);
        });
    for (std::thread& t : pool) t.join();
    CHECK(identical(a, c));
}

TEST_CASE("vulkan: the executor reports progress in bands and draws the same image") {
    auto vk = vulkanOrSkip();
    if (!vk) return;
    auto program = test::compileOk(kScene);
    const FrameValues fv = frameOf(*program);
    const KernelFrame frame{fv.uniforms.data(), fv.width, fv.height};
    auto kernel = vk->compile(program->kernel);
    std::vector<double> seen;
    ExecOptions options;
    options.progress = [&](double f) { seen.push_back(f); };
    const Image banded = runKernel(*kernel, frame, options);
    CHECK(identical(banded, runKernel(*kernel, frame)));
    REQUIRE(seen.size() == 16);
    CHECK(std::is_sorted(seen.begin(), seen.end()));
    CHECK(seen.front() > 0.0);
    CHECK(seen.back() == 1.0);
}

TEST_CASE("vulkan: every family draws what the interpreter draws") {
    // Beyond the examples (examples_test.cpp): each standard-library family, the lattices with
    // their points and their edges, and a field-encoded layer, over a small frame, to the
    // examples' criteria for Vulkan (2/255 on 99.9% of the samples, mean under 0.5/255).
    auto vk = vulkanOrSkip();
    if (!vk) return;
    auto interp = makeBackend("interp");
    const char* layers[] = {
        "family = lines; angle = 30deg; spacing = 5",
        "family = circles; spacing = 4; origin = (7, -3)",
        "family = squares; spacing = 6; rotation = 10deg",
        "family = triangles; spacing = 6; phase = 2",
        "family = hexagons; spacing = 7; offset = (2, 1); turn = 1deg",
        "family = ngon; sides = 7; spacing = 6; turn = -0.5deg",
        "family = wave; spacing = 6; amplitude = 5; frequency = 2",
        "family = parabola; spacing = 5; bend = 0.5",
        "family = hyperbola; spacing = 6; rotation = 30deg",
        "family = spiral; arms = 3; spacing = 6",
        "family = pencil; lines = 24; start = 0.3; origin = (5, 3)",
        "family = lines; spacing = 5.8; field = saddle; gain = 1",
        "family = square_lattice; spacing = 9; scale = (1, 1.3)",
        "family = triangle_lattice; spacing = 10; edges = 1",
        "family = hex_lattice; spacing = 8; scale = (1, 1.7); edges = 1",
    };
    for (const std::string layer : layers) {
        CAPTURE(layer);
        auto program =
            test::compileOk("scene { size = (120, 80) }\nlayer { " + layer + "; stroke = 1.5 }\n");
        const Image want = test::renderScene(*program, *interp);
        test::ImageDiff d = test::compareImages(want, test::renderScene(*program, *vk), 2.0 / 255);
        double ink = 0.0;
        for (float v : want.pixels) ink += 1.0 - v;
        INFO("max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255, "/255, within ",
             d.fractionWithin());
        if (std::getenv("MOIRE_PARITY_REPORT"))
            MESSAGE(layer, ": max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255,
                    "/255, within 2/255: ", d.fractionWithin());
        // Something is drawn: dots of 1.5 on a 9 x 11.7 lattice, as written, ink about 1.5%.
        CHECK(ink > 0.01 * want.pixels.size());
        CHECK(d.fractionWithin() >= 0.999);
        CHECK(d.meanAbs < 0.5 / 255);
    }
}

TEST_CASE("vulkan: a scene whose numbers change reuses its pipeline") {
    auto vk = vulkanOrSkip();
    if (!vk) return;
    auto interp = makeBackend("interp");
    auto render = [&](const std::string& text, Backend& b) {
        auto program = test::compileOk("scene { size = (96, 64) }\n" + text);
        return test::renderScene(*program, b);
    };
    const std::string a = "layer { family = circles; spacing = 6; origin = (3, 1) }\n"
                          "layer { family = lines; spacing = 4; rotation = 10deg }\n";
    // Every number edited, the structure kept.
    const std::string b = "layer { family = circles; spacing = 9.5; origin = (-7, 2) }\n"
                          "layer { family = lines; spacing = 3; rotation = 35deg }\n";
    // One more layer: a new structure.
    const std::string c = b + "layer { family = circles; spacing = 4 }\n";
    CHECK(vk->compileCount() == 0);
    Image ia = render(a, *vk);
    CHECK(vk->compileCount() == 1);
    Image ib = render(b, *vk);
    CHECK(vk->compileCount() == 1);
    // The reused pipeline draws the edited numbers, not the first scene's.
    CHECK(test::compareImages(ia, ib, 0.1).fractionWithin() < 0.9);
    test::ImageDiff d = test::compareImages(render(b, *interp), ib, 2.0 / 255);
    INFO("max ", d.maxAbs * 255, "/255, within ", d.fractionWithin());
    CHECK(d.fractionWithin() >= 0.999);
    render(c, *vk);
    CHECK(vk->compileCount() == 2);
    render(a, *vk);
    CHECK(vk->compileCount() == 2);
}

namespace {

// A walking layer compiled once per shape (WalkingHarness's Walker: sentinel numbers found
// by slot), probed on the Vulkan kernel and on the JIT at the settings of the sweep.
struct GpuWalker {
    Walker exact; // the program, and its interpreter probe (unused here)
    Prober gpu, jit;
    GpuWalker(const std::string& fam, Backend& vk, Backend& jitBackend)
        : exact(fam), gpu(*exact.program, &vk), jit(*exact.program, &jitBackend) {}
};

} // namespace

TEST_CASE("vulkan: the walking families against the brute-force reference (reduced sweep)") {
    // walking_sweep_test.cpp's sweep, thinned to 432 settings of 8 points (6 shapes x 3
    // spacings x 4 drifts x 3 turns x 2 zooms), probed on the Vulkan kernel in single
    // precision and held against the double brute force of tests/reference. The claim is
    // the sweep's (exact wherever the certified interval fits the budget, or the closed form
    // answers), to within what single precision allows:
    //  - distance: the kernel gets the point, spacing, offset, phase and turn rounded to 24
    //    bits, and forms rho(Rot(-n theta) p - n delta) - (n s + phase), so its error is a
    //    few roundings of the magnitudes it cancels, S = |p| (1 + n |theta|) + n (s + |delta|)
    //    + |phase| + s (the n theta term: the turn angle's own rounding, swung through |p|).
    //    Allowed: 64 ulps of S, i.e. |d - ref| <= 64 * 2^-24 * S. Measured on lavapipe: 7.2
    //    at worst (the JIT at the same points: 1.5); 64 leaves room for a GPU's sin and cos,
    //    which the Vulkan spec lets be much less exact than libm's (absolute 2^-11 on
    //    [-pi, pi]) and which n theta takes far outside that range;
    //  - what is drawn: coverage within 2/255 of the reference's at 99.9% of the points, and
    //    a mean difference under 0.5/255 (examples_test.cpp's criteria for a picture).
    //    Measured: worst 0.17/255, mean 0.003/255.
    // Both sides inked solid (distance within the accept band) count as agreeing, as in the
    // sweep: the solver may stop early there.
    auto vk = vulkanOrSkip();
    auto jitBackend = test::makeBackendOrSkip("jit");
    if (!vk || !jitBackend) return;
    std::map<std::string, std::unique_ptr<GpuWalker>> walkers;
    const int shapes[] = {0, 3, 4, 6, 5, 9};
    const double spacings[] = {1.0, 8.0, 45.0};
    const double drifts[] = {0.0, 0.8, 1.0, 1.4}; // m / s
    const double turns[] = {0.0, 0.4 * kDeg, 6.0 * kDeg};
    const double zooms[] = {2.0, 0.2};
    const int kPoints = 8;
    const double kUlps = 64.0;
    std::mt19937_64 rng(20240612);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    long settings = 0, points = 0, compared = 0, valued = 0, coverageOver = 0;
    double worst = 0, jitWorst = 0, worstCoverage = 0, sumCoverage = 0;
    for (int shape : shapes)
        for (double s : spacings)
            for (double f : drifts)
                for (double turn : turns)
                    for (double zoom : zooms) {
                        Setting st;
                        st.w.facets = shape;
                        st.w.spacing = s;
                        st.w.turn = (unit(rng) < 0.5 ? -1 : 1) * turn;
                        st.w.phase = s * std::vector<double>{0.0, 0.37, 1.6, -0.2}[settings % 4];
                        st.zoom = zoom;
                        st.stroke = settings % 3 == 0 ? 0.2 * s : 1.5;
                        // -delta at a facet normal or anywhere, sized so that m = f s.
                        const int sides = std::max(shape, 1);
                        setDrift(st.w, f,
                                 settings % 2 == 0 ? 2 * kPi * std::floor(unit(rng) * sides) / sides
                                                   : 2 * kPi * unit(rng));
                        ++settings;
                        const bool closed =
                            st.w.turn == 0.0 && (shape == 0 || reference::drift(st.w) <= s + 1e-4);
                        std::unique_ptr<GpuWalker>& gw = walkers[familyOf(shape)];
                        if (!gw)
                            gw = std::make_unique<GpuWalker>(familyOf(shape), *vk, *jitBackend);
                        const double extent = 650.0 / zoom; // the frame of a 1200 x 800 view
                        for (int i = 0; i < kPoints; ++i) {
                            double x, y; // half uniform over the frame, half on or near members
                            if (i % 2 == 0)
                                inDisc(extent, rng, x, y);
                            else
                                nearMember(st, extent, rng, x, y);
                            ++points;
                            const Out g = probeOn(gw->gpu, gw->exact, st, x, y);
                            INFO(describe(st));
                            SHOW(x, y, g.distance, g.lo, g.hi);
                            REQUIRE(std::isfinite(g.distance));
                            if (g.hi - g.lo + 1.0 > 1024.0 && !closed)
                                continue; // strided: no claim
                            const reference::Nearest ref =
                                reference::nearest(st.w, x, y, st.guard(), 50000);
                            if (!ref.complete) continue; // too costly for the reference
                            ++compared;
                            const double n =
                                std::max(static_cast<double>(ref.argmin), std::hypot(x, y) / s);
                            const double scale =
                                std::hypot(x, y) * (1.0 + n * std::fabs(st.w.turn)) +
                                n * (s + std::hypot(st.w.offsetX, st.w.offsetY)) +
                                std::fabs(st.w.phase) + s;
                            auto ulps = [&](double d) {
                                if (d <= st.accept() && ref.distance <= st.accept()) return 0.0;
                                return std::fabs(d - ref.distance) / (scale * 0x1p-24);
                            };
                            valued += ref.distance > st.accept();
                            const Out j = probeOn(gw->jit, gw->exact, st, x, y);
                            SHOW(ref.distance, ref.argmin, j.distance, ulps(g.distance));
                            CHECK(ulps(g.distance) <= kUlps);
                            worst = std::max(worst, ulps(g.distance));
                            jitWorst = std::max(jitWorst, ulps(j.distance));
                            const double dc =
                                std::fabs(st.coverage(g.distance) - st.coverage(ref.distance));
                            worstCoverage = std::max(worstCoverage, dc);
                            sumCoverage += dc;
                            coverageOver += dc > 2.0 / 255;
                        }
                    }
    REPORT("vulkan walking sweep: ", settings, " settings, ", points, " points, ", compared,
           " compared with the reference (", valued, " not inked solid); distance error at worst ",
           worst, " ulps of S (the JIT: ", jitWorst, "); coverage at worst ", worstCoverage * 255,
           "/255, mean ", sumCoverage / compared * 255, "/255, over 2/255: ", coverageOver);
    CHECK(settings == 432);
    CHECK(compared >= points / 2);
    CHECK(valued >= compared / 4);
    CHECK(coverageOver <= compared / 1000);
    CHECK(sumCoverage / compared < 0.5 / 255);
}

// The viewer's render thread without a window. A frame with the view's pan, zoom and a layer's
// motion is the picture of the scene with that placement written into it (Placement.h), as
// the interpreter renders it: another backend, and the view's adjustments as scene text
// rather than literal slots. Only the newest of a burst of jobs matters; a frame whose
// uniforms did not change is the last one again; a still is the frame, written beside the
// scene.
#include "runtime/output/ImageIO.h"
#include "runtime/view/FrameRenderer.h"
#include "runtime/view/Placement.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <doctest/doctest.h>
#include <mutex>

using namespace moire;
using namespace moire::view;

namespace {

const char* kScene = R"(scene { size = (320, 200); background = #f6f3ec }
camera { center = (5, -3); zoom = 1.2; rotation = 10deg }
timing sway { period = 2; mode = once }
layer a { family = circles; spacing = 6; stroke = 1.7; color = #18181c
          origin = ramp(sway, (-30, 0), (-10, 0)) }
layer b { family = lines; spacing = 7; stroke = 1.5; color = #203080; rotation = 15deg }
)";

// A renderer and the frames it finishes, waited for as the window's loop would be woken.
struct Frames {
    std::mutex mutex;
    std::condition_variable cv;
    FrameRenderer renderer{2, [this] {
                               std::lock_guard<std::mutex> lock(mutex);
                               cv.notify_all();
                           }};

    // The first frame of `version` or later (those before it are passed over).
    RenderedFrame waitFor(uint64_t version, std::vector<RenderedFrame>* seen = nullptr) {
        std::unique_lock<std::mutex> lock(mutex);
        std::optional<RenderedFrame> f;
        cv.wait_for(lock, std::chrono::seconds(60), [&] {
            while ((f = renderer.takeFrame())) {
                if (seen) seen->push_back(*f);
                if (f->version >= version) return true;
            }
            return false;
        });
        REQUIRE_MESSAGE(f, "no frame of version ", version);
        return *f;
    }
    std::string waitMessage() {
        std::unique_lock<std::mutex> lock(mutex);
        std::vector<std::string> m;
        cv.wait_for(lock, std::chrono::seconds(60),
                    [&] { return !(m = renderer.takeMessages()).empty(); });
        REQUIRE(!m.empty());
        return m.front();
    }
};

struct Built {
    std::unique_ptr<Backend> backend;
    std::unique_ptr<SceneBuilder> builder;
    std::shared_ptr<const LiveProgram> build;

    explicit Built(const std::string& text) {
        backend = test::makeBackendOrSkip("jit");
        if (!backend) return;
        builder = std::make_unique<SceneBuilder>(
            *backend, CompileOptions{.mode = CompileOptions::Mode::Interactive});
        BuildResult r = builder->build("s.moire", text);
        REQUIRE_MESSAGE(r.good(), r.diagnostics);
        build = r.build;
    }
};

RenderJob jobOf(const Built& b, uint64_t version, double time = 0.0, ViewAdjust view = {}) {
    RenderJob j;
    j.build = b.build;
    j.view = std::move(view);
    j.time = time;
    j.width = 160;
    j.height = 100;
    j.version = version;
    return j;
}

// Samples of an RGBA8 frame more than `tolerance` levels from the float image's.
int differing(const RenderedFrame& f, const Image& img, int tolerance) {
    REQUIRE(f.width == img.width);
    REQUIRE(f.height == img.height);
    int n = 0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 4; ++c) {
                const int want =
                    static_cast<int>(std::lround(std::clamp(img.at(x, y, c), 0.0f, 1.0f) * 255));
                const int got = f.rgba[(static_cast<size_t>(y) * f.width + x) * 4 + c];
                n += std::abs(got - want) > tolerance;
            }
    return n;
}

} // namespace

TEST_CASE("frame renderer: a frame with the view's adjustments is the scene placed so") {
    Built b(kScene);
    if (!b.build) return;
    ViewAdjust view;
    view.panX = 12, view.panY = -7, view.zoomFactor = 1.7;
    view.layerRef(1).dx = 3.5, view.layerRef(1).dy = -2, view.layerRef(1).turn = 0.2;
    Frames frames;
    frames.renderer.submit(jobOf(b, 1, 0.5, view));
    RenderedFrame f = frames.waitFor(1);
    REQUIRE_MESSAGE(f.error.empty(), f.error);
    CHECK(f.version == 1);
    CHECK(f.divisor == 1);
    CHECK(f.time == 0.5);
    CHECK(!f.reused);

    std::string placed, why;
    REQUIRE_MESSAGE(placedSource(*b.build->program, view, placed, why), why);
    INFO("placed:\n", placed);
    auto program = test::compileOk(placed);
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    const Image expect = test::renderScene(*program, *interp, 160, 100, 0.5);
    // Within a level of rounding (the JIT computes in float, the interpreter in double, and
    // the placement's numbers have seven significant digits).
    CHECK(differing(f, expect, 1) == 0);
    // Without the adjustments the picture is another.
    frames.renderer.submit(jobOf(b, 2, 0.5));
    CHECK(differing(frames.waitFor(2), expect, 8) > 1000);
}

TEST_CASE("frame renderer: the newest job wins, and an unchanged frame is not rendered again") {
    Built b(kScene);
    if (!b.build) return;
    Frames frames;
    for (uint64_t v = 1; v <= 6; ++v) frames.renderer.submit(jobOf(b, v, 0.1 * v));
    std::vector<RenderedFrame> seen;
    RenderedFrame last = frames.waitFor(6, &seen);
    CHECK(last.version == 6);
    CHECK(last.time == doctest::Approx(0.6));
    for (size_t i = 1; i < seen.size(); ++i) CHECK(seen[i].version > seen[i - 1].version);

    // After the sway ends (2 s), nothing moves: t = 3 and t = 5 are the same picture.
    frames.renderer.submit(jobOf(b, 7, 3.0));
    RenderedFrame at3 = frames.waitFor(7);
    CHECK(!at3.reused);
    frames.renderer.submit(jobOf(b, 8, 5.0));
    RenderedFrame at5 = frames.waitFor(8);
    CHECK(at5.reused);
    CHECK(at5.time == 5.0);
    CHECK(at5.rgba == at3.rgba);
    // A moved layer is a new picture.
    ViewAdjust moved;
    moved.layerRef(0).dx = 4;
    frames.renderer.submit(jobOf(b, 9, 5.0, moved));
    RenderedFrame shifted = frames.waitFor(9);
    CHECK(!shifted.reused);
    CHECK(shifted.rgba != at3.rgba);
}

TEST_CASE("frame renderer: s writes the frame beside the scene, never over a file") {
    Built b(kScene);
    if (!b.build) return;
    test::TempDir dir("stills");
    const std::string scene = dir.file("s.moire");
    dir.write("s-still-001.png", "taken");
    Frames frames;
    frames.renderer.submit(jobOf(b, 1, 0.25));
    RenderedFrame f = frames.waitFor(1);
    frames.renderer.saveStill(jobOf(b, 2, 0.25), scene);
    const std::string message = frames.waitMessage();
    CHECK(message == "moire: saved " + dir.file("s-still-002.png") + " (160x100)");
    CHECK(test::readFile(dir.file("s-still-001.png")) == "taken");
    CHECK(differing(f, readImage(dir.file("s-still-002.png")), 0) == 0);
}

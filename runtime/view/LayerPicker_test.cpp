// Picking off the window's thread: a click on a stroke's centre line picks its layer, within
// the tolerance in pixels and no further, the topmost on a tie, with the view's pan, zoom and
// layer motions as the picture has them. The expectations are where the strokes lie by the
// families' definitions: layer a's lines at x = 20 k, layer b's (turned a quarter) at
// y = 5 + 20 k, taken to pixels by ViewCamera.
#include "runtime/FrameEval.h"
#include "runtime/view/LayerPicker.h"
#include "tests/support/Support.h"

#include <chrono>
#include <condition_variable>
#include <doctest/doctest.h>
#include <mutex>

using namespace moire;
using namespace moire::view;

namespace {

const char* kScene = R"(scene { size = (200, 100) }
layer a { family = lines; spacing = 20 }
layer b { family = lines; spacing = 20; rotation = 90deg; origin = (0, 5) }
)";

// Answers as they come, waited for as the window's loop would be woken.
struct Answers {
    std::mutex mutex;
    std::condition_variable cv;
    int notified = 0;
    LayerPicker picker{[this] {
        std::lock_guard<std::mutex> lock(mutex);
        ++notified;
        cv.notify_all();
    }};

    PickResult next() {
        std::unique_lock<std::mutex> lock(mutex);
        std::optional<PickResult> r;
        // Generous: the first answer includes a compile of the scene.
        cv.wait_for(lock, std::chrono::seconds(30),
                    [&] { return (r = picker.take()).has_value(); });
        REQUIRE_MESSAGE(r, "no answer from the picker");
        return *r;
    }
};

struct Click {
    std::shared_ptr<const LiveProgram> build;
    SceneCamera camera;
    int width = 200, height = 100;

    explicit Click(const std::string& text = kScene) {
        auto live = std::make_shared<LiveProgram>();
        live->program = test::compileOk(text, {.interactive = true});
        build = live;
        FrameValues fv;
        std::string diags;
        REQUIRE(evaluateFrame(*build->program, FrameRequest{}, fv, diags));
        camera = SceneCamera::from(fv);
    }
    // A request for a click on world point `world` under `view`.
    PickRequest at(Vec2 world, const ViewAdjust& view = {}, uint64_t id = 1) const {
        PickRequest r;
        r.picture.build = build;
        r.picture.view = view;
        r.picture.width = width;
        r.picture.height = height;
        r.at = ViewCamera(camera, view, width, height).toPixel(world);
        r.id = id;
        return r;
    }
};

} // namespace

TEST_CASE("layer picker: picks the stroke under the click, off the caller's thread") {
    Click click;
    Answers answers;
    const ViewAdjust none;
    struct Case {
        Vec2 world;
        int layer;
    };
    const double pixel = ViewCamera(click.camera, none, 200, 100).pixelSize();
    const Case cases[] = {
        {{20, 13}, 0},                // on a's line, 8 from b's
        {{-40, 13}, 0},               // another of a's
        {{10, 25}, 1},                // on b's line, 10 from a's
        {{10, 15}, -1},               // 10 from both
        {{20 + 3.5 * pixel, 13}, 0},  // within 4 pixels
        {{20 + 4.5 * pixel, 13}, -1}, // beyond them
    };
    uint64_t id = 0;
    for (const Case& c : cases) {
        INFO("world (", c.world.x, ", ", c.world.y, ")");
        answers.picker.request(click.at(c.world, none, ++id));
        PickResult r = answers.next();
        CHECK(r.id == id);
        CHECK(r.build == click.build);
        CHECK(r.ok);
        CHECK(r.layer == c.layer);
    }
    CHECK(answers.notified >= static_cast<int>(std::size(cases)));
}

TEST_CASE("layer picker: the view's layer motions and zoom are the picture's") {
    Click click;
    Answers answers;
    // Layer a moved 7 to the right: its line is at x = 27 now, and none at 20.
    ViewAdjust moved;
    moved.layerRef(0).dx = 7;
    answers.picker.request(click.at({27, 13}, moved));
    CHECK(answers.next().layer == 0);
    answers.picker.request(click.at({20, 13}, moved));
    CHECK(answers.next().layer == -1);

    // Zoomed in twice: 3 world units are 6 pixels (too far), 1.5 are 3 (near enough).
    ViewAdjust zoomed;
    zoomed.zoomFactor = 2;
    const double pixel = ViewCamera(click.camera, zoomed, 200, 100).pixelSize();
    REQUIRE(pixel == doctest::Approx(ViewCamera(click.camera, {}, 200, 100).pixelSize() / 2));
    answers.picker.request(click.at({20 + 6 * pixel, 13}, zoomed));
    CHECK(answers.next().layer == -1);
    answers.picker.request(click.at({20 + 3 * pixel, 13}, zoomed));
    CHECK(answers.next().layer == 0);
}

TEST_CASE("layer picker: of two layers on the same lines, the topmost") {
    Click click(R"(scene { size = (200, 100) }
layer a { family = lines; spacing = 20 }
layer again { family = lines; spacing = 20 }
layer other { family = circles; spacing = 30 }
)");
    Answers answers;
    answers.picker.request(click.at({20, 13}));
    CHECK(answers.next().layer == 1);
}

TEST_CASE("layer picker: a request it cannot answer says so") {
    Answers answers;
    PickRequest r;
    r.id = 9; // no build
    answers.picker.request(r);
    PickResult a = answers.next();
    CHECK(a.id == 9);
    CHECK(!a.ok);
}

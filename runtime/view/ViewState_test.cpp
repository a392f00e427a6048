// The viewer's state without a window: gestures move the view as the camera maths says (the
// point under the cursor stays under it), a click asks for a pick and only the answer to the
// last click still wanted selects, the clock pauses and steps, every change of what is drawn
// asks for a frame, and a reload carries the view's motions and the selection over by layer
// name. The expectations are world points through ViewCamera (itself held to a brute-force
// copy of the kernel's camera in ViewCamera_test.cpp), never the state's own arithmetic.
#include "runtime/FrameEval.h"
#include "runtime/view/ViewState.h"
#include "tests/support/Support.h"
#include "tests/support/ViewStateSupport.h"

#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>

using namespace moire;
using namespace moire::view;

namespace {

using Clock = ViewState::Clock;
using test::at;
using test::buildOf;

const char* kScene = R"(scene { size = (200, 100) }
camera { center = (3, -2); zoom = 1.5; rotation = 20deg }
layer a { family = circles; spacing = 6 }
layer b { family = lines; spacing = 4 }
layer { family = lines; spacing = 5 }
)";

SceneCamera cameraOf(const ViewState& state) {
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateFrame(*state.build()->program, FrameRequest{}, fv, diags));
    return SceneCamera::from(fv);
}

Vec2 worldAt(const ViewState& state, Vec2 pixel) {
    return ViewCamera(cameraOf(state), state.view(), state.width(), state.height()).toWorld(pixel);
}

double distance(Vec2 a, Vec2 b) {
    return std::hypot(a.x - b.x, a.y - b.y);
}

ViewState opened(const std::string& text = kScene) {
    ViewState state(0.0, false, at(0));
    state.adopt(buildOf(text));
    state.resize(400, 200);
    return state;
}

} // namespace

TEST_CASE("view state: the wheel zooms about the cursor, a drag pans, and a press that "
          "barely moves is a click") {
    ViewState state = opened();
    const Vec2 cursor{130, 70};
    const Vec2 before = worldAt(state, cursor);
    uint64_t v = state.version();
    state.scroll(2, cursor, at(1));
    CHECK(state.version() > v);
    CHECK(state.view().zoomFactor == doctest::Approx(1.1 * 1.1));
    CHECK(distance(worldAt(state, cursor), before) < 1e-9);

    // Within the threshold (3 screen units, here 2 pixels to the unit): no drag yet.
    const Vec2 from{100, 100};
    const Vec2 grabbed = worldAt(state, from);
    state.press(1, from);
    v = state.version();
    const ViewAdjust zoomed = state.view();
    state.cursorMoved({104, 103}, false, 2.0, at(1));
    CHECK(state.version() == v);
    CHECK(state.view().panX == zoomed.panX);
    CHECK(state.view().panY == zoomed.panY);
    state.cursorMoved({140, 120}, false, 2.0, at(1));
    state.cursorMoved({160, 130}, false, 2.0, at(1));
    CHECK(state.version() > v);
    // The world point first grabbed is under the cursor where the drag ends.
    CHECK(distance(worldAt(state, {160, 130}), grabbed) < 1e-9);
    CHECK(!state.release(1, at(1))); // a drag is no click
    CHECK(!state.dragging());

    // A primary click comes back as a pick request at the press, with the view as it is.
    state.press(kPrimaryButton, {50, 60});
    state.cursorMoved({51, 60}, false, 2.0, at(2));
    std::optional<PickRequest> pick = state.release(kPrimaryButton, at(2));
    REQUIRE(pick);
    CHECK(pick->at.x == 50);
    CHECK(pick->at.y == 60);
    CHECK(pick->picture.width == 400);
    CHECK(pick->picture.height == 200);
    CHECK(pick->picture.view.zoomFactor == state.view().zoomFactor);
    CHECK(pick->picture.build == state.build());
    // Another button's click picks nothing; a release of a button not held is ignored.
    state.press(1, {50, 60});
    CHECK(!state.release(2, at(2)));
    CHECK(state.dragging());
    CHECK(!state.release(1, at(2)));
}

TEST_CASE("view state: with a layer selected, a drag moves it and a turn-drag turns it") {
    ViewState state = opened();
    state.select(1);
    CHECK(state.takeRedraw());
    const Vec2 from{120, 80}, to{170, 95};
    const Vec2 grabbed = worldAt(state, from);
    state.press(kPrimaryButton, from);
    state.cursorMoved(to, false, 1.0, at(0));
    state.release(kPrimaryButton, at(0));
    // The layer's point that was under the cursor is under it still; the camera did not move.
    CHECK(!state.view().cameraMoved());
    CHECK(distance(state.view().layer(1).apply(grabbed), worldAt(state, to)) < 1e-9);
    CHECK(state.view().layer(0).identity());

    // A turn keeps the layer's distance from the world origin, and moves it by an angle.
    const LayerMotion moved = state.view().layer(1);
    state.press(kPrimaryButton, {300, 40});
    state.cursorMoved({300, 160}, true, 1.0, at(0));
    const LayerMotion turned = state.view().layer(1);
    CHECK(std::fabs(turned.turn - moved.turn) > 0.1);
    const Vec2 p{7, -4};
    CHECK(std::hypot(turned.apply(p).x, turned.apply(p).y) ==
          doctest::Approx(std::hypot(moved.apply(p).x, moved.apply(p).y)));

    // `r` puts everything back.
    state.resetView();
    CHECK(state.view().layer(1).identity());
    CHECK(state.view().zoomFactor == 1.0);
}

TEST_CASE("view state: only the answer to the last click still wanted selects") {
    ViewState state = opened();
    auto click = [&](Vec2 p) {
        state.press(kPrimaryButton, p);
        auto r = state.release(kPrimaryButton, at(0));
        REQUIRE(r);
        return *r;
    };
    auto answer = [&](const PickRequest& r, int layer, bool ok = true) {
        return PickResult{r.id, r.picture.build, ok, layer};
    };
    PickRequest first = click({10, 10});
    PickRequest second = click({20, 20});
    state.picked(answer(first, 2)); // superseded by the second click
    CHECK(state.selected() == -1);
    state.picked(answer(second, 1));
    CHECK(state.selected() == 1);
    state.picked(answer(second, 0)); // answered once, taken once
    CHECK(state.selected() == 1);

    // A click on nothing selects none; a pick that could not be made leaves the selection.
    PickRequest third = click({30, 30});
    state.picked(answer(third, -1, false));
    CHECK(state.selected() == 1);
    PickRequest fourth = click({30, 30});
    state.picked(answer(fourth, -1));
    CHECK(state.selected() == -1);

    // A key pressed after the click wins over its late answer, and so does a reload.
    PickRequest fifth = click({40, 40});
    state.select(0);
    state.picked(answer(fifth, 2));
    CHECK(state.selected() == 0);
    PickRequest sixth = click({40, 40});
    state.adopt(buildOf(kScene));
    state.picked(answer(sixth, 2));
    CHECK(state.selected() == 0);

    // Out of range is none.
    state.select(7);
    CHECK(state.selected() == -1);
}

TEST_CASE("view state: a reload carries motions and the selection over by layer name") {
    ViewState state = opened();
    state.select(1); // b
    state.press(kPrimaryButton, {100, 100});
    state.cursorMoved({150, 100}, false, 1.0, at(0));
    state.release(kPrimaryButton, at(0));
    state.select(2); // the unnamed layer, third
    state.press(kPrimaryButton, {100, 100});
    state.cursorMoved({100, 150}, false, 1.0, at(0));
    state.release(kPrimaryButton, at(0));
    const LayerMotion b = state.view().layer(1), unnamed = state.view().layer(2);
    REQUIRE(!b.identity());
    REQUIRE(!unnamed.identity());
    state.select(1);

    // b now comes first and a is gone; a new layer c takes the third place, so the unnamed
    // layer (matched by position) has no counterpart.
    const uint64_t v = state.version();
    BuildResult reload;
    reload.kind = BuildResult::Kind::Structure;
    reload.build = buildOf(R"(scene { size = (200, 100) }
layer b { family = lines; spacing = 4 }
layer c { family = circles; spacing = 6 }
layer { family = lines; spacing = 5 }
)");
    state.reloaded(reload);
    CHECK(state.version() > v);
    CHECK(state.layerNames() == std::vector<std::string>{"b", "c", ""});
    CHECK(state.selected() == 0);
    CHECK(state.view().layer(0).dx == b.dx);
    CHECK(state.view().layer(0).dy == b.dy);
    CHECK(state.view().layer(1).identity());
    CHECK(state.view().layer(2).dx == unnamed.dx);
    CHECK(state.view().layer(2).dy == unnamed.dy);

    // A bad save keeps the build and the view, and says why.
    BuildResult bad;
    bad.kind = BuildResult::Kind::Failed;
    bad.diagnostics = "s.moire:2:1: error: something\n";
    state.reloaded(bad);
    CHECK(state.buildErrors() == bad.diagnostics);
    CHECK(state.layerNames().size() == 3);
    CHECK(state.view().layer(0).dx == b.dx);
    state.reloaded(reload);
    CHECK(state.buildErrors().empty());
}

TEST_CASE("view state: w writes the placement, and its reload makes the view the scene's") {
    test::TempDir dir("viewstate");
    const std::string path = dir.file("s.moire");
    dir.write("s.moire", kScene);
    ViewState state(0.0, false, at(0));
    auto build = buildOf(kScene);
    state.adopt(build);
    state.resize(400, 200);
    CHECK(!state.writePlacement("").ok); // the default scene has no file
    CHECK(state.sceneSize(at(0)) == std::make_pair(200, 100));
    state.scroll(1, {100, 50}, at(0));
    state.select(0);
    state.press(kPrimaryButton, {100, 100});
    state.cursorMoved({130, 90}, false, 1.0, at(0));
    state.release(kPrimaryButton, at(0));

    // Refused while the file is newer than the text on screen.
    dir.write("s.moire", std::string(kScene) + "// edited\n");
    PlacementWrite refused = state.writePlacement(path);
    CHECK(!refused.ok);
    CHECK(refused.message.find("changed since it was loaded") != std::string::npos);
    dir.write("s.moire", kScene);

    const std::string report = state.placementReport(at(0));
    CHECK(report.rfind("// placement at t = 0.000 s", 0) == 0);
    CHECK(report.find("camera { center = (") != std::string::npos);
    CHECK(report.find("layer a { origin = (") != std::string::npos);

    PlacementWrite wrote = state.writePlacement(path);
    REQUIRE_MESSAGE(wrote.ok, wrote.message);
    const std::string written = test::readFile(path);
    CHECK(written != kScene);
    // Its reload draws the same picture with the view's adjustments dropped: they are in
    // the text. The scene's camera now is the old camera with the view's pan and zoom.
    const ViewCamera shown(cameraOf(state), state.view(), 400, 200);
    BuildResult reload;
    reload.kind = BuildResult::Kind::Numbers;
    reload.build = buildOf(written);
    state.reloaded(reload);
    CHECK(!state.view().cameraMoved());
    CHECK(state.view().layer(0).identity());
    const Vec2 p = worldAt(state, {33, 44}), q = shown.toWorld({33, 44});
    CHECK(distance(p, q) < 1e-4);

    // A reload of any other text keeps the view's adjustments.
    state.scroll(1, {100, 50}, at(0));
    reload.build = buildOf(std::string(kScene) + "// another\n");
    state.reloaded(reload);
    CHECK(state.view().cameraMoved());
}

TEST_CASE("view state: the clock, the frames asked for, and the status line") {
    ViewState state(2.0, true, at(10));
    CHECK(!state.job(at(10)).build);
    state.adopt(buildOf(kScene));
    state.resize(400, 200);
    CHECK(state.timeNow(at(11)) == doctest::Approx(3.0));
    state.restartClock(at(20)); // the window opened
    CHECK(state.timeNow(at(20.5)) == doctest::Approx(2.5));

    // The job is the state as it is; a gesture marks it interactive until it is submitted.
    state.scroll(1, {10, 10}, at(20.5));
    RenderJob j = state.job(at(21));
    CHECK(j.interactive);
    CHECK(j.version == state.version());
    CHECK(j.time == doctest::Approx(3.0));
    CHECK(j.width == 400);
    CHECK(j.view.zoomFactor == doctest::Approx(1.1));
    state.submitted(j);
    CHECK(!state.job(at(21)).interactive);

    // Pausing stops at the last frame asked for (the one on screen), steps move from there.
    state.togglePlay(at(21.05));
    CHECK(!state.playing());
    CHECK(state.timeNow(at(99)) == doctest::Approx(3.0));
    uint64_t v = state.version();
    state.stepFrames(1, at(99));
    CHECK(state.version() > v);
    CHECK(state.timeNow(at(99)) == doctest::Approx(3.0 + kFrameStep));
    state.stepFrames(-2, at(99));
    CHECK(state.timeNow(at(99)) == doctest::Approx(3.0 - kFrameStep));
    state.skip(1.0, at(99));
    CHECK(state.timeNow(at(120)) == doctest::Approx(4.0 - kFrameStep));

    state.select(0);
    CHECK(state.statusLine(at(120), nullptr, 12.34, "jit") ==
          "t=" + fmt::format("{:.3f}", 4.0 - kFrameStep) + "  paused  layer 1 a  12.3 ms  jit");
    RenderedFrame preview;
    preview.time = 1.5;
    preview.divisor = 4;
    state.select(2);
    CHECK(state.statusLine(at(120), &preview, 7, "vulkan") ==
          "t=1.500  paused  layer 3  preview  7.0 ms  vulkan");
    state.togglePlay(at(121));
    CHECK(state.playing());
}

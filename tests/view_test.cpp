// `moire view` in a virtual X server (Xvfb, whose screen is readable as an XWD file), driven
// with xdotool: the window shows the bytes `moire render` writes; the wheel, drags and layer
// gestures move the picture as the placement `p` prints says, and that placement pasted into
// the scene renders the same picture; a save reloads, a broken save shows its errors over the
// last frame, and `s` writes the frame as a still. Skipped where Xvfb or xdotool is missing.
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/view/Placement.h"
#include "runtime/view/ViewCamera.h"
#include "tests/support/Support.h"
#include "tests/support/ViewerHarness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <doctest/doctest.h>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <regex>
#include <thread>

using namespace moire;
using namespace moire::test::xview;
namespace fs = std::filesystem;

namespace {

const char* kScene = R"(scene { size = (320, 200); background = #f6f3ec }
camera { center = (5, -3); zoom = 1.2; rotation = 10deg }
layer a { family = circles; spacing = 6; stroke = 1.7; color = #18181c; origin = (-24, 0) }
layer b { family = squares; spacing = 7; stroke = 1.5; color = #203080
          origin = (20, 4); rotation = 15deg }
)";

// The scene with its camera line, and optionally layer a's placing properties, replaced by
// the blocks a placement printed.
std::string pasted(std::string scene, const std::string& placement) {
    std::smatch m;
    if (std::regex_search(placement, m, std::regex(R"(camera \{[^}]*\})"))) {
        size_t at = scene.find("camera {");
        scene.replace(at, scene.find('\n', at) - at, m.str());
    }
    if (std::regex_search(placement, m, std::regex(R"(layer a \{([^}]*)\})"))) {
        size_t at = scene.find("origin = (-24, 0)");
        scene.replace(at, std::strlen("origin = (-24, 0)"), m[1].str());
    }
    return scene;
}

} // namespace

TEST_CASE("view: the window shows what render writes, and follows the wheel and drags") {
    SKIP_WITHOUT_X();
    Session session;
    if (!session.start(kScene)) return;
    test::TempDir& dir = session.dir;
    VirtualScreen& screen = session.screen;
    Viewer& viewer = *session.viewer;
    const auto origin = session.origin;
    auto at = [&](double x, double y) { return session.at(x, y); };

    // Without the status line, the window is the render, byte for byte (within rounding).
    Rgb expect = offline(dir, kScene);
    CHECK(differing(windowMatching(screen, origin, expect), expect) == 0);

    // The scene's camera, as the placements are checked against it.
    auto program = test::compileOk(kScene);
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateFrame(*program, FrameRequest{}, fv, diags));
    view::SceneCamera cam = view::SceneCamera::from(fv);
    auto cameraOf = [&](const Placed& p) {
        view::SceneCamera c = cam;
        c.centerX = p.cx, c.centerY = p.cy, c.zoom = p.zoom;
        return view::ViewCamera(c, {}, 320, 200);
    };

    // One wheel notch up at (100, 80): 1.1 times the zoom, the world point there stays put.
    screen.xdo("mousemove " + at(100, 80) + " click 4");
    Placed zoomed = viewer.place();
    CHECK(zoomed.zoom == doctest::Approx(1.2 * 1.1).epsilon(1e-6));
    view::Vec2 before = view::ViewCamera(cam, {}, 320, 200).toWorld({100, 80});
    view::Vec2 after = cameraOf(zoomed).toWorld({100, 80});
    CHECK(std::hypot(after.x - before.x, after.y - before.y) < 1e-4);
    REQUIRE(viewer.settled(zoomed.version));
    expect = offline(dir, pasted(kScene, zoomed.text));
    CHECK(differing(windowMatching(screen, origin, expect), expect) == 0);

    // A drag of (50, 30) pixels moves the centre the other way by as much of the world.
    screen.xdo("mousemove " + at(150, 100) + " mousedown 1 mousemove " + at(170, 110) +
               " mousemove " + at(200, 130) + " mouseup 1");
    Placed panned = viewer.place();
    view::Vec2 d = cameraOf(zoomed).deltaToWorld({50, 30});
    CHECK(panned.cx == doctest::Approx(zoomed.cx - d.x).epsilon(1e-5));
    CHECK(panned.cy == doctest::Approx(zoomed.cy - d.y).epsilon(1e-5));
    CHECK(panned.zoom == doctest::Approx(zoomed.zoom).epsilon(1e-6));
    REQUIRE(viewer.settled(panned.version));
    expect = offline(dir, pasted(kScene, panned.text));
    CHECK(differing(windowMatching(screen, origin, expect), expect) == 0);

    // Layer 1 selected: a drag moves it, an alt-drag turns it about the world origin.
    screen.xdo("key 1");
    screen.xdo("mousemove " + at(60, 60) + " mousedown 1 mousemove " + at(75, 65) + " mousemove " +
               at(90, 70) + " mouseup 1");
    screen.xdo("keydown alt mousemove " + at(250, 60) + " mousedown 1 mousemove " + at(252, 90) +
               " mousemove " + at(250, 120) + " mouseup 1 keyup alt");
    Placed moved = viewer.place();
    CHECK(moved.cx == doctest::Approx(panned.cx));
    view::SceneCamera c = cam;
    c.centerX = panned.cx, c.centerY = panned.cy, c.zoom = panned.zoom;
    view::ViewAdjust v;
    view::moveLayer(c, v, 320, 200, 0, {60, 60}, {90, 70});
    view::turnLayer(c, v, 320, 200, 0, {250, 60}, {252, 90});
    view::turnLayer(c, v, 320, 200, 0, {252, 90}, {250, 120});
    CHECK(std::fabs(v.layer(0).turn) > 0.05); // it did turn (clockwise)
    std::smatch m;
    REQUIRE(std::regex_search(
        moved.text, m,
        std::regex(
            R"(layer a \{ origin = \(([-\d.e]+), ([-\d.e]+)\); rotation = ([-\d.e]+)deg \})")));
    view::Vec2 o = v.layer(0).apply({-24, 0});
    CHECK(std::stod(m[1]) == doctest::Approx(o.x).epsilon(1e-5));
    CHECK(std::stod(m[2]) == doctest::Approx(o.y).epsilon(1e-5));
    CHECK(std::stod(m[3]) ==
          doctest::Approx(v.layer(0).turn * 180 / std::numbers::pi).epsilon(1e-5));
    CHECK(moved.text.find("layer b") == std::string::npos);
    REQUIRE(viewer.settled(moved.version));
    expect = offline(dir, pasted(kScene, moved.text));
    CHECK(differing(windowMatching(screen, origin, expect), expect) == 0);

    screen.xdo("key q");
    CHECK(viewer.process().wait(5.0) == 0);
}

TEST_CASE("view: a save reloads, a broken save shows its errors, s saves a still") {
    SKIP_WITHOUT_X();
    Session session;
    if (!session.start(kScene)) return;
    test::TempDir& dir = session.dir;
    VirtualScreen& screen = session.screen;
    Viewer& viewer = *session.viewer;
    const auto origin = session.origin;
    auto at = [&](double x, double y) { return session.at(x, y); };

    // Pan first: the view's adjustments outlive the reload.
    screen.xdo("mousemove " + at(100, 100) + " mousedown 1 mousemove " + at(120, 100) +
               " mousemove " + at(140, 90) + " mouseup 1");
    Placed panned = viewer.place();
    REQUIRE(viewer.settled(panned.version));

    // A save that changes a number: a new frame of the new text, still panned.
    std::string edited = kScene;
    edited.replace(edited.find("spacing = 6"), 11, "spacing = 8");
    uint64_t seen = viewer.fullVersion();
    dir.write("s.moire", edited);
    REQUIRE(viewer.waitLine([&](const std::string&) { return viewer.fullVersion() > seen; }));
    Rgb good = offline(dir, pasted(edited, panned.text));
    CHECK(differing(windowMatching(screen, origin, good), good) == 0);

    // A broken save: the errors over the top of the last frame, the rest of it unchanged.
    dir.write("s.moire", "scene { size = (320, 200) }\nlayer a { family = circles; spacing = 6 +");
    REQUIRE(viewer.nextFrame());
    Rgb shot = windowMatching(screen, origin, good, 60, 200);
    CHECK(differing(shot, good, 60, 200) == 0);
    CHECK(differing(shot, good, 0, 10) > 100);       // the error box
    CHECK(shot.at(2, 2)[0] > shot.at(2, 2)[2] + 20); // and it is red
    CHECK(viewer.stderrText().find("s.moire:2:") != std::string::npos);

    // Fixed again: the box goes.
    std::string fixed = kScene;
    fixed.replace(fixed.find("spacing = 7"), 11, "spacing = 5");
    seen = viewer.fullVersion();
    dir.write("s.moire", fixed);
    REQUIRE(viewer.waitLine([&](const std::string&) { return viewer.fullVersion() > seen; }));
    good = offline(dir, pasted(fixed, panned.text));
    CHECK(differing(windowMatching(screen, origin, good), good) == 0);

    // `s` writes the frame at the window's resolution beside the scene, never over a file.
    for (const char* name : {"s-still-001.png", "s-still-002.png"}) {
        screen.xdo("key s");
        auto line = viewer.waitLine(
            [](const std::string& l) { return l.find("saved") != std::string::npos; });
        REQUIRE_MESSAGE(line, viewer.stderrText());
        CHECK(line->find(name) != std::string::npos);
        Rgb still = toRgb(readImage(dir.file(name)));
        CHECK(differing(still, good) == 0);
    }

    screen.xdo("key q");
    CHECK(viewer.process().wait(5.0) == 0);
}

TEST_CASE("view: pausing stops at the frame on screen, and a step moves it by 1/30 s") {
    SKIP_WITHOUT_X();
    Session session;
    if (!session.start(kScene, false)) return;
    Viewer& viewer = *session.viewer;
    // The clock runs over a still picture: a frame about ten times a second, t advancing.
    const double first = viewer.shownTime();
    const int seen = viewer.frames();
    REQUIRE(viewer.waitLine([&](const std::string&) { return viewer.frames() >= seen + 4; }));
    CHECK(viewer.shownTime() > first);

    session.screen.xdo("key space");
    // Whatever frames were on their way have arrived: the time on screen is the paused one.
    viewer.waitLine([](const std::string&) { return false; }, 0.6);
    const double paused = viewer.shownTime();
    session.screen.xdo("key period");
    REQUIRE(viewer.waitLine([&](const std::string&) { return viewer.shownTime() != paused; }));
    // Exactly one step from the time shown (the trace prints four decimals); it was 1/30 s
    // plus however long the clock had run since the last frame (up to 0.1 s).
    CHECK(std::fabs(viewer.shownTime() - paused - 1.0 / 30.0) < 2e-4);

    session.screen.xdo("key q");
    CHECK(viewer.process().wait(5.0) == 0);
}

TEST_CASE("view: w writes the placement into the scene file, which draws what the window shows") {
    SKIP_WITHOUT_X();
    // Comments and layout the write must keep; layer a writes its origin, layer b's rotation
    // only, and there is no camera block.
    const std::string scene = R"(// two layers, placed by hand
scene { size = (320, 200); background = #f6f3ec }
layer a { family = circles; spacing = 6; stroke = 1.7; color = #18181c; origin = (-24, 0) }
/* b turns */ layer b { family = squares; spacing = 7; stroke = 1.5; color = #203080
          rotation = 15deg }
)";
    Session session;
    if (!session.start(scene)) return;
    test::TempDir& dir = session.dir;
    VirtualScreen& screen = session.screen;
    Viewer& viewer = *session.viewer;
    auto at = [&](double x, double y) { return session.at(x, y); };

    // Zoom, pan, move layer a, turn layer b.
    screen.xdo("mousemove " + at(100, 80) + " click 4");
    screen.xdo("mousemove " + at(150, 100) + " mousedown 1 mousemove " + at(170, 110) +
               " mousemove " + at(190, 120) + " mouseup 1");
    screen.xdo("key 1");
    screen.xdo("mousemove " + at(60, 60) + " mousedown 1 mousemove " + at(75, 65) + " mousemove " +
               at(90, 70) + " mouseup 1");
    screen.xdo("key 2");
    screen.xdo("keydown alt mousemove " + at(250, 60) + " mousedown 1 mousemove " + at(252, 90) +
               " mousemove " + at(250, 120) + " mouseup 1 keyup alt");
    Placed placed = viewer.place();
    REQUIRE(viewer.settled(placed.version));
    const auto shot =
        readScreen(screen.fbFile(), session.origin.first, session.origin.second, 320, 200);
    REQUIRE(shot);

    screen.xdo("key w");
    auto wrote = viewer.waitLine(
        [](const std::string& l) { return l.rfind("moire: wrote the placement into ", 0) == 0; });
    REQUIRE_MESSAGE(wrote, viewer.stderrText());
    const std::string written = test::readFile(dir.file("s.moire"));
    INFO("written:\n", written);
    // Edited in place: the rest of the text as it was, one scene, one camera, one layer a.
    CHECK(written.rfind("// two layers, placed by hand\nscene { size = (320, 200); background = "
                        "#f6f3ec }\ncamera { center = (",
                        0) == 0);
    CHECK(written.find("/* b turns */ layer b { rotation = ") == std::string::npos);
    CHECK(written.find("/* b turns */ layer b { origin = (") != std::string::npos);
    CHECK(written.find("color = #203080\n          rotation = ") != std::string::npos);
    CHECK(written.find("origin = (-24, 0)") == std::string::npos);
    CHECK(std::count(written.begin(), written.end(), '{') == 4);
    // No temporary left beside it.
    for (const std::string& name : dir.names()) CHECK(name.find(".tmp") == std::string::npos);

    // The written scene renders what the window showed.
    Rgb expect = offline(dir, written);
    CHECK(differing(*shot, expect) == 0);
    // And after its reload the window still shows it, the view's adjustments now the
    // scene's own: `p` prints the written camera, and no layer moved.
    auto reloaded = [&] {
        return viewer.stderrText().find("moire: reloaded") != std::string::npos;
    };
    REQUIRE(viewer.waitLine([&](const std::string&) { return reloaded(); }));
    Placed after = viewer.place();
    REQUIRE(viewer.settled(after.version));
    CHECK(after.text.find("layer a") == std::string::npos);
    CHECK(after.text.find("layer b") == std::string::npos);
    CHECK(written.find("center = (" + view::formatNumber(after.cx) + ", " +
                       view::formatNumber(after.cy) + ")") != std::string::npos);
    CHECK(differing(windowMatching(screen, session.origin, expect), expect) == 0);

    // A save with errors is newer work than the view: w leaves it alone.
    dir.write("s.moire", "scene { size = (320, 200) }\nlayer a { family = circles; spacing = 6 +");
    REQUIRE(viewer.nextFrame());
    // The trace has nothing more to say (the clock is paused): watch stderr.
    auto stderrSays = [&](const std::string& what) {
        for (auto end = Clock::now() + std::chrono::seconds(10);
             viewer.stderrText().find(what) == std::string::npos && Clock::now() < end;)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        return viewer.stderrText().find(what) != std::string::npos;
    };
    REQUIRE(stderrSays("s.moire:2:"));
    screen.xdo("key w");
    REQUIRE(stderrSays("cannot write the placement"));
    CHECK(viewer.stderrText().find("cannot write the placement: the file has errors") !=
          std::string::npos);
    CHECK(test::readFile(dir.file("s.moire")).find("spacing = 6 +") != std::string::npos);

    screen.xdo("key q");
    CHECK(viewer.process().wait(5.0) == 0);
}

// The parameter panel of `moire view` in a virtual X server, driven with xdotool: Tab shows it,
// a slider dragged (or a value typed into it) changes the picture to what `moire render -D`
// draws for that value, the drag never pans the picture under the panel, and `W` writes the
// values into the scene file as the smallest edit, after which the reload compiles no kernel
// and the picture does not move. Skipped where Xvfb or xdotool is missing.
#include "tests/support/Support.h"
#include "tests/support/ViewerHarness.h"

#include <doctest/doctest.h>
#include <map>
#include <regex>
#include <string>

using namespace moire;
using namespace moire::test::xview;

namespace {

constexpr int kWidth = 480, kHeight = 300;

// Comments, odd spacing and an expression default the write-back must keep.
const char* kScene = R"(scene { size = (480, 300); background = #f6f3ec }
// how far apart the circles stand
param drift = 1.2 in 0 .. 5 step 0.1
param tilt  =  10deg in 0deg .. 45deg /* turns b */
param gap = 2 * 3.5 in 5 .. 9
layer a { family = circles; spacing = 6 + drift; stroke = 1.7; color = #18181c }
layer b { family = squares; spacing = gap; stroke = 1.5; color = #203080; rotation = tilt }
)";

struct Rect {
    int x = 0, y = 0, w = 0, h = 0;
};

// Tab, then the panel's widgets as the trace prints them (window coordinates).
std::map<std::string, Rect> showPanel(Session& s) {
    std::map<std::string, Rect> items;
    s.screen.xdo("key Tab");
    const std::regex item(R"(panel (\S+) (-?\d+) (-?\d+) (\d+) (\d+))");
    auto done = s.viewer->waitLine([&](const std::string& l) {
        std::smatch m;
        if (std::regex_match(l, m, item))
            items[m[1]] = {std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), std::stoi(m[5])};
        return l.rfind("panel defaults ", 0) == 0;
    });
    REQUIRE_MESSAGE(done, "no panel in the trace; stderr:\n", s.viewer->stderrText());
    return items;
}

// The `param NAME=VALUE v=N` lines printed within `seconds` (until a quiet spell), the last
// value of each name, and the version of the last.
struct Changes {
    std::map<std::string, std::string> values;
    uint64_t version = 0;
};
Changes changes(Session& s, double seconds = 1.0) {
    Changes c;
    const std::regex line(R"(param (\S+)=(.+) v=(\d+))");
    s.viewer->waitLine(
        [&](const std::string& l) {
            std::smatch m;
            if (std::regex_match(l, m, line)) c.values[m[1]] = m[2], c.version = std::stoull(m[3]);
            return false;
        },
        seconds);
    return c;
}

bool stderrSays(Viewer& viewer, const std::string& what) {
    for (auto end = Clock::now() + std::chrono::seconds(10);
         viewer.stderrText().find(what) == std::string::npos && Clock::now() < end;)
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return viewer.stderrText().find(what) != std::string::npos;
}

} // namespace

TEST_CASE("view params: sliders change the picture as render -D does, and W writes the file") {
    SKIP_WITHOUT_X();
    Session session;
    if (!session.start(kScene, true, kWidth, kHeight)) return;
    test::TempDir& dir = session.dir;
    VirtualScreen& screen = session.screen;
    Viewer& viewer = *session.viewer;
    const std::string size = std::to_string(kWidth) + "x" + std::to_string(kHeight);
    auto at = [&](double x, double y) { return session.at(x, y); };
    const Placed before = viewer.place();

    std::map<std::string, Rect> items = showPanel(session);
    for (const char* name : {"play", "t", "drift", "tilt", "gap", "write", "defaults"})
        REQUIRE_MESSAGE(items.count(name), name, " is not on the panel");

    // Drag drift's slider from its left part to its right part: the value follows, on the
    // step, and the picture under the panel does not pan.
    const Rect d = items["drift"];
    const int y = d.y + d.h / 2;
    screen.xdo("mousemove " + at(d.x + 0.1 * d.w, y) + " sleep 0.2 mousedown 1 sleep 0.2 " +
               "mousemove " + at(d.x + 0.3 * d.w, y) + " sleep 0.2 mousemove " +
               at(d.x + 0.45 * d.w, y) + " sleep 0.3 mouseup 1");
    Changes dragged = changes(session);
    REQUIRE_MESSAGE(dragged.values.count("drift"), "no drift change; stderr:\n",
                    viewer.stderrText());
    const std::string drift = dragged.values["drift"];
    const double driftValue = std::stod(drift);
    CHECK(driftValue > 1.2);
    CHECK(driftValue < 5);
    CHECK(std::regex_match(drift, std::regex(R"(\d\.\d|\d)"))); // on the 0.1 step
    Placed after = viewer.place();
    CHECK(after.cx == before.cx);
    CHECK(after.cy == before.cy);
    CHECK(after.zoom == before.zoom);

    // Typed into a slider (ctrl-click): the characters are the field's, not the viewer's
    // keys (`.` would step the clock).
    const double t = viewer.shownTime();
    for (const auto& [name, value] :
         {std::pair<std::string, std::string>{"tilt", "22.5"}, {"gap", "8"}}) {
        const Rect r = items[name];
        screen.xdo("mousemove " + at(r.x + r.w / 3, r.y + r.h / 2) +
                   " sleep 0.2 keydown ctrl click 1 keyup ctrl sleep 0.3");
        screen.xdo("key ctrl+a type " + value);
        screen.xdo("key Return");
    }
    Changes typed = changes(session);
    CHECK(typed.values["tilt"] == "22.5deg");
    CHECK(typed.values["gap"] == "8");
    CHECK(viewer.shownTime() == t);

    // The panel hidden, the window is the render with those values given on the command line.
    // (The pointer leaves the window: over the panel ImGui gave it a visible arrow.)
    screen.xdo("key Tab mousemove " + at(kWidth + 20, kHeight + 20));
    REQUIRE(viewer.settled(typed.version));
    const Rgb expect =
        offline(dir, kScene, size, "-D drift=" + drift + " -D tilt=22.5deg -D gap=8");
    CHECK(differing(windowMatching(screen, session.origin, expect), expect) == 0);

    // W: the literal defaults replaced in place, the expression kept (and said so).
    screen.xdo("key shift+w");
    auto wrote =
        viewer.waitLine([](const std::string& l) { return l.rfind("moire: wrote ", 0) == 0; });
    REQUIRE_MESSAGE(wrote, viewer.stderrText());
    CHECK(*wrote == "moire: wrote drift, tilt into " + dir.file("s.moire"));
    std::string want = kScene;
    want.replace(want.find("1.2 in"), 3, drift);
    want.replace(want.find("10deg in"), 5, "22.5deg");
    CHECK(test::readFile(dir.file("s.moire")) == want);
    auto kept =
        viewer.waitLine([](const std::string& l) { return l.rfind("moire: kept", 0) == 0; });
    REQUIRE(kept);
    CHECK(*kept == "moire: kept gap: its default is an expression (2 * 3.5); the file keeps it");
    for (const std::string& name : dir.names()) CHECK(name.find(".tmp") == std::string::npos);

    // The reload sees new numbers only: no kernel compiled, and the picture stays.
    REQUIRE(stderrSays(viewer, "moire: reloaded"));
    CHECK(viewer.stderrText().find("moire: reloaded (numbers only") != std::string::npos);
    CHECK(viewer.stderrText().find("recompiled") == std::string::npos);
    viewer.waitLine([](const std::string&) { return false; }, 0.5);
    const Placed reloaded = viewer.place();
    REQUIRE(viewer.settled(reloaded.version));
    CHECK(differing(windowMatching(screen, session.origin, expect), expect) == 0);
    // And the written file draws it too (gap set on the command line: the file keeps 7).
    CHECK(differing(offline(dir, want, size, "-D gap=8"), expect) == 0);

    screen.xdo("key q");
    CHECK(viewer.process().wait(5.0) == 0);
}

// The panel's values in the view's state: a value set is the frame the scene draws with that
// default written in its text (the uniforms compared with a build of the edited text), a
// reload keeps it unless the file changed that default, the panel is shown each parameter's
// value in the frame, and `W` writes the file so that its reload draws the same uniforms, bit
// for bit, from a kernel of the same structure.
#include "runtime/FrameEval.h"
#include "runtime/view/ParamBinding.h"
#include "tests/support/Support.h"
#include "tests/support/ViewStateSupport.h"

#include <cmath>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <numbers>

using namespace moire;
using namespace moire::view;

namespace {

using Clock = ViewState::Clock;
using test::at;
using test::buildOf;

std::string scene(const std::string& drift, const std::string& tilt) {
    return fmt::format(R"(scene {{ size = (200, 100) }}
timing sway {{ period = 3; mode = pingpong }}
// drift: how far apart
param drift = {} in 0 .. 5 step 0.1
param tilt = {} in 0deg .. 45deg
param wave = 0.5 * t
layer a {{ family = circles; spacing = 6 + drift + wave; rotation = tilt; stroke = ramp(sway, 1, 2) }}
)",
                       drift, tilt);
}

// The uniforms of the frame the state asks for at `now`.
std::vector<double> uniformsOf(const ViewState& state, Clock::time_point now) {
    const RenderJob j = state.job(now);
    FrameValues fv;
    std::string diags;
    REQUIRE(evaluateViewFrame(*j.build->program, j.view, j.time, j.width, j.height, fv, diags,
                              &j.params));
    return fv.uniforms;
}

ViewState opened(const std::string& text) {
    ViewState state(0.0, false, at(0));
    state.adopt(buildOf(text));
    state.resize(200, 100);
    return state;
}

constexpr double kRad = std::numbers::pi / 180.0;

} // namespace

TEST_CASE("param binding: a value set draws what the text with that default draws") {
    ViewState state = opened(scene("1.2", "10deg"));
    ViewState edited = opened(scene("2.5", "30deg"));
    CHECK(state.build()->program->kernelHash == edited.build()->program->kernelHash);
    CHECK(uniformsOf(state, at(0)) != uniformsOf(edited, at(0)));
    const uint64_t v = state.version();
    state.setParam(0, {2.5, 0, 0, 0}, true);
    state.setParam(1, {30 * kRad, 0, 0, 0}, true);
    CHECK(state.version() > v);
    CHECK(state.job(at(0)).interactive);
    CHECK(uniformsOf(state, at(0)) == uniformsOf(edited, at(0)));
    // Out of range indices change nothing; defaults return the text's values.
    state.setParam(7, {1, 0, 0, 0}, false);
    state.resetParams();
    CHECK(uniformsOf(state, at(0)) == uniformsOf(opened(scene("1.2", "10deg")), at(0)));
}

TEST_CASE("param binding: a reload keeps a value unless the file changed its default") {
    ViewState state = opened(scene("1.2", "10deg"));
    state.setParam(0, {2.5, 0, 0, 0}, false);
    state.setParam(1, {30 * kRad, 0, 0, 0}, false);
    BuildResult reload;
    reload.kind = BuildResult::Kind::Numbers;
    // Another layer's number and a comment changed: both values stay.
    reload.build = buildOf(scene("1.2", "10deg") + "// more\n");
    state.reloaded(reload);
    REQUIRE(state.params().size() == 3);
    CHECK(state.params()[0] == ParamValue{2.5, 0, 0, 0});
    CHECK(state.params()[1] == ParamValue{30 * kRad, 0, 0, 0});
    // drift's default edited in the file: the file's value wins; tilt's stays.
    reload.build = buildOf(scene("0.7", "10deg") + "// more\n");
    state.reloaded(reload);
    CHECK_FALSE(state.params()[0]);
    CHECK(state.params()[1] == ParamValue{30 * kRad, 0, 0, 0});
}

TEST_CASE("param binding: the panel shows each value in the frame, and what it did applies") {
    ViewState state = opened(scene("1.2", "10deg"));
    state.skip(2.0, at(0)); // t = 2
    PanelModel m = panelModel(state, at(0), "a status");
    REQUIRE(m.params.size() == 3);
    CHECK(m.params[0].name == "drift");
    CHECK(m.values[0][0] == 1.2);
    CHECK(m.values[1][0] == 10 * kRad);
    CHECK(m.values[2][0] == doctest::Approx(1.0)); // 0.5 * t at t = 2
    CHECK(m.set == std::vector<bool>{false, false, false});
    CHECK(m.time == doctest::Approx(2.0));
    CHECK_FALSE(m.playing);
    CHECK(m.scrubEnd == doctest::Approx(6.0)); // sway's cycle: a pingpong of 3 s
    CHECK(m.status == "a status");

    PanelActions a;
    a.changes.push_back({0, snapParamValue(m.params[0], {3.14159, 0, 0, 0})});
    a.changes.push_back({2, {4, 0, 0, 0}}); // an expression default, overridden while set
    a.holding = true;
    a.scrubTo = 1.5;
    a.togglePlay = true;
    std::vector<std::string> lines = applyPanel(state, a, at(0));
    REQUIRE(lines.size() == 2);
    CHECK(lines[0].rfind("param drift=3.1 v=", 0) == 0);
    CHECK(lines[1].rfind("param wave=4 v=", 0) == 0);
    CHECK(state.playing());
    CHECK(state.timeNow(at(0)) == doctest::Approx(1.5));
    m = panelModel(state, at(0), "");
    CHECK(m.values[0][0] == 3.1);
    CHECK(m.values[2][0] == 4);
    CHECK(m.set == std::vector<bool>{true, false, true});
}

TEST_CASE("param binding: W writes the defaults, and the reload draws the same uniforms") {
    test::TempDir dir("parambinding");
    const std::string path = dir.file("s.moire");
    const std::string text = scene("1.2", "10deg");
    dir.write("s.moire", text);
    ViewState state = opened(text);
    CHECK_FALSE(state.writeParams("").ok); // the default scene has no file
    PlacementWrite nothing = state.writeParams(path);
    CHECK(nothing.ok);
    CHECK(nothing.message == "moire: the file already has these values");

    state.setParam(0, {2.3, 0, 0, 0}, false);
    state.setParam(
        1, snapParamValue(state.build()->program->parameters[1], {17.25 * kRad, 0, 0, 0}), false);
    state.setParam(2, {4, 0, 0, 0}, false);
    // Refused while the file is newer than the text on screen.
    dir.write("s.moire", text + "// edited\n");
    CHECK(state.writeParams(path).message == "the file has changed since it was loaded; try again");
    dir.write("s.moire", text);

    PlacementWrite wrote = state.writeParams(path);
    REQUIRE_MESSAGE(wrote.ok, wrote.message);
    CHECK(wrote.message == "moire: wrote drift, tilt into " + path +
                               "\nmoire: kept wave: its default is an expression (0.5 * t); "
                               "the file keeps it");
    const std::string written = test::readFile(path);
    CHECK(written == scene("2.3", "17.25deg"));

    const std::vector<double> before = uniformsOf(state, at(0));
    BuildResult reload;
    reload.kind = BuildResult::Kind::Numbers;
    reload.build = buildOf(written);
    CHECK(reload.build->program->kernelHash == state.build()->program->kernelHash);
    state.reloaded(reload);
    CHECK_FALSE(state.params()[0]);
    CHECK_FALSE(state.params()[1]);
    CHECK(state.params()[2] == ParamValue{4, 0, 0, 0});
    CHECK(uniformsOf(state, at(0)) == before);
}

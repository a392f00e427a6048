// The viewer's `e`, `v` and `o` (ViewState::toggleEnvelope, toggleRatio, toggleOverlay): what
// the state asks the next build for flips from what is on screen, whatever the scene's own
// `view` and `overlay` say, and a build made with it is what the state then shows.
#include "runtime/view/ViewState.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>

using namespace moire;
using namespace moire::view;

namespace {

// The build the viewer makes for what the state asks.
std::shared_ptr<const LiveProgram> buildFor(const std::string& text, const ViewState& state) {
    auto live = std::make_shared<LiveProgram>();
    live->program = test::compileOk(text, {.mode = CompileOptions::Mode::Interactive,
                                           .view = state.viewOverride(),
                                           .overlay = state.overlayOverride()});
    return live;
}

const char* kLayers = "layer { family = circles; spacing = 6; stroke = 2 }\n"
                      "layer { family = lines; spacing = 6; stroke = 2; rotation = 5deg }\n";

} // namespace

TEST_CASE("view state: e shows the envelope, and again the pattern") {
    ViewState state(0.0, false, ViewState::Clock::now());
    CHECK(state.shownView() == sema::ViewMode::Pattern);
    CHECK(!state.viewOverride());
    state.adopt(buildFor(kLayers, state));
    CHECK(state.shownView() == sema::ViewMode::Pattern);
    state.toggleEnvelope();
    REQUIRE(state.viewOverride());
    CHECK(*state.viewOverride() == sema::ViewMode::Envelope);
    state.adopt(buildFor(kLayers, state)); // the viewer builds again
    CHECK(state.shownView() == sema::ViewMode::Envelope);
    state.toggleEnvelope();
    CHECK(*state.viewOverride() == sema::ViewMode::Pattern);
    state.adopt(buildFor(kLayers, state));
    CHECK(state.shownView() == sema::ViewMode::Pattern);
}

TEST_CASE("view state: e over a scene drawn as its envelope or split goes to the pattern first") {
    for (const char* view : {"envelope", "split"}) {
        CAPTURE(view);
        const std::string text = std::string("scene { view = ") + view + " }\n" + kLayers;
        ViewState state(0.0, false, ViewState::Clock::now());
        state.adopt(buildFor(text, state));
        CHECK(state.shownView() == *sema::viewNamed(view));
        state.toggleEnvelope();
        // From the envelope, e goes back to the pattern; from the split, to the envelope.
        CHECK(
            *state.viewOverride() ==
            (std::string(view) == "envelope" ? sema::ViewMode::Pattern : sema::ViewMode::Envelope));
    }
}

TEST_CASE(
    "view state: v shows the ratio view, and again the pattern, and e from there the envelope") {
    ViewState state(0.0, false, ViewState::Clock::now());
    state.adopt(buildFor(kLayers, state));
    state.toggleRatio();
    REQUIRE(state.viewOverride());
    CHECK(*state.viewOverride() == sema::ViewMode::Ratio);
    state.adopt(buildFor(kLayers, state));
    CHECK(state.shownView() == sema::ViewMode::Ratio);
    state.toggleEnvelope();
    CHECK(*state.viewOverride() == sema::ViewMode::Envelope);
    state.adopt(buildFor(kLayers, state));
    state.toggleRatio();
    state.adopt(buildFor(kLayers, state));
    state.toggleRatio();
    CHECK(*state.viewOverride() == sema::ViewMode::Pattern);
}

TEST_CASE("view state: o turns the scene's overlay off and on, through any view") {
    for (const char* overlay : {"", "scene { overlay = true }\n", "scene { overlay = false }\n"}) {
        const std::string text = std::string(overlay) + kLayers;
        ViewState state(0.0, false, ViewState::Clock::now());
        state.adopt(buildFor(text, state));
        const bool scene = std::string(overlay).find("true") != std::string::npos;
        CAPTURE(overlay);
        CHECK(state.shownOverlay() == scene);
        state.toggleOverlay();
        REQUIRE(state.overlayOverride());
        CHECK(*state.overlayOverride() == !scene);
        state.adopt(buildFor(text, state));
        CHECK(state.shownOverlay() == !scene);
        state.toggleRatio(); // the overlay stays as it is through a change of view
        state.adopt(buildFor(text, state));
        CHECK(state.shownOverlay() == !scene);
        state.toggleOverlay();
        state.adopt(buildFor(text, state));
        CHECK(state.shownOverlay() == scene);
    }
}

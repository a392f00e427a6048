// The viewer's `e` (ViewState::toggleEnvelope): the view the state asks the next build for
// flips between the envelope and the pattern from the view on screen, whatever the scene's
// own `view` says, and a build made with that view is what the state then shows.
#include "runtime/view/ViewState.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>

using namespace moire;
using namespace moire::view;

namespace {

std::shared_ptr<const LiveProgram> buildOf(const std::string& text,
                                           std::optional<sema::ViewMode> view) {
    auto live = std::make_shared<LiveProgram>();
    live->program =
        test::compileOk(text, {.mode = CompileOptions::Mode::Interactive, .view = view});
    return live;
}

const char* kLayers = "layer { family = circles; spacing = 6; stroke = 2 }\n"
                      "layer { family = lines; spacing = 6; stroke = 2; rotation = 5deg }\n";

} // namespace

TEST_CASE("view state: e shows the envelope, and again the pattern") {
    ViewState state(0.0, false, ViewState::Clock::now());
    CHECK(state.shownView() == sema::ViewMode::Pattern);
    CHECK(!state.viewOverride());
    state.adopt(buildOf(kLayers, state.viewOverride()));
    CHECK(state.shownView() == sema::ViewMode::Pattern);
    state.toggleEnvelope();
    REQUIRE(state.viewOverride());
    CHECK(*state.viewOverride() == sema::ViewMode::Envelope);
    state.adopt(buildOf(kLayers, state.viewOverride())); // the viewer builds again
    CHECK(state.shownView() == sema::ViewMode::Envelope);
    state.toggleEnvelope();
    CHECK(*state.viewOverride() == sema::ViewMode::Pattern);
    state.adopt(buildOf(kLayers, state.viewOverride()));
    CHECK(state.shownView() == sema::ViewMode::Pattern);
}

TEST_CASE("view state: e over a scene drawn as its envelope or split goes to the pattern first") {
    for (const char* view : {"envelope", "split"}) {
        CAPTURE(view);
        const std::string text = std::string("scene { view = ") + view + " }\n" + kLayers;
        ViewState state(0.0, false, ViewState::Clock::now());
        state.adopt(buildOf(text, std::nullopt));
        CHECK(state.shownView() == *sema::viewNamed(view));
        state.toggleEnvelope();
        // From the envelope, e goes back to the pattern; from the split, to the envelope.
        CHECK(
            *state.viewOverride() ==
            (std::string(view) == "envelope" ? sema::ViewMode::Pattern : sema::ViewMode::Envelope));
    }
}

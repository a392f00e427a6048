// Between the panel (ParamPanel, ImGui) and the view's state (ViewState): what the panel is
// shown of the state each frame, and the state changed by what the hand did on it. No window
// or GL here, so the unit tests drive it as the viewer does.
#pragma once

#include "runtime/view/ParamPanel.h"
#include "runtime/view/ViewState.h"

#include <string>
#include <vector>

namespace moire::view {

// The clock slider's end when the scene has no timings: ten seconds.
constexpr double kDefaultScrubEnd = 10.0;

// The panel's contents at `now`: the build's parameters with their values in the frame, the
// clock, and `status` (the last write-back's outcome). The model points into the state's
// build, so it lives no longer than the state's next reload.
PanelModel panelModel(const ViewState& state, ViewState::Clock::time_point now,
                      const std::string& status);

// Applies what the hand did on the panel, except the write-back (the window's, as `W`).
// Returns a line per parameter changed, `param NAME=LITERAL v=VERSION` (the literal as the
// file would write it, so that `moire render -D NAME=LITERAL` draws the same picture), for
// `moire view --trace`.
std::vector<std::string> applyPanel(ViewState& state, const PanelActions& actions,
                                    ViewState::Clock::time_point now);

} // namespace moire::view

#include "runtime/view/ParamBinding.h"

#include "runtime/FrameEval.h"

#include <algorithm>
#include <fmt/format.h>

namespace moire::view {

PanelModel panelModel(const ViewState& state, ViewState::Clock::time_point now,
                      const std::string& status) {
    PanelModel m;
    m.time = state.timeNow(now);
    m.playing = state.playing();
    m.status = status;
    if (!state.build()) return m;
    const SceneProgram& program = *state.build()->program;
    m.params = program.parameters;
    for (const auto& v : state.params()) m.set.push_back(v.has_value());
    if (m.params.empty()) m.error = "no parameters: declare one with\n  param name = 1 in 0 .. 10";
    // The frame on screen (the panel's values in it) gives each parameter's value and the
    // timings, whose longest cycle the clock slider spans.
    const RenderJob job = state.job(now);
    FrameValues fv;
    std::string diags;
    double end = 0.0;
    if (evaluateViewFrame(program, job.view, job.time, 0, 0, fv, diags, &job.params)) {
        for (const auto& v : fv.parameters) {
            ParamValue value{};
            std::copy(v.begin(), v.end(), value.begin());
            m.values.push_back(value);
        }
        for (const TimingValues& t : fv.timings) end = std::max(end, t.cycle());
    }
    m.values.resize(m.params.size(), ParamValue{});
    m.scrubEnd = end > 0.0 ? end : kDefaultScrubEnd;
    return m;
}

std::vector<std::string> applyPanel(ViewState& state, const PanelActions& actions,
                                    ViewState::Clock::time_point now) {
    std::vector<std::string> lines;
    if (state.build()) {
        const std::vector<Parameter>& params = state.build()->program->parameters;
        for (const PanelActions::Change& c : actions.changes) {
            if (c.param < 0 || c.param >= static_cast<int>(params.size())) continue;
            state.setParam(c.param, c.value, actions.holding);
            lines.push_back(fmt::format("param {}={} v={}", params[c.param].name,
                                        literalText(params[c.param], c.value), state.version()));
        }
    }
    if (actions.resetAll) state.resetParams();
    if (actions.togglePlay) state.togglePlay(now);
    if (actions.scrubTo) state.skip(*actions.scrubTo - state.timeNow(now), now);
    return lines;
}

} // namespace moire::view

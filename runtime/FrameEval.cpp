#include "runtime/FrameEval.h"

#include "compiler/backend/interp/Interpreter.h"

#include <cmath>

namespace moire {

namespace {
SourceRange propRange(const ast::Decl* block, const char* name) {
    if (!block) return {};
    const ast::Property* p = block->prop(name);
    return p ? p->value->range : SourceRange{};
}
} // namespace

bool evaluateFrame(const SceneProgram& program, const FrameRequest& request, FrameValues& out,
                   std::string& diagnostics) {
    Interpreter interp(program.frame);
    std::vector<double> outputs(program.frame.numOutputs);
    std::vector<double> regs;
    InterpEnv env;
    env.time = request.time;
    const std::vector<double>& literals = request.literals ? *request.literals : program.literals;
    env.params = literals.data();
    env.numParams = literals.size();
    env.outputs = outputs.data();
    interp.run(env, regs);

    const int u = program.numUniforms;
    out.uniforms.assign(outputs.begin(), outputs.begin() + u);
    double w = outputs[u + lower::OutputLayout::kSettingWidth];
    double h = outputs[u + lower::OutputLayout::kSettingHeight];
    out.zoom = outputs[u + lower::OutputLayout::kSettingZoom];
    out.centerX = outputs[u + lower::OutputLayout::kSettingCenterX];
    out.centerY = outputs[u + lower::OutputLayout::kSettingCenterY];
    out.turn = outputs[u + lower::OutputLayout::kSettingTurn];

    DiagEngine diags(*program.sources);
    auto whole = [](double v) {
        return std::isfinite(v) && v == std::floor(v) && v >= 1 && v <= kMaxImageSide;
    };
    out.sceneWidth = w;
    out.sceneHeight = h;
    if (request.width > 0 && request.height > 0) {
        w = request.width;
        h = request.height;
    }
    if (!whole(w) || !whole(h)) {
        diags.error(propRange(program.checked.scene, "size"), Msg::BadSize, kMaxImageSide, w, h);
    } else {
        out.width = static_cast<int>(w);
        out.height = static_cast<int>(h);
    }
    if (!(std::isfinite(out.zoom) && out.zoom > 0))
        diags.error(propRange(program.checked.camera, "zoom"), Msg::BadZoom, out.zoom);
    const lower::OutputLayout& layout = program.layout;
    out.timings.clear();
    for (size_t i = 0; i < layout.timings.size(); ++i) {
        const double* v = &outputs[u + layout.timingSetting(static_cast<int>(i))];
        TimingValues tv;
        tv.name = layout.timings[i];
        tv.period = v[0];
        tv.delay = v[1];
        tv.mode = static_cast<TimingValues::Mode>(static_cast<int>(v[2]));
        if (!(std::isfinite(tv.period) && tv.period > 0))
            diags.error(layout.timingPeriods[i], Msg::BadPeriod, tv.period);
        // A negative delay would start each pass part way through (or never end the cycle).
        if (!(std::isfinite(tv.delay) && tv.delay >= 0))
            diags.error(layout.timingDelays[i], Msg::BadDelay, tv.delay);
        out.timings.push_back(tv);
    }
    diagnostics = diags.render();
    return !diags.hasErrors();
}

} // namespace moire

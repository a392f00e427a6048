#include "runtime/FrameEval.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/lower/CameraModel.h"

#include <cmath>
#include <fmt/format.h>

namespace moire {

namespace {
SourceRange propRange(const ast::Decl* block, const char* name) {
    if (!block) return {};
    const ast::Property* p = block->prop(name);
    return p ? p->value->range : SourceRange{};
}

// What `rule` asks of a value, or null when `v` meets it (lower::ValueCheck).
const char* requirement(lower::ValueCheck::Rule rule, double v, bool angle) {
    using R = lower::ValueCheck::Rule;
    const double most = lower::kMaxMagnitude;
    switch (rule) {
    case R::Finite:
        if (std::fabs(v) <= most) return nullptr;
        return angle ? "between -1e12 and 1e12 radians" : "between -1e12 and 1e12";
    case R::Positive:
        if (v > 0 && v <= most) return nullptr;
        return "more than 0 and at most 1e12 (to hide a layer, set its opacity to 0)";
    case R::Spacing:
        if (v >= lower::kMinSpacing && v <= most) return nullptr;
        return "from 1e-6 to 1e12";
    case R::Unit:
        if (v >= 0 && v <= 1) return nullptr;
        return "from 0 to 1";
    case R::Sides:
        if (v >= 3 && v <= most && v == std::floor(v)) return nullptr;
        return "a whole number of sides, 3 or more";
    case R::Range: // its bounds are the param's own: evaluateFrame words it
        return nullptr;
    }
    return nullptr;
}
} // namespace

bool evaluateFrame(const SceneProgram& program, const FrameRequest& request, FrameValues& out,
                   std::string& diagnostics, std::vector<LocatedDiagnostic>* located) {
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
    auto whole = [](double v, int maxSide = kMaxImageSide) {
        return std::isfinite(v) && v == std::floor(v) && v >= 1 && v <= maxSide;
    };
    out.sceneWidth = w;
    out.sceneHeight = h;
    // The scene's own size frames the picture even when the image has another size (the
    // pixel is scaled by it), so it is checked either way.
    if (!whole(w) || !whole(h))
        diags.error(propRange(program.checked.scene, "size"), Msg::BadSize, kMaxImageSide, w, h);
    if (request.width > 0 && request.height > 0) {
        w = request.width;
        h = request.height;
        if (!whole(w) || !whole(h)) diags.error(SourceRange{}, Msg::BadSize, kMaxImageSide, w, h);
    }
    // A command that holds the frame whole takes less than the scene may say.
    const int maxSide = std::min(request.maxSide, kMaxImageSide);
    if (whole(w) && whole(h) && (!whole(w, maxSide) || !whole(h, maxSide)))
        diags.error(request.width > 0 ? SourceRange{} : propRange(program.checked.scene, "size"),
                    Msg::BadSize, maxSide, w, h);
    else if (whole(w) && whole(h)) {
        out.width = static_cast<int>(w);
        out.height = static_cast<int>(h);
    }
    out.pixelSize = lower::fitScale(out.sceneWidth, out.sceneHeight, w, h) / out.zoom;
    MOIRE_CHECK(request.pixelSize <= 0 || program.pixelSlot >= 0,
                "a pixel size asked of a program compiled without its slot");
    if (program.pixelSlot >= 0) {
        // The pixel's size is a literal the kernel reads: run again with it set (the frame
        // program is a few hundred instructions; only the uniforms it feeds change).
        if (request.pixelSize > 0) out.pixelSize = request.pixelSize;
        std::vector<double> set = literals;
        set.at(static_cast<size_t>(program.pixelSlot)) = out.pixelSize;
        env.params = set.data();
        interp.run(env, regs);
        out.uniforms.assign(outputs.begin(), outputs.begin() + u);
        env.params = literals.data();
    }
    auto outOfRange = [&](SourceRange at, const std::string& what, const char* need, double v,
                          bool angle) {
        diags.error(at, Msg::ValueOutOfRange, what, need,
                    fmt::format("{:.6g}{}", v, angle ? "rad" : ""));
    };
    if (!(std::isfinite(out.zoom) && out.zoom > 0))
        diags.error(propRange(program.checked.camera, "zoom"), Msg::BadZoom, out.zoom);
    else if (out.zoom < lower::kMinZoom || out.zoom > lower::kMaxZoom)
        outOfRange(propRange(program.checked.camera, "zoom"), "'zoom'", "from 1e-6 to 1e6",
                   out.zoom, false);
    for (auto [v, name] : {std::pair{out.centerX, "center"}, std::pair{out.centerY, "center"},
                           std::pair{out.turn, "rotation"}}) {
        const bool angle = std::string_view(name) == "rotation";
        if (const char* need = requirement(lower::ValueCheck::Finite, v, angle))
            outOfRange(propRange(program.checked.camera, name), fmt::format("'{}'", name), need, v,
                       angle);
    }
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
    for (size_t i = 0; i < layout.checks.size(); ++i) {
        const lower::ValueCheck& c = layout.checks[i];
        if (c.perPixel) continue;
        const double v = outputs[u + layout.firstCheckSetting() + static_cast<int>(i)];
        if (c.rule == lower::ValueCheck::Range) {
            if (!(v >= c.lo && v <= c.hi))
                outOfRange(c.where, c.what,
                           fmt::format("from {:.6g} to {:.6g}", c.lo, c.hi).c_str(), v, c.angle);
            continue;
        }
        if (const char* need = requirement(c.rule, v, c.angle))
            outOfRange(c.where, c.what, need, v, c.angle);
    }
    out.parameters.assign(static_cast<size_t>(layout.numParameters), {});
    for (int p = 0; p < layout.numParameters; ++p)
        for (int i = 0; i < lower::OutputLayout::kParameterWidth; ++i)
            out.parameters[static_cast<size_t>(p)][static_cast<size_t>(i)] =
                outputs[u + layout.parameterSetting(p) + i];
    diagnostics = diags.render();
    if (located) *located = diags.located();
    return !diags.hasErrors();
}

} // namespace moire

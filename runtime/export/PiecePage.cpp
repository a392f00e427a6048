#include "runtime/export/PiecePage.h"

#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/backend/js/JsFrame.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/stdlib/Embedded.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <string_view>

namespace moire::embedded {
// runtime/export/page/*, built in by moire_embed_as (runtime/CMakeLists.txt).
const std::vector<File>& exportPage();
} // namespace moire::embedded

namespace moire {

namespace {

std::string_view pageFile(std::string_view name) {
    for (const embedded::File& f : embedded::exportPage())
        if (std::string_view(f.path).ends_with(name)) return f.text;
    MOIRE_ICE("the export page's '{}' is not built in", name);
}

std::string htmlEscape(std::string_view s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        default:
            out += c;
        }
    }
    return out;
}

const char* ruleName(lower::ValueCheck::Rule rule) {
    using R = lower::ValueCheck::Rule;
    switch (rule) {
    case R::Finite:
        return "finite";
    case R::Positive:
        return "positive";
    case R::Spacing:
        return "spacing";
    case R::Unit:
        return "unit";
    case R::Sides:
        return "sides";
    case R::Range:
        return "range";
    }
    return "finite";
}

// The frame values `moire render` checks before it draws (runtime/FrameEval.cpp), as the
// page checks them: which output, which rule, and the value's name. The image size is not
// among them: the page's canvas keeps the size it was exported at.
nlohmann::json frameChecks(const SceneProgram& program) {
    using L = lower::OutputLayout;
    const lower::OutputLayout& layout = program.layout;
    const int u = program.numUniforms;
    nlohmann::json checks = nlohmann::json::array();
    auto add = [&](int setting, const char* rule, const std::string& what) {
        checks.push_back({{"output", u + setting}, {"rule", rule}, {"what", what}});
    };
    add(L::kSettingZoom, "zoom", "'zoom'");
    add(L::kSettingCenterX, "finite", "'center'");
    add(L::kSettingCenterY, "finite", "'center'");
    add(L::kSettingTurn, "finite", "'rotation'");
    for (size_t i = 0; i < layout.timings.size(); ++i) {
        const int at = layout.timingSetting(static_cast<int>(i));
        add(at, "period", "the period of '" + layout.timings[i] + "'");
        add(at + 1, "delay", "the delay of '" + layout.timings[i] + "'");
    }
    for (size_t i = 0; i < layout.checks.size(); ++i) {
        const lower::ValueCheck& c = layout.checks[i];
        if (c.perPixel) continue;
        add(layout.firstCheckSetting() + static_cast<int>(i), ruleName(c.rule), c.what);
        if (c.rule == lower::ValueCheck::Range) {
            checks.back()["lo"] = c.lo;
            checks.back()["hi"] = c.hi;
        }
    }
    return checks;
}

// The sliders' parameters: what each is, its range, the literal slots a slider writes
// (compiler/Parameters.h), and the frame output that holds its value, set or default (a
// default may be an expression of t: the slider follows it until it is moved).
nlohmann::json parameters(const SceneProgram& program) {
    nlohmann::json out = nlohmann::json::array();
    for (size_t i = 0; i < program.parameters.size(); ++i) {
        const Parameter& p = program.parameters[i];
        nlohmann::json j = {
            {"name", p.name},
            {"type", parameterKind(p.type)},
            {"components", p.components},
            {"unit", p.unit == Unit::Deg ? "deg" : ""},
            {"label", p.unitLabel},
            {"valueSlot", p.valueSlot},
            {"setSlot", p.setSlot},
            {"output", program.numUniforms + program.layout.parameterSetting(static_cast<int>(i))},
        };
        if (p.min) j["min"] = *p.min;
        if (p.max) j["max"] = *p.max;
        if (p.step) j["step"] = *p.step;
        out.push_back(std::move(j));
    }
    return out;
}

// `text` with every marker replaced, in one pass (a replacement is never searched again).
std::string fill(std::string_view text,
                 const std::vector<std::pair<std::string_view, std::string>>& values) {
    std::string out;
    size_t at = 0;
    while (at < text.size()) {
        size_t next = text.find('@', at);
        if (next == std::string_view::npos) break;
        bool replaced = false;
        for (const auto& [marker, value] : values)
            if (text.substr(next).starts_with(marker)) {
                out.append(text.substr(at, next - at));
                out += value;
                at = next + marker.size();
                replaced = true;
                break;
            }
        if (!replaced) {
            out.append(text.substr(at, next + 1 - at));
            at = next + 1;
        }
    }
    out.append(text.substr(std::min(at, text.size())));
    return out;
}

} // namespace

std::string piecePage(const SceneProgram& program, const PieceOptions& options) {
    MOIRE_CHECK(!program.layout.layerFields && program.layout.numKernelOutputs == 4,
                "export: the kernel must output RGBA only");
    nlohmann::json literals = nlohmann::json::array();
    for (double v : program.literals) // JSON has no NaN or infinity: null, read back as NaN
        literals.push_back(std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr));
    nlohmann::json data = {
        {"title", options.title},
        {"width", options.width},
        {"height", options.height},
        {"time", options.time},
        {"playing", options.playing},
        {"loop", options.loop},
        {"moves", options.moves},
        {"numUniforms", program.numUniforms},
        {"uniformVectors", glsl::uniformVectors(program.kernel)},
        {"frameOutputs", program.frame.numOutputs},
        {"literals", literals},
        {"checks", frameChecks(program)},
        {"parameters", parameters(program)},
        {"shader", glsl::emitGlsl(program.kernel, glsl::Dialect::WebGl)},
    };
    // Inside a <script> element nothing may read as "</script": '<' is written as its JSON
    // escape (it occurs only in strings: the shader's comparisons).
    std::string json;
    for (char c : data.dump()) json += c == '<' ? std::string("\\u003c") : std::string(1, c);
    const std::string frame = js::emitFrameJs(program.frame);
    MOIRE_CHECK(frame.find("</") == std::string::npos, "export: the frame program reads as HTML");
    return fill(pageFile("piece.html"), {
                                            {"@MOIRE_VERSION@", MOIRE_VERSION},
                                            {"@MOIRE_TITLE@", htmlEscape(options.title)},
                                            {"@MOIRE_WIDTH@", std::to_string(options.width)},
                                            {"@MOIRE_HEIGHT@", std::to_string(options.height)},
                                            {"@MOIRE_DATA@", json},
                                            {"@MOIRE_FRAME@", frame},
                                            {"@MOIRE_SCRIPT@", std::string(pageFile("piece.js"))},
                                        });
}

} // namespace moire

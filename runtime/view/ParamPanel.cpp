#include "runtime/view/ParamPanel.h"

#define GLFW_INCLUDE_NONE
#include <algorithm>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl2.h>
#include <cfloat>
#include <cmath>
#include <fmt/format.h>
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <numbers>

namespace moire::view {

namespace {

using ast::Type;

constexpr double kDegree = 180.0 / std::numbers::pi;

// The shown value's unit: degrees for an angle written in degrees, else the value's own.
double unitOf(const Parameter& p) {
    return p.type == Type::Angle && p.unit == Unit::Deg ? kDegree : 1.0;
}

// A printf format for the slider's number: as many decimals as the step has (what the
// slider rounds to before the value is snapped), else about a thousandth of the range.
std::string numberFormat(const Parameter& p, double unit) {
    int decimals = 3;
    if (p.step && *p.step > 0) {
        const std::string s = fmt::format("{:.12g}", *p.step * unit);
        const size_t dot = s.find('.');
        decimals = dot == std::string::npos || s.find('e') != std::string::npos
                       ? (s.find("e-") != std::string::npos ? 6 : 0)
                       : static_cast<int>(s.size() - dot - 1);
    } else if (p.min && p.max && *p.max > *p.min) {
        decimals = std::clamp(
            3 - static_cast<int>(std::floor(std::log10((*p.max - *p.min) * unit))), 0, 6);
    }
    // The angle's unit, or the word of `unit mm` (a `%` in it doubled for printf).
    std::string suffix = p.type != Type::Angle ? "" : unit == 1.0 ? " rad" : " deg";
    if (!p.unitLabel.empty()) suffix = " ";
    for (char c : p.unitLabel) suffix += c == '%' ? std::string("%%") : std::string(1, c);
    return fmt::format("%.{}f{}", decimals, suffix);
}

// A slider for one number or a vector's two (a drag field when the range is not closed).
bool numbers(const Parameter& p, ParamValue& v) {
    const double unit = unitOf(p);
    double shown[2] = {v[0] * unit, v[1] * unit};
    const std::string format = numberFormat(p, unit);
    const int n = p.components;
    bool changed = false;
    if (p.min && p.max && *p.max > *p.min) {
        const double lo = *p.min * unit, hi = *p.max * unit;
        changed = ImGui::SliderScalarN(p.name.c_str(), ImGuiDataType_Double, shown, n, &lo, &hi,
                                       format.c_str(), ImGuiSliderFlags_AlwaysClamp);
    } else {
        // One end, or none: ImGui clamps only between two, so the snap clamps to the one.
        const double speed = p.step ? *p.step * unit : 0.01;
        changed = ImGui::DragScalarN(p.name.c_str(), ImGuiDataType_Double, shown, n,
                                     static_cast<float>(speed), nullptr, nullptr, format.c_str());
    }
    if (changed)
        for (int i = 0; i < n; ++i) v[i] = shown[i] / unit;
    return changed;
}

bool widget(const Parameter& p, ParamValue& v) {
    switch (p.type) {
    case Type::Color: {
        float c[4] = {float(v[0]), float(v[1]), float(v[2]), float(v[3])};
        if (!ImGui::ColorEdit4(p.name.c_str(), c, ImGuiColorEditFlags_AlphaBar)) return false;
        for (int i = 0; i < 4; ++i) v[i] = c[i];
        return true;
    }
    case Type::Bool: {
        bool on = v[0] != 0;
        if (!ImGui::Checkbox(p.name.c_str(), &on)) return false;
        v[0] = on ? 1 : 0;
        return true;
    }
    default:
        return numbers(p, v);
    }
}

} // namespace

ParamPanel::ParamPanel(GLFWwindow* window) : window_(window) {
    IMGUI_CHECKVERSION();
    context_ = ImGui::CreateContext();
    ImGui::SetCurrentContext(context_);
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // nothing written beside the scene or in the current directory
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui_ImplGlfw_InitForOpenGL(window, false); // the viewer's callbacks hand events on
    ImGui_ImplOpenGL2_Init();
    // ImGui reads the pointer only over a focused window or after the pointer entered it; a
    // window that opens under the pointer (and has no window manager to focus it, as under
    // Xvfb) never gets that event.
    ImGui_ImplGlfw_CursorEnterCallback(window, glfwGetWindowAttrib(window, GLFW_HOVERED));
}

ParamPanel::~ParamPanel() {
    ImGui::SetCurrentContext(context_);
    ImGui_ImplOpenGL2_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext(context_);
}

bool ParamPanel::over(double x, double y) const {
    return visible_ && x >= rx_ && y >= ry_ && x < rx_ + rw_ && y < ry_ + rh_;
}

bool ParamPanel::mouseButton(int button, int action, int mods, double x, double y) {
    ImGui::SetCurrentContext(context_);
    ImGui_ImplGlfw_MouseButtonCallback(window_, button, action, mods);
    settle_ = 3;
    if (action == GLFW_PRESS) {
        if (!pressed_ && !over(x, y)) return false;
        pressed_ = true;
        return true;
    }
    if (action == GLFW_RELEASE && pressed_) {
        pressed_ = false;
        return true;
    }
    return false;
}

bool ParamPanel::scroll(double dx, double dy, double x, double y) {
    ImGui::SetCurrentContext(context_);
    if (!over(x, y)) return false;
    ImGui_ImplGlfw_ScrollCallback(window_, dx, dy);
    settle_ = 3;
    return true;
}

void ParamPanel::key(int key, int scancode, int action, int mods) {
    ImGui::SetCurrentContext(context_);
    ImGui_ImplGlfw_KeyCallback(window_, key, scancode, action, mods);
    settle_ = 3;
}

void ParamPanel::character(unsigned codepoint) {
    ImGui::SetCurrentContext(context_);
    ImGui_ImplGlfw_CharCallback(window_, codepoint);
    settle_ = 3;
}

void ParamPanel::cursorMoved(double x, double y) {
    if (pressed_ || over(x, y)) settle_ = 2;
}

void ParamPanel::cursorEnter(int entered) {
    ImGui::SetCurrentContext(context_);
    ImGui_ImplGlfw_CursorEnterCallback(window_, entered);
}

void ParamPanel::focus(int focused) {
    ImGui::SetCurrentContext(context_);
    ImGui_ImplGlfw_WindowFocusCallback(window_, focused);
}

bool ParamPanel::typing() const {
    ImGui::SetCurrentContext(context_);
    return visible_ && ImGui::GetIO().WantTextInput;
}

bool ParamPanel::busy() const {
    ImGui::SetCurrentContext(context_);
    return visible_ &&
           (settle_ > 0 || pressed_ || ImGui::IsAnyItemActive() || ImGui::GetIO().WantTextInput);
}

PanelActions ParamPanel::draw(const PanelModel& m, float scale) {
    PanelActions a;
    items_.clear();
    if (!visible_) {
        rw_ = rh_ = 0;
        return a;
    }
    ImGui::SetCurrentContext(context_);
    ImGui_ImplOpenGL2_NewFrame();
    ImGui_ImplGlfw_NewFrame();
    ImGui::GetIO().FontGlobalScale = scale;
    ImGui::NewFrame();
    auto record = [&](std::string name) {
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        items_.push_back({std::move(name), lo.x, lo.y, hi.x - lo.x, hi.y - lo.y});
        a.holding = a.holding || ImGui::IsItemActive();
    };

    ImGui::SetNextWindowPos(ImVec2(6 * scale, 6 * scale), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("parameters", nullptr,
                 ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoSavedSettings |
                     ImGuiWindowFlags_NoCollapse);
    ImGui::PushItemWidth(150 * scale);

    // The clock: play or pause, and the time, to scrub.
    if (ImGui::Button(m.playing ? "pause" : "play")) a.togglePlay = true;
    record("play");
    ImGui::SameLine();
    double t = m.time;
    const double t0 = 0.0, t1 = std::max(m.scrubEnd, m.time);
    if (ImGui::SliderScalar("t", ImGuiDataType_Double, &t, &t0, &t1, "%.3f s")) a.scrubTo = t;
    record("t");
    ImGui::Separator();

    if (!m.error.empty()) ImGui::TextUnformatted(m.error.c_str());
    for (size_t i = 0; i < m.params.size() && i < m.values.size(); ++i) {
        const Parameter& p = m.params[i];
        ImGui::PushID(static_cast<int>(i));
        ParamValue v = m.values[i];
        // A value the panel set shows in the accent colour: the default no longer stands.
        const bool set = i < m.set.size() && m.set[i];
        if (set) ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.8f, 0.35f, 1.0f));
        const bool changed = widget(p, v);
        if (set) ImGui::PopStyleColor();
        record(p.name);
        if (changed) a.changes.push_back({static_cast<int>(i), snapParamValue(p, v)});
        ImGui::PopID();
    }

    ImGui::Separator();
    if (ImGui::Button("write to file (W)")) a.writeBack = true;
    record("write");
    ImGui::SameLine();
    if (ImGui::Button("defaults")) a.resetAll = true;
    record("defaults");
    if (!m.status.empty()) {
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + 300 * scale);
        ImGui::TextUnformatted(m.status.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::PopItemWidth();
    const ImVec2 pos = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    rx_ = pos.x, ry_ = pos.y, rw_ = size.x, rh_ = size.y;
    ImGui::End();

    ImGui::Render();
    ImGui_ImplOpenGL2_RenderDrawData(ImGui::GetDrawData());
    if (settle_ > 0) --settle_;
    return a;
}

} // namespace moire::view

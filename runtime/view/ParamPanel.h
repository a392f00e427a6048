// The viewer's panel (Tab): a window of Dear ImGui drawn over the picture with a slider per
// parameter (spec §8.1: every slider is a uniform), a colour picker per colour, a checkbox per
// boolean, and the clock (play, pause, scrub). It draws with ImGui's OpenGL 2 backend into
// the viewer's window after the picture's quad, and takes the input that lands on it before
// the picture's gestures see it.
//
// The panel holds no values of its own: each frame it is handed what to show (PanelModel)
// and hands back what the hand did (PanelActions), which the viewer applies to its ViewState.
#pragma once

#include "runtime/view/ParamValues.h"

#include <optional>
#include <span>
#include <string>
#include <vector>

struct GLFWwindow;
struct ImGuiContext;

namespace moire::view {

struct PanelModel {
    std::span<const Parameter> params;
    std::vector<ParamValue> values; // each parameter's value in the frame on screen
    std::vector<bool> set;          // whether the panel set it (else its default stands)
    double time = 0.0;
    bool playing = false;
    double scrubEnd = 10.0; // the clock slider's end (seconds)
    std::string status;     // the last write-back's outcome, under the buttons
    std::string error;      // why there is nothing to turn (the scene has no parameters)
};

struct PanelActions {
    struct Change {
        int param = -1;
        ParamValue value{}; // snapped (snapParamValue)
    };
    std::vector<Change> changes;
    bool holding = false; // a slider is held: the frames asked for are part of a gesture
    bool resetAll = false;
    bool togglePlay = false;
    std::optional<double> scrubTo;
    bool writeBack = false;
};

// Where a widget was drawn, in the window's screen units (what xdotool moves the pointer in):
// what `moire view --trace` prints, so that a test can find a slider.
struct PanelItem {
    std::string name;
    float x = 0, y = 0, w = 0, h = 0;
    bool operator==(const PanelItem&) const = default;
};

class ParamPanel {
  public:
    // Sets up ImGui over `window`, whose GL context must be current. The viewer keeps its own
    // GLFW callbacks and hands the panel each event (below).
    explicit ParamPanel(GLFWwindow* window);
    ~ParamPanel();
    ParamPanel(const ParamPanel&) = delete;
    ParamPanel& operator=(const ParamPanel&) = delete;

    bool visible() const { return visible_; }
    void toggle() { visible_ = !visible_; }

    // Each returns true when the panel takes the event: the picture must not act on it. A
    // press on the panel is the panel's until its release, wherever the pointer goes.
    bool mouseButton(int button, int action, int mods, double x, double y);
    bool scroll(double dx, double dy, double x, double y);
    // Keys and characters go to ImGui; typing() says whether it is typing into a field
    // (ctrl-click on a slider), when the viewer's keys must not act.
    void key(int key, int scancode, int action, int mods);
    void character(unsigned codepoint);
    void cursorMoved(double x, double y); // over the panel: a frame for its hover colours
    void cursorEnter(int entered);
    void focus(int focused);
    bool typing() const;
    // True while ImGui needs more frames than the events ask for (a press being settled, a
    // widget held, a field being typed into).
    bool busy() const;

    // Lays the panel out and draws it into the current framebuffer (nothing when hidden).
    PanelActions draw(const PanelModel& model, float scale);
    // The widgets of the last draw.
    const std::vector<PanelItem>& items() const { return items_; }

  private:
    bool over(double x, double y) const;

    GLFWwindow* window_ = nullptr;
    ImGuiContext* context_ = nullptr;
    bool visible_ = false;
    bool pressed_ = false;                    // a press on the panel, not yet released
    int settle_ = 0;                          // frames still to draw after an event
    float rx_ = 0, ry_ = 0, rw_ = 0, rh_ = 0; // the panel's window in the last draw
    std::vector<PanelItem> items_;
};

} // namespace moire::view

// What the viewer's window shows and how the hand changes it, with no window in sight: the
// build on screen, the view's adjustments (pan, zoom, each layer's motion), the selected layer,
// the clock, the gesture in progress, and what is carried over when a save reloads the scene.
// The window (Viewer.cpp) turns GLFW's events into calls here, in framebuffer pixels and with
// the wall clock given, and asks for frames (RenderJob) as the version here changes; the unit
// tests drive it the same way, without a display.
//
// The panel laid over the picture (sliders for a scene's parameters, ParamPanel) keeps its
// values here beside the view's adjustments, and bumps the version when it changes what is to
// be drawn; the window hands a press to the panel first and to press() only when the panel
// leaves it.
#pragma once

#include "runtime/live/SceneBuilder.h"
#include "runtime/view/FrameRenderer.h"
#include "runtime/view/LayerPicker.h"
#include "runtime/view/ParamValues.h"
#include "runtime/view/ViewCamera.h"
#include "runtime/view/ViewClock.h"

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace moire::view {

// Mouse buttons as GLFW numbers them: 0 is the primary (left) button.
constexpr int kPrimaryButton = 0;

constexpr double kFrameStep = 1.0 / 30.0; // `.` and `,`: one frame at 30 fps
constexpr double kWheelZoom = 1.1;        // per wheel notch
constexpr double kDragThreshold = 3.0;    // screen units before a press becomes a drag
constexpr double kPickTolerance = 4.0;    // pixels from a stroke's centre line that pick it

// The outcome of writing the placement into the scene file (`w`).
struct PlacementWrite {
    bool ok = false;
    // ok: a line for stdout; else the reason, for `cannot write the placement: ` (empty
    // before any good build: nothing to place, nothing to say)
    std::string message;
};

class ViewState {
  public:
    using Clock = std::chrono::steady_clock;

    ViewState(double time, bool playing, Clock::time_point now) : clock_(time, playing, now) {}

    // --- The build --------------------------------------------------------------------

    // Takes a new build, carrying the view's layer motions and the selection over by layer
    // name (by position for unnamed layers), so that an edit keeps the placement in hand.
    void adopt(std::shared_ptr<const LiveProgram> build);
    // A reload's outcome: a good build is adopted (the view's adjustments dropped when it is
    // the text `w` wrote, whose own values they now are); a bad one leaves the last good
    // build on screen and its diagnostics in errors().
    void reloaded(const BuildResult& result);
    const std::shared_ptr<const LiveProgram>& build() const { return build_; }
    // The file's diagnostics while its last save has errors, else empty.
    const std::string& buildErrors() const { return buildError_; }
    void setBuildErrors(std::string diagnostics) { buildError_ = std::move(diagnostics); }
    const std::vector<std::string>& layerNames() const { return names_; }
    int numLayers() const { return static_cast<int>(names_.size()); }
    // The scene's own image size at `now` (it may move with the clock), before any build.
    std::optional<std::pair<int, int>> sceneSize(Clock::time_point now) const;

    // --- The view ---------------------------------------------------------------------

    const ViewAdjust& view() const { return view_; }
    int selected() const { return selected_; }
    // Selects layer `layer` (none when out of range); a pick still on its way is dropped.
    void select(int layer);
    // `r`: the camera and every layer back where the scene puts them.
    void resetView();
    // The framebuffer the picture is drawn into (and the cursor positions are in).
    void resize(int width, int height);
    int width() const { return width_; }
    int height() const { return height_; }

    // `e`: shows the envelope, or the pattern when the envelope is on screen. The view is
    // structure, so the viewer builds the scene again with viewOverride() (and keeps it
    // through reloads); unset, the scene's own `view` is drawn.
    void toggleEnvelope();
    // `v`: the ratio view (§4.2), or the pattern when it is on screen; as `e`.
    void toggleRatio();
    std::optional<sema::ViewMode> viewOverride() const { return viewOverride_; }
    // `o`: the fringe overlay on or off (structure too, so built again with overlayOverride();
    // unset, the scene's own `overlay`).
    void toggleOverlay();
    std::optional<bool> overlayOverride() const { return overlayOverride_; }
    bool shownOverlay() const;
    // The view of the build on screen (the pattern before any build).
    sema::ViewMode shownView() const;

    // --- Gestures (positions in framebuffer pixels) -----------------------------------

    // A button goes down at `at`; a second button while one is held is ignored.
    void press(int button, Vec2 at);
    // The cursor moves to `at`. A press becomes a drag once the cursor is kDragThreshold
    // screen units away (`pixelsPerUnit` framebuffer pixels to the unit). The primary button
    // with a layer selected moves the layer, or turns it about the world origin when `turn`
    // (alt or ctrl held); any other drag pans.
    void cursorMoved(Vec2 at, bool turn, double pixelsPerUnit, Clock::time_point now);
    // A button comes up. A click of the primary button (a press that never became a drag)
    // asks for the layer under it: the request to hand to a LayerPicker.
    std::optional<PickRequest> release(int button, Clock::time_point now);
    // The picker's answer: selects its layer if it answers the last click still wanted (no
    // selection, reload or newer click since) and could be made.
    void picked(const PickResult& result);
    // Wheel notches (`dy` > 0 zooms in) about `at`.
    void scroll(double dy, Vec2 at, Clock::time_point now);
    bool dragging() const { return drag_ >= 0; }

    // --- The clock --------------------------------------------------------------------

    double timeNow(Clock::time_point now) const { return clock_.at(now); }
    bool playing() const { return clock_.playing(); }
    // The clock starts with the window, not with the compile before it.
    void restartClock(Clock::time_point now) { clock_.restart(now); }
    void togglePlay(Clock::time_point now);
    // `.` / `,`: pauses, then one frame (kFrameStep) forward (`frames` > 0) or back.
    void stepFrames(int frames, Clock::time_point now);
    // Right / left: jumps by `dt` seconds from the time now, running on if the clock runs.
    void skip(double dt, Clock::time_point now);

    // --- Frames -----------------------------------------------------------------------

    // The picture must be rendered again; `interactive` while a gesture is under way.
    void changed(bool interactive);
    // Increases with every change of what is to be drawn.
    uint64_t version() const { return version_; }
    // The frame of the state as it is (at `now`'s time), at the framebuffer's size.
    RenderJob job(Clock::time_point now) const;
    // The job was handed to the renderer: the clock records its time, and the gesture flag
    // starts afresh for the next change.
    void submitted(const RenderJob& job);
    // Something the window shows changed without a new frame (the selection, the clock's
    // state on the status line): true once, then false until the next such change.
    bool takeRedraw() { return std::exchange(redraw_, false); }

    // What matters most first, since a narrow window cuts the line's end: the clock, the
    // selection, then the frame time and the backend. `shown` is the frame on screen.
    std::string statusLine(Clock::time_point now, const RenderedFrame* shown, double lastFullMs,
                           const std::string& backend) const;

    // --- The placement ----------------------------------------------------------------

    // `p`: the placement as values to set in the scene's blocks, with a heading line.
    std::string placementReport(Clock::time_point now) const;
    // `w`: writes the placement into the scene file `path` (Placement.h: placedSource),
    // atomically. Refused while the file has errors, has changed since the build on screen
    // was loaded, or for the default scene (an empty path). The view keeps its adjustments
    // until the reload of the written text, which then carries them itself: the picture
    // never jumps.
    PlacementWrite writePlacement(const std::string& path);

    // --- The parameters (the panel) ---------------------------------------------------

    // The values the panel set, one entry per parameter of the build on screen. A reload
    // keeps each by name (ParamValues.h: carryParams), except where the file changed the
    // parameter's default: the file's edit is newer.
    const ParamSet& params() const { return params_; }
    // Sets parameter `param` of the build on screen (`interactive` while a slider is held).
    void setParam(int param, const ParamValue& value, bool interactive);
    // Every parameter back to its default.
    void resetParams();
    // `W`: writes the set values into the scene file as the defaults' new literals
    // (ParamWriteBack.h), atomically, refused as `w` is. The reload of the written text sees
    // new numbers only (no kernel is compiled), and its defaults are the values on screen:
    // the picture does not move. `message` names what was written, and what was kept, why.
    PlacementWrite writeParams(const std::string& path);

  private:
    // Why the scene file at `path` cannot be written over now (errors, a newer save, no
    // file), or empty.
    std::string unwritable(const std::string& path) const;
    // The scene's own camera at `now` (it may move with the clock); the last one known when
    // the frame cannot be evaluated.
    SceneCamera sceneCamera(Clock::time_point now);

    std::shared_ptr<const LiveProgram> build_;
    std::vector<std::string> names_; // build_'s layer names
    std::string buildError_;
    std::optional<std::string> placedText_; // what `w` last wrote, until its reload
    ParamSet params_;                       // the panel's values for build_'s parameters
    ViewAdjust view_;
    SceneCamera camera_;
    int selected_ = -1;
    int width_ = 0, height_ = 0;
    std::optional<sema::ViewMode> viewOverride_;
    std::optional<bool> overlayOverride_;

    ViewClock clock_;
    uint64_t version_ = 1;
    bool interactive_ = false;
    bool redraw_ = false;

    int drag_ = -1; // the button held, -1 none
    Vec2 pressAt_, lastAt_;
    bool moved_ = false;
    uint64_t pickWanted_ = 0, picks_ = 0; // the click whose answer would be taken; clicks so far
};

} // namespace moire::view

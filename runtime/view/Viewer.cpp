// The window around ViewState: GLFW's events in, the frame on screen out. What the hand does
// to the view is ViewState's; which layer a click picks is LayerPicker's, on its own thread;
// the pixels are FrameRenderer's, on its. What stays here is the window itself (opening it,
// the texture it shows), when to ask for a frame, and the terminal's lines.
#include "runtime/view/Viewer.h"

#include "compiler/Compile.h"
#include "compiler/sema/Properties.h"
#include "runtime/live/SceneReloader.h"
#include "runtime/TextFile.h"
#include "runtime/view/FrameRenderer.h"
#include "runtime/view/LayerPicker.h"
#include "runtime/view/Overlay.h"
#include "runtime/view/ParamBinding.h"
#include "runtime/view/ParamPanel.h"
#include "runtime/view/ViewState.h"
#include "runtime/view/WindowCanvas.h"

#define GLFW_INCLUDE_NONE
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <memory>
#include <mutex>
#include <new>
#include <optional>

namespace moire::view {

namespace {

using Clock = std::chrono::steady_clock;

constexpr double kPlayInterval = 1.0 / 60.0; // the fastest the clock's frames are asked for
// While the clock plays over a picture that does not move (its uniforms came back the same),
// only the status line's t changes: ten frames a second are enough for that.
constexpr double kStillInterval = 1.0 / 10.0;

std::string glfwLastError;

// Ctrl-C in the terminal closes the window as `q` does: the handler only records the signal,
// the loop (which wakes at least twice a second) sees it, and the render thread finishes the
// still it may be writing before the process ends.
class StopSignals {
  public:
    static inline volatile std::sig_atomic_t requested = 0;
    StopSignals() {
        struct sigaction sa {};
        sa.sa_handler = [](int) { requested = 1; };
        sigemptyset(&sa.sa_mask);
        for (int i = 0; i < 2; ++i) {
            sigaction(kSignals[i], nullptr, &old_[i]);
            if (old_[i].sa_handler != SIG_IGN) sigaction(kSignals[i], &sa, nullptr);
        }
    }
    ~StopSignals() {
        for (int i = 0; i < 2; ++i) sigaction(kSignals[i], &old_[i], nullptr);
    }

  private:
    static constexpr int kSignals[2] = {SIGINT, SIGTERM};
    struct sigaction old_[2];
};

void onGlfwError(int, const char* description) {
    glfwLastError = description ? description : "";
}

class Viewer {
  public:
    Viewer(Backend& backend, const ViewerOptions& options)
        : backend_(backend), options_(options),
          state_(options.time, !options.paused, Clock::now()) {}

    ~Viewer() {
        // The reloader's, the picker's and the renderer's threads call back into this
        // object: stop them before anything they touch goes.
        if (reloader_) reloader_->stop();
        picker_.reset();
        renderer_.reset();
        panel_.reset(); // its GL objects go with the context
        if (window_) {
            if (texture_) glDeleteTextures(1, &texture_);
            glfwDestroyWindow(window_);
        }
        if (glfwUp_) glfwTerminate();
    }

    int run() {
        if (!loadScene()) return 1;
        if (!openWindow()) return 1;
        renderer_ = std::make_unique<FrameRenderer>(options_.threads, [] { glfwPostEmptyEvent(); });
        picker_ = std::make_unique<LayerPicker>([] { glfwPostEmptyEvent(); });
        startReloader();
        state_.restartClock(Clock::now());
        StopSignals signals;
        while (!glfwWindowShouldClose(window_) && !StopSignals::requested) {
            guard([&] { step(); });
            // The panel settling a press or following a held slider wants frames too.
            const bool panel = panel_ && panel_->busy();
            glfwWaitEventsTimeout(panel ? kPlayInterval : state_.playing() ? playInterval() : 0.5);
        }
        return 0;
    }

  private:
    // GLFW calls back through C: nothing may be thrown across it, and no scene, however
    // broken, may take the window down. A failure is reported and the viewer goes on.
    template <class F>
    void guard(F&& f) {
        try {
            f();
        } catch (const std::bad_alloc&) {
            fmt::print(stderr, "moire: error: out of memory\n");
            frameError_ = "moire: error: out of memory";
            redraw_ = true;
        } catch (const std::exception& e) {
            fmt::print(stderr, "moire: error: {}\n", e.what());
            frameError_ = std::string("moire: error: ") + e.what();
            redraw_ = true;
        }
    }

    void startReloader() {
        if (!reloader_) return;
        reloader_->start([this](const BuildResult& ev) {
            {
                std::lock_guard<std::mutex> lock(reloadMutex_);
                reloads_.push_back(ev);
            }
            glfwPostEmptyEvent();
        });
    }

    // `e`, `v`, `o`: the view and the overlay are structure, so the scene is built again with
    // what the state now asks for, and the reloader goes on with it.
    void switchView(void (ViewState::*toggle)()) {
        (state_.*toggle)();
        if (reloader_) reloader_->stop();
        reloader_.reset();
        builder_.reset();
        if (loadScene()) startReloader();
        redraw_ = true;
    }

    // --- Setting up ---------------------------------------------------------------------

    bool loadScene() {
        CompileOptions compile;
        compile.mode = CompileOptions::Mode::Interactive;
        compile.view = state_.viewOverride();
        compile.overlay = state_.overlayOverride();
        compile.defines = options_.defines;
        compile.filter = options_.filter;
        BuildResult first;
        if (options_.scenePath.empty()) {
            builder_ = std::make_unique<SceneBuilder>(backend_, compile);
            EmbeddedScene d = defaultScene();
            first = builder_->build(d.path, d.text);
        } else {
            std::string text, reason;
            if (!readWholeFile(options_.scenePath, text, reason)) {
                fmt::print(stderr, "moire: error: cannot read '{}': {}\n", options_.scenePath,
                           reason);
                return false;
            }
            SceneReloader::Options ro;
            ro.compile = compile;
            ro.watch.debounce = std::chrono::milliseconds(options_.debounceMs);
            try {
                reloader_ =
                    std::make_unique<SceneReloader>(options_.scenePath, backend_, std::move(ro));
            } catch (const std::exception& e) {
                fmt::print(stderr, "moire: error: {}\n", e.what());
                return false;
            }
            first = reloader_->loadNow();
        }
        // A scene with errors still opens: the window shows them until a save fixes them.
        state_.reloaded(first);
        if (!first.good()) fmt::print(stderr, "{}", first.diagnostics);
        return true;
    }

    bool openWindow() {
        glfwSetErrorCallback(onGlfwError);
        if (!glfwInit()) {
            fmt::print(stderr,
                       "moire: error: cannot open a window: {}\n"
                       "moire: note: without a display, 'moire watch SCENE -o IMAGE' keeps an "
                       "image up to date instead\n",
                       glfwLastError.empty() ? "no display" : glfwLastError);
            return false;
        }
        glfwUp_ = true;
        int w = options_.width, h = options_.height;
        if (w <= 0 || h <= 0) {
            w = static_cast<int>(sema::kDefaultWidth), h = static_cast<int>(sema::kDefaultHeight);
            if (auto size = state_.sceneSize(Clock::now())) std::tie(w, h) = *size;
            // A scene larger than the screen opens at the most of it that fits, same aspect.
            int mx = 0, my = 0, mw = 0, mh = 0;
            if (GLFWmonitor* m = glfwGetPrimaryMonitor())
                glfwGetMonitorWorkarea(m, &mx, &my, &mw, &mh);
            if (mw > 0 && mh > 0) {
                const double s = std::min({1.0, 0.9 * mw / w, 0.9 * mh / h});
                w = std::max(1, static_cast<int>(w * s)), h = std::max(1, static_cast<int>(h * s));
            }
        }
        glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_API);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 2);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 1);
        glfwWindowHint(GLFW_SCALE_TO_MONITOR, GLFW_TRUE); // screen units on high-DPI screens
        const std::string name =
            options_.scenePath.empty()
                ? std::string("default scene")
                : std::filesystem::path(options_.scenePath).filename().string();
        window_ = glfwCreateWindow(w, h, (name + " - moire view").c_str(), nullptr, nullptr);
        if (!window_) {
            fmt::print(stderr, "moire: error: cannot open a window: {}\n", glfwLastError);
            return false;
        }
        glfwMakeContextCurrent(window_);
        glfwSwapInterval(1);
        glfwSetWindowUserPointer(window_, this);
        int fbW = 0, fbH = 0;
        glfwGetFramebufferSize(window_, &fbW, &fbH);
        state_.resize(fbW, fbH);
        glfwGetCursorPos(window_, &cursorX_, &cursorY_);
        panel_ = std::make_unique<ParamPanel>(window_);
        installCallbacks();

        glGenTextures(1, &texture_);
        glBindTexture(GL_TEXTURE_2D, texture_);
        // One texel per framebuffer pixel, never filtered: the window shows the render's bytes.
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTexEnvi(GL_TEXTURE_ENV, GL_TEXTURE_ENV_MODE, GL_REPLACE);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glDisable(GL_DITHER);
        glDisable(GL_BLEND);
        glDisable(GL_DEPTH_TEST);
        redraw_ = true;
        return true;
    }

    static Viewer& of(GLFWwindow* w) { return *static_cast<Viewer*>(glfwGetWindowUserPointer(w)); }

    void installCallbacks() {
        // The panel sees each event first; what it takes (a press on it and that press's
        // release, the wheel over it, keys while typing into a field) the picture never sees.
        glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int scancode, int action, int mods) {
            Viewer& v = of(w);
            v.panel_->key(key, scancode, action, mods);
            if (!v.panel_->typing()) v.guard([&] { v.onKey(key, action, mods); });
        });
        glfwSetCharCallback(window_, [](GLFWwindow* w, unsigned c) { of(w).panel_->character(c); });
        glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
            Viewer& v = of(w);
            if (v.panel_->mouseButton(button, action, mods, v.cursorX_, v.cursorY_)) return;
            v.guard([&] { v.onButton(button, action); });
        });
        glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
            Viewer& v = of(w);
            v.panel_->cursorMoved(x, y);
            v.guard([&] { v.onCursor(x, y); });
        });
        glfwSetScrollCallback(window_, [](GLFWwindow* w, double dx, double dy) {
            Viewer& v = of(w);
            if (v.panel_->scroll(dx, dy, v.cursorX_, v.cursorY_)) return;
            v.guard([&] { v.state_.scroll(dy, v.cursor(), Clock::now()); });
        });
        glfwSetCursorEnterCallback(window_,
                                   [](GLFWwindow* w, int in) { of(w).panel_->cursorEnter(in); });
        glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int in) { of(w).panel_->focus(in); });
        glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int width, int height) {
            of(w).state_.resize(width, height);
        });
        glfwSetWindowRefreshCallback(window_, [](GLFWwindow* w) { of(w).redraw_ = true; });
        glfwSetWindowContentScaleCallback(
            window_, [](GLFWwindow* w, float, float) { of(w).redraw_ = true; });
    }

    // --- The loop -----------------------------------------------------------------------

    void step() {
        applyReloads();
        for (const std::string& m : renderer_->takeMessages()) {
            const bool error = m.rfind("moire: error", 0) == 0;
            fmt::print(error ? stderr : stdout, "{}\n", m);
            std::fflush(stdout);
        }
        while (std::optional<PickResult> p = picker_->take()) state_.picked(*p);
        if (std::optional<RenderedFrame> f = renderer_->takeFrame()) accept(std::move(*f));
        if (state_.takeRedraw()) redraw_ = true;
        if (panel_->busy()) redraw_ = true;
        if (redraw_) present();
        applyPanel();
        schedule();
    }

    void applyReloads() {
        std::vector<BuildResult> events;
        {
            std::lock_guard<std::mutex> lock(reloadMutex_);
            events.swap(reloads_);
        }
        for (const BuildResult& ev : events) {
            state_.reloaded(ev);
            if (ev.good())
                fmt::print(stderr, "moire: reloaded ({}, {:.0f} ms)\n",
                           ev.kind == BuildResult::Kind::Numbers ? "numbers only" : "recompiled",
                           ev.frontEndMs + ev.kernelMs);
            else
                fmt::print(stderr, "{}", ev.diagnostics);
        }
    }

    // Asks for a frame when the picture changed, or when the clock runs and the last frame
    // is done (never more often than kPlayInterval).
    double playInterval() const { return still_ ? kStillInterval : kPlayInterval; }

    void schedule() {
        if (!state_.build()) return;
        if (state_.playing() && state_.version() == submitted_ && !renderer_->busy() &&
            Clock::now() - lastSubmit_ >= std::chrono::duration<double>(playInterval()))
            state_.changed(false);
        if (state_.version() == submitted_) return;
        RenderJob j = state_.job(Clock::now());
        state_.submitted(j);
        submitted_ = j.version;
        renderer_->submit(std::move(j));
        lastSubmit_ = Clock::now();
    }

    void accept(RenderedFrame&& f) {
        redraw_ = true;
        if (!f.error.empty()) {
            frameError_ = f.error; // the last good frame stays under it
            return;
        }
        frameError_.clear();
        if (f.divisor == 1) lastFullMs_ = f.ms;
        still_ = f.reused;
        shown_ = std::move(f);
    }

    // --- Drawing ------------------------------------------------------------------------

    void present() {
        redraw_ = false;
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_, &w, &h);
        if (w <= 0 || h <= 0) return; // minimised
        // `h` hides the status line; errors always show, so a broken save is never missed.
        OverlayText text;
        const RenderedFrame* shown = shown_ ? &*shown_ : nullptr;
        if (overlay_)
            text.status =
                state_.statusLine(Clock::now(), shown, lastFullMs_, options_.backendLabel);
        const std::string& errors =
            state_.buildErrors().empty() ? frameError_ : state_.buildErrors();
        if (!errors.empty()) text.errorLines = errorLines(errors);
        composeWindow(shown, w, h, text, textScale(), canvas_);

        glViewport(0, 0, w, h);
        glMatrixMode(GL_PROJECTION);
        glLoadIdentity();
        glOrtho(0.0, 1.0, 1.0, 0.0, -1.0, 1.0); // (0, 0) top left, like the image's rows
        glMatrixMode(GL_MODELVIEW);
        glLoadIdentity();
        glEnable(GL_TEXTURE_2D);
        glBindTexture(GL_TEXTURE_2D, texture_);
        if (w != texW_ || h != texH_) {
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                         canvas_.data());
            texW_ = w, texH_ = h;
        } else {
            glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE,
                            canvas_.data());
        }
        glBegin(GL_QUADS);
        glTexCoord2f(0, 0), glVertex2f(0, 0);
        glTexCoord2f(1, 0), glVertex2f(1, 0);
        glTexCoord2f(1, 1), glVertex2f(1, 1);
        glTexCoord2f(0, 1), glVertex2f(0, 1);
        glEnd();
        glDisable(GL_TEXTURE_2D);
        if (panel_->visible())
            panelActions_ = panel_->draw(panelModel(state_, Clock::now(), panelStatus_),
                                         static_cast<float>(textScale()));
        glfwSwapBuffers(window_);
        glFinish();
        if (options_.trace && shown_) {
            ++presented_;
            fmt::print("frame {} {}x{} t={:.4f} {} v={}\n", presented_, shown_->width,
                       shown_->height, shown_->time, shown_->divisor > 1 ? "preview" : "full",
                       shown_->version);
            std::fflush(stdout);
        }
    }

    int textScale() const {
        float xs = 1, ys = 1;
        glfwGetWindowContentScale(window_, &xs, &ys);
        return std::max(1, static_cast<int>(std::lround(std::max(xs, ys))));
    }

    // --- Input --------------------------------------------------------------------------

    // Framebuffer pixels per screen unit (more than 1 on a high-DPI screen).
    double pixelsPerUnit() const {
        int ww = 1, wh = 1;
        glfwGetWindowSize(window_, &ww, &wh);
        return static_cast<double>(state_.width()) / std::max(ww, 1);
    }

    // A cursor position (screen units) as a framebuffer position, in the image's pixels.
    Vec2 toPixels(double x, double y) const {
        int ww = 1, wh = 1;
        glfwGetWindowSize(window_, &ww, &wh);
        return {x * state_.width() / std::max(ww, 1), y * state_.height() / std::max(wh, 1)};
    }

    // Where the cursor was as of the last event handled. glfwGetCursorPos asks the X server
    // where the pointer is now, which during a quick gesture is already events ahead: a press
    // would land where the drag ends.
    Vec2 cursor() const { return toPixels(cursorX_, cursorY_); }

    void onKey(int key, int action, int mods) {
        if (action == GLFW_RELEASE) return;
        const bool repeat = action == GLFW_REPEAT;
        const bool shift = mods & GLFW_MOD_SHIFT;
        const Clock::time_point now = Clock::now();
        if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) return state_.select(key - GLFW_KEY_1);
        if (key >= GLFW_KEY_KP_1 && key <= GLFW_KEY_KP_9) return state_.select(key - GLFW_KEY_KP_1);
        switch (key) {
        case GLFW_KEY_0:
        case GLFW_KEY_KP_0:
        case GLFW_KEY_ESCAPE:
            return state_.select(-1);
        case GLFW_KEY_SPACE:
            if (!repeat) state_.togglePlay(now);
            return;
        case GLFW_KEY_PERIOD:
        case GLFW_KEY_COMMA:
            return state_.stepFrames(key == GLFW_KEY_PERIOD ? 1 : -1, now);
        case GLFW_KEY_RIGHT:
        case GLFW_KEY_LEFT:
            return state_.skip((key == GLFW_KEY_RIGHT ? 1 : -1) * (shift ? 0.1 : 1.0), now);
        case GLFW_KEY_R:
            return state_.resetView();
        case GLFW_KEY_S:
            if (!repeat && state_.build()) {
                RenderJob j = state_.job(now);
                j.interactive = false;
                renderer_->saveStill(std::move(j), options_.scenePath);
            }
            return;
        case GLFW_KEY_P:
            if (!repeat && state_.build()) {
                fmt::print("{}", state_.placementReport(now));
                if (options_.trace) fmt::print("placed v={}\n", state_.version());
                std::fflush(stdout);
            }
            return;
        case GLFW_KEY_W: // shift: the panel's values; else the placement
            if (!repeat) shift ? writeParams() : writePlacement();
            return;
        case GLFW_KEY_TAB: // the parameter panel
            if (!repeat) panel_->toggle();
            redraw_ = true;
            return;
        case GLFW_KEY_H:
            overlay_ = !overlay_;
            redraw_ = true;
            return;
        case GLFW_KEY_Q:
            glfwSetWindowShouldClose(window_, GLFW_TRUE);
            return;
        case GLFW_KEY_E: // the envelope (§4.4)
            if (!repeat) switchView(&ViewState::toggleEnvelope);
            return;
        case GLFW_KEY_V: // the ratio view (§4.2)
            if (!repeat) switchView(&ViewState::toggleRatio);
            return;
        case GLFW_KEY_O: // the fringe overlay (Fig. 5d)
            if (!repeat) switchView(&ViewState::toggleOverlay);
            return;
        default:
            return;
        }
    }

    void onButton(int button, int action) {
        if (action == GLFW_PRESS) return state_.press(button, cursor());
        if (action != GLFW_RELEASE) return;
        if (std::optional<PickRequest> pick = state_.release(button, Clock::now()))
            picker_->request(std::move(*pick));
    }

    void onCursor(double x, double y) {
        cursorX_ = x, cursorY_ = y;
        if (!state_.dragging()) return;
        // Alt turns the layer about the world origin; Ctrl too, where the window manager
        // keeps alt-drag for itself.
        auto held = [&](int key) { return glfwGetKey(window_, key) == GLFW_PRESS; };
        const bool turn = held(GLFW_KEY_LEFT_ALT) || held(GLFW_KEY_RIGHT_ALT) ||
                          held(GLFW_KEY_LEFT_CONTROL) || held(GLFW_KEY_RIGHT_CONTROL);
        state_.cursorMoved(toPixels(x, y), turn, pixelsPerUnit(), Clock::now());
    }

    // What the hand did on the panel in the frame just drawn.
    void applyPanel() {
        PanelActions a = std::exchange(panelActions_, {});
        for (const std::string& line : view::applyPanel(state_, a, Clock::now()))
            if (options_.trace) fmt::print("{}\n", line);
        if (a.writeBack) writeParams();
        // For tests: where the panel's widgets are, whenever they move.
        if (options_.trace && panel_->items() != tracedItems_) {
            tracedItems_ = panel_->items();
            for (const PanelItem& i : tracedItems_)
                fmt::print("panel {} {:.0f} {:.0f} {:.0f} {:.0f}\n", i.name, i.x, i.y, i.w, i.h);
        }
        std::fflush(stdout);
    }

    // `W`: the panel's values into the scene file; the outcome also under the panel's buttons.
    void writeParams() {
        PlacementWrite r = state_.writeParams(options_.scenePath);
        if (!report(r, "parameters")) return;
        panelStatus_ = r.ok ? r.message : "cannot write: " + r.message;
        redraw_ = true;
    }

    void writePlacement() { report(state_.writePlacement(options_.scenePath), "placement"); }

    // A write's outcome on the terminal; false when there is nothing to say.
    static bool report(const PlacementWrite& r, const char* what) {
        if (r.message.empty()) return false;
        if (r.ok)
            fmt::print("{}\n", r.message);
        else
            fmt::print(stderr, "moire: error: cannot write the {}: {}\n", what, r.message);
        std::fflush(stdout);
        return true;
    }

    Backend& backend_;
    ViewerOptions options_;
    bool glfwUp_ = false;
    GLFWwindow* window_ = nullptr;
    GLuint texture_ = 0;
    int texW_ = 0, texH_ = 0;
    std::vector<uint8_t> canvas_;

    std::unique_ptr<SceneReloader> reloader_; // a scene file
    std::unique_ptr<SceneBuilder> builder_;   // the default scene
    std::unique_ptr<FrameRenderer> renderer_;
    std::unique_ptr<LayerPicker> picker_;
    std::unique_ptr<ParamPanel> panel_; // from the window's opening

    std::mutex reloadMutex_; // guards reloads_, filled on the reloader's thread
    std::vector<BuildResult> reloads_;

    // Everything below belongs to the window's thread.
    ViewState state_;
    std::string frameError_; // the last frame could not be drawn
    bool overlay_ = true;
    uint64_t submitted_ = 0; // the version of the last frame asked for
    Clock::time_point lastSubmit_{};
    std::optional<RenderedFrame> shown_;
    double lastFullMs_ = 0.0;
    bool still_ = false; // the last frame was the one before it (nothing moved)
    bool redraw_ = false;
    int presented_ = 0;
    PanelActions panelActions_;          // from the last draw, applied after it
    std::string panelStatus_;            // the last write-back's outcome
    std::vector<PanelItem> tracedItems_; // the panel's widgets as --trace last printed them
    double cursorX_ = 0, cursorY_ = 0;   // screen units, as of the last cursor event
};

} // namespace

int runViewer(Backend& backend, const ViewerOptions& options) {
    Viewer viewer(backend, options);
    return viewer.run();
}

} // namespace moire::view

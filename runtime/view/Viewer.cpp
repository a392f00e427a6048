#include "runtime/view/Viewer.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/live/SceneReloader.h"
#include "runtime/output/OutputFile.h"
#include "runtime/TextFile.h"
#include "runtime/view/FrameRenderer.h"
#include "runtime/view/Overlay.h"
#include "runtime/view/Placement.h"
#include "runtime/view/ViewCamera.h"
#include "runtime/view/ViewClock.h"

#define GLFW_INCLUDE_NONE
#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
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

constexpr double kStep = 1.0 / 30.0;         // `.` and `,`: one frame at 30 fps
constexpr double kWheelZoom = 1.1;           // per wheel notch
constexpr double kDragThreshold = 3.0;       // screen pixels before a press becomes a drag
constexpr double kPickTolerance = 4.0;       // pixels from a stroke's centre line that pick it
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

// The layers' names, for carrying the view's adjustments across a reload.
std::vector<std::string> layerNames(const SceneProgram& program) {
    std::vector<std::string> names;
    for (const sema::CheckedLayer& l : program.checked.layers) names.push_back(l.decl->name);
    return names;
}

class Viewer {
  public:
    Viewer(Backend& backend, const ViewerOptions& options)
        : backend_(backend), options_(options),
          clock_(options.time, !options.paused, Clock::now()) {}

    ~Viewer() {
        // The reloader's and the renderer's threads call back into this object: stop them
        // before anything they touch goes.
        if (reloader_) reloader_->stop();
        renderer_.reset();
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
        if (reloader_)
            reloader_->start([this](const BuildResult& ev) {
                {
                    std::lock_guard<std::mutex> lock(reloadMutex_);
                    reloads_.push_back(ev);
                }
                glfwPostEmptyEvent();
            });
        // The clock starts with the window, not with the compile before it.
        clock_.restart(Clock::now());
        StopSignals signals;
        while (!glfwWindowShouldClose(window_) && !StopSignals::requested) {
            guard([&] { step(); });
            glfwWaitEventsTimeout(clock_.playing() ? playInterval() : 0.5);
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

    // --- Setting up ---------------------------------------------------------------------

    bool loadScene() {
        CompileOptions compile;
        compile.interactive = true;
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
        if (first.good()) {
            adopt(first.build);
        } else {
            // A scene with errors still opens: the window shows them until a save fixes them.
            buildError_ = first.diagnostics;
            fmt::print(stderr, "{}", first.diagnostics);
        }
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
            w = 1200, h = 800;
            FrameValues fv;
            std::string diags;
            FrameRequest req;
            req.time = timeNow();
            if (build_ && evaluateFrame(*build_->program, req, fv, diags))
                w = fv.width, h = fv.height;
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
        glfwGetFramebufferSize(window_, &fbW_, &fbH_);
        glfwGetCursorPos(window_, &cursorX_, &cursorY_);
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
        glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int mods) {
            Viewer& v = of(w);
            v.guard([&] { v.onKey(key, action, mods); });
        });
        glfwSetMouseButtonCallback(window_, [](GLFWwindow* w, int button, int action, int mods) {
            Viewer& v = of(w);
            v.guard([&] { v.onButton(button, action, mods); });
        });
        glfwSetCursorPosCallback(window_, [](GLFWwindow* w, double x, double y) {
            Viewer& v = of(w);
            v.guard([&] { v.onCursor(x, y); });
        });
        glfwSetScrollCallback(window_, [](GLFWwindow* w, double, double dy) {
            Viewer& v = of(w);
            v.guard([&] { v.onScroll(dy); });
        });
        glfwSetFramebufferSizeCallback(window_, [](GLFWwindow* w, int width, int height) {
            Viewer& v = of(w);
            v.fbW_ = width, v.fbH_ = height;
            v.changed(true); // resizing by hand is a gesture: previews while it lasts
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
        if (std::optional<RenderedFrame> f = renderer_->takeFrame()) accept(std::move(*f));
        if (redraw_) present();
        schedule();
    }

    void applyReloads() {
        std::vector<BuildResult> events;
        {
            std::lock_guard<std::mutex> lock(reloadMutex_);
            events.swap(reloads_);
        }
        for (const BuildResult& ev : events) {
            if (ev.good()) {
                // The text `w` wrote holds the view's adjustments: they are the scene's now.
                if (placedText_ && sourceOf(*ev.build->program) == *placedText_) view_.reset();
                placedText_.reset();
                adopt(ev.build);
                buildError_.clear();
                const bool numbers = ev.kind == BuildResult::Kind::Numbers;
                fmt::print(stderr, "moire: reloaded ({}, {:.0f} ms)\n",
                           numbers ? "numbers only" : "recompiled", ev.frontEndMs + ev.kernelMs);
            } else {
                // The last good build stays on screen under the errors.
                buildError_ = ev.diagnostics;
                fmt::print(stderr, "{}", ev.diagnostics);
            }
            redraw_ = true;
        }
    }

    // Takes a new build, carrying the view's layer motions and the selection over by layer
    // name (by position for unnamed layers), so that an edit keeps the placement in hand.
    void adopt(std::shared_ptr<const LiveProgram> build) {
        std::vector<std::string> names = layerNames(*build->program);
        ViewAdjust next = view_;
        next.layers.clear();
        int selected = -1;
        for (int j = 0; j < static_cast<int>(names.size()); ++j) {
            int from = -1;
            for (int i = 0; i < static_cast<int>(names_.size()) && from < 0; ++i)
                if (names[j].empty() ? (i == j && names_[i].empty()) : names_[i] == names[j])
                    from = i;
            if (from < 0) continue;
            if (!view_.layer(from).identity()) next.layerRef(j) = view_.layer(from);
            if (from == selected_) selected = j;
        }
        view_ = std::move(next);
        selected_ = selected;
        names_ = std::move(names);
        build_ = std::move(build);
        probe_.reset();
        changed(false);
    }

    // Asks for a frame when the picture changed, or when the clock runs and the last frame
    // is done (never more often than kPlayInterval).
    double playInterval() const { return still_ ? kStillInterval : kPlayInterval; }

    void schedule() {
        if (!build_) return;
        if (clock_.playing() && version_ == submitted_ && !renderer_->busy() &&
            Clock::now() - lastSubmit_ >= std::chrono::duration<double>(playInterval()))
            ++version_;
        if (version_ == submitted_) return;
        RenderJob j = job();
        clock_.asked(j.time);
        renderer_->submit(std::move(j));
        submitted_ = version_;
        interactive_ = false;
        lastSubmit_ = Clock::now();
    }

    RenderJob job() const {
        RenderJob j;
        j.build = build_;
        j.view = view_;
        j.time = timeNow();
        j.width = fbW_;
        j.height = fbH_;
        j.interactive = interactive_;
        j.version = version_;
        return j;
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
        canvas_.assign(static_cast<size_t>(w) * h * 4, 0);
        if (shown_)
            blit(*shown_, w, h);
        else
            for (size_t i = 0; i < canvas_.size(); i += 4)
                canvas_[i] = 48, canvas_[i + 1] = 48, canvas_[i + 2] = 52, canvas_[i + 3] = 255;
        // `h` hides the status line; errors always show, so a broken save is never missed.
        OverlayText text;
        if (overlay_) text.status = statusLine();
        const std::string& errors = !buildError_.empty() ? buildError_ : frameError_;
        if (!errors.empty()) text.errorLines = errorLines(errors);
        Canvas canvas{canvas_.data(), w, h};
        drawOverlay(canvas, text, textScale());

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

    // The shown frame into the canvas: 1:1 when it is the window's size, block by block for a
    // preview of it, stretched while a resize waits for its frame.
    void blit(const RenderedFrame& f, int w, int h) {
        const bool preview = f.divisor > 1 && f.fullWidth == w && f.fullHeight == h;
        const int d = f.divisor;
        for (int y = 0; y < h; ++y) {
            const int sy =
                preview ? y / d : static_cast<int>(static_cast<int64_t>(y) * f.height / h);
            const uint8_t* src =
                f.rgba.data() + static_cast<size_t>(std::min(sy, f.height - 1)) * f.width * 4;
            uint8_t* dst = canvas_.data() + static_cast<size_t>(y) * w * 4;
            if (!preview && f.width == w) {
                std::memcpy(dst, src, static_cast<size_t>(w) * 4);
                continue;
            }
            for (int x = 0; x < w; ++x) {
                const int sx =
                    preview ? x / d : static_cast<int>(static_cast<int64_t>(x) * f.width / w);
                std::memcpy(dst + x * 4, src + std::min(sx, f.width - 1) * 4, 4);
            }
        }
        // The picture is opaque (straight alpha over nothing): the window has no backdrop.
        for (size_t i = 3; i < canvas_.size(); i += 4) canvas_[i] = 255;
    }

    int textScale() const {
        float xs = 1, ys = 1;
        glfwGetWindowContentScale(window_, &xs, &ys);
        return std::max(1, static_cast<int>(std::lround(std::max(xs, ys))));
    }

    // What matters most first, since a narrow window cuts the line's end: the clock, the
    // selection, then the frame time and the backend.
    std::string statusLine() const {
        std::string s = fmt::format("t={:.3f}", shown_ ? shown_->time : timeNow());
        if (!clock_.playing()) s += "  paused";
        if (selected_ >= 0) {
            s += fmt::format("  layer {}", selected_ + 1);
            if (!names_[selected_].empty()) s += " " + names_[selected_];
        }
        if (shown_ && shown_->divisor > 1) s += "  preview";
        return s + fmt::format("  {:.1f} ms  {}", lastFullMs_, options_.backendLabel);
    }

    // --- The clock ----------------------------------------------------------------------

    double timeNow() const { return clock_.at(Clock::now()); }

    void setTime(double t, bool interactive) {
        clock_.set(t, Clock::now());
        changed(interactive);
    }

    void togglePlay() {
        if (clock_.playing())
            clock_.pause(Clock::now());
        else
            clock_.play(Clock::now());
        redraw_ = true; // the status line says so
    }

    // The picture must be rendered again; `interactive` while a gesture is under way.
    void changed(bool interactive) {
        ++version_;
        interactive_ = interactive_ || interactive;
    }

    // --- Input --------------------------------------------------------------------------

    // A cursor position (screen units) as a framebuffer position, in the image's pixels.
    Vec2 toPixels(double x, double y) const {
        int ww = 1, wh = 1;
        glfwGetWindowSize(window_, &ww, &wh);
        return {x * fbW_ / std::max(ww, 1), y * fbH_ / std::max(wh, 1)};
    }

    // Where the cursor was as of the last event handled. glfwGetCursorPos asks the X server
    // where the pointer is now, which during a quick gesture is already events ahead: a press
    // would land where the drag ends.
    Vec2 cursor() const { return toPixels(cursorX_, cursorY_); }

    // The scene's own camera now (it may move with the clock).
    SceneCamera sceneCamera() {
        if (!build_) return camera_;
        FrameRequest req;
        req.time = timeNow();
        FrameValues fv;
        std::string diags;
        if (evaluateFrame(*build_->program, req, fv, diags)) camera_ = SceneCamera::from(fv);
        return camera_;
    }

    int numLayers() const { return static_cast<int>(names_.size()); }

    void select(int layer) {
        selected_ = layer >= 0 && layer < numLayers() ? layer : -1;
        redraw_ = true;
    }

    void onKey(int key, int action, int mods) {
        if (action == GLFW_RELEASE) return;
        const bool repeat = action == GLFW_REPEAT;
        const bool shift = mods & GLFW_MOD_SHIFT;
        if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) return select(key - GLFW_KEY_1);
        if (key >= GLFW_KEY_KP_1 && key <= GLFW_KEY_KP_9) return select(key - GLFW_KEY_KP_1);
        switch (key) {
        case GLFW_KEY_0:
        case GLFW_KEY_KP_0:
        case GLFW_KEY_ESCAPE:
            return select(-1);
        case GLFW_KEY_SPACE:
            if (!repeat) togglePlay();
            return;
        case GLFW_KEY_PERIOD:
        case GLFW_KEY_COMMA:
            clock_.step(key == GLFW_KEY_PERIOD ? kStep : -kStep, Clock::now());
            redraw_ = true;
            return changed(true);
        case GLFW_KEY_RIGHT:
        case GLFW_KEY_LEFT:
            return setTime(timeNow() + (key == GLFW_KEY_RIGHT ? 1 : -1) * (shift ? 0.1 : 1.0),
                           true);
        case GLFW_KEY_R:
            view_.reset();
            return changed(false);
        case GLFW_KEY_S:
            if (!repeat && build_) {
                RenderJob j = job();
                j.interactive = false;
                renderer_->saveStill(std::move(j), options_.scenePath);
            }
            return;
        case GLFW_KEY_P:
            if (!repeat) printPlacement();
            return;
        case GLFW_KEY_W:
            if (!repeat) writePlacement();
            return;
        case GLFW_KEY_H:
            overlay_ = !overlay_;
            redraw_ = true;
            return;
        case GLFW_KEY_Q:
            glfwSetWindowShouldClose(window_, GLFW_TRUE);
            return;
        // Views: the envelope and ratio views of §4.2 and §4.4 will toggle here ('e' and
        // 'v'), each a per-pixel evaluation at several index offsets, once the compiler
        // can build them.
        default:
            return;
        }
    }

    void onButton(int button, int action, int mods) {
        if (action == GLFW_PRESS) {
            if (drag_ >= 0) return;
            drag_ = button;
            pressAt_ = lastAt_ = cursor();
            moved_ = false;
            return;
        }
        if (action != GLFW_RELEASE || button != drag_) return;
        drag_ = -1;
        // A click (a press that never became a drag) on a stroke selects its layer.
        if (!moved_ && button == GLFW_MOUSE_BUTTON_LEFT) pick(pressAt_);
    }

    void onCursor(double x, double y) {
        cursorX_ = x, cursorY_ = y;
        if (drag_ < 0 || !build_) return;
        const Vec2 at = toPixels(x, y);
        if (!moved_) {
            int ww = 1, wh = 1;
            glfwGetWindowSize(window_, &ww, &wh);
            const double ratio = static_cast<double>(fbW_) / std::max(ww, 1);
            if (std::hypot(at.x - pressAt_.x, at.y - pressAt_.y) < kDragThreshold * ratio) return;
            moved_ = true;
        }
        const SceneCamera cam = sceneCamera();
        if (drag_ == GLFW_MOUSE_BUTTON_LEFT && selected_ >= 0) {
            // Alt turns the layer about the world origin; Ctrl too, where the window manager
            // keeps alt-drag for itself.
            const bool turn = glfwGetKey(window_, GLFW_KEY_LEFT_ALT) == GLFW_PRESS ||
                              glfwGetKey(window_, GLFW_KEY_RIGHT_ALT) == GLFW_PRESS ||
                              glfwGetKey(window_, GLFW_KEY_LEFT_CONTROL) == GLFW_PRESS ||
                              glfwGetKey(window_, GLFW_KEY_RIGHT_CONTROL) == GLFW_PRESS;
            if (turn)
                turnLayer(cam, view_, fbW_, fbH_, selected_, lastAt_, at);
            else
                moveLayer(cam, view_, fbW_, fbH_, selected_, lastAt_, at);
        } else {
            panDrag(cam, view_, fbW_, fbH_, lastAt_, at);
        }
        lastAt_ = at;
        changed(true);
    }

    void onScroll(double dy) {
        if (!build_ || dy == 0.0) return;
        zoomAbout(sceneCamera(), view_, fbW_, fbH_, cursor(), std::pow(kWheelZoom, dy));
        changed(true);
    }

    // Selects the layer whose stroke passes nearest the click (within kPickTolerance
    // pixels; the topmost on a tie), or none. Each layer's distance at the clicked pixel
    // comes from a second compile of the same text with the layers' fields as outputs,
    // evaluated there once by the interpreter, with the view's slots as they are.
    void pick(Vec2 at) {
        if (!build_) return;
        const SceneProgram& program = *build_->program;
        if (!probe_) {
            const SourceFile& src = program.sources->file(program.userModule().file);
            CompileOptions o;
            o.layerFields = true;
            o.interactive = true;
            CompileResult r = compileScene(src.path(), src.text(), o);
            if (!r.program) return;
            probe_ = std::move(r.program);
            probeKernel_ = std::make_unique<Interpreter>(probe_->kernel);
        }
        const int n = static_cast<int>(probe_->checked.layers.size());
        std::vector<double> literals = probe_->literals;
        view_.write(literals, probe_->viewSlot, n);
        FrameRequest req;
        req.time = timeNow();
        req.width = fbW_;
        req.height = fbH_;
        req.literals = &literals;
        FrameValues fv;
        std::string diags;
        if (!evaluateFrame(*probe_, req, fv, diags)) return;
        const std::vector<double> out = probeKernel_->atPixel(fv.uniforms, at.x, at.y, fbW_, fbH_);
        const double pixel = ViewCamera(SceneCamera::from(fv), view_, fbW_, fbH_).pixelSize();
        int best = -1;
        double bestDistance = kPickTolerance;
        for (int i = n - 1; i >= 0; --i) {
            const double d = std::fabs(out[probe_->layout.distanceSlot(i)]) / pixel;
            if (std::isfinite(d) && d < bestDistance) best = i, bestDistance = d;
        }
        select(best);
    }

    void printPlacement() {
        if (!build_) return;
        fmt::print("// placement at t = {:.3f} s: set these in the scene's blocks (w writes "
                   "them into the file)\n{}",
                   timeNow(), placementText(*build_->program, view_));
        if (options_.trace) fmt::print("placed v={}\n", version_);
        std::fflush(stdout);
    }

    static const std::string& sourceOf(const SceneProgram& program) {
        return program.sources->file(program.userModule().file).text();
    }

    // Writes the placement into the scene file (Placement.h: placedSource), atomically. The
    // view keeps its adjustments until the reload of the written text, which then carries
    // them itself: the picture never jumps.
    void writePlacement() {
        if (!build_) return;
        auto fail = [](const std::string& why) {
            fmt::print(stderr, "moire: error: cannot write the placement: {}\n", why);
        };
        if (options_.scenePath.empty())
            return fail("the default scene has no file (p prints the placement)");
        // The file must still be the text on screen: a save with errors, or one not yet
        // reloaded, is the user's newer work, never to be replaced by an older text.
        if (!buildError_.empty()) return fail("the file has errors; fix them first");
        const std::string& loaded = sourceOf(*build_->program);
        std::string now, why;
        if (!readWholeFile(options_.scenePath, now, why)) return fail(why);
        if (now != loaded) return fail("the file has changed since it was loaded; try again");
        std::string placed;
        if (!placedSource(*build_->program, view_, placed, why)) return fail(why);
        if (placed == loaded) {
            fmt::print("moire: the scene already has this placement\n");
        } else {
            try {
                writeFileAtomically(options_.scenePath, placed.data(), placed.size());
            } catch (const IoError& e) {
                return fail(e.what());
            }
            placedText_ = placed;
            fmt::print("moire: wrote the placement into {}\n", options_.scenePath);
        }
        std::fflush(stdout);
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

    std::mutex reloadMutex_; // guards reloads_, filled on the reloader's thread
    std::vector<BuildResult> reloads_;

    // Everything below belongs to the window's thread.
    std::shared_ptr<const LiveProgram> build_;
    std::vector<std::string> names_;      // build_'s layer names
    std::string buildError_;              // the file's diagnostics while it has errors
    std::string frameError_;              // the last frame could not be drawn
    std::unique_ptr<SceneProgram> probe_; // build_ with layer fields, for picking
    std::unique_ptr<Interpreter> probeKernel_;
    std::optional<std::string> placedText_; // what `w` last wrote, until its reload
    ViewAdjust view_;
    SceneCamera camera_;
    int selected_ = -1;
    bool overlay_ = true;

    ViewClock clock_;
    Clock::time_point lastSubmit_{};

    uint64_t version_ = 1, submitted_ = 0;
    bool interactive_ = false;
    int fbW_ = 0, fbH_ = 0;
    std::optional<RenderedFrame> shown_;
    double lastFullMs_ = 0.0;
    bool still_ = false; // the last frame was the one before it (nothing moved)
    bool redraw_ = false;
    int presented_ = 0;

    double cursorX_ = 0, cursorY_ = 0; // screen units, as of the last cursor event
    int drag_ = -1;                    // the button held, -1 none
    Vec2 pressAt_, lastAt_;
    bool moved_ = false;
};

} // namespace

int runViewer(Backend& backend, const ViewerOptions& options) {
    Viewer viewer(backend, options);
    return viewer.run();
}

} // namespace moire::view

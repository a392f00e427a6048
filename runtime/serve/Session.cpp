#include "runtime/serve/Session.h"

#include "compiler/sema/Views.h"
#include "runtime/FrameEval.h"
#include "runtime/serve/ParameterValues.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace moire::serve {

namespace {

using Clock = std::chrono::steady_clock;
using json = nlohmann::json;

// The clock's frames while it runs: at most this many a second are asked for.
constexpr auto kPlayInterval = std::chrono::milliseconds(33);

const char* buildKindName(BuildResult::Kind kind) {
    return kind == BuildResult::Kind::Numbers ? "numbers" : "structure";
}

void requireFinite(double v, const char* what) {
    if (!std::isfinite(v)) throw RequestError(fmt::format("{} must be a finite number", what));
}

} // namespace

Session::Session(Backend& backend, SessionOptions options)
    : backend_(backend), options_(std::move(options)),
      clock_(options_.time, !options_.paused, Clock::now()) {
    options_.compile.mode = CompileOptions::Mode::Interactive;
    width_ = options_.width;
    height_ = options_.height;
    SceneReloader::Options ro;
    ro.compile = options_.compile;
    ro.watch = options_.watch;
    reloader_ = std::make_unique<SceneReloader>(options_.scene, backend_, ro);
}

Session::~Session() {
    stop();
}

BuildResult Session::start() {
    worker_ = std::make_unique<FrameWorker>(options_.threads,
                                            [this](EncodedFrame f) { framed(std::move(f)); });
    BuildResult first = reloader_->loadNow();
    {
        std::lock_guard<std::mutex> lock(mutex_);
        clock_.restart(Clock::now()); // the clock starts with the page, not the compile
    }
    reloaded(first);
    reloader_->start([this](const BuildResult& r) {
        reloaded(r);
        if (options_.onReload) options_.onReload(r);
    });
    clockThread_ = std::thread([this] { tick(); });
    return first;
}

void Session::stop() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_) return;
        stopping_ = true;
    }
    clockWake_.notify_all();
    if (clockThread_.joinable()) clockThread_.join();
    {
        std::lock_guard<std::mutex> lock(rebuildMutex_);
        if (reloader_) reloader_->stop();
    }
    worker_.reset(); // finishes the frame in hand
    channel_.close();
}

// --- The scene ------------------------------------------------------------------------------

void Session::reloaded(const BuildResult& result) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (result.good()) {
        build_ = result.build;
        // A slider's value outlives a save while it still fits the declaration.
        for (auto it = parameterValues_.begin(); it != parameterValues_.end();) {
            bool fits = false;
            for (const Parameter& p : build_->program->parameters)
                if (p.name == it->first) fits = checkParameterValue(p, it->second).empty();
            it = fits ? std::next(it) : parameterValues_.erase(it);
        }
        buildKind_ = buildKindName(result.kind);
        kernelMs_ = result.kernelMs;
        buildErrors_.clear();
        changedLocked();
    } else if (result.kind == BuildResult::Kind::Failed) {
        // The last good build stays, and so does its picture, under the diagnostics.
        buildErrors_ = result.diagnostics;
        publishLocked();
    }
}

void Session::rebuild() {
    std::lock_guard<std::mutex> rebuilding(rebuildMutex_);
    CompileOptions compile = options_.compile;
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (stopping_) return;
        compile.view = viewOverride_;
        compile.overlay = overlayOverride_;
    }
    reloader_->stop();
    SceneReloader::Options ro;
    ro.compile = compile;
    ro.watch = options_.watch;
    reloader_ = std::make_unique<SceneReloader>(options_.scene, backend_, ro);
    reloaded(reloader_->loadNow());
    reloader_->start([this](const BuildResult& r) {
        reloaded(r);
        if (options_.onReload) options_.onReload(r);
    });
}

// --- Requests -------------------------------------------------------------------------------

uint64_t Session::resize(int width, int height) {
    if (width < 1 || height < 1 || width > kMaxFrameSide || height > kMaxFrameSide)
        throw RequestError(
            fmt::format("the frame's size must be 1 to {} pixels each way, not {}x{}",
                        kMaxFrameSide, width, height));
    std::lock_guard<std::mutex> lock(mutex_);
    if (options_.width > 0) return version_; // --size fixes it
    if (width == width_ && height == height_) return version_;
    width_ = width;
    height_ = height;
    return changedLocked();
}

uint64_t Session::setView(const std::string& name) {
    std::optional<sema::ViewMode> mode;
    if (name != "scene") {
        mode = sema::viewNamed(name);
        if (!mode)
            throw RequestError(fmt::format("unknown view '{}': the views are {}, or scene", name,
                                           sema::viewList()));
    }
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (viewOverride_ == mode) return version_;
        viewOverride_ = mode;
    }
    rebuild();
    return version();
}

uint64_t Session::setOverlay(std::optional<bool> overlay) {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        if (overlayOverride_ == overlay) return version_;
        overlayOverride_ = overlay;
    }
    rebuild();
    return version();
}

uint64_t Session::zoom(double x, double y, double factor) {
    requireFinite(x, "the zoom's x");
    requireFinite(y, "the zoom's y");
    requireFinite(factor, "the zoom factor");
    if (factor < 1.0 / kMaxZoomStep || factor > kMaxZoomStep)
        throw RequestError(fmt::format("the zoom factor must be from 1/{0} to {0}, not {1}",
                                       kMaxZoomStep, factor));
    std::lock_guard<std::mutex> lock(mutex_);
    if (width_ <= 0 || height_ <= 0) return version_;
    view::zoomAbout(sceneCameraLocked(), view_, width_, height_, {x, y}, factor);
    return changedLocked();
}

uint64_t Session::pan(double fromX, double fromY, double toX, double toY) {
    for (double v : {fromX, fromY, toX, toY}) requireFinite(v, "a pan's position");
    std::lock_guard<std::mutex> lock(mutex_);
    if (width_ <= 0 || height_ <= 0) return version_;
    view::panDrag(sceneCameraLocked(), view_, width_, height_, {fromX, fromY}, {toX, toY});
    return changedLocked();
}

uint64_t Session::resetView() {
    std::lock_guard<std::mutex> lock(mutex_);
    view_.reset();
    return changedLocked();
}

uint64_t Session::setParameter(const std::string& name, std::optional<std::vector<double>> value) {
    std::lock_guard<std::mutex> lock(mutex_);
    const Parameter* found = nullptr;
    if (build_)
        for (const Parameter& p : build_->program->parameters)
            if (p.name == name) found = &p;
    if (!found) {
        std::string names;
        if (build_)
            for (const Parameter& p : build_->program->parameters)
                names += (names.empty() ? "" : ", ") + p.name;
        throw RequestError(
            names.empty() ? fmt::format("unknown parameter '{}': the scene has none", name)
                          : fmt::format("unknown parameter '{}': the scene's are {}", name, names));
    }
    if (value) {
        if (std::string why = checkParameterValue(*found, *value); !why.empty())
            throw RequestError(why); // it names the parameter
        parameterValues_[name] = std::move(*value);
    } else {
        parameterValues_.erase(name);
    }
    return changedLocked();
}

std::optional<Parameter> Session::parameter(const std::string& name) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (build_)
        for (const Parameter& p : build_->program->parameters)
            if (p.name == name) return p;
    return std::nullopt;
}

std::string Session::parametersJson() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return parametersJsonLocked();
}

uint64_t Session::play() {
    std::lock_guard<std::mutex> lock(mutex_);
    clock_.play(Clock::now());
    clockWake_.notify_all();
    publishLocked();
    return version_;
}

uint64_t Session::pause() {
    std::lock_guard<std::mutex> lock(mutex_);
    clock_.pause(Clock::now());
    return changedLocked();
}

uint64_t Session::seek(double time) {
    requireFinite(time, "the time");
    std::lock_guard<std::mutex> lock(mutex_);
    clock_.set(time, Clock::now());
    return changedLocked();
}

// --- Frames ---------------------------------------------------------------------------------

uint64_t Session::changedLocked() {
    ++version_;
    if (worker_ && build_ && !stopping_) {
        const double t = clock_.at(Clock::now());
        clock_.asked(t);
        worker_->submit(jobLocked(t));
    }
    publishLocked();
    return version_;
}

FrameJob Session::jobLocked(double time) const {
    FrameJob job;
    job.build = build_;
    job.literals = build_->program->literals;
    view_.write(job.literals, build_->program->viewSlot,
                static_cast<int>(build_->program->checked.layers.size()));
    for (const Parameter& p : build_->program->parameters)
        if (auto it = parameterValues_.find(p.name); it != parameterValues_.end())
            setParameterValue(p, it->second, job.literals);
    job.time = time;
    job.width = width_;
    job.height = height_;
    job.version = version_;
    return job;
}

void Session::framed(EncodedFrame f) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!f.error.empty()) {
        frameError_ = f.error;
        // No picture: the last one stays under the message.
        shown_.version = f.version;
        publishLocked();
        return;
    }
    frameError_.clear();
    if (!f.reused || frames_.empty() || frames_.back().rgba != f.rgba) {
        frames_.push_back(Frame{nextFrameId_++, f.width, f.height, f.rgba});
        while (frames_.size() > kFramesKept) frames_.pop_front();
    }
    if (options_.width <= 0 && width_ <= 0) {
        // The scene's own size until the page says its own.
        width_ = f.width;
        height_ = f.height;
    }
    shown_ =
        Shown{frames_.back().id,      f.version, f.width, f.height, f.time, f.renderMs, f.reused,
              std::move(f.parameters)};
    publishLocked();
}

std::optional<Session::Frame> Session::frame(uint64_t id) const {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const Frame& f : frames_)
        if (f.id == id) return f;
    return std::nullopt;
}

std::shared_ptr<const std::vector<unsigned char>> Session::framePng(uint64_t id) const {
    std::optional<Frame> f = frame(id);
    if (!f) return nullptr;
    std::lock_guard<std::mutex> lock(pngMutex_);
    for (const auto& [pid, png] : pngs_)
        if (pid == id) return png;
    auto png = std::make_shared<const std::vector<unsigned char>>(
        encodeFramePng(f->width, f->height, *f->rgba));
    pngs_.emplace_back(id, png);
    while (pngs_.size() > kFramesKept) pngs_.pop_front();
    return png;
}

uint64_t Session::version() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return version_;
}

uint64_t Session::shownVersion() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return shown_.version;
}

view::SceneCamera Session::sceneCameraLocked() {
    if (build_) {
        FrameRequest req;
        req.time = clock_.at(Clock::now());
        FrameValues fv;
        std::string diags;
        if (evaluateFrame(*build_->program, req, fv, diags)) camera_ = view::SceneCamera::from(fv);
    }
    return camera_;
}

void Session::tick() {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!stopping_) {
        if (!clock_.playing()) {
            clockWake_.wait(lock, [&] { return stopping_ || clock_.playing(); });
            continue;
        }
        // While the clock runs, the next frame is asked for when the last is done: a slow
        // scene shows fewer frames a second rather than a growing lag.
        if (build_ && worker_ && worker_->idle()) {
            const double t = clock_.at(Clock::now());
            clock_.asked(t);
            worker_->submit(jobLocked(t));
        }
        clockWake_.wait_for(lock, kPlayInterval, [&] { return stopping_; });
    }
}

// --- The state ------------------------------------------------------------------------------

std::string Session::parametersJsonLocked() const {
    json list = json::array();
    if (!build_) return list.dump();
    const std::vector<Parameter>& params = build_->program->parameters;
    for (size_t i = 0; i < params.size(); ++i) {
        const Parameter& p = params[i];
        std::vector<double> value;
        auto set = parameterValues_.find(p.name);
        if (set != parameterValues_.end()) {
            value = set->second;
        } else if (i < shown_.parameters.size()) {
            value.assign(shown_.parameters[i].begin(),
                         shown_.parameters[i].begin() + std::min(p.components, 4));
        }
        list.push_back(parameterJson(p, value, set != parameterValues_.end()));
    }
    return list.dump(-1, ' ', false, json::error_handler_t::replace);
}

void Session::publishLocked() {
    channel_.publish(stateJsonLocked());
}

std::string Session::stateJson() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return stateJsonLocked();
}

std::string Session::stateJsonLocked() const {
    json state;
    state["version"] = version_;
    state["scene"] = options_.scene;
    state["backend"] = options_.backend;
    if (shown_.id > 0) {
        state["frame"] = {{"id", shown_.id},        {"version", shown_.version},
                          {"width", shown_.width},  {"height", shown_.height},
                          {"time", shown_.time},    {"renderMs", shown_.renderMs},
                          {"reused", shown_.reused}};
    } else {
        state["frame"] = nullptr;
    }
    state["shownVersion"] = shown_.version;
    state["errors"] = buildErrors_;
    state["frameError"] = frameError_;
    state["build"] = build_ ? json{{"kind", buildKind_}, {"kernelMs", kernelMs_}} : json(nullptr);
    json views = json::array();
    for (const sema::ViewName& v : sema::viewNames()) views.push_back(v.name);
    state["views"] = views;
    state["view"] = viewOverride_ ? sema::viewName(*viewOverride_) : "scene";
    state["shownView"] = build_ ? sema::viewName(build_->program->view) : "pattern";
    state["overlay"] = overlayOverride_ ? json(*overlayOverride_) : json(nullptr);
    state["playing"] = clock_.playing();
    state["time"] = clock_.at(Clock::now());
    state["zoom"] = view_.zoomFactor;
    state["size"] = {width_, height_};
    state["fixedSize"] = options_.width > 0;
    state["params"] = json::parse(parametersJsonLocked());
    // Diagnostics quote the scene, whose bytes need not be UTF-8.
    return state.dump(-1, ' ', false, json::error_handler_t::replace);
}

} // namespace moire::serve

#include "runtime/live/SceneReloader.h"

#include "runtime/TextFile.h"

#include <fmt/format.h>

namespace moire {

SceneReloader::SceneReloader(std::string path, Backend& backend, Options options)
    : path_(path), builder_(backend, options.compile), watch_(std::move(path), options.watch) {}

SceneReloader::~SceneReloader() {
    stop();
}

ReloadEvent SceneReloader::readAndBuild(std::chrono::steady_clock::time_point changedAt) {
    ReloadEvent ev;
    ev.changedAt = changedAt;
    std::string text, reason;
    if (readWholeFile(path_, text, reason))
        ev.result = builder_.build(path_, text);
    else
        ev.result = builder_.unreadable(
            fmt::format("{}: error: cannot read the scene: {}\n", path_, reason));
    if (ev.result.kind != BuildResult::Kind::Unchanged) ev.generation = ++generation_;
    return ev;
}

ReloadEvent SceneReloader::loadNow() {
    return readAndBuild(std::chrono::steady_clock::now());
}

void SceneReloader::start(std::function<void(const ReloadEvent&)> onEvent) {
    stop();
    onEvent_ = std::move(onEvent);
    stopping_ = false;
    thread_ = std::thread([this] { run(); });
}

void SceneReloader::stop() {
    if (!thread_.joinable()) return;
    stopping_ = true;
    watch_.interrupt();
    thread_.join();
}

void SceneReloader::run() {
    while (!stopping_) {
        FileWatch::Wait w = watch_.wait(std::chrono::milliseconds(1000));
        if (w == FileWatch::Wait::Interrupted || stopping_) break;
        if (w != FileWatch::Wait::Changed) continue;
        ReloadEvent ev = readAndBuild(watch_.firstEvent());
        if (ev.result.kind == BuildResult::Kind::Unchanged) continue;
        if (onEvent_) onEvent_(ev);
    }
}

} // namespace moire

#include "runtime/live/SceneReloader.h"

#include "runtime/TextFile.h"

#include <fmt/format.h>

namespace moire {

SceneReloader::SceneReloader(std::string path, Backend& backend, Options options)
    : path_(path), builder_(backend, options.compile), watch_(std::move(path), options.watch) {}

SceneReloader::~SceneReloader() {
    stop();
}

BuildResult SceneReloader::loadNow() {
    std::string text, reason;
    if (readWholeFile(path_, text, reason)) return builder_.build(path_, text);
    return builder_.unreadable(
        fmt::format("{}: error: cannot read the scene: {}\n", path_, reason));
}

void SceneReloader::start(std::function<void(const BuildResult&)> onEvent) {
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
        BuildResult ev = loadNow();
        if (ev.kind == BuildResult::Kind::Unchanged) continue;
        if (onEvent_) onEvent_(ev);
    }
}

} // namespace moire

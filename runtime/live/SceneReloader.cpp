#include "runtime/live/SceneReloader.h"

#include <cerrno>
#include <cstring>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <sys/stat.h>

namespace moire {

bool readWholeFile(const std::string& path, std::string& text, std::string& reason) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode)) {
        reason = "it is a directory";
        return false;
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        reason = std::strerror(errno);
        return false;
    }
    std::ostringstream ss;
    ss << in.rdbuf();
    if (in.bad()) {
        reason = "read failed";
        return false;
    }
    text = ss.str();
    return true;
}

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

#include "runtime/live/SceneBuilder.h"

#include "compiler/diag/Diagnostics.h"

#include <chrono>
#include <exception>
#include <fmt/format.h>
#include <vector>

namespace moire {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

uint64_t contentHash(const std::string& bytes) {
    uint64_t h = 0xcbf29ce484222325ull;
    for (unsigned char c : bytes) {
        h ^= c;
        h *= 0x100000001b3ull;
    }
    return h;
}

SceneBuilder::SceneBuilder(Backend& backend, CompileOptions options)
    : backend_(backend), options_(options) {}

BuildResult SceneBuilder::unreadable(const std::string& message) {
    BuildResult r;
    r.kind = BuildResult::Kind::Failed;
    r.unreadable = true;
    r.diagnostics = message;
    // Whatever comes back next is new, even the bytes that were there before.
    haveLast_ = false;
    return r;
}

BuildResult SceneBuilder::build(const std::string& path, const std::string& text) {
    BuildResult r;
    r.contentHash = contentHash(text);
    // Editors often save bytes that did not change (a save with no edit, a touch, the second
    // half of a truncate-then-write that restored the file): nothing to do.
    if (haveLast_ && r.contentHash == lastHash_) return r;
    haveLast_ = true;
    lastHash_ = r.contentHash;

    r.kind = BuildResult::Kind::Failed;
    auto t0 = std::chrono::steady_clock::now();
    std::unique_ptr<SceneProgram> program;
    try {
        ++frontEnd_;
        CompileResult c = compileScene(path, text, options_);
        r.diagnostics = std::move(c.diagnostics);
        program = std::move(c.program);
    } catch (const InternalError& e) {
        // A bug in moire, not in the scene; a live session must survive it all the same.
        r.diagnostics = fmt::format("{}: {}\n", path, e.what());
        return r;
    }
    r.frontEndMs = msSince(t0);
    if (!program) return r;

    auto build = std::make_shared<LiveProgram>();
    build->contentHash = r.contentHash;
    // Only the kernel's structure decides whether the backend must compile: numbers are
    // uniforms, computed by the frame program, which is interpreted every frame.
    if (current_ && current_->program->kernelHash == program->kernelHash) {
        build->kernel = current_->kernel;
        r.kind = BuildResult::Kind::Numbers;
    } else {
        auto t1 = std::chrono::steady_clock::now();
        try {
            ++kernels_;
            build->kernel = backend_.compile(program->kernel);
            // One pixel, here and now: a driver that finishes compiling at the first dispatch
            // (lavapipe builds its machine code then) does so on this thread rather than on
            // the render thread, which meanwhile keeps showing the last frame.
            std::vector<double> uniforms(static_cast<size_t>(program->numUniforms), 0.0);
            std::vector<float> pixel(static_cast<size_t>(build->kernel->numOutputs()));
            KernelFrame kf{uniforms.data(), 1, 1};
            build->kernel->runTile(kf, TileRect{0, 0, 1, 1}, pixel.data(), pixel.size());
        } catch (const std::exception& e) {
            r.diagnostics += fmt::format("{}: error: the {} backend failed: {}\n", path,
                                         backend_.name(), e.what());
            return r;
        }
        r.kernelMs = msSince(t1);
        r.kind = BuildResult::Kind::Structure;
    }
    build->program = std::move(program);
    current_ = build;
    r.build = std::move(build);
    return r;
}

} // namespace moire

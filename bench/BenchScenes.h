// The scenes the benchmarks measure: the embedded default scene and every example, or the
// files named on the command line.
#pragma once

#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/TextFile.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <malloc.h>
#include <string>
#include <vector>

namespace moire::bench {

struct Scene {
    std::string name, path, text;
    double time = 0.0; // the clock's time of the frame measured
};

// A scene file named by the user; exits with a message when it cannot be read.
inline Scene sceneFile(const std::string& path) {
    Scene s{std::filesystem::path(path).stem().string(), path, {}};
    std::string reason;
    if (!readWholeFile(path, s.text, reason)) {
        std::fprintf(stderr, "cannot read %s: %s\n", path.c_str(), reason.c_str());
        std::exit(2);
    }
    return s;
}

// The default scene, then examples/*.moire in name order.
inline std::vector<Scene> defaultScenes() {
    std::vector<Scene> out;
    EmbeddedScene d = defaultScene();
    out.push_back({"default", d.path, d.text});
    std::vector<std::string> paths;
    for (auto& e : std::filesystem::directory_iterator(MOIRE_SOURCE_DIR "/examples"))
        if (e.path().extension() == ".moire") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    for (const std::string& p : paths) out.push_back(sceneFile(p));
    return out;
}

// Reads the options every benchmark takes, --size WxH and --repeat N, at argv[i] (moving i
// past a value); false when argv[i] is neither.
inline bool sizeOrRepeat(int argc, char** argv, int& i, int& w, int& h, int& repeat) {
    std::string a = argv[i];
    if (a == "--size" && i + 1 < argc)
        std::sscanf(argv[++i], "%dx%d", &w, &h);
    else if (a == "--repeat" && i + 1 < argc)
        repeat = std::max(1, std::atoi(argv[++i]));
    else
        return false;
    return true;
}

// A scene compiled to its program, with its frame at t = 0 at width x height evaluated;
// exits with the diagnostics when either fails.
struct CompiledScene {
    std::unique_ptr<SceneProgram> program;
    FrameValues values;
    KernelFrame frame() const { return {values.uniforms.data(), values.width, values.height}; }
};
inline CompiledScene compileFrame(const Scene& s, int width, int height) {
    CompiledScene out;
    CompileResult r = compileScene(s.path, s.text);
    if (!r.program) {
        std::fprintf(stderr, "%s", r.diagnostics.c_str());
        std::exit(1);
    }
    out.program = std::move(r.program);
    FrameRequest req;
    req.width = width;
    req.height = height;
    std::string diags;
    if (!evaluateFrame(*out.program, req, out.values, diags)) {
        std::fprintf(stderr, "%s", diags.c_str());
        std::exit(1);
    }
    return out;
}

// The fastest of `repeat` renders of the frame, in seconds (other work on the machine can
// only add time).
inline double bestRender(const CompiledKernel& kernel, const KernelFrame& frame, int repeat) {
    // A 1080p frame of four floats is 33 MB, which malloc maps afresh for every frame and
    // unmaps on free: each frame would then pay 8,000 page faults as the kernel first writes
    // it (several milliseconds, and most of a light kernel's time). Taken from the heap and
    // kept there instead, every frame after the first reuses the same memory, and the time is
    // the kernel's.
    static const bool heapFrames = [] {
        mallopt(M_MMAP_THRESHOLD, 1 << 30);
        mallopt(M_TRIM_THRESHOLD, 1 << 30);
        return true;
    }();
    (void)heapFrames;
    double best = 1e30;
    for (int i = 0; i < repeat; ++i) {
        auto t0 = std::chrono::steady_clock::now();
        Image img = runKernel(kernel, frame);
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return best;
}

} // namespace moire::bench

// Edit-to-pixels latency of live coding: from the moment an editor writes the scene file to
// the moment the new frame's pixels exist, for an edit of numbers only (the kernel is reused,
// only uniforms change) and for a structural edit (a new kernel is compiled), on each backend
// side by side in one run.
//
//   build/bin/moire_live_bench [--scene FILE] [--size WxH] [--edits N] [--debounce MS]
//                              [--backends jit,vulkan]
//
// The path measured is the one `moire view` takes: the reload thread wakes on the file's
// change (after the debounce), reads and compiles the scene (SceneBuilder), and the frame is
// evaluated and rendered by the backend's kernel. Besides the full frame it times the quarter
// resolution preview the viewer shows first while a full frame is slower than ~50 ms.
// Structural edits raise one layer's phase term to a new whole power each time, so every one
// of them is a kernel the backend has never seen (no cache hit).
#include "bench/BenchScenes.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/live/SceneReloader.h"
#include "runtime/output/Render.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace moire;
using Clock = std::chrono::steady_clock;
namespace fs = std::filesystem;

namespace {

double ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

struct Sample {
    double detect = 0, build = 0, preview = 0, full = 0; // stage times
    double toPreview = 0, toFull = 0;                    // from the write
    bool compiled = false;
};

struct Stats {
    double median = 0, worst = 0;
};
Stats stats(std::vector<double> v) {
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    return {v[v.size() / 2], v.back()};
}

void writeFile(const std::string& path, const std::string& text) {
    int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || ::write(fd, text.data(), text.size()) != static_cast<ssize_t>(text.size())) {
        fmt::print(stderr, "cannot write {}\n", path);
        std::exit(1);
    }
    ::close(fd);
}

// The scene with edit i applied: numbers only, or a new structure each time.
std::string edited(const std::string& scene, int i, bool structural) {
    std::string t = scene;
    size_t at = t.find("stroke = ");
    if (at == std::string::npos) {
        fmt::print(stderr, "the scene needs a layer with a `stroke = ` line\n");
        std::exit(1);
    }
    size_t end = t.find_first_of(";\n}", at);
    std::string stroke = fmt::format("stroke = {:.3f}", 2.0 + 0.01 * (i % 40));
    if (structural)
        stroke += fmt::format("; phase = 0.001 * (x / 400)^{}", 2 + i); // a new powi chain
    return t.replace(at, end - at, stroke);
}

struct Run {
    std::vector<Sample> numbers, structure;
    std::string backend;
};

Run measure(const std::string& backendName, const std::string& sceneText, int w, int h, int edits,
            int debounceMs) {
    Run run;
    std::unique_ptr<Backend> backend = makeBackend(backendName);
    run.backend = backend->name();
    fs::path dir = fs::temp_directory_path() / fmt::format("moire-live-bench-{}", ::getpid());
    fs::create_directories(dir);
    std::string path = (dir / "live.moire").string();
    writeFile(path, edited(sceneText, 0, false));

    SceneReloader::Options options;
    options.compile.mode = CompileOptions::Mode::Interactive; // as the viewer compiles
    options.watch.debounce = std::chrono::milliseconds(debounceMs);
    SceneReloader reloader(path, *backend, options);
    if (!reloader.loadNow().good()) {
        fmt::print(stderr, "the scene does not compile\n");
        std::exit(1);
    }

    std::mutex m;
    std::condition_variable cv;
    bool ready = false;
    Sample current;
    Clock::time_point written;
    reloader.start([&](const BuildResult& ev) {
        Clock::time_point got = Clock::now();
        Sample s;
        s.detect = ms(written, got) - ev.frontEndMs - ev.kernelMs;
        s.build = ev.frontEndMs + ev.kernelMs;
        s.compiled = ev.kind == BuildResult::Kind::Structure;
        if (ev.good()) {
            const SceneProgram& p = *ev.build->program;
            auto render = [&](int rw, int rh) {
                FrameRequest req;
                req.width = rw;
                req.height = rh;
                FrameValues frame;
                std::string diags;
                evaluateFrame(p, req, frame, diags);
                KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
                runKernel(*ev.build->kernel, kf);
            };
            Clock::time_point t0 = Clock::now();
            render(std::max(1, w / 4), std::max(1, h / 4));
            Clock::time_point t1 = Clock::now();
            render(w, h);
            Clock::time_point t2 = Clock::now();
            s.preview = ms(t0, t1);
            s.full = ms(t1, t2);
            s.toPreview = ms(written, t1);
            s.toFull = ms(written, t1) + s.full;
        }
        std::lock_guard<std::mutex> lock(m);
        current = s;
        ready = true;
        cv.notify_all();
    });

    for (int round = 0; round < 2; ++round) {
        const bool structural = round == 1;
        for (int i = 1; i <= edits; ++i) {
            std::string text = edited(sceneText, i, structural);
            {
                std::lock_guard<std::mutex> lock(m);
                ready = false;
                written = Clock::now();
            }
            writeFile(path, text);
            std::unique_lock<std::mutex> lock(m);
            if (!cv.wait_for(lock, std::chrono::seconds(60), [&] { return ready; })) {
                fmt::print(stderr, "edit {} was not seen within a minute\n", i);
                std::exit(1);
            }
            (structural ? run.structure : run.numbers).push_back(current);
            lock.unlock();
            std::this_thread::sleep_for(std::chrono::milliseconds(20)); // an editor's pace
        }
    }
    reloader.stop();
    fs::remove_all(dir);
    return run;
}

void report(const Run& run, const char* what, const std::vector<Sample>& samples, double goal) {
    auto col = [&](double Sample::*field) {
        std::vector<double> v;
        for (const Sample& s : samples) v.push_back(s.*field);
        return stats(v);
    };
    Stats detect = col(&Sample::detect), build = col(&Sample::build),
          preview = col(&Sample::preview), full = col(&Sample::full),
          toPreview = col(&Sample::toPreview), toFull = col(&Sample::toFull);
    int compiled = 0;
    for (const Sample& s : samples) compiled += s.compiled;
    auto verdict = [&](double v) { return v < goal ? "met" : "not met"; };
    fmt::print("{:<8} {:<10} {:>3}/{:<3} {:>6.1f} {:>7.1f} {:>8.1f} {:>7.1f} | {:>7.1f} {:>7.1f} | "
               "{:>7.1f} {:>7.1f} | {:>3.0f} ms: preview {}, full {}\n",
               run.backend, what, compiled, samples.size(), detect.median, build.median,
               preview.median, full.median, toPreview.median, toPreview.worst, toFull.median,
               toFull.worst, goal, verdict(toPreview.median), verdict(toFull.median));
}

} // namespace

int main(int argc, char** argv) {
    std::string scenePath, size = "1280x720", backends = "jit,vulkan";
    int edits = 50, debounce = 30;
    for (int i = 1; i < argc; ++i) {
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        std::string a = argv[i];
        if (a == "--scene")
            scenePath = next();
        else if (a == "--size")
            size = next();
        else if (a == "--edits")
            edits = std::max(1, std::atoi(next().c_str()));
        else if (a == "--debounce")
            debounce = std::max(0, std::atoi(next().c_str()));
        else if (a == "--backends")
            backends = next();
        else {
            fmt::print(stderr, "usage: moire_live_bench [--scene FILE] [--size WxH] [--edits N] "
                               "[--debounce MS] [--backends jit,vulkan]\n");
            return 2;
        }
    }
    int w = 0, h = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &w, &h) != 2 || w < 4 || h < 4) {
        fmt::print(stderr, "bad --size '{}'\n", size);
        return 2;
    }
    std::string sceneText;
    if (scenePath.empty()) {
        sceneText = defaultScene().text;
    } else {
        sceneText = bench::sceneFile(scenePath).text;
    }

    fmt::print("edit-to-pixels, {} scene at {}x{}, {} edits of each kind, debounce {} ms, "
               "{} hardware threads\n",
               scenePath.empty() ? "default" : scenePath, w, h, edits, debounce,
               std::thread::hardware_concurrency());
    fmt::print("medians of each stage (ms), then from the write: median and worst (ms)\n");
    fmt::print("{:<8} {:<10} {:>7} {:>6} {:>7} {:>8} {:>7} | {:>15} | {:>15} | goal (median)\n",
               "backend", "edit", "kernels", "detect", "build", "preview", "full", "to preview",
               "to full frame");
    std::stringstream list(backends);
    std::string name;
    while (std::getline(list, name, ',')) {
        Run run;
        try {
            run = measure(name, sceneText, w, h, edits, debounce);
        } catch (const BackendError& e) {
            fmt::print("{:<8} skipped: {}\n", name, e.what());
            continue;
        }
        report(run, "numbers", run.numbers, 50);
        report(run, "structure", run.structure, 150);
    }
    return 0;
}

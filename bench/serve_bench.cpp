// Latency of the `moire serve` page: from a message or a save to the new picture on the page,
// over HTTP as the page sees it.
//
//   build/bin/moire_serve_bench [--size WxH] [--runs N] [--debounce MS]
//
// The server runs in this process on a free port of 127.0.0.1 (the Session and Server that
// `moire serve` runs), with the JIT, on a copy of the default scene with its clock stopped.
// A client follows the event stream (/api/events) as the page does. Each sample is timed
// from sending the request (or writing the file) to the end of fetching the bytes of the
// first frame whose version includes the change (/frame/ID.rgba, as the page does):
//   - a slider message: the default scene's two `spacing = 9` turned into one parameter
//     (`param gap = 9 in 5 .. 14 step 0.1`), moved by 0.1 and back; the kernel is kept,
//     only uniforms change;
//   - a structural save: the scene file written with one layer's phase term raised to a new
//     whole power, so each save is a kernel never compiled before (the JIT's disk cache is
//     turned off for the run). The figure includes the file watcher's debounce.
// Targets (issue 17): slider message under 100 ms, structural save under 300 ms, at 1280x720.
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/serve/Server.h"
#include "runtime/serve/Session.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <httplib.h>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <unistd.h>

using namespace moire;
using Clock = std::chrono::steady_clock;
using json = nlohmann::json;
namespace fs = std::filesystem;

namespace {

double ms(Clock::time_point a, Clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

// The event stream, as the page reads it: the newest state, and a wait for a version.
class Follower {
  public:
    Follower(int port, std::string token) : client_("127.0.0.1", port), token_(std::move(token)) {
        thread_ = std::thread([this] {
            std::string buffer;
            client_.Get("/api/events?token=" + token_, [&](const char* data, size_t n) {
                buffer.append(data, n);
                for (size_t end; (end = buffer.find("\n\n")) != std::string::npos;) {
                    std::string event = buffer.substr(0, end);
                    buffer.erase(0, end + 2);
                    size_t at = event.find("data: ");
                    if (at == std::string::npos) continue;
                    json s = json::parse(event.substr(at + 6));
                    {
                        std::lock_guard<std::mutex> lock(m_);
                        state_ = std::move(s);
                    }
                    cv_.notify_all();
                }
                return !stop_;
            });
        });
    }
    ~Follower() {
        stop_ = true;
        client_.stop();
        thread_.join();
    }
    // The first state showing version `v`'s frame.
    json waitShown(uint64_t v) {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [&] {
            return !state_.is_null() && !state_["frame"].is_null() &&
                   state_["shownVersion"].get<uint64_t>() >= v && state_["frameError"] == "";
        });
        return state_;
    }
    // The first state whose frame is not `id` and shows no errors.
    json waitNewFrame(uint64_t id) {
        std::unique_lock<std::mutex> lock(m_);
        cv_.wait(lock, [&] {
            return !state_.is_null() && !state_["frame"].is_null() &&
                   state_["frame"]["id"].get<uint64_t>() != id && state_["errors"] == "" &&
                   state_["shownVersion"] == state_["version"];
        });
        return state_;
    }

  private:
    httplib::Client client_;
    std::string token_;
    std::mutex m_;
    std::condition_variable cv_;
    json state_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

struct Sample {
    double total = 0, render = 0, kernel = 0;
};

void summary(const char* what, std::vector<Sample> s, double target) {
    std::sort(s.begin(), s.end(), [](auto& a, auto& b) { return a.total < b.total; });
    const Sample& med = s[s.size() / 2];
    fmt::print("{:<22} min {:7.1f}  median {:7.1f}  max {:7.1f} ms   (median's render {:.1f}, "
               "kernel compile {:.1f})   target < {:.0f} ms: {}\n",
               what, s.front().total, med.total, s.back().total, med.render, med.kernel, target,
               med.total < target ? "met" : "NOT met");
}

void writeFile(const std::string& path, const std::string& text) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// The default scene with edit i: a new structure each time (see live_bench).
std::string structural(const std::string& scene, int i) {
    std::string t = scene;
    size_t at = t.find("stroke = ");
    size_t end = t.find_first_of(";\n}", at);
    return t.replace(at, end - at,
                     fmt::format("stroke = 2.2; phase = 0.001 * (x / 400)^{}", 2 + i));
}

} // namespace

int main(int argc, char** argv) {
    int w = 1280, h = 720, runs = 15, debounce = 30;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--size") && i + 1 < argc)
            std::sscanf(argv[++i], "%dx%d", &w, &h);
        else if (!std::strcmp(argv[i], "--runs") && i + 1 < argc)
            runs = std::atoi(argv[++i]);
        else if (!std::strcmp(argv[i], "--debounce") && i + 1 < argc)
            debounce = std::atoi(argv[++i]);
        else {
            fmt::print(stderr,
                       "usage: moire_serve_bench [--size WxH] [--runs N] [--debounce MS]\n");
            return 2;
        }
    }
    setenv("MOIRE_CACHE_DIR", "off", 1); // every structural save compiles
    fs::path dir = fs::temp_directory_path() / fmt::format("moire-serve-bench-{}", ::getpid());
    fs::create_directories(dir);
    const std::string path = (dir / "scene.moire").string();
    // The default scene with its rings' spacing as a parameter, for the slider to move.
    std::string scene = "param gap = 9 in 5 .. 14 step 0.1\n" + defaultScene().text;
    for (size_t at; (at = scene.find("spacing = 9")) != std::string::npos;)
        scene.replace(at, 11, "spacing = gap");
    writeFile(path, scene);

    LlvmJitBackend jit;
    serve::SessionOptions options;
    options.scene = path;
    options.width = w;
    options.height = h;
    options.paused = true;
    options.watch.debounce = std::chrono::milliseconds(debounce);
    options.backend = "jit";
    serve::Session session(jit, options);
    if (!session.start().good()) {
        fmt::print(stderr, "the default scene does not compile\n");
        return 1;
    }
    serve::Server server(session, "bench");
    const int port = server.bind("127.0.0.1", 0);
    server.start();
    Follower follower(port, "bench");
    httplib::Client client("127.0.0.1", port);
    const std::string q = "?token=bench";
    auto fetchFrame = [&](const json& state) {
        auto r =
            client.Get(fmt::format("/frame/{}.rgba{}", state["frame"]["id"].get<uint64_t>(), q));
        if (!r || r->status != 200) {
            fmt::print(stderr, "cannot fetch the frame\n");
            std::exit(1);
        }
    };
    auto sampleOf = [](const json& state, Clock::time_point t0) {
        const json& f = state["frame"];
        return Sample{ms(t0, Clock::now()), f["renderMs"].get<double>(),
                      state["build"]["kernelMs"].get<double>()};
    };
    follower.waitShown(1);

    fmt::print("moire serve, {}x{}, the default scene, {} on {} threads; {} runs each\n", w, h,
               jit.name(), std::thread::hardware_concurrency(), runs);
    std::vector<Sample> sliders;
    for (int i = 0; i < runs + 1; ++i) {
        const auto t0 = Clock::now();
        // 9.1, then 9 again: the picture changes each time.
        auto r = client.Post("/api/param" + q,
                             fmt::format(R"({{"name": "gap", "value": {}}})", i % 2 ? 9.0 : 9.1),
                             "application/json");
        if (!r || r->status != 200) {
            fmt::print(stderr, "the message was refused: {}\n", r ? r->body : "no answer");
            return 1;
        }
        json state = follower.waitShown(json::parse(r->body)["version"].get<uint64_t>());
        fetchFrame(state);
        if (i > 0) sliders.push_back(sampleOf(state, t0)); // the first warms the caches
    }
    summary("slider message", sliders, 100);

    std::vector<Sample> saves;
    for (int i = 0; i < std::max(3, runs / 2); ++i) {
        const uint64_t id = json::parse(session.stateJson())["frame"]["id"].get<uint64_t>();
        const auto t0 = Clock::now();
        writeFile(path, structural(scene, i));
        json state = follower.waitNewFrame(id);
        fetchFrame(state);
        saves.push_back(sampleOf(state, t0));
    }
    summary("structural save", saves, 300);

    // What the page avoids by taking the bytes: a PNG of the frame, as /frame/ID.png makes it.
    const uint64_t id = json::parse(session.stateJson())["frame"]["id"].get<uint64_t>();
    std::optional<serve::Session::Frame> last = session.frame(id);
    std::vector<double> encodes;
    for (int i = 0; i < 5; ++i) {
        const auto t0 = Clock::now();
        serve::encodeFramePng(last->width, last->height, *last->rgba);
        encodes.push_back(ms(t0, Clock::now()));
    }
    std::sort(encodes.begin(), encodes.end());
    fmt::print("a PNG of that frame (zlib level 1, not on the page's path): median {:.1f} ms\n",
               encodes[encodes.size() / 2]);
    server.stop();
    session.stop();
    fs::remove_all(dir);
    return 0;
}

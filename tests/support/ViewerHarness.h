// Driving `moire view` in a virtual X server (Xvfb, whose screen is readable as an XWD file)
// with xdotool, for the viewer's integration tests: a child process, the server, the screen's
// pixels, a viewer started with `--trace` and what its trace says, and a session of the two.
// Tests skip (SKIP_WITHOUT_X) where Xvfb or xdotool is missing.
#pragma once

#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <poll.h>
#include <regex>
#include <spawn.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

extern char** environ;

namespace moire::test::xview {

namespace fs = std::filesystem;

using Clock = std::chrono::steady_clock;

inline bool haveTool(const char* name) {
    return test::runCommand(std::string("command -v ") + name).status == 0;
}

// A child process, stopped (SIGTERM, then SIGKILL) and reaped when the object goes, so that a
// failing test leaves nothing running. Its stdout can be read line by line.
class Process {
  public:
    Process(const std::vector<std::string>& argv, const std::vector<std::string>& env, bool pipeOut,
            const std::string& errPath) {
        int fds[2] = {-1, -1};
        if (pipeOut) REQUIRE(::pipe2(fds, O_CLOEXEC) == 0);
        posix_spawn_file_actions_t actions;
        posix_spawn_file_actions_init(&actions);
        if (pipeOut)
            posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
        else
            posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, 2, errPath.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                         0644);
        std::vector<std::string> envs = env;
        for (char** e = environ; *e; ++e) {
            std::string kv = *e, key = kv.substr(0, kv.find('='));
            bool replaced = false;
            for (const std::string& o : env) replaced |= o.substr(0, o.find('=')) == key;
            if (!replaced) envs.push_back(kv);
        }
        std::vector<char*> av, ev;
        for (const std::string& a : argv) av.push_back(const_cast<char*>(a.c_str()));
        av.push_back(nullptr);
        for (const std::string& e : envs) ev.push_back(const_cast<char*>(e.c_str()));
        ev.push_back(nullptr);
        int rc = posix_spawnp(&pid_, av[0], &actions, nullptr, av.data(), ev.data());
        posix_spawn_file_actions_destroy(&actions);
        if (pipeOut) {
            ::close(fds[1]);
            out_ = fds[0];
        }
        REQUIRE_MESSAGE(rc == 0, "cannot start ", argv[0], ": ", std::strerror(rc));
    }
    ~Process() {
        stop();
        if (out_ >= 0) ::close(out_);
    }

    bool alive() {
        if (pid_ <= 0) return false;
        int status = 0;
        pid_t r = ::waitpid(pid_, &status, WNOHANG);
        if (r == pid_) {
            status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
            pid_ = -1;
            return false;
        }
        return true;
    }
    // The exit status, or -1 when still running after `seconds`.
    int wait(double seconds) {
        auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (alive() && Clock::now() < end)
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        return alive() ? -1 : status_;
    }
    void stop() {
        if (!alive()) return;
        ::kill(pid_, SIGTERM);
        if (wait(3.0) < 0 && pid_ > 0) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
            pid_ = -1;
        }
    }
    // The next line of stdout, or nothing after `seconds` (or at the end of the stream).
    std::optional<std::string> readLine(double seconds) {
        auto end = Clock::now() + std::chrono::duration<double>(seconds);
        for (;;) {
            size_t nl = buffer_.find('\n');
            if (nl != std::string::npos) {
                std::string line = buffer_.substr(0, nl);
                buffer_.erase(0, nl + 1);
                return line;
            }
            auto left = std::chrono::duration_cast<std::chrono::milliseconds>(end - Clock::now());
            if (left.count() <= 0 || out_ < 0) return std::nullopt;
            pollfd p{out_, POLLIN, 0};
            if (::poll(&p, 1, static_cast<int>(left.count())) <= 0) continue;
            char chunk[4096];
            ssize_t n = ::read(out_, chunk, sizeof chunk);
            if (n <= 0) return std::nullopt;
            buffer_.append(chunk, static_cast<size_t>(n));
        }
    }

  private:
    pid_t pid_ = -1;
    int status_ = -1;
    int out_ = -1;
    std::string buffer_;
};

// An Xvfb server on the first free display from a per-process start, its screen mapped to
// an XWD file in `dir`.
class VirtualScreen {
  public:
    explicit VirtualScreen(const std::string& dir) {
        for (int n = 100 + ::getpid() % 400, tries = 0; tries < 30 && !server_; ++n, ++tries) {
            const std::string socket = "/tmp/.X11-unix/X" + std::to_string(n);
            if (fs::exists(socket) || fs::exists("/tmp/.X" + std::to_string(n) + "-lock")) continue;
            auto server = std::make_unique<Process>(
                std::vector<std::string>{"Xvfb", ":" + std::to_string(n), "-screen", "0",
                                         "640x480x24", "-fbdir", dir, "-nolisten", "tcp"},
                std::vector<std::string>{}, false, "/dev/null");
            auto end = Clock::now() + std::chrono::seconds(5);
            while (server->alive() && !fs::exists(socket) && Clock::now() < end)
                std::this_thread::sleep_for(std::chrono::milliseconds(20));
            if (server->alive() && fs::exists(socket)) {
                display_ = ":" + std::to_string(n);
                server_ = std::move(server);
            }
        }
        fbFile_ = dir + "/Xvfb_screen0";
    }
    bool ok() const { return server_ != nullptr; }
    const std::string& display() const { return display_; }
    const std::string& fbFile() const { return fbFile_; }
    // Runs xdotool on this display.
    std::string xdo(const std::string& args) const {
        test::CommandResult r =
            test::runCommand("DISPLAY=" + display_ + " timeout 10 xdotool " + args);
        INFO("xdotool ", args, ": ", r.err);
        CHECK(r.status == 0);
        return r.out;
    }

  private:
    std::unique_ptr<Process> server_;
    std::string display_, fbFile_;
};

// 8-bit RGB pixels, rows top to bottom.
struct Rgb {
    int width = 0, height = 0;
    std::vector<uint8_t> px;
    const uint8_t* at(int x, int y) const { return &px[(static_cast<size_t>(y) * width + x) * 3]; }
};

inline uint32_t be32(const std::string& d, size_t at) {
    return (uint32_t(uint8_t(d[at])) << 24) | (uint32_t(uint8_t(d[at + 1])) << 16) |
           (uint32_t(uint8_t(d[at + 2])) << 8) | uint32_t(uint8_t(d[at + 3]));
}

// The rectangle (x, y, w, h) of an XWD screen dump (X11/XWDFile.h: a header of big-endian
// 32-bit fields, the window name, the colour map, then the pixels in the server's order).
inline std::optional<Rgb> readScreen(const std::string& path, int x0, int y0, int w, int h) {
    std::string d;
    {
        std::ifstream in(path, std::ios::binary);
        if (!in) return std::nullopt;
        d.assign(std::istreambuf_iterator<char>(in), {});
    }
    if (d.size() < 100) return std::nullopt;
    const uint32_t headerSize = be32(d, 0), width = be32(d, 16), height = be32(d, 20);
    const uint32_t byteOrder = be32(d, 28), bitsPerPixel = be32(d, 44), bytesPerLine = be32(d, 48);
    const uint32_t masks[3] = {be32(d, 56), be32(d, 60), be32(d, 64)};
    const uint32_t colours = be32(d, 76);
    const size_t pixels = headerSize + size_t(colours) * 12;
    if (bitsPerPixel != 32 && bitsPerPixel != 24) return std::nullopt;
    if (x0 < 0 || y0 < 0 || x0 + w > int(width) || y0 + h > int(height)) return std::nullopt;
    if (d.size() < pixels + size_t(bytesPerLine) * height) return std::nullopt;
    Rgb out{w, h, std::vector<uint8_t>(size_t(w) * h * 3)};
    const int bytes = bitsPerPixel / 8;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t at = pixels + size_t(y0 + y) * bytesPerLine + size_t(x0 + x) * bytes;
            uint32_t v = 0;
            for (int b = 0; b < bytes; ++b) {
                const uint32_t byte = uint8_t(d[at + b]);
                v |= byteOrder == 0 ? byte << (8 * b) : byte << (8 * (bytes - 1 - b));
            }
            for (int c = 0; c < 3; ++c) {
                uint32_t m = masks[c];
                int shift = 0;
                while (m && !(m & 1)) m >>= 1, ++shift;
                out.px[(size_t(y) * w + x) * 3 + c] = uint8_t((v >> shift) & m);
            }
        }
    return out;
}

inline Rgb toRgb(const Image& img) {
    Rgb out{img.width, img.height, std::vector<uint8_t>(size_t(img.width) * img.height * 3)};
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            for (int c = 0; c < 3; ++c)
                out.px[(size_t(y) * img.width + x) * 3 + c] =
                    uint8_t(std::lround(std::clamp(img.at(x, y, c), 0.0f, 1.0f) * 255.0f));
    return out;
}

// Pixels (in rows [y0, y1)) where a channel differs by more than 1/255.
inline int differing(const Rgb& a, const Rgb& b, int y0 = 0, int y1 = 1 << 30) {
    REQUIRE(a.width == b.width);
    REQUIRE(a.height == b.height);
    int n = 0;
    for (int y = std::max(y0, 0); y < std::min(y1, a.height); ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 3; ++c)
                if (std::abs(int(a.at(x, y)[c]) - int(b.at(x, y)[c])) > 1) {
                    ++n;
                    break;
                }
    return n;
}

struct Placed {
    std::string text;
    uint64_t version = 0;
    double cx = 0, cy = 0, zoom = 0;
};

// A running `moire view --trace` and what its trace says.
class Viewer {
  public:
    Viewer(const test::TempDir& dir, const VirtualScreen& screen, const std::string& scene,
           bool paused = true, const std::string& size = "320x200",
           const std::vector<std::string>& extra = {})
        : dir_(dir), screen_(screen), errPath_(dir.file("view.err")),
          process_(commandLine(scene, paused, size, extra), {"DISPLAY=" + screen.display()}, true,
                   errPath_) {}

    // moire view on `scene` with the trace, the JIT and `extra` (more options, as given).
    static std::vector<std::string> commandLine(const std::string& scene, bool paused,
                                                const std::string& size,
                                                const std::vector<std::string>& extra) {
        std::vector<std::string> args{test::moireBinary(),
                                      "view",
                                      scene,
                                      "--size",
                                      size,
                                      paused ? "--paused" : "--time=0",
                                      "--trace",
                                      "--backend",
                                      "jit"};
        args.insert(args.end(), extra.begin(), extra.end());
        return args;
    }

    std::string stderrText() const {
        std::ifstream in(errPath_);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }

    // Reads lines until one satisfies `pred` (frame lines also update what was seen).
    std::optional<std::string> waitLine(const std::function<bool(const std::string&)>& pred,
                                        double seconds = 10.0) {
        auto end = Clock::now() + std::chrono::duration<double>(seconds);
        while (Clock::now() < end) {
            double left = std::chrono::duration<double>(end - Clock::now()).count();
            std::optional<std::string> line = process_.readLine(left);
            if (!line) return std::nullopt;
            lines_.push_back(*line);
            std::smatch m;
            if (std::regex_match(*line, m,
                                 std::regex(R"(frame (\d+) \d+x\d+ t=(\S+) (\w+) v=(\d+))"))) {
                frames_ = std::stoi(m[1]);
                time_ = std::stod(m[2]);
                if (m[3] == "full")
                    fullVersion_ = std::max<uint64_t>(fullVersion_, std::stoull(m[4]));
            }
            if (pred(*line)) return line;
        }
        return std::nullopt;
    }
    // Waits for a frame presented after the ones seen so far.
    bool nextFrame() {
        int seen = frames_;
        return waitLine([&](const std::string&) { return frames_ > seen; }).has_value();
    }
    // Waits until the full frame of state `version` (or a later one) is on screen.
    bool settled(uint64_t version) {
        if (fullVersion_ >= version) return true;
        return waitLine([&](const std::string&) { return fullVersion_ >= version; }).has_value();
    }
    bool firstFrame() {
        return waitLine([&](const std::string&) { return fullVersion_ > 0; }, 30.0).has_value();
    }
    uint64_t fullVersion() const { return fullVersion_; }
    // The clock time of the last frame presented.
    double shownTime() const { return time_; }
    int frames() const { return frames_; }

    // Presses `p` and reads the placement up to its `placed` line.
    Placed place() {
        size_t from = lines_.size();
        screen_.xdo("key p");
        auto done = waitLine([](const std::string& l) { return l.rfind("placed v=", 0) == 0; });
        REQUIRE_MESSAGE(done, "no placement; stderr:\n", stderrText());
        Placed p;
        for (size_t i = from; i + 1 < lines_.size(); ++i)
            if (lines_[i].rfind("frame ", 0) != 0) p.text += lines_[i] + "\n";
        p.version = std::stoull(done->substr(9));
        std::smatch m;
        REQUIRE(std::regex_search(
            p.text, m, std::regex(R"(center = \(([-\d.e]+), ([-\d.e]+)\); zoom = ([-\d.e]+);)")));
        p.cx = std::stod(m[1]), p.cy = std::stod(m[2]), p.zoom = std::stod(m[3]);
        return p;
    }

    Process& process() { return process_; }

  private:
    const test::TempDir& dir_;
    const VirtualScreen& screen_;
    std::string errPath_;
    Process process_;
    std::vector<std::string> lines_;
    int frames_ = 0;
    double time_ = 0.0;
    uint64_t fullVersion_ = 0;
};

// The window's top-left corner on the screen (a window of width x height).
inline std::pair<int, int> windowOrigin(const VirtualScreen& screen, int width = 320,
                                        int height = 200) {
    std::string out =
        screen.xdo("search --onlyvisible --name 'moire view' getwindowgeometry --shell");
    std::smatch x, y, w, h;
    REQUIRE(std::regex_search(out, x, std::regex(R"(X=(\d+))")));
    REQUIRE(std::regex_search(out, y, std::regex(R"(Y=(\d+))")));
    REQUIRE(std::regex_search(out, w, std::regex(R"(WIDTH=(\d+))")));
    REQUIRE(std::regex_search(out, h, std::regex(R"(HEIGHT=(\d+))")));
    CHECK(w[1] == std::to_string(width));
    CHECK(h[1] == std::to_string(height));
    return {std::stoi(x[1]), std::stoi(y[1])};
}

// `scene` as `moire render` draws it at `size` (with `extra` arguments, such as `-D x=1`).
inline Rgb offline(const test::TempDir& dir, const std::string& scene,
                   const std::string& size = "320x200", const std::string& extra = "") {
    static int n = 0;
    const std::string name = "offline" + std::to_string(n++);
    dir.write(name + ".moire", scene);
    auto r = test::runCommand("'" + test::moireBinary() + "' render '" + dir.file(name + ".moire") +
                              "' --size " + size + " -q --backend jit " + extra + " -o '" +
                              dir.file(name + ".png") + "'");
    INFO(r.err);
    REQUIRE(r.status == 0);
    return toRgb(readImage(dir.file(name + ".png")));
}

// The window's pixels once they match `expect` in rows [y0, y1) (the X server may show the
// frame a moment after the trace line), or as they are after a few seconds.
inline Rgb windowMatching(const VirtualScreen& screen, std::pair<int, int> origin,
                          const Rgb& expect, int y0 = 0, int y1 = 200) {
    auto end = Clock::now() + std::chrono::seconds(3);
    std::optional<Rgb> shot;
    for (;;) {
        shot =
            readScreen(screen.fbFile(), origin.first, origin.second, expect.width, expect.height);
        REQUIRE(shot);
        if (differing(*shot, expect, y0, y1) == 0 || Clock::now() > end) return *shot;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

#define SKIP_WITHOUT_X()                                                                           \
    if (!haveTool("Xvfb") || !haveTool("xdotool")) {                                               \
        test::skip("the viewer's tests need Xvfb and xdotool");                                    \
        return;                                                                                    \
    }

// Starts the viewer and waits for its first frame; false (with a message) when this machine
// cannot open a window at all (no GLX in the X server).
inline bool started(Viewer& viewer) {
    if (viewer.firstFrame()) return true;
    std::string err = viewer.stderrText();
    if (err.find("cannot open a window") != std::string::npos) {
        test::skip(err);
        return false;
    }
    FAIL("no frame from moire view; stderr:\n", err);
    return false;
}

// A viewer on a scene in an X server of its own, showing its first frame with the status line
// hidden (so that the window is the picture alone).
struct Session {
    test::TempDir dir{"view"};
    VirtualScreen screen{dir.path()};
    std::optional<Viewer> viewer;
    std::pair<int, int> origin;

    // False (with a message) when this machine cannot open a window.
    // `extra`: more options for moire view, as given.
    bool start(const std::string& scene, bool paused = true, int width = 320, int height = 200,
               const std::vector<std::string>& extra = {}) {
        REQUIRE_MESSAGE(screen.ok(), "Xvfb did not start");
        dir.write("s.moire", scene);
        viewer.emplace(dir, screen, dir.file("s.moire"), paused,
                       std::to_string(width) + "x" + std::to_string(height), extra);
        if (!started(*viewer)) return false;
        origin = windowOrigin(screen, width, height);
        screen.xdo("key h");
        REQUIRE(viewer->nextFrame());
        return true;
    }
    // Window pixel (x, y) as screen coordinates for xdotool.
    std::string at(double x, double y) const {
        return std::to_string(origin.first + int(x)) + " " + std::to_string(origin.second + int(y));
    }
};

} // namespace moire::test::xview

// `moire clip` as a user runs it: frame n is exactly the still `moire render --time` draws at
// from + n / fps, ranges repeat byte for byte, a default clip is one loop, videos go through
// ffmpeg (when installed), and Ctrl-C leaves only complete files.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <map>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

struct Workdir : test::TempDir {
    Workdir() : test::TempDir("clip") {}
    test::CommandResult moire(const std::string& args, const std::string& env = "") const {
        return test::runCommand("cd '" + path() + "' && " + env + " '" + test::moireBinary() +
                                "' " + args);
    }
    std::vector<std::string> namesIn(const std::string& dir) const {
        std::vector<std::string> v;
        for (const auto& e : fs::directory_iterator(file(dir)))
            v.push_back(e.path().filename().string());
        std::sort(v.begin(), v.end());
        return v;
    }
};

// Two looping timings of 1.5 s and 2.5 s (the second pingpong, so 5 s): the loop is 15 s.
// The first layer's spacing and the second's turn (it walks, so turning shows) both move.
const char* kAnimated = "scene { size = (48, 32) }\n"
                        "timing drift { period = 1.5; mode = loop; easing = sine }\n"
                        "timing sway { period = 2.5; mode = pingpong }\n"
                        "layer { family = circles; spacing = ramp(drift, 3, 5) }\n"
                        "layer { family = circles; spacing = 4; offset = (0.4, 0); "
                        "turn = ramp(sway, 0deg, 4deg) }\n";

bool haveFfmpeg() {
    return test::runCommand("command -v ffmpeg >/dev/null && command -v ffprobe >/dev/null")
               .status == 0;
}

// ffprobe's view of a video's first stream: codec_name, width, height, nb_read_frames.
std::map<std::string, std::string> probe(const std::string& path) {
    auto r = test::runCommand("ffprobe -v error -count_frames -select_streams v:0 -show_entries "
                              "stream=codec_name,width,height,nb_read_frames -of default=nw=1 '" +
                              path + "'");
    INFO(r.err);
    REQUIRE(r.status == 0);
    std::map<std::string, std::string> m;
    std::istringstream in(r.out);
    for (std::string line; std::getline(in, line);) {
        size_t eq = line.find('=');
        if (eq != std::string::npos) m[line.substr(0, eq)] = line.substr(eq + 1);
    }
    return m;
}

// Starts moire in `dir` with stdout discarded and stderr to `errFile`; returns its pid.
pid_t startMoire(const std::string& dir, const std::vector<std::string>& args,
                 const std::string& errFile) {
    std::vector<std::string> all = {test::moireBinary()};
    all.insert(all.end(), args.begin(), args.end());
    std::vector<char*> argv;
    for (std::string& a : all) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = fork();
    REQUIRE(pid >= 0);
    if (pid == 0) {
        int err = open(errFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int nul = open("/dev/null", O_WRONLY);
        if (err < 0 || nul < 0 || chdir(dir.c_str()) != 0) _exit(127);
        dup2(nul, 1);
        dup2(err, 2);
        signal(SIGINT, SIG_DFL); // as from a terminal, whatever the test runner chose
        execv(argv[0], argv.data());
        _exit(127);
    }
    return pid;
}

// Polls `ready` for up to `seconds`.
template <class F>
bool waitFor(F ready, double seconds) {
    auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (std::chrono::steady_clock::now() < end) {
        if (ready()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return ready();
}

// The child's exit status, or -1 if it was still running after `seconds` (it is killed).
int exitStatus(pid_t pid, double seconds) {
    int status = 0;
    bool done = waitFor([&] { return waitpid(pid, &status, WNOHANG) == pid; }, seconds);
    if (!done) {
        kill(pid, SIGKILL);
        waitpid(pid, &status, 0);
        return -1;
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

} // namespace

TEST_CASE("frame n of a clip is the still render draws at from + n / fps") {
    Workdir w;
    w.write("a.moire", kAnimated);
    struct Case {
        double fps, from;
        int first, last;
        std::vector<int> frames;
    };
    for (const Case& c : {Case{24, 0.0, 0, 9, {1, 5, 9}}, Case{30, 0.35, 0, 7, {0, 3, 7}},
                          Case{30, 0.35, 995, 997, {997}}, Case{7, 1.25, 2, 4, {2, 4}}}) {
        CAPTURE(c.fps);
        CAPTURE(c.from);
        std::string dir = fmt::format("f{}_{}", c.fps, c.first);
        auto r = w.moire(fmt::format("clip a.moire -q --fps {} --from {} --frames {}..{} -o "
                                     "{}/f_%04d.png",
                                     c.fps, c.from, c.first, c.last, dir));
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(w.namesIn(dir).size() == static_cast<size_t>(c.last - c.first + 1));
        for (int n : c.frames) {
            CAPTURE(n);
            const double t = c.from + n / c.fps;
            auto still = w.moire(fmt::format("render a.moire -q --time {:.17g} -o still.png", t));
            REQUIRE(still.status == 0);
            CHECK(test::readFile(w.file(fmt::format("{}/f_{:04}.png", dir, n))) ==
                  test::readFile(w.file("still.png")));
        }
    }
    // The frames do differ, so matching them is not matching one picture to itself.
    CHECK(test::readFile(w.file("f24_0/f_0001.png")) != test::readFile(w.file("f24_0/f_0005.png")));
}

TEST_CASE("the same range rendered twice is the same files twice") {
    Workdir w;
    w.write("a.moire", kAnimated);
    for (const char* dir : {"one", "two"})
        REQUIRE(w.moire(fmt::format("clip a.moire -q --fps 24 --frames 3..6 -o {}/f_%04d.png", dir))
                    .status == 0);
    const std::vector<std::string> expected = {"f_0003.png", "f_0004.png", "f_0005.png",
                                               "f_0006.png"};
    REQUIRE(w.namesIn("one") == expected);
    REQUIRE(w.namesIn("two") == expected);
    for (const std::string& name : expected)
        CHECK(test::readFile(w.file("one/" + name)) == test::readFile(w.file("two/" + name)));
}

TEST_CASE("a clip given no length is one loop, and the frame at its length is its first") {
    Workdir w;
    w.write("a.moire", kAnimated);
    // lcm(1.5 s, 2 x 2.5 s) = 15 s: 120 frames at 8 fps.
    auto r = w.moire("clip a.moire --fps 8 --size 24x16 -o loop/f_%04d.png");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("the loop is 15 s") != std::string::npos);
    std::vector<std::string> names = w.namesIn("loop");
    REQUIRE(names.size() == 120);
    CHECK(names.front() == "f_0000.png");
    CHECK(names.back() == "f_0119.png");
    REQUIRE(w.moire("clip a.moire -q --fps 8 --size 24x16 --frames 120..120 -o loop/f_%04d.png")
                .status == 0);
    CHECK(test::readFile(w.file("loop/f_0120.png")) == test::readFile(w.file("loop/f_0000.png")));
    CHECK(test::readFile(w.file("loop/f_0060.png")) != test::readFile(w.file("loop/f_0000.png")));

    auto plan = w.moire("clip a.moire --fps 8 --plan");
    CHECK(plan.status == 0);
    CHECK(plan.out.find("frames 0..119 (120 frames") != std::string::npos);
}

TEST_CASE("a scene that does not move writes one frame, and one that reads t needs a length") {
    Workdir w;
    w.write("still.moire", "scene { size = (24, 16) }\nlayer { family = circles; spacing = 4 }\n");
    auto r = w.moire("clip still.moire --fps 30 -o s/f_%03d.png");
    INFO(r.err);
    REQUIRE(r.status == 0);
    CHECK(r.err.find("the scene does not move: writing one frame") != std::string::npos);
    CHECK(w.namesIn("s") == std::vector<std::string>{"f_000.png"});

    w.write("clock.moire",
            "scene { size = (24, 16) }\nlayer { family = circles; spacing = 4 + t }\n");
    auto none = w.moire("clip clock.moire --fps 30 -o c/f_%03d.png");
    CHECK(none.status == 2);
    CHECK(none.err.find("give --to or --frames") != std::string::npos);
    CHECK_FALSE(fs::exists(w.file("c")));
    REQUIRE(w.moire("clip clock.moire -q --fps 10 --to 0.5 -o c/f_%03d.png").status == 0);
    CHECK(w.namesIn("c").size() == 5); // t = 0, 0.1, ..., 0.4: --to is not included
}

TEST_CASE("bad clip command lines exit with status 2 and write nothing") {
    Workdir w;
    w.write("a.moire", kAnimated);
    for (const char* args :
         {"clip a.moire --fps 24 -o one.png", "clip a.moire --fps 24 -o f_%s.png",
          "clip a.moire --fps 24 -o f_%d_%d.png", "clip a.moire --fps 24 -o v_%d.mp4",
          "clip a.moire --fps 24 -o f.bmp", "clip a.moire --fps 0 -o f_%d.png",
          "clip a.moire -o f_%d.png", "clip a.moire --fps 24 --frames 5..2 -o f_%d.png",
          "clip a.moire --fps 24 --frames 3 --to 1 -o f_%d.png",
          "clip a.moire --fps 24 --from 2 --to 1 -o f_%d.png",
          "clip a.moire --fps 24 --depth 16 -o v.webm",
          "clip a.moire --fps 24 --size 47x32 -o v.mp4"}) {
        CAPTURE(args);
        auto r = w.moire(args);
        CHECK(r.status == 2);
        CHECK_FALSE(r.err.empty());
    }
    CHECK(w.names() == std::vector<std::string>{"a.moire"});
}

TEST_CASE("videos: mp4, webm and gif, read back with ffprobe") {
    if (!haveFfmpeg()) {
        test::skip("ffmpeg and ffprobe are not installed");
        return;
    }
    Workdir w;
    w.write("a.moire", kAnimated);
    for (auto [name, codec] :
         {std::pair{"v.mp4", "h264"}, std::pair{"v.webm", "vp9"}, std::pair{"v.gif", "gif"}}) {
        CAPTURE(name);
        auto r = w.moire(fmt::format("clip a.moire -q --fps 24 --frames 12 -o {}", name));
        INFO(r.err);
        REQUIRE(r.status == 0);
        auto info = probe(w.file(name));
        CHECK(info["codec_name"] == codec);
        CHECK(info["width"] == "48");
        CHECK(info["height"] == "32");
        CHECK(info["nb_read_frames"] == "12");
    }
    CHECK(w.names() == std::vector<std::string>{"a.moire", "v.gif", "v.mp4", "v.webm"});
}

TEST_CASE("without ffmpeg a video is one line of error, status 3, and nothing else") {
    Workdir w;
    w.write("a.moire", kAnimated);
    for (const char* ext : {"mp4", "webm", "gif"}) {
        auto r = w.moire(fmt::format("clip a.moire --fps 24 --frames 4 -o v.{}", ext),
                         "PATH=/nonexistent");
        CHECK(r.status == 3);
        CHECK(r.err == fmt::format("moire: error: writing .{} needs ffmpeg (Debian package "
                                   "'ffmpeg')\n",
                                   ext));
    }
    CHECK(w.names() == std::vector<std::string>{"a.moire"});
}

TEST_CASE("ffmpeg failing is reported with the end of what it said") {
    Workdir w;
    w.write("a.moire", kAnimated);
    fs::create_directory(w.file("bin"));
    w.write("bin/ffmpeg", "#!/bin/sh\necho 'first line' >&2\necho 'Unknown encoder libx264' >&2\n"
                          "exit 3\n");
    fs::permissions(w.file("bin/ffmpeg"), fs::perms::owner_all);
    auto r = w.moire("clip a.moire --fps 24 --frames 30 -o v.mp4", "PATH=\"$PWD/bin:$PATH\"");
    CHECK(r.status == 3);
    CHECK(r.err.find("moire: error: cannot write 'v.mp4'") == 0);
    CHECK(r.err.find("exit status 3") != std::string::npos);
    CHECK(r.err.find("Unknown encoder libx264") != std::string::npos);
    CHECK(w.names("bin") == std::vector<std::string>{"a.moire"});
}

TEST_CASE("Ctrl-C stops an image clip after a frame: only complete frames, status 130") {
    Workdir w, logs;
    w.write("a.moire", kAnimated);
    pid_t pid = startMoire(w.path(),
                           {"clip", "a.moire", "--fps", "24", "--frames", "100000", "--size",
                            "320x200", "-o", "out/f_%05d.png"},
                           logs.file("err"));
    bool started = waitFor([&] { return fs::exists(w.file("out/f_00000.png")); }, 60);
    kill(pid, SIGINT);
    int status = exitStatus(pid, 60);
    REQUIRE(started);
    std::string err = test::readFile(logs.file("err"));
    INFO(err);
    CHECK(status == 130);
    CHECK(err.find("moire: interrupted: frames 0 to ") != std::string::npos);
    std::vector<std::string> names = w.namesIn("out");
    CHECK(names.size() < 100000);
    for (size_t i = 0; i < names.size(); ++i) { // f_00000 ... in order, none temporary
        CHECK(names[i] == fmt::format("f_{:05}.png", i));
        Image img = readImage(w.file("out/" + names[i]));
        CHECK((img.width == 320 && img.height == 200));
    }
}

TEST_CASE("Ctrl-C during a video discards it and leaves no temporary file") {
    if (!haveFfmpeg()) {
        test::skip("ffmpeg is not installed");
        return;
    }
    Workdir w, logs;
    w.write("a.moire", kAnimated);
    w.write("v.mp4", "an earlier video");
    pid_t pid = startMoire(w.path(),
                           {"clip", "a.moire", "--fps", "24", "--frames", "100000", "--size",
                            "320x200", "-o", "v.mp4"},
                           logs.file("err"));
    // ffmpeg's temporary appears once it is running and taking frames.
    bool started = waitFor([&] { return w.names().size() > 2; }, 60);
    kill(pid, SIGINT);
    int status = exitStatus(pid, 60);
    REQUIRE(started);
    std::string err = test::readFile(logs.file("err"));
    INFO(err);
    CHECK(status == 130);
    CHECK(err.find("moire: interrupted: v.mp4 was not written") != std::string::npos);
    CHECK(w.names() == std::vector<std::string>{"a.moire", "v.mp4"});
    CHECK(test::readFile(w.file("v.mp4")) == "an earlier video");
}

// Output that is never lost or half-written, as a user meets it: a file size limit
// (RLIMIT_FSIZE, the same failure a full disk gives a write) makes every writer of every
// format fail with the system's words and leave nothing; signals leave no temporary, and
// what a killed process left is removed by the next run; ffmpeg's failures are reported as
// they were; a GIF's delays add up to its length.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <chrono>
#include <csignal>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <mutex>
#include <regex>
#include <sstream>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

// Frames per second 4: a 2 s loop of spacing from 3 to 5.
const char* kScene = "scene { size = (48, 32) }\n"
                     "timing drift { period = 2; mode = loop }\n"
                     "layer { family = circles; spacing = ramp(drift, 3, 5) }\n";

// A file size limit far below any image or video moire writes (the smallest, a 48x32 JPEG,
// is several hundred bytes).
constexpr rlim_t kTinyLimit = 100;

// `moire ARGS` run in `dir`, stderr read through a pipe (a pipe has no file size limit, so
// the whole message arrives), optionally under a file size limit.
class Moire {
  public:
    Moire(const std::string& dir, std::vector<std::string> args, rlim_t fileSizeLimit = 0,
          const std::string& path = "") {
        args.insert(args.begin(), test::moireBinary());
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        // The environment is made before fork: the child only calls what is safe after it.
        std::vector<std::string> env;
        for (char** e = environ; *e; ++e)
            if (path.empty() || std::string_view(*e).rfind("PATH=", 0) != 0) env.push_back(*e);
        if (!path.empty()) env.push_back("PATH=" + path);
        std::vector<char*> envp;
        for (std::string& e : env) envp.push_back(e.data());
        envp.push_back(nullptr);
        int fds[2];
        REQUIRE(::pipe(fds) == 0);
        pid_ = ::fork();
        REQUIRE(pid_ >= 0);
        if (pid_ == 0) {
            int nul = ::open("/dev/null", O_RDWR);
            if (nul < 0 || ::chdir(dir.c_str()) != 0) ::_exit(127);
            ::dup2(nul, 0);
            ::dup2(nul, 1);
            ::dup2(fds[1], 2);
            ::close(fds[0]);
            ::close(fds[1]);
            if (fileSizeLimit > 0) {
                struct rlimit limit {
                    fileSizeLimit, fileSizeLimit
                };
                if (::setrlimit(RLIMIT_FSIZE, &limit) != 0) ::_exit(126);
            }
            // As from a shell: the default actions, whatever the test runner chose.
            for (int s : {SIGINT, SIGTERM, SIGXFSZ, SIGPIPE}) ::signal(s, SIG_DFL);
            ::execve(argv[0], argv.data(), envp.data());
            ::_exit(127);
        }
        ::close(fds[1]);
        reader_ = std::thread([this, fd = fds[0]] {
            char buf[4096];
            for (;;) {
                ssize_t n = ::read(fd, buf, sizeof buf);
                if (n < 0 && errno == EINTR) continue;
                if (n <= 0) break;
                std::lock_guard<std::mutex> lock(mutex_);
                err_.append(buf, static_cast<size_t>(n));
            }
            ::close(fd);
        });
    }
    ~Moire() {
        if (pid_ > 0) {
            ::kill(pid_, SIGKILL);
            ::waitpid(pid_, nullptr, 0);
        }
        if (reader_.joinable()) reader_.join();
    }
    Moire(const Moire&) = delete;
    Moire& operator=(const Moire&) = delete;

    void signal(int s) const { ::kill(pid_, s); }
    // Waits up to a minute for moire to catch signal `s` (a handler installed, as
    // /proc/PID/status's SigCgt mask shows), so that the test does not race its start-up.
    // Until the child has exec'd moire, the mask is the test runner's own.
    bool waitUntilCatching(int s) const {
        const fs::path moire = fs::canonical(test::moireBinary());
        auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < end) {
            std::error_code ec;
            if (fs::read_symlink(fmt::format("/proc/{}/exe", pid_), ec) != moire) {
                std::this_thread::sleep_for(std::chrono::milliseconds(5));
                continue;
            }
            std::ifstream in(fmt::format("/proc/{}/status", pid_));
            for (std::string line; std::getline(in, line);)
                if (line.rfind("SigCgt:", 0) == 0 &&
                    (std::stoull(line.substr(7), nullptr, 16) >> (s - 1) & 1))
                    return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        return false;
    }
    // The exit status, or -N when a signal N ended it (-1000 when still running after 120 s;
    // it is then killed).
    int wait() {
        int status = 0;
        auto end = std::chrono::steady_clock::now() + std::chrono::seconds(120);
        while (::waitpid(pid_, &status, WNOHANG) != pid_) {
            if (std::chrono::steady_clock::now() > end) return -1000;
            std::this_thread::sleep_for(std::chrono::milliseconds(5));
        }
        pid_ = 0;
        if (reader_.joinable()) reader_.join();
        return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }
    std::string err() {
        std::lock_guard<std::mutex> lock(mutex_);
        return err_;
    }
    // Waits up to a minute for `needle` to appear `count` times in stderr.
    bool waitForErr(const std::string& needle, int count = 1) {
        auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
        while (std::chrono::steady_clock::now() < end) {
            std::string text = err();
            int n = 0;
            for (size_t at = text.find(needle); at != std::string::npos;
                 at = text.find(needle, at + 1))
                ++n;
            if (n >= count) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return false;
    }

  private:
    pid_t pid_ = 0;
    std::thread reader_;
    std::mutex mutex_;
    std::string err_;
};

struct Result {
    int status;
    std::string err;
};
Result run(const std::string& dir, std::vector<std::string> args, rlim_t fileSizeLimit = 0,
           const std::string& path = "") {
    Moire m(dir, std::move(args), fileSizeLimit, path);
    int status = m.wait();
    return {status, m.err()};
}

// Every name under `dir`, recursively, relative to it, sorted (directories too).
std::vector<std::string> tree(const std::string& dir) {
    std::vector<std::string> v;
    for (const auto& e : fs::recursive_directory_iterator(dir))
        v.push_back(fs::relative(e.path(), dir).string());
    std::sort(v.begin(), v.end());
    return v;
}

bool haveFfmpeg() {
    return test::runCommand("command -v ffmpeg >/dev/null && command -v ffprobe >/dev/null")
               .status == 0;
}

} // namespace

TEST_CASE("render under a file size limit: every format and depth fails with the reason and "
          "leaves nothing") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    for (auto [name, depth] : std::vector<std::pair<const char*, const char*>>{{"x.png", "8"},
                                                                               {"x.png", "16"},
                                                                               {"x.tif", "16"},
                                                                               {"x.tif", "8"},
                                                                               {"x.exr", "float"},
                                                                               {"x.exr", "half"},
                                                                               {"x.jpg", "8"}}) {
        CAPTURE(name);
        CAPTURE(depth);
        Result r =
            run(w.path(), {"render", "a.moire", "-q", "--depth", depth, "-o", name}, kTinyLimit);
        CHECK(r.status == 3);
        CHECK(r.err == fmt::format("moire: error: cannot write '{}': File too large\n", name));
        CHECK(w.names() == std::vector<std::string>{"a.moire"});
    }
    // An earlier image of the name is left as it was.
    w.write("x.png", "an earlier image");
    Result r = run(w.path(), {"render", "a.moire", "-q", "-o", "x.png"}, kTinyLimit);
    CHECK(r.status == 3);
    CHECK(test::readFile(w.file("x.png")) == "an earlier image");
    CHECK(w.names() == std::vector<std::string>{"a.moire", "x.png"});
}

TEST_CASE("clip under a file size limit: frames of every format fail with the reason, none "
          "left behind") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    for (const char* ext : {"png", "tif", "exr", "jpg"}) {
        CAPTURE(ext);
        Result r =
            run(w.path(),
                {"clip", "a.moire", "-q", "--fps", "4", "-o", fmt::format("f/f_%02d.{}", ext)},
                kTinyLimit);
        CHECK(r.status == 3);
        // Frames are written several at a time: the first to fail is reported, whichever.
        CHECK(std::regex_match(
            r.err, std::regex(fmt::format("moire: error: cannot write 'f/f_0[0-7]\\.{}': File "
                                          "too large\n",
                                          ext))));
        CHECK(tree(w.path()) == std::vector<std::string>{"a.moire", "f"});
    }
}

TEST_CASE("clip under a file size limit: a video fails with ffmpeg's reason, none left behind") {
    if (!haveFfmpeg()) {
        test::skip("ffmpeg is not installed");
        return;
    }
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    for (const char* name : {"v.mp4", "v.webm", "v.gif"}) {
        CAPTURE(name);
        Result r = run(w.path(), {"clip", "a.moire", "-q", "--fps", "4", "-o", name}, kTinyLimit);
        INFO(r.err);
        CHECK(r.status == 3);
        CHECK(r.err.find(fmt::format("moire: error: cannot write '{}': ffmpeg failed", name)) == 0);
        CHECK(r.err.find("File too large") != std::string::npos);
        CHECK(r.err.find(".tmp") == std::string::npos); // ffmpeg's words name the user's file
        CHECK(w.names() == std::vector<std::string>{"a.moire"});
    }
}

TEST_CASE("watch under a file size limit: --once and a live save fail with the reason and "
          "leave nothing") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    Result r = run(w.path(), {"watch", "a.moire", "--once", "-o", "w.png"}, kTinyLimit);
    CHECK(r.status == 3);
    CHECK(r.err.find("moire: error: cannot write 'w.png': File too large\n") == 0);
    CHECK(r.err.find("kept") == std::string::npos); // there is no image to keep
    CHECK(w.names() == std::vector<std::string>{"a.moire"});

    Moire live(w.path(), {"watch", "a.moire", "-o", "w.jpg", "--debounce", "10"}, kTinyLimit);
    REQUIRE(live.waitForErr("watching"));
    std::string edited = kScene;
    edited.replace(edited.find("3, 5"), 4, "4, 6");
    w.write("a.moire", edited);
    CHECK(live.waitForErr("cannot write 'w.jpg': File too large", 2));
    live.signal(SIGINT);
    CHECK(live.wait() == 0);
    CHECK(w.names() == std::vector<std::string>{"a.moire"});
}

TEST_CASE("watch --once on a missing scene is an error that keeps nothing") {
    test::TempDir w("outsafe");
    Result r = run(w.path(), {"watch", "missing.moire", "--once", "-o", "w.png"});
    CHECK(r.status == 3);
    CHECK(r.err.find("missing.moire: error: cannot read the scene: No such file or directory") !=
          std::string::npos);
    CHECK(r.err.find("kept") == std::string::npos);
    CHECK(r.err.find("moire: watch: w.png not written") != std::string::npos);
    CHECK(w.names().empty());
}

TEST_CASE("render creates a missing output directory, as clip does") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    Result r = run(w.path(), {"render", "a.moire", "-q", "-o", "new/deeper/x.png"});
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(readImage(w.file("new/deeper/x.png")).width == 48);
    // A file in the way: the error names the user's path, never a temporary.
    w.write("plain", "");
    r = run(w.path(), {"render", "a.moire", "-q", "-o", "plain/x.png"});
    CHECK(r.status == 3);
    CHECK(r.err.find("moire: error: cannot write into 'plain': ") == 0);
    CHECK(r.err.find(".tmp") == std::string::npos);
}

TEST_CASE("SIGINT and SIGTERM stop a render: status 128 + N, a message, no file, no temporary") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    for (int s : {SIGINT, SIGTERM}) {
        CAPTURE(s);
        // Minutes of work on the interpreter: the signal comes while it compiles or renders.
        Moire m(w.path(), {"render", "a.moire", "--backend", "interp", "--size", "3000x3000",
                           "--threads", "1", "-o", "big.png"});
        REQUIRE(m.waitUntilCatching(s));
        m.signal(s);
        CHECK(m.wait() == 128 + s);
        INFO(m.err());
        CHECK(m.err().find("moire: interrupted: big.png was not written\n") != std::string::npos);
        CHECK(w.names() == std::vector<std::string>{"a.moire"});
    }
}

TEST_CASE("temporaries of killed processes are removed by the next render, clip or watch") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    // A pid that was in use a moment ago and is free now.
    pid_t gone = ::fork();
    REQUIRE(gone >= 0);
    if (gone == 0) ::_exit(0);
    REQUIRE(::waitpid(gone, nullptr, 0) == gone);
    // This process's own start time, as the writer records it (field 22 of /proc/PID/stat).
    std::string stat = test::readFile(fmt::format("/proc/{}/stat", ::getpid()));
    std::istringstream fields(stat.substr(stat.rfind(')') + 2));
    std::string start;
    for (int field = 3; field <= 22; ++field) fields >> start;
    const int me = ::getpid();
    auto plant = [&](const std::string& dir) {
        fs::create_directories(w.file(dir));
        for (const std::string& n :
             {fmt::format(".x.{}-{}-0.tmp.png", gone, start),               // its process is gone
              fmt::format(".x.{}-7-3.tmp.png", me),                         // its pid was reused
              fmt::format(".v.{}-2.tmp.mp4", gone),                         // the older naming
              fmt::format(".x.{}-{}-5.tmp.png", me, start),                 // alive: kept
              std::string(".notes.tmp.png"), std::string("x.1-2.tmp.png")}) // not ours
            w.write(dir + "/" + n, "partial");
    };
    const std::vector<std::string> kept = {
        ".notes.tmp.png", fmt::format(".x.{}-{}-5.tmp.png", me, start), "x.1-2.tmp.png"};
    auto leftIn = [&](const std::string& dir) {
        std::vector<std::string> v;
        for (const auto& e : fs::directory_iterator(w.file(dir)))
            if (e.path().filename().string().find(".tmp") != std::string::npos)
                v.push_back(e.path().filename().string());
        std::sort(v.begin(), v.end());
        return v;
    };

    plant("r");
    CHECK(run(w.path(), {"render", "a.moire", "-q", "-o", "r/x.png"}).status == 0);
    CHECK_MESSAGE(leftIn("r") == kept, fmt::format("{}", fmt::join(leftIn("r"), " ")));

    plant("c");
    CHECK(
        run(w.path(), {"clip", "a.moire", "-q", "--fps", "4", "--frames", "2", "-o", "c/f_%d.png"})
            .status == 0);
    CHECK(leftIn("c") == kept);

    plant("w");
    CHECK(run(w.path(), {"watch", "a.moire", "--once", "-q", "-o", "w/x.png"}).status == 0);
    CHECK(leftIn("w") == kept);

    // A clip killed while it writes frames: whatever it left, the next run removes.
    {
        Moire m(w.path(), {"clip", "a.moire", "--fps", "4", "--frames", "100000", "--size",
                           "640x480", "-o", "k/f_%05d.tif"});
        for (int i = 0; i < 6000 && !fs::exists(w.file("k/f_00001.tif")); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        m.signal(SIGKILL);
        CHECK(m.wait() == -SIGKILL);
    }
    CHECK(run(w.path(),
              {"clip", "a.moire", "-q", "--fps", "4", "--frames", "1", "-o", "k/f_%05d.tif"})
              .status == 0);
    CHECK(leftIn("k").empty());
}

TEST_CASE("SIGTERM stops a clip like Ctrl-C: status 143, complete frames only") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    Moire m(w.path(), {"clip", "a.moire", "--fps", "4", "--frames", "100000", "--size", "320x200",
                       "-o", "out/f_%05d.png"});
    for (int i = 0; i < 6000 && !fs::exists(w.file("out/f_00000.png")); ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    m.signal(SIGTERM);
    CHECK(m.wait() == 143);
    CHECK(m.err().find("moire: interrupted: frames 0 to ") != std::string::npos);
    for (const auto& e : fs::directory_iterator(w.file("out"))) {
        CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
        CHECK(readImage(e.path().string()).width == 320);
    }
}

TEST_CASE("ffmpeg failing after it has read every frame is reported with its own status") {
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    fs::create_directory(w.file("bin"));
    // Takes every frame, then fails as ffmpeg does when it cannot finish the file.
    w.write("bin/ffmpeg", "#!/bin/sh\ncat >/dev/null\necho 'Error writing trailer' >&2\nexit 3\n");
    fs::permissions(w.file("bin/ffmpeg"), fs::perms::owner_all);
    Result r = run(w.path(), {"clip", "a.moire", "--fps", "4", "--frames", "3", "-o", "v.gif"}, 0,
                   w.file("bin") + ":/usr/bin:/bin");
    CHECK(r.status == 3);
    CHECK(r.err == "moire: error: cannot write 'v.gif': ffmpeg failed (exit status 3); ffmpeg "
                   "said:\nError writing trailer\n");
    CHECK(w.names() == std::vector<std::string>{"a.moire", "bin"});
}

TEST_CASE("a GIF's frame delays add up to the clip's length exactly") {
    if (!haveFfmpeg()) {
        test::skip("ffmpeg and ffprobe are not installed");
        return;
    }
    test::TempDir w("outsafe");
    w.write("a.moire", kScene);
    // 8 s at 12 fps is 96 frames of 8.33 cs: the delays (8, 8, 9, 8, 8, 9, ...) must add up
    // to 800 cs, however the last one rounds. Likewise 7 fps (14.29 cs).
    for (int fps : {12, 7}) {
        CAPTURE(fps);
        Result r = run(w.path(), {"clip", "a.moire", "-q", "--fps", std::to_string(fps), "--to",
                                  "8", "-o", "v.gif"});
        INFO(r.err);
        REQUIRE(r.status == 0);
        auto p = test::runCommand("ffprobe -v error -select_streams v:0 -show_entries "
                                  "packet=duration -of csv=p=0 '" +
                                  w.file("v.gif") + "'");
        REQUIRE(p.status == 0);
        std::istringstream in(p.out);
        long total = 0, frames = 0;
        for (long d; in >> d;) total += d, ++frames;
        CHECK(frames == 8 * fps);
        CHECK(total == 800); // centiseconds: the GIF's time base
    }
}

TEST_CASE("every file the project writes goes through the one checked writer") {
    // Writing a file any other way (a stream, stdio, a library writing by name, a rename of
    // one's own) is how "wrote" came to be printed over a truncated image. Only
    // runtime/output/OutputFile.cpp opens files for writing; OiioCodec.cpp hands OpenImageIO a
    // memory buffer (or a memory file) and VideoWriter a temporary that OutputFile names and
    // commits.
    const std::string dir = "runtime/output/";
    const std::vector<std::pair<std::string, std::string>> allowed = {
        {dir + "OutputFile.cpp", "O_CREAT"},   {dir + "OutputFile.cpp", "O_WRONLY"},
        {dir + "OutputFile.cpp", "rename"},    {dir + "OiioCodec.cpp", "ImageOutput::create"},
        {dir + "VideoWriter.cpp", "O_WRONLY"}, // ffmpeg's stdout to /dev/null
    };
    const std::regex writer(R"(std::ofstream|\bfopen\s*\(|\bfreopen\s*\(|\bcreat\s*\(|O_CREAT|)"
                            R"(O_WRONLY|O_RDWR|ImageOutput::create|\brename\s*\(|)"
                            R"(copy_file\s*\(|TIFFOpen|fdopen\s*\()");
    std::vector<std::string> offenders;
    for (const char* root : {"compiler", "runtime"}) {
        for (const auto& e : fs::recursive_directory_iterator(test::sourcePath(root))) {
            const std::string path = e.path().string();
            if (!e.is_regular_file() || path.ends_with("_test.cpp") ||
                !(path.ends_with(".cpp") || path.ends_with(".h")))
                continue;
            const std::string rel = fs::relative(e.path(), test::sourcePath("")).string();
            std::ifstream in(path);
            int line = 0;
            for (std::string text; std::getline(in, text);) {
                ++line;
                bool ok = true;
                for (std::sregex_iterator m(text.begin(), text.end(), writer), end; m != end; ++m) {
                    const std::string token = m->str();
                    ok = ok && std::any_of(allowed.begin(), allowed.end(), [&](const auto& a) {
                             return a.first == rel && token.find(a.second) != std::string::npos;
                         });
                }
                if (!ok) offenders.push_back(fmt::format("{}:{}: {}", rel, line, text));
            }
        }
    }
    std::string list;
    for (const std::string& o : offenders) list += o + "\n";
    CHECK_MESSAGE(offenders.empty(), "write files through runtime/output/OutputFile.h instead:\n",
                  list);
}

TEST_CASE("an output that is not a file (a FIFO, a device) is written into, never replaced") {
    // Renaming a finished temporary over /dev/null would put a regular file where the device
    // was; a FIFO shows the same without needing root: it must still be a FIFO afterwards, and
    // what came through it must be the image.
    test::TempDir dir("stream");
    dir.write("s.moire", "scene { size = (40, 24) }\nlayer { family = circles; spacing = 5 }\n");
    const std::string moire = "'" + test::moireBinary() + "'";
    auto direct = test::runCommand("cd '" + dir.path() + "' && " + moire +
                                   " render -q s.moire -o direct.png && " + moire +
                                   " render -q s.moire -o direct.tif");
    REQUIRE_MESSAGE(direct.status == 0, direct.err);
    for (const char* ext : {"png", "tif"}) {
        CAPTURE(ext);
        const std::string fifo = dir.file(std::string("pipe.") + ext);
        REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
        auto r = test::runCommand("cd '" + dir.path() + "' && (cat pipe." + ext + " > copy." + ext +
                                  " &) && " + moire + " render -q s.moire -o pipe." + ext +
                                  " && sleep 0.2");
        REQUIRE_MESSAGE(r.status == 0, r.err);
        struct stat st {};
        REQUIRE(::stat(fifo.c_str(), &st) == 0);
        CHECK(S_ISFIFO(st.st_mode));
        Image copy = readImage(dir.file(std::string("copy.") + ext));
        Image expected = readImage(dir.file(std::string("direct.") + ext));
        CHECK(test::compareImages(copy, expected, 0.0).maxAbs == 0.0);
        ::unlink(fifo.c_str());
    }
}

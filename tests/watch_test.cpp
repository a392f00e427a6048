// Live coding without a window: a scripted session of a thousand random edits, saved every
// way editors save, against a running watch. Whatever the file goes through, the watch never
// crashes, never loses the file, reports every bad state, and the image on disk is always the
// render of the last good state, whole (a reader polling it never sees half a file).
#include "compiler/backend/interp/Interpreter.h"
#include "runtime/FrameEval.h"
#include "runtime/live/WatchSession.h"
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <deque>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <map>
#include <mutex>
#include <random>
#include <thread>
#include <unistd.h>
#include <vector>

namespace moire {
namespace {

const char* kScene = R"(// a live scene
scene { size = (40, 24); background = #f4f1ea }
camera { zoom = 1.25 }
layer rings { family = circles; spacing = 4; stroke = 1.1; color = #1c1c24; origin = (-2, 1) }
layer bars { family = lines; spacing = 3; rotation = 20deg; stroke = 0.9; color = #703030 }
)";

// The reports of a running session, and a way to wait for the one about given bytes.
class Recorder {
  public:
    void add(const WatchReport& r) {
        std::lock_guard<std::mutex> lock(m_);
        reports_.push_back(r);
        cv_.notify_all();
    }
    // The first report from index `from` on whose bytes hash to `hash` (or, with `missing`,
    // the report of a file that could not be read); null after the timeout.
    const WatchReport* waitFor(size_t from, uint64_t hash, bool missing) {
        std::unique_lock<std::mutex> lock(m_);
        const WatchReport* found = nullptr;
        cv_.wait_for(lock, std::chrono::seconds(10), [&] {
            for (size_t i = from; i < reports_.size() && !found; ++i) {
                const BuildResult& b = reports_[i].result;
                bool unreadable = b.kind == BuildResult::Kind::Failed && b.contentHash == 0 &&
                                  b.diagnostics.find("cannot read") != std::string::npos;
                if (missing ? unreadable : (!unreadable && b.contentHash == hash))
                    found = &reports_[i];
            }
            return found != nullptr;
        });
        return found;
    }
    size_t size() {
        std::lock_guard<std::mutex> lock(m_);
        return reports_.size();
    }
    // The last report from index `from` up to `upTo` (included) whose state was written.
    const WatchReport* lastWritten(size_t from, const WatchReport* upTo) {
        std::lock_guard<std::mutex> lock(m_);
        const WatchReport* last = nullptr;
        for (size_t i = from; i < reports_.size(); ++i) {
            if (reports_[i].wrote) last = &reports_[i];
            if (&reports_[i] == upTo) break;
        }
        return last;
    }

  private:
    std::mutex m_;
    std::condition_variable cv_;
    std::deque<WatchReport> reports_; // a deque: pointers into it stay valid as it grows
};

void writeAll(int fd, const std::string& bytes) {
    size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
        REQUIRE(n > 0);
        done += static_cast<size_t>(n);
    }
}

enum class Save { InPlace, Rename, TruncateThenWrite, DeleteRecreate, DeleteOnly };

void save(const std::string& path, const std::string& text, Save how, std::mt19937& rng) {
    auto pause = [&] { std::this_thread::sleep_for(std::chrono::microseconds(rng() % 3000)); };
    switch (how) {
    case Save::InPlace: {
        int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        REQUIRE(fd >= 0);
        writeAll(fd, text);
        ::close(fd);
        break;
    }
    case Save::Rename: { // vim, emacs and many others: a new file renamed over the old
        std::string tmp = path + ".swp~";
        int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        REQUIRE(fd >= 0);
        writeAll(fd, text);
        ::close(fd);
        REQUIRE(::rename(tmp.c_str(), path.c_str()) == 0);
        break;
    }
    case Save::TruncateThenWrite: { // emptied first, then written in pieces
        int fd = ::open(path.c_str(), O_WRONLY | O_CREAT, 0644);
        REQUIRE(fd >= 0);
        REQUIRE(::ftruncate(fd, 0) == 0);
        pause();
        size_t half = text.size() / 2;
        writeAll(fd, text.substr(0, half));
        pause();
        writeAll(fd, text.substr(half));
        ::close(fd);
        break;
    }
    case Save::DeleteRecreate:
        ::unlink(path.c_str());
        pause();
        save(path, text, Save::InPlace, rng);
        break;
    case Save::DeleteOnly:
        ::unlink(path.c_str());
        break;
    }
}

// A random edit of the scene: most break it in some way an editor's buffer passes through.
std::string edit(const std::string& good, std::mt19937& rng, std::string& kind) {
    auto pick = [&](size_t n) { return static_cast<size_t>(rng() % std::max<size_t>(n, 1)); };
    std::string t = good;
    switch (rng() % 8) {
    case 0: // a change of numbers only (spacing, stroke, zoom, origin)
    case 1: {
        kind = "numbers";
        const char* keys[] = {"spacing = ", "stroke = ", "zoom = ", "origin = ("};
        std::string key = keys[pick(4)];
        size_t at = t.find(key, pick(t.size() / 2));
        if (at == std::string::npos) at = t.find(key);
        if (at == std::string::npos) return t + "\n// no " + key + "here\n";
        at += key.size();
        size_t end = t.find_first_of(";,) }", at);
        if (end == std::string::npos) end = t.size();
        t.replace(at, end - at,
                  std::to_string(1 + static_cast<int>(pick(6))) + "." + std::to_string(pick(10)));
        return t;
    }
    case 2:
        kind = "truncation";
        return t.substr(0, pick(t.size()));
    case 3: { // garbage bytes typed somewhere
        kind = "garbage";
        static const char kJunk[] = "{}()=;,#@$%&*!?<>~`\"'\\x9 \n";
        std::string junk;
        for (size_t i = 0, n = 1 + pick(6); i < n; ++i)
            junk += kJunk[pick(sizeof kJunk - 1)]; // any character but the terminating NUL
        return t.insert(pick(t.size()), junk);
    }
    case 4: { // invalid UTF-8: a stray continuation, a cut sequence, bytes never valid
        kind = "utf8";
        const char* bad[] = {"\x80", "\xc3", "\xff\xfe", "\xe2\x82", "\xed\xa0\x80"};
        return t.insert(pick(t.size()), bad[pick(5)]);
    }
    case 5:
        kind = "bom";
        return "\xef\xbb\xbf" + t;
    case 6: { // a structural change: another family or a new layer
        kind = "structure";
        const std::string extra = "layer extra { family = circles; spacing = 3 }\n";
        size_t at = t.find(extra);
        if (rng() % 2 && at != std::string::npos) return t.erase(at, extra.size());
        if (rng() % 2 && at == std::string::npos) return t + extra;
        if ((at = t.find("family = lines")) != std::string::npos)
            return t.replace(at, 14, "family = hexagons");
        if ((at = t.find("family = hexagons")) != std::string::npos)
            return t.replace(at, 17, "family = lines");
        return t + "layer more { family = squares; spacing = 5 }\n";
    }
    default: { // a deleted or doubled line
        kind = "lines";
        size_t a = t.find('\n', pick(t.size()));
        if (a == std::string::npos) return t.substr(0, t.size() / 2);
        size_t b = t.find('\n', a + 1);
        if (b == std::string::npos) b = t.size();
        return rng() % 2 ? t.erase(a, b - a) : t.insert(a, t.substr(a, b - a));
    }
    }
}

} // namespace

TEST_CASE("watch: 1000 random edits saved every way: no crash, no lost watch, last good image") {
    test::TempDir dir("watch");
    const std::string scene = dir.file("live.moire");
    const std::string output = dir.file("live.png");
    dir.write("live.moire", kScene);

    InterpBackend interp;
    WatchOptions options;
    options.scene = scene;
    options.output = output;
    options.exec.threads = 1;
    options.request.width = 40; // edits that drop the scene's size must not make it large
    options.request.height = 24;
    options.watch.debounce = std::chrono::milliseconds(8);
    WatchSession session(interp, options);
    REQUIRE(session.processNow().good());

    // The independent expectation: each good text compiled and rendered apart from the watch.
    InterpBackend reference;
    std::map<uint64_t, Image> renders;
    auto expected = [&](const std::string& text) -> const Image* {
        uint64_t h = contentHash(text);
        auto it = renders.find(h);
        if (it != renders.end()) return &it->second;
        CompileResult c = compileScene(scene, text);
        if (!c.program) return nullptr;
        FrameValues fv;
        std::string diags;
        if (!evaluateFrame(*c.program, {}, fv, diags)) return nullptr;
        return &renders.emplace(h, test::renderScene(*c.program, reference, 40, 24)).first->second;
    };
    const Image* lastGood = expected(kScene);
    REQUIRE(lastGood);

    // An image viewer polling the output all along: every read must be a whole image.
    std::atomic<bool> done{false};
    std::atomic<int> reads{0}, badReads{0};
    std::thread viewer([&] {
        while (!done) {
            try {
                Image img = readImage(output);
                if (img.width != 40 || img.height != 24) ++badReads;
            } catch (const std::exception&) {
                ++badReads;
            }
            ++reads;
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
    });

    struct Joiner { // a failed REQUIRE unwinds through here: stop the reader first
        std::atomic<bool>& done;
        std::thread& thread;
        ~Joiner() {
            done = true;
            if (thread.joinable()) thread.join();
        }
    } joiner{done, viewer};

    Recorder recorder;
    session.start([&](const WatchReport& r) { recorder.add(r); });
    std::mt19937 rng(20261121);
    std::string current = kScene, previous = kScene;
    bool exists = true;
    std::map<std::string, int> kinds, goodKinds;
    int lost = 0, unreported = 0, wrongImage = 0, wrongVerdict = 0, deletions = 0;
    for (int i = 0; i < 1000; ++i) {
        // Each edit starts from the last good text (as a person edits a working scene) or,
        // one time in four, from whatever the file holds now.
        std::string base = rng() % 4 ? previous : current;
        std::string kind;
        std::string text = edit(base, rng, kind);
        Save how = static_cast<Save>(rng() % 4);
        if (exists && rng() % 50 == 0) how = Save::DeleteOnly;
        if (exists && how != Save::DeleteOnly && text == current) continue; // nothing to see
        ++kinds[kind];
        size_t from = recorder.size();
        save(scene, text, how, rng);
        const WatchReport* r = recorder.waitFor(from, contentHash(text), how == Save::DeleteOnly);
        if (!r) {
            ++lost;
            CHECK_MESSAGE(false, "edit ", i, " (", kind, ") was never reported");
            break;
        }
        if (how == Save::DeleteOnly) {
            ++deletions;
            current.clear();
            exists = false;
            CHECK(!r->good());
        } else {
            current = text;
            exists = true;
            const Image* want = expected(text);
            if (want) {
                lastGood = want;
                previous = text;
                ++goodKinds[kind];
            } else if (const WatchReport* w = recorder.lastWritten(from, r)) {
                // A save passes through other states on its way: empty (opened with O_TRUNC,
                // or truncated first) and, written in two pieces, its first half. A slow
                // writer (a loaded machine) lets the watch read one; if that one is a good
                // scene of its own it is rendered, and stays the last good image when the
                // whole text is bad.
                std::vector<std::string> passed;
                if (how != Save::Rename) passed.push_back("");
                if (how == Save::TruncateThenWrite)
                    passed.push_back(text.substr(0, text.size() / 2));
                const std::string* seen = nullptr;
                for (const std::string& state : passed)
                    if (w->result.contentHash == contentHash(state)) seen = &state;
                CHECK_MESSAGE(seen, "edit ", i, " (", kind, "): a state never saved was drawn");
                if (seen) {
                    const Image* drawn = expected(*seen);
                    CHECK_MESSAGE(drawn, "edit ", i, " (", kind, "): a bad state was drawn");
                    if (drawn) lastGood = drawn;
                }
            }
            if (r->good() != (want != nullptr)) {
                ++wrongVerdict;
                CHECK_MESSAGE(false, "edit ", i, " (", kind, "): watch says ",
                              r->good() ? "good" : "bad", "\n", text);
            }
        }
        if (!r->good() &&
            (r->diagnostics.empty() || r->diagnostics.find("error") == std::string::npos)) {
            ++unreported;
            CHECK_MESSAGE(false, "edit ", i, " (", kind, ") failed without a diagnostic");
        }
        // The image on disk is the last good state's render, whatever this state was.
        Image onDisk = readImage(output);
        if (test::compareImages(onDisk, *lastGood, 0.6 / 255.0, 3).over != 0) {
            ++wrongImage;
            CHECK_MESSAGE(false, "edit ", i, " (", kind, "): the image is not the last good one");
        }
    }
    done = true;
    viewer.join();
    session.stop();

    MESSAGE("edits by kind: ", kinds.size(), " kinds; good states ", renders.size(), "; deletions ",
            deletions, "; image reads during the session ", reads.load());
    for (auto& [k, n] : kinds) MESSAGE(k, ": ", n, " edits, ", goodKinds[k], " good");
    CHECK(lost == 0);
    CHECK(unreported == 0);
    CHECK(wrongImage == 0);
    CHECK(wrongVerdict == 0);
    CHECK(badReads == 0);
    CHECK(reads > 0);
    // Both kinds of good edit happened, and number edits did not compile kernels: the
    // interpreter "compiles" too, and the builder counts the kernels it asked for.
    CHECK(goodKinds["numbers"] > 50);
    CHECK(goodKinds["structure"] > 10);
    CHECK(session.builder().kernelBuilds() < session.builder().frontEndCompiles() / 2);
}

} // namespace moire

// The command itself: a good save rewrites the image, a bad one prints file:line:col and
// keeps it, a rename-save is seen, and Ctrl-C ends it cleanly with the image whole.
#include <csignal>
#include <fstream>
#include <spawn.h>
#include <sys/wait.h>

namespace moire {
namespace {
std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
}
// Waits until `log` holds `needle` at least `count` times.
bool waitForLog(const std::string& log, const std::string& needle, int count) {
    for (int i = 0; i < 1000; ++i) {
        std::string text = slurp(log);
        int n = 0;
        for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
            ++n;
        if (n >= count) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return false;
}
} // namespace

TEST_CASE("watch: the command rewrites on good saves, reports bad ones, stops on SIGINT") {
    test::TempDir dir("watchcmd");
    dir.write("s.moire", kScene);
    const std::string log = dir.file("log.txt"), out = dir.file("s.png");
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 2, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::string bin = test::moireBinary(), scene = dir.file("s.moire");
    std::vector<std::string> args = {bin,     "watch",      scene, "-o",        out,  "--size",
                                     "40x24", "--debounce", "10",  "--backend", "jit"};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    pid_t pid = 0;
    REQUIRE(posix_spawn(&pid, bin.c_str(), &actions, nullptr, argv.data(), environ) == 0);
    posix_spawn_file_actions_destroy(&actions);
    struct Killer {
        pid_t pid;
        ~Killer() {
            if (pid > 0) {
                ::kill(pid, SIGKILL);
                ::waitpid(pid, nullptr, 0);
            }
        }
    } killer{pid};

    REQUIRE(waitForLog(log, "watching", 1));
    CHECK(waitForLog(log, "wrote", 1));
    Image first = readImage(out);

    // A number edit: rewritten, kernel reused.
    std::string edited = kScene;
    edited.replace(edited.find("spacing = 4"), 11, "spacing = 6");
    dir.write("s.moire", edited);
    REQUIRE(waitForLog(log, "kernel reused", 1));
    Image second = readImage(out);
    CHECK(test::compareImages(first, second, 0.5 / 255, 3).over > 0);

    // A bad save: the diagnostic names file:line:col; the image stays.
    std::string broken = edited;
    broken.replace(broken.find("circles"), 7, "circels");
    dir.write("s.moire", broken);
    REQUIRE(waitForLog(log, "kept", 1));
    std::string text = slurp(log);
    CHECK(text.find(scene + ":4:") != std::string::npos);
    CHECK(text.find("unknown family 'circels'") != std::string::npos);
    CHECK(test::compareImages(readImage(out), second, 0.0, 4).maxAbs == 0.0);

    // A rename-save back to the first text: the first image again.
    dir.write("s.moire.tmp", kScene);
    REQUIRE(::rename(dir.file("s.moire.tmp").c_str(), scene.c_str()) == 0);
    REQUIRE(waitForLog(log, "wrote", 3));
    CHECK(test::compareImages(readImage(out), first, 0.0, 4).maxAbs == 0.0);

    ::kill(pid, SIGINT);
    int status = 0;
    REQUIRE(::waitpid(pid, &status, 0) == pid);
    killer.pid = 0;
    CHECK(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 0);
    // Nothing but the scene, its log and the image: no temporary left behind.
    CHECK(dir.names() == std::vector<std::string>{"log.txt", "s.moire", "s.png"});
}

TEST_CASE("watch: a missing directory and --once on a bad scene fail with a message") {
    test::TempDir dir("watchonce");
    test::CommandResult r = test::runCommand(
        test::moireBinary() + " watch " + dir.file("nowhere/s.moire") + " -o " + dir.file("o.png"));
    CHECK(r.status == 3);
    CHECK(r.err.find("moire: error: ") != std::string::npos);
    dir.write("bad.moire", "layer a { family = circles; spacing = }\n");
    r = test::runCommand(test::moireBinary() + " watch --once " + dir.file("bad.moire") + " -o " +
                         dir.file("o.png"));
    CHECK(r.status == 1);
    CHECK(r.err.find("bad.moire:1:") != std::string::npos);
    CHECK(dir.names() == std::vector<std::string>{"bad.moire"});
    dir.write("good.moire", kScene);
    r = test::runCommand(test::moireBinary() + " watch --once " + dir.file("good.moire") + " -o " +
                         dir.file("o.png"));
    CHECK(r.status == 0);
    CHECK(readImage(dir.file("o.png")).width == 40);
}

} // namespace moire

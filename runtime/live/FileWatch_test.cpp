// The file watcher against every way an editor saves, in a fresh temporary directory. Most
// cases set the safety-net poll far beyond their run time, so what they see came from inotify
// alone; the cases about spurious reports poll often, so the safety net is checked not to
// report what inotify already did.
#include "runtime/live/FileWatch.h"

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <sys/stat.h>
#include <thread>
#include <unistd.h>

using namespace moire;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;
using Wait = FileWatch::Wait;

namespace {

// A directory made with mkdtemp, removed with everything in it at the end.
class ScratchDir {
  public:
    ScratchDir() {
        std::string tmpl = (std::filesystem::temp_directory_path() / "moire-watch-XXXXXX").string();
        REQUIRE_MESSAGE(::mkdtemp(tmpl.data()) != nullptr, "mkdtemp: ", std::strerror(errno));
        path_ = tmpl;
    }
    ~ScratchDir() {
        std::error_code ec;
        std::filesystem::remove_all(path_, ec);
    }
    std::string file(const std::string& name) const { return path_ + "/" + name; }
    const std::string& path() const { return path_; }

  private:
    std::string path_;
};

// Writes through open/write/close, as an editor saving in place does.
void writeFile(const std::string& path, const std::string& text) {
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    REQUIRE_MESSAGE(fd >= 0, "open ", path, ": ", std::strerror(errno));
    REQUIRE(::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()));
    REQUIRE(::close(fd) == 0);
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Writes a temporary file beside `path` and renames it over, as vim and emacs save.
void renameSave(const std::string& path, const std::string& text) {
    const std::string tmp = path + ".tmp~";
    writeFile(tmp, text);
    REQUIRE(::rename(tmp.c_str(), path.c_str()) == 0);
}

// inotify alone: the safety net does not tick within any of these cases.
FileWatch::Options inotifyOnly(std::chrono::milliseconds debounce = 15ms) {
    FileWatch::Options o;
    o.debounce = debounce;
    o.poll = 60s;
    return o;
}

// The safety net ticking often, to show it does not report a change a second time.
FileWatch::Options pollingOften() {
    FileWatch::Options o;
    o.debounce = 15ms;
    o.poll = 10ms;
    return o;
}

} // namespace

TEST_CASE("FileWatch: no event until the timeout says Timeout, after the timeout") {
    ScratchDir dir;
    writeFile(dir.file("scene.moire"), "a");
    FileWatch watch(dir.file("scene.moire"), pollingOften());
    const auto t0 = Clock::now();
    CHECK(watch.wait(80ms) == Wait::Timeout);
    const auto took = Clock::now() - t0;
    CHECK(took >= 80ms);
    CHECK(took < 1s);
    CHECK(watch.wait(0ms) == Wait::Timeout);
    CHECK(watch.watching());
}

TEST_CASE("FileWatch: a missing directory throws a reason naming the path") {
    ScratchDir dir;
    const std::string path = dir.file("no-such-dir/scene.moire");
    try {
        FileWatch watch(path);
        FAIL("constructed a watch on a file in a missing directory");
    } catch (const std::runtime_error& e) {
        CHECK(std::string(e.what()).find(path) != std::string::npos);
    }
    // A file that does not exist yet in a directory that does is fine, and its creation counts.
    FileWatch watch(dir.file("later.moire"), inotifyOnly());
    CHECK(watch.path() == dir.file("later.moire"));
    writeFile(dir.file("later.moire"), "x");
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: a bare file name watches the current directory") {
    // Nothing is written to the current directory: only that the watch is set up on ".".
    FileWatch watch("moire-filewatch-test-no-such-file.moire", inotifyOnly());
    CHECK(watch.watching());
    CHECK(watch.wait(0ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: a plain write is reported once, with when it began") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, pollingOften());
    const auto before = Clock::now();
    writeFile(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
    CHECK(watch.firstEvent() >= before);
    CHECK(watch.firstEvent() <= Clock::now());
    CHECK(watch.wait(100ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: truncate then write in two chunks is one change, reported after both") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "old contents");
    FileWatch::Options options = pollingOften();
    options.debounce = 20ms;
    FileWatch watch(path, options);

    // The writer runs while wait() blocks, pausing between chunks for less than the debounce.
    std::thread writer([&] {
        std::this_thread::sleep_for(20ms);
        const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC);
        CHECK(fd >= 0);
        CHECK(::write(fd, "first ", 6) == 6);
        std::this_thread::sleep_for(4ms);
        CHECK(::write(fd, "second", 6) == 6);
        CHECK(::close(fd) == 0);
    });
    const Wait w = watch.wait(2s);
    const std::string seen = readFile(path); // what a reload at this moment would read
    writer.join();
    CHECK(w == Wait::Changed);
    CHECK(seen == "first second");
    CHECK(watch.wait(100ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: a rename-save through a temporary file is reported") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, inotifyOnly());
    renameSave(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
    CHECK(readFile(path) == "two");
    CHECK(watch.wait(60ms) == Wait::Timeout); // the temporary file's own events do not count
}

TEST_CASE("FileWatch: delete then re-create is reported") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, inotifyOnly());
    REQUIRE(::unlink(path.c_str()) == 0);
    writeFile(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
    CHECK(watch.wait(60ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: deleting alone is reported") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, inotifyOnly());
    REQUIRE(::unlink(path.c_str()) == 0);
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: touching the attributes is reported") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, inotifyOnly());
    REQUIRE(::chmod(path.c_str(), 0600) == 0);
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: other files in the same directory are not reported") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, pollingOften());
    writeFile(dir.file("other.moire"), "x");
    renameSave(dir.file("scene.moire.bak"), "y"); // a name that starts like ours
    REQUIRE(::unlink(dir.file("other.moire").c_str()) == 0);
    CHECK(watch.wait(150ms) == Wait::Timeout);
    // And the watch still works afterwards.
    writeFile(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: 200 rename-saves in a row are each observed") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "v-1");
    // A short debounce keeps 200 rounds quick; each wait still has to see its own save.
    FileWatch watch(path, inotifyOnly(5ms));
    int changed = 0;
    for (int i = 0; i < 200; ++i) {
        std::string text = "v"; // (not "v" + to_string: GCC 12 warns falsely about that)
        text += std::to_string(i);
        renameSave(path, text);
        if (watch.wait(2s) == Wait::Changed && readFile(path) == text) ++changed;
    }
    CHECK(changed == 200);
    CHECK(watch.wait(30ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: the watch survives its directory being removed and re-created") {
    ScratchDir dir;
    const std::string sub = dir.file("scenes");
    const std::string path = sub + "/scene.moire";
    REQUIRE(::mkdir(sub.c_str(), 0755) == 0);
    writeFile(path, "one");
    FileWatch::Options options;
    options.debounce = 15ms;
    options.poll = 20ms; // how soon the re-created directory is found again
    FileWatch watch(path, options);
    REQUIRE(watch.watching());

    REQUIRE(::unlink(path.c_str()) == 0);
    REQUIRE(::rmdir(sub.c_str()) == 0);
    CHECK(watch.wait(2s) == Wait::Changed);
    CHECK_FALSE(watch.watching());
    CHECK(watch.wait(60ms) == Wait::Timeout); // polling a missing directory reports nothing

    REQUIRE(::mkdir(sub.c_str(), 0755) == 0);
    CHECK(watch.wait(2s) == Wait::Changed); // found again, and watched
    CHECK(watch.watching());

    writeFile(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
    CHECK(watch.wait(60ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: a directory renamed away is followed by its path, not its inode") {
    ScratchDir dir;
    const std::string sub = dir.file("scenes");
    const std::string moved = dir.file("scenes.old");
    const std::string path = sub + "/scene.moire";
    REQUIRE(::mkdir(sub.c_str(), 0755) == 0);
    writeFile(path, "one");
    FileWatch::Options options;
    options.debounce = 15ms;
    options.poll = 20ms;
    FileWatch watch(path, options);

    REQUIRE(::rename(sub.c_str(), moved.c_str()) == 0);
    CHECK(watch.wait(2s) == Wait::Changed);
    writeFile(moved + "/scene.moire", "not ours any more");
    CHECK(watch.wait(80ms) == Wait::Timeout);

    REQUIRE(::mkdir(sub.c_str(), 0755) == 0);
    CHECK(watch.wait(2s) == Wait::Changed);
    REQUIRE(watch.watching());
    writeFile(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: a parent renamed away is noticed by the poll, and the path watched anew") {
    // Renaming a parent sends the watched directory no event at all: only the safety net's
    // look at the directory's identity can tell that the path now leads elsewhere.
    ScratchDir dir;
    const std::string parent = dir.file("project");
    const std::string path = parent + "/scenes/scene.moire";
    const std::string stale = dir.file("project.old") + "/scenes/scene.moire";
    std::filesystem::create_directories(parent + "/scenes");
    writeFile(path, "one");
    FileWatch::Options options;
    options.debounce = 15ms;
    options.poll = 20ms;
    FileWatch watch(path, options);

    REQUIRE(::rename(parent.c_str(), dir.file("project.old").c_str()) == 0);
    CHECK(watch.wait(2s) == Wait::Changed); // the file is gone from the path
    CHECK_FALSE(watch.watching());

    std::filesystem::create_directories(parent + "/scenes");
    CHECK(watch.wait(2s) == Wait::Changed); // the new directory is watched
    CHECK(watch.watching());
    writeFile(stale, "not ours any more");
    CHECK(watch.wait(80ms) == Wait::Timeout);
    writeFile(path, "two");
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: interrupt() from another thread ends a wait") {
    ScratchDir dir;
    FileWatch watch(dir.file("scene.moire"), inotifyOnly());
    std::thread other([&] {
        std::this_thread::sleep_for(30ms);
        watch.interrupt();
    });
    const auto t0 = Clock::now();
    const Wait w = watch.wait(10s);
    const auto took = Clock::now() - t0;
    other.join();
    CHECK(w == Wait::Interrupted);
    CHECK(took >= 25ms);
    CHECK(took < 2s);

    // An interrupt with nobody waiting ends the next wait at once, and only that one.
    watch.interrupt();
    CHECK(watch.wait(10s) == Wait::Interrupted);
    CHECK(watch.wait(30ms) == Wait::Timeout);
}

TEST_CASE("FileWatch: events made while nobody waits are reported by the next wait") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "one");
    FileWatch watch(path, inotifyOnly());
    writeFile(path, "two");
    std::this_thread::sleep_for(50ms);
    CHECK(watch.wait(2s) == Wait::Changed);
    CHECK(watch.wait(30ms) == Wait::Timeout);

    // Seen by a wait that then times out within the debounce, and kept for the next one (the
    // file is left open: a finished save would be reported without the debounce).
    FileWatch slow(path, inotifyOnly(100ms));
    const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC);
    REQUIRE(fd >= 0);
    REQUIRE(::write(fd, "three", 5) == 5);
    CHECK(slow.wait(20ms) == Wait::Timeout);
    CHECK(slow.wait(2s) == Wait::Changed);
    ::close(fd);

    // And kept across an interrupted wait.
    writeFile(path, "four");
    watch.interrupt();
    CHECK(watch.wait(2s) == Wait::Interrupted);
    CHECK(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: a finished save skips the debounce, a write still open waits for it") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "a");
    FileWatch watch(path, inotifyOnly(400ms));

    // Closed after writing, or renamed into place: reported after a few milliseconds.
    for (int i = 0; i < 2; ++i) {
        const Clock::time_point t0 = Clock::now();
        if (i == 0)
            writeFile(path, "b");
        else
            renameSave(path, "c");
        REQUIRE(watch.wait(2s) == Wait::Changed);
        CHECK(Clock::now() - t0 < 200ms);
    }

    // Written and not yet closed: the writer may go on, so the whole debounce is waited.
    const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC);
    REQUIRE(fd >= 0);
    const Clock::time_point t0 = Clock::now();
    REQUIRE(::write(fd, "dd", 2) == 2);
    CHECK(watch.wait(200ms) == Wait::Timeout);
    REQUIRE(watch.wait(2s) == Wait::Changed);
    CHECK(Clock::now() - t0 >= 400ms);
    ::close(fd);
    // The close is an event of its own, and it ends the save at once.
    REQUIRE(watch.wait(2s) == Wait::Changed);
}

TEST_CASE("FileWatch: a save paused between its truncate and its write is reported whole") {
    ScratchDir dir;
    const std::string path = dir.file("scene.moire");
    writeFile(path, "old contents");
    FileWatch watch(path, inotifyOnly(15ms));

    // Truncated and still open, as a writer on a loaded machine leaves it between open(O_TRUNC)
    // and its write: many debounces pass and nothing is reported, since a reload would read an
    // empty scene.
    const int fd = ::open(path.c_str(), O_WRONLY | O_TRUNC);
    REQUIRE(fd >= 0);
    CHECK(watch.wait(150ms) == Wait::Timeout);
    REQUIRE(::write(fd, "new", 3) == 3);
    REQUIRE(::close(fd) == 0);
    REQUIRE(watch.wait(2s) == Wait::Changed);
    CHECK(readFile(path) == "new");

    // Emptied on purpose (closed): reported without waiting for anything more.
    const Clock::time_point t0 = Clock::now();
    writeFile(path, "");
    REQUIRE(watch.wait(2s) == Wait::Changed);
    CHECK(Clock::now() - t0 < 500ms);

    // Left truncated and open for good: reported once the batch is a second old, so a writer
    // that never writes does not hide the change forever.
    writeFile(path, "again");
    REQUIRE(watch.wait(2s) == Wait::Changed);
    const int stuck = ::open(path.c_str(), O_WRONLY | O_TRUNC);
    REQUIRE(stuck >= 0);
    REQUIRE(watch.wait(3s) == Wait::Changed);
    ::close(stuck);
}

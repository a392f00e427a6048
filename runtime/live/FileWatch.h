// Watching one scene file for changes, however an editor saves it: written in place, truncated
// and rewritten in chunks, written to a temporary file and renamed over, deleted and created
// again. Used by the live-reload viewer and by `moire watch` (Linux, inotify).
//
// The file's directory is watched rather than the file: a rename-save or a delete replaces the
// inode, and a watch on the file itself would go with the old one. Events are filtered by the
// file's name. Because inotify is silent on some filesystems (network mounts, FUSE, bind mounts
// changed from elsewhere), the file is also stat()ed every `poll` interval as a safety net, and
// while the directory itself is gone the watcher polls until it is back and then watches it
// again. Nothing fails after construction: whatever goes wrong degrades to polling.
#pragma once

#include <chrono>
#include <cstdint>
#include <ctime>
#include <string>

namespace moire {

// FileWatch::Options. Declared outside the class because GCC cannot use a nested struct's
// default member initializers in a default argument of its enclosing class (`Options options =
// {}` below) before that class is complete.
struct FileWatchOptions {
    std::chrono::milliseconds debounce{30}; // quiet time after the last event before reporting
    std::chrono::milliseconds poll{250};    // safety-net stat() check interval
};

class FileWatch {
  public:
    using Options = FileWatchOptions;
    enum class Wait { Changed, Timeout, Interrupted };

    // Watches `path` (a file; it need not exist yet, but its directory must, else throws
    // std::runtime_error with a one-line reason naming the path).
    explicit FileWatch(std::string path, Options options = {});
    ~FileWatch();
    FileWatch(const FileWatch&) = delete;
    FileWatch& operator=(const FileWatch&) = delete;

    // Blocks until the file may have changed (written, truncated, created, deleted, renamed onto,
    // its attributes touched) and then stayed quiet for `debounce`; or until `timeout` passes; or
    // until interrupt() is called from any thread (or a signal handler). Events that arrive while
    // nobody waits are not lost: the next wait reports them. One thread waits at a time. A file
    // written without a pause is reported anyway once its batch is max(1 s, 10 x debounce) old.
    // A file truncated to nothing and still open for writing waits for its close (or that age):
    // it is a save between its truncate and its write, not an empty scene.
    Wait wait(std::chrono::milliseconds timeout);
    // Thread-safe and async-signal-safe (writes an eventfd); makes the current or next wait()
    // return Interrupted.
    void interrupt();
    // When the first event of the batch the last Changed reported arrived (for edit-to-pixels
    // latency). Events that queued while nobody waited count from when a wait() read them.
    std::chrono::steady_clock::time_point firstEvent() const;
    const std::string& path() const;
    // Whether the directory is watched with inotify right now; false while degraded to polling
    // (the directory is gone, or inotify is unavailable).
    bool watching() const;

  private:
    using Clock = std::chrono::steady_clock;

    // What stat() says about the file; two differing snapshots count as an event.
    struct Snapshot {
        bool exists = false;
        uint64_t dev = 0, ino = 0;
        int64_t size = 0;
        timespec mtime{}, ctime{};
        bool operator==(const Snapshot& o) const;
    };

    Snapshot snapshot() const;
    // Sets up inotify and the directory watch where they are missing; true when the watch was
    // (re-)added by this call.
    bool ensureWatch();
    void dropWatch();
    void closeInotify();
    // Reads every queued inotify event; true when one concerns the file.
    bool drainInotify();
    // The safety net: the file's stat() differs from the last look, or the path no longer names
    // the watched directory (which then is watched anew). True when that counts as an event.
    bool pollTick();
    void markEvent(Clock::time_point now);

    std::string path_, dir_, name_;
    Options options_;
    int eventFd_ = -1;
    int inotifyFd_ = -1;
    int wd_ = -1;                      // the directory's watch, -1 while it has none
    uint64_t dirDev_ = 0, dirIno_ = 0; // which directory wd_ watches
    Snapshot last_;                    // the file as last seen
    bool pending_ = false;             // events seen and not yet reported
    bool saved_ = false;               // the batch's last event ended a save
    Clock::time_point batchFirst_{}, batchLast_{};
    Clock::time_point firstEvent_{};
    Clock::time_point nextPoll_{};
};

} // namespace moire

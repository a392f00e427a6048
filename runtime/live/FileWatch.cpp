#include "runtime/live/FileWatch.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <poll.h>
#include <stdexcept>
#include <sys/eventfd.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>
#include <utility>

namespace moire {

namespace {

using namespace std::chrono_literals;

// What happens to the directory's entries that can mean the file changed. IN_MODIFY catches a
// truncate-then-write before the editor closes the file (and writers that never close it);
// IN_CLOSE_WRITE catches a write that changed nothing inotify saw as a modification; the moves,
// creates and deletes catch rename-saves and delete-and-recreate; IN_ATTRIB catches touch and
// chmod. The *_SELF events tell that the directory itself went away (IN_IGNORED and IN_UNMOUNT
// always come).
constexpr uint32_t kWatchMask = IN_CLOSE_WRITE | IN_MODIFY | IN_MOVED_TO | IN_MOVED_FROM |
                                IN_CREATE | IN_DELETE | IN_ATTRIB | IN_DELETE_SELF | IN_MOVE_SELF |
                                IN_ONLYDIR;
constexpr uint32_t kDirGone = IN_DELETE_SELF | IN_MOVE_SELF | IN_IGNORED | IN_UNMOUNT;

// A file written without pause (a log, a generator streaming into it) would never be quiet for
// `debounce`; a batch is reported anyway once it is this old, so the viewer still follows.
constexpr std::chrono::milliseconds kMaxBatchFloor = 1000ms;

// After an event that ends a save, how long to wait for a save made of several steps (a
// backup rename, then the write) before reporting: far shorter than the debounce, so that an
// edit reaches the screen without paying for it.
constexpr std::chrono::milliseconds kSavedGrace = 3ms;

std::string inQuotes(const std::string& s) {
    return "'" + s + "'";
}

timespec toTimespec(std::chrono::steady_clock::duration d) {
    if (d < d.zero()) d = d.zero();
    const auto secs = std::chrono::duration_cast<std::chrono::seconds>(d);
    // ppoll takes any time_t; a day is as good as forever here and cannot overflow anything.
    if (secs > std::chrono::hours(24)) return timespec{24 * 3600, 0};
    const auto nanos = std::chrono::duration_cast<std::chrono::nanoseconds>(d - secs);
    return timespec{static_cast<time_t>(secs.count()), static_cast<long>(nanos.count())};
}

} // namespace

bool FileWatch::Snapshot::operator==(const Snapshot& o) const {
    return exists == o.exists && dev == o.dev && ino == o.ino && size == o.size &&
           mtime.tv_sec == o.mtime.tv_sec && mtime.tv_nsec == o.mtime.tv_nsec &&
           ctime.tv_sec == o.ctime.tv_sec && ctime.tv_nsec == o.ctime.tv_nsec;
}

FileWatch::FileWatch(std::string path, Options options)
    : path_(std::move(path)), options_(options) {
    // The parent as written, not canonicalized: a symlinked scene file is watched where its
    // link is (replacing the link is an event there; edits to a target elsewhere are caught by
    // the stat() safety net, which follows the link), and a symlinked directory is watched
    // through whatever it points at now.
    const std::filesystem::path p(path_);
    const std::filesystem::path name = p.filename();
    if (name.empty() || name == "." || name == "..")
        throw std::runtime_error("cannot watch " + inQuotes(path_) + ": not a path to a file");
    name_ = name.string();
    dir_ = p.parent_path().empty() ? std::string(".") : p.parent_path().string();

    struct stat st {};
    if (::stat(dir_.c_str(), &st) != 0) {
        const int err = errno;
        throw std::runtime_error("cannot watch " + inQuotes(path_) + ": directory " +
                                 inQuotes(dir_) + ": " + std::strerror(err));
    }
    if (!S_ISDIR(st.st_mode))
        throw std::runtime_error("cannot watch " + inQuotes(path_) + ": " + inQuotes(dir_) +
                                 " is not a directory");

    eventFd_ = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
    if (eventFd_ < 0) {
        const int err = errno;
        throw std::runtime_error("cannot watch " + inQuotes(path_) +
                                 ": eventfd: " + std::strerror(err));
    }

    // Nonsense intervals would make wait() spin; clamp them to something that sleeps.
    options_.debounce = std::max(options_.debounce, 0ms);
    options_.poll = std::max(options_.poll, 1ms);

    // Watch first, then look: a change after the watch is added arrives as an event, one
    // before it is in the snapshot. inotify may be unavailable (instance or watch limits); that
    // degrades to polling, and every poll tick tries again.
    ensureWatch();
    last_ = snapshot();
    nextPoll_ = Clock::now() + options_.poll;
}

FileWatch::~FileWatch() {
    closeInotify();
    if (eventFd_ >= 0) ::close(eventFd_);
}

const std::string& FileWatch::path() const {
    return path_;
}

bool FileWatch::watching() const {
    return inotifyFd_ >= 0 && wd_ >= 0;
}

std::chrono::steady_clock::time_point FileWatch::firstEvent() const {
    return firstEvent_;
}

void FileWatch::interrupt() {
    // Only write(2): async-signal-safe. A full counter (EAGAIN) already means "interrupted".
    const uint64_t one = 1;
    [[maybe_unused]] ssize_t n = ::write(eventFd_, &one, sizeof one);
}

FileWatch::Snapshot FileWatch::snapshot() const {
    Snapshot s;
    struct stat st {};
    if (::stat(path_.c_str(), &st) != 0) return s;
    s.exists = true;
    s.dev = static_cast<uint64_t>(st.st_dev);
    s.ino = static_cast<uint64_t>(st.st_ino);
    s.size = static_cast<int64_t>(st.st_size);
    s.mtime = st.st_mtim;
    s.ctime = st.st_ctim;
    return s;
}

bool FileWatch::ensureWatch() {
    if (inotifyFd_ < 0) {
        inotifyFd_ = ::inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
        if (inotifyFd_ < 0) return false;
    }
    if (wd_ >= 0) return false;
    const int wd = ::inotify_add_watch(inotifyFd_, dir_.c_str(), kWatchMask);
    if (wd < 0) return false; // gone, not a directory, or out of watches: keep polling
    // Which directory the watch is on, looked up after adding it: if the path was swapped in
    // between, the next poll tick sees the difference and watches the path's directory anew.
    struct stat st {};
    if (::stat(dir_.c_str(), &st) != 0) {
        ::inotify_rm_watch(inotifyFd_, wd);
        return false;
    }
    wd_ = wd;
    dirDev_ = static_cast<uint64_t>(st.st_dev);
    dirIno_ = static_cast<uint64_t>(st.st_ino);
    return true;
}

void FileWatch::dropWatch() {
    // A watch on a directory that was renamed away would still report its entries; remove it
    // (its IN_IGNORED then arrives under a descriptor that is no longer wd_ and is skipped).
    if (wd_ >= 0 && inotifyFd_ >= 0) ::inotify_rm_watch(inotifyFd_, wd_);
    wd_ = -1;
}

void FileWatch::closeInotify() {
    if (inotifyFd_ >= 0) ::close(inotifyFd_);
    inotifyFd_ = -1;
    wd_ = -1;
}

bool FileWatch::drainInotify() {
    bool relevant = false, dirLost = false;
    alignas(inotify_event) char buf[16 * 1024];
    while (inotifyFd_ >= 0) {
        const ssize_t n = ::read(inotifyFd_, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) break;
        if (n <= 0) {
            // The descriptor is broken; events may have been lost with it. Start over with a
            // new one at the next poll tick and say the file may have changed.
            closeInotify();
            return true;
        }
        for (ssize_t off = 0; off + static_cast<ssize_t>(sizeof(inotify_event)) <= n;) {
            const auto* ev = reinterpret_cast<const inotify_event*>(buf + off);
            off += static_cast<ssize_t>(sizeof(inotify_event) + ev->len);
            if (ev->mask & IN_Q_OVERFLOW) {
                relevant = true; // the kernel dropped events: ours may have been among them
                continue;
            }
            if (wd_ < 0 || ev->wd != wd_) continue; // a watch already dropped
            if (ev->len == 0) {
                // No name: about the directory itself. Only its going away matters.
                if (ev->mask & kDirGone) {
                    dropWatch();
                    dirLost = relevant = true;
                }
                continue;
            }
            if (name_ == ev->name) {
                relevant = true;
                // A close after writing, or a rename onto the name, is how a save ends; any
                // other event (a modify, a truncate, a delete) may be followed by more.
                saved_ = (ev->mask & (IN_CLOSE_WRITE | IN_MOVED_TO)) != 0;
            }
        }
    }
    // Try again at once: a directory replaced by a rename is already there. If it is not, the
    // poll ticks keep trying.
    if (dirLost) ensureWatch();
    // What inotify reported is now known; the safety net must not report it a second time.
    if (relevant) last_ = snapshot();
    return relevant;
}

bool FileWatch::pollTick() {
    bool event = false;
    // The watch follows the directory's inode, the user means its path: if the path now names
    // another directory (a parent was renamed, the directory replaced), watch that one.
    if (wd_ >= 0) {
        struct stat st {};
        if (::stat(dir_.c_str(), &st) != 0 || static_cast<uint64_t>(st.st_dev) != dirDev_ ||
            static_cast<uint64_t>(st.st_ino) != dirIno_) {
            dropWatch();
            event = true;
        }
    }
    if (ensureWatch()) event = true; // watching again after a blind spell: look at the file
    const Snapshot now = snapshot();
    if (!(now == last_)) {
        last_ = now;
        event = true;
    }
    return event;
}

void FileWatch::markEvent(Clock::time_point now) {
    if (!pending_) {
        pending_ = true;
        batchFirst_ = now;
    }
    batchLast_ = now;
}

FileWatch::Wait FileWatch::wait(std::chrono::milliseconds timeout) {
    const Clock::time_point start = Clock::now();
    Clock::time_point deadline = start;
    if (timeout > 0ms) {
        const auto room =
            std::chrono::duration_cast<std::chrono::milliseconds>(Clock::time_point::max() - start);
        deadline = timeout >= room ? Clock::time_point::max() : start + timeout;
    }
    const auto maxBatch = std::max(kMaxBatchFloor, 10 * options_.debounce);
    // When the batch's last event ended a save (IN_CLOSE_WRITE, IN_MOVED_TO), the file is
    // whole: only a short grace is left for a save made of several steps. Otherwise the full
    // debounce, since a writer may be between two write() calls.
    //
    // A file left empty by an event that did not end a save is a writer that has truncated it
    // (open with O_TRUNC) and not yet written: on a loaded machine the write can come later
    // than the debounce, and reloading then would draw an empty scene for a moment. So that
    // state waits for the close (or the batch's age limit); an empty file saved on purpose
    // ends with a close and is reported at once.
    const auto reportAt = [&] {
        if (!saved_ && last_.exists && last_.size == 0) return batchFirst_ + maxBatch;
        const auto quiet = saved_ ? std::min(options_.debounce, kSavedGrace) : options_.debounce;
        return std::min(batchLast_ + quiet, batchFirst_ + maxBatch);
    };

    for (;;) {
        Clock::time_point wake = std::min(deadline, nextPoll_);
        if (pending_) wake = std::min(wake, reportAt());
        const timespec ts = toTimespec(wake - Clock::now());

        pollfd fds[2] = {{eventFd_, POLLIN, 0}, {inotifyFd_, POLLIN, 0}};
        const nfds_t nfds = inotifyFd_ >= 0 ? 2 : 1;
        const int r = ::ppoll(fds, nfds, &ts, nullptr);
        if (r < 0 && errno != EINTR) {
            // EINVAL/ENOMEM: nothing to watch with this round; sleep instead of spinning.
            ::nanosleep(&ts, nullptr);
        }
        const Clock::time_point now = Clock::now();

        if (r > 0 && fds[0].revents != 0) {
            uint64_t count;
            [[maybe_unused]] ssize_t n = ::read(eventFd_, &count, sizeof count);
            return Wait::Interrupted; // pending events stay for the next wait
        }
        if (r > 0 && nfds == 2 && fds[1].revents != 0) {
            if (fds[1].revents & POLLIN) {
                if (drainInotify()) markEvent(now);
            } else { // POLLERR/POLLNVAL: the descriptor is unusable; degrade to polling
                closeInotify();
                markEvent(now);
            }
        }
        if (now >= nextPoll_) {
            if (pollTick()) {
                saved_ = false; // the safety net cannot tell whether a writer is done
                markEvent(now);
            }
            nextPoll_ = now + options_.poll;
        }
        if (pending_ && now >= reportAt()) {
            pending_ = false;
            firstEvent_ = batchFirst_;
            last_ = snapshot();
            return Wait::Changed;
        }
        if (now >= deadline) return Wait::Timeout;
    }
}

} // namespace moire

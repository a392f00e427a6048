#include "runtime/output/OutputFile.h"

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <regex>
#include <sys/stat.h>
#include <unistd.h>

namespace moire {

namespace fs = std::filesystem;

namespace {

IoError cannotWrite(const std::string& path, int error) {
    return IoError(fmt::format("cannot write '{}': {}", path, std::strerror(error)));
}

// When process `pid` started, in clock ticks after boot (field 22 of /proc/PID/stat), or 0
// when that cannot be read. With the pid it names a process for good: a pid is reused, the
// pair is not.
unsigned long long startTimeOf(pid_t pid) {
    char path[64];
    std::snprintf(path, sizeof path, "/proc/%d/stat", static_cast<int>(pid));
    int fd = ::open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    char buf[1024];
    ssize_t n;
    while ((n = ::read(fd, buf, sizeof buf - 1)) < 0 && errno == EINTR) {
    }
    ::close(fd);
    if (n <= 0) return 0;
    buf[n] = '\0';
    // The command name (field 2) is in parentheses and may hold spaces: count from after it.
    const char* p = std::strrchr(buf, ')');
    if (!p) return 0;
    ++p;
    for (int field = 3; field < 22 && *p; ++field) {
        while (*p == ' ') ++p;
        while (*p && *p != ' ') ++p;
    }
    return std::strtoull(p, nullptr, 10);
}

// Kept with the pid it was read for: a child forked without exec has a start time of its own.
unsigned long long ownStartTime() {
    static std::atomic<pid_t> pid{0};
    static std::atomic<unsigned long long> start{0};
    const pid_t me = ::getpid();
    if (pid.load() != me) {
        start = startTimeOf(me);
        pid = me;
    }
    return start;
}

// Removes `temp` on the way out of a failed write, keeping errno for the message.
void removeQuietly(const std::string& temp) {
    int saved = errno;
    ::unlink(temp.c_str());
    errno = saved;
}

std::string directoryOf(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    return dir.empty() ? "." : dir.string();
}

} // namespace

std::string temporaryBeside(const std::string& target) {
    static std::atomic<unsigned> counter{0};
    const fs::path t(target);
    const std::string name = fmt::format(".{}.{}-{}-{}.tmp{}", t.stem().string(), ::getpid(),
                                         ownStartTime(), counter++, t.extension().string());
    return t.has_parent_path() ? (t.parent_path() / name).string() : name;
}

namespace {

// Writes every byte to `fd`; returns 0, or the errno of the write that failed.
int writeAll(int fd, const void* data, size_t size) {
    const char* p = static_cast<const char*>(data);
    size_t left = size;
    while (left > 0) {
        // A file size limit (RLIMIT_FSIZE) shows up here as EFBIG because main() ignores
        // SIGXFSZ; a full disk as ENOSPC, possibly after a short write.
        ssize_t n = ::write(fd, p, left);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return errno;
        if (n == 0) return EIO;
        p += n;
        left -= static_cast<size_t>(n);
    }
    return 0;
}

} // namespace

void writeStandardOutput(const void* data, size_t size) {
    // A closed pipe is EPIPE here rather than a SIGPIPE that ends moire with nothing said.
    struct sigaction ignore = {};
    struct sigaction old = {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGPIPE, &ignore, &old);
    const int error = writeAll(STDOUT_FILENO, data, size);
    ::sigaction(SIGPIPE, &old, nullptr);
    if (error)
        throw IoError(fmt::format("cannot write to standard output: {}", std::strerror(error)));
}

namespace {
// An existing destination that is not a file (a device such as /dev/null, a FIFO, a socket):
// it is written into, not replaced. Renaming over it would put a regular file in the place
// of a device node, and a half-written stream is what a reader of one expects anyway.
bool isStream(const std::string& path) {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}
} // namespace

AtomicFile::AtomicFile(const std::string& path) : path_(path) {
    if (isStream(path_)) {
        fd_ = ::open(path_.c_str(), O_WRONLY | O_CLOEXEC);
        if (fd_ < 0) throw cannotWrite(path_, errno);
        return;
    }
    temp_ = temporaryBeside(path);
    // O_EXCL: the name is ours alone; never follow a link someone left in its place.
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd_ < 0) throw cannotWrite(path_, errno);
}

AtomicFile::~AtomicFile() {
    if (fd_ >= 0) {
        ::close(fd_);
        if (!temp_.empty()) removeQuietly(temp_);
    }
}

void AtomicFile::fail(int error) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (!temp_.empty()) removeQuietly(temp_);
    throw cannotWrite(path_, error);
}

void AtomicFile::write(const void* data, size_t size) {
    if (fd_ < 0) throw cannotWrite(path_, EBADF);
    if (int error = writeAll(fd_, data, size)) fail(error);
}

void AtomicFile::commit() {
    if (fd_ < 0) throw cannotWrite(path_, EBADF);
    if (temp_.empty()) { // a stream: written in place (isStream)
        int rc = ::close(fd_);
        fd_ = -1;
        if (rc != 0 && errno != EINTR) throw cannotWrite(path_, errno);
        return;
    }
    // A file that is replaced keeps its permissions (a scene the viewer writes the placement
    // into, an image someone made read-only for others); a new one gets 0666 less the umask.
    struct stat before {};
    if (::stat(path_.c_str(), &before) == 0 && S_ISREG(before.st_mode) &&
        ::fchmod(fd_, before.st_mode & 07777) != 0)
        fail(errno);
    // Delayed allocation can leave ENOSPC for fsync or close to report; and without the
    // fsync a crash soon after the rename could leave an empty file under the final name.
    if (::fsync(fd_) != 0) fail(errno);
    int rc = ::close(fd_);
    fd_ = -1;
    // On Linux the descriptor is released even when close reports EINTR; nothing was lost.
    if (rc != 0 && errno != EINTR) {
        int error = errno;
        removeQuietly(temp_);
        throw cannotWrite(path_, error);
    }
    if (::rename(temp_.c_str(), path_.c_str()) != 0) {
        int error = errno;
        removeQuietly(temp_);
        throw cannotWrite(path_, error);
    }
}

void writeFileAtomically(const std::string& path, const void* data, size_t size) {
    AtomicFile file(path);
    file.write(data, size);
    file.commit();
}

void commitTemporary(const std::string& temp, const std::string& path) {
    if (isStream(path)) { // copied into it, never renamed over it (isStream)
        std::string bytes;
        std::ifstream in(temp, std::ios::binary);
        bytes.assign(std::istreambuf_iterator<char>(in), {});
        const bool read = in.good() || in.eof();
        removeQuietly(temp);
        if (!read) throw cannotWrite(path, EIO);
        writeFileAtomically(path, bytes.data(), bytes.size());
        return;
    }
    int fd = ::open(temp.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        int e = errno;
        removeQuietly(temp);
        throw cannotWrite(path, e);
    }
    if (::fsync(fd) != 0) {
        int e = errno;
        ::close(fd);
        removeQuietly(temp);
        throw cannotWrite(path, e);
    }
    ::close(fd);
    if (::rename(temp.c_str(), path.c_str()) != 0) {
        int e = errno;
        removeQuietly(temp);
        throw cannotWrite(path, e);
    }
}

void prepareOutputDirectory(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) return;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw IoError(fmt::format("cannot write into '{}': {}", dir.string(),
                                  ec ? ec.message() : "it is not a directory"));
}

int removeStaleTemporaries(const std::string& path) {
    // .<stem>.<pid>-<start>-<n>.tmp<ext>, and the names before the start time was recorded
    // (.<stem>.<pid>-<n>.tmp<ext>), which only a vanished pid can clear.
    static const std::regex pattern(
        R"(^\..+\.([0-9]+)-(?:([0-9]+)-)?[0-9]+\.tmp(\.[A-Za-z0-9]+)?$)");
    int removed = 0;
    std::error_code ec;
    fs::directory_iterator it(directoryOf(path), ec);
    if (ec) return 0;
    const uid_t me = ::geteuid();
    for (const fs::directory_entry& entry : it) {
        const std::string name = entry.path().filename().string();
        std::smatch m;
        if (name.empty() || name[0] != '.' || !std::regex_match(name, m, pattern)) continue;
        struct stat st {};
        if (::lstat(entry.path().c_str(), &st) != 0 || !S_ISREG(st.st_mode) || st.st_uid != me)
            continue;
        errno = 0;
        const long long pid = std::strtoll(m[1].str().c_str(), nullptr, 10);
        if (pid <= 0 || pid > 0x3fffffff) continue;
        bool gone = ::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH;
        if (!gone && m[2].matched) {
            // The number is in use: by the writer itself, or by a later process that was
            // given the same number after the writer died.
            unsigned long long recorded = std::strtoull(m[2].str().c_str(), nullptr, 10);
            unsigned long long now = startTimeOf(static_cast<pid_t>(pid));
            gone = now != 0 && recorded != 0 && now != recorded;
        }
        if (gone && ::unlink(entry.path().c_str()) == 0) ++removed;
    }
    return removed;
}

} // namespace moire

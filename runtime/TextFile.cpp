#include "runtime/TextFile.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

namespace moire {

namespace {

std::string tooLong() {
    return fmt::format("it is longer than {} MiB, the most a scene may be", kMaxSourceBytes >> 20);
}

// Reads `fd` to its end, or until it has given more than kMaxSourceBytes (then false).
bool readBounded(int fd, std::string& text, std::string& reason) {
    std::string buffer;
    size_t used = 0;
    for (;;) {
        if (buffer.size() - used < 65536)
            buffer.resize(std::min(buffer.size() + (size_t{1} << 20), kMaxSourceBytes + 1));
        if (used == buffer.size()) {
            reason = tooLong();
            return false;
        }
        const ssize_t n = ::read(fd, buffer.data() + used, buffer.size() - used);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            reason = std::strerror(errno);
            return false;
        }
        if (n == 0) break;
        used += static_cast<size_t>(n);
    }
    buffer.resize(used);
    text = std::move(buffer);
    return true;
}

class Fd {
  public:
    explicit Fd(int fd) : fd_(fd) {}
    ~Fd() {
        if (fd_ >= 0) ::close(fd_);
    }
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    int get() const { return fd_; }

  private:
    int fd_;
};

} // namespace

bool readWholeFile(const std::string& path, std::string& text, std::string& reason) {
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer (forever). The
    // kind of file is then asked of the descriptor opened, not of the name, which may have
    // changed in between.
    Fd fd(::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC));
    if (fd.get() < 0) {
        reason = std::strerror(errno);
        return false;
    }
    struct stat st {};
    if (::fstat(fd.get(), &st) != 0) {
        reason = std::strerror(errno);
        return false;
    }
    if (!S_ISREG(st.st_mode)) {
        reason = S_ISDIR(st.st_mode)                          ? "it is a directory"
                 : S_ISFIFO(st.st_mode)                       ? "it is a FIFO, not a file"
                 : S_ISSOCK(st.st_mode)                       ? "it is a socket, not a file"
                 : S_ISCHR(st.st_mode) || S_ISBLK(st.st_mode) ? "it is a device, not a file"
                                                              : "it is not a regular file";
        return false;
    }
    if (static_cast<uint64_t>(st.st_size) > kMaxSourceBytes) {
        reason = tooLong();
        return false;
    }
    // A regular file never blocks; the bound holds even if it grows while being read.
    return readBounded(fd.get(), text, reason);
}

bool readStandardInput(std::string& text, std::string& reason) {
    return readBounded(STDIN_FILENO, text, reason);
}

} // namespace moire

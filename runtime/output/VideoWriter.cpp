#include "runtime/output/VideoWriter.h"

#include "compiler/lower/Rational.h"
#include "runtime/output/OutputFile.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace moire {

namespace fs = std::filesystem;

std::optional<VideoFormat> videoFormatOf(const std::string& path) {
    std::string ext = fs::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".mp4") return VideoFormat::Mp4;
    if (ext == ".webm") return VideoFormat::WebM;
    if (ext == ".gif") return VideoFormat::Gif;
    return std::nullopt;
}

const char* extensionOf(VideoFormat format) {
    switch (format) {
    case VideoFormat::Mp4:
        return ".mp4";
    case VideoFormat::WebM:
        return ".webm";
    case VideoFormat::Gif:
        break;
    }
    return ".gif";
}

std::string findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    if (!path) return "";
    std::string_view dirs = path;
    for (;;) {
        size_t end = std::min(dirs.find(':'), dirs.size());
        // An empty entry means the current directory, as the shell reads it.
        fs::path candidate =
            fs::path(end == 0 ? std::string_view(".") : dirs.substr(0, end)) / name;
        struct stat st {};
        if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) &&
            ::access(candidate.c_str(), X_OK) == 0)
            return candidate.string();
        if (end == dirs.size()) return "";
        dirs.remove_prefix(end + 1);
    }
}

std::string videoSizeProblem(VideoFormat format, int width, int height) {
    // yuv420p stores colour at half resolution in both directions, and libx264 refuses a
    // picture whose sides do not halve evenly.
    if (format == VideoFormat::Mp4 && (width % 2 != 0 || height % 2 != 0))
        return fmt::format("H.264 video (.mp4, yuv420p) needs an even width and height, not "
                           "{}x{}; use --size {}x{}",
                           width, height, width + width % 2, height + height % 2);
    return "";
}

int64_t gifFinalDelay(double fps, int64_t frames) {
    // Frame k starts at round(100 k / fps) centiseconds, as ffmpeg rounds each frame's time
    // into the GIF's time base (to nearest, halves away from zero); the last frame lasts until
    // the clip's end, round(100 N / fps). Exact in integers when the rate is a fraction.
    if (frames < 1) return 0;
    Rational r = approximate(fps, 1001);
    auto start = [&](int64_t k) -> int64_t {
        if (std::fabs(r.value() - fps) <= 1e-12 * fps && r.num > 0) {
            __int128 num = static_cast<__int128>(k) * 100 * r.den; // k / fps = k den / num
            return static_cast<int64_t>((2 * num + r.num) / (2 * static_cast<__int128>(r.num)));
        }
        return std::llround(100.0 * static_cast<double>(k) / fps);
    };
    return start(frames) - start(frames - 1);
}

std::vector<std::string> ffmpegArguments(VideoFormat format, int width, int height, double fps,
                                         int64_t frames, const std::string& output) {
    // The rate as a fraction when it is one (24, 30000/1001), so the container's time base
    // is exact; otherwise every digit of the double.
    Rational r = approximate(fps, 1001);
    std::string rate = std::fabs(r.value() - fps) <= 1e-12 * fps
                           ? fmt::format("{}/{}", r.num, r.den)
                           : fmt::format("{:.17g}", fps);
    // -xerror: ffmpeg 5 reports a failed write of the file ("Error writing trailer of
    // v.mp4: No space left on device") and still exits 0 without it, leaving a truncated
    // video that would be renamed into place.
    std::vector<std::string> args = {"-hide_banner",
                                     "-nostdin",
                                     "-nostats",
                                     "-loglevel",
                                     "error",
                                     "-xerror",
                                     "-y",
                                     "-f",
                                     "rawvideo",
                                     "-pix_fmt",
                                     "rgba",
                                     "-video_size",
                                     fmt::format("{}x{}", width, height),
                                     "-framerate",
                                     rate,
                                     "-i",
                                     "pipe:0",
                                     "-an"};
    // The frames are sRGB: convert with (and tag) BT.709 primaries and matrix, so players do
    // not assume the BT.601 matrix ffmpeg would otherwise use without saying so.
    const std::vector<std::string> colour = {
        "-vf",
        "scale=out_color_matrix=bt709:out_range=tv,format=yuv420p",
        "-colorspace",
        "bt709",
        "-color_primaries",
        "bt709",
        "-color_trc",
        "iec61966-2-1"};
    switch (format) {
    case VideoFormat::Mp4:
        args.insert(args.end(), colour.begin(), colour.end());
        // A fixed thread count: libx264 splits its work, and writes its settings into the
        // file, by the number of threads, which by default follows the cores it sees; fixed,
        // the same frames give the same file on any machine (a farm's join must equal a clip).
        for (const char* a : {"-c:v", "libx264", "-preset", "medium", "-crf", "18", "-threads", "8",
                              "-movflags", "+faststart", "-f", "mp4"})
            args.push_back(a);
        break;
    case VideoFormat::WebM:
        args.insert(args.end(), colour.begin(), colour.end());
        // -b:v 0 makes -crf a constant quality rather than a cap on a target bitrate.
        // +bitexact: the Matroska muxer otherwise draws a random segment UID each run, and the
        // same frames would not give the same file twice (a farm's join must equal a clip).
        for (const char* a : {"-c:v", "libvpx-vp9", "-crf", "30", "-b:v", "0", "-row-mt", "1",
                              "-fflags", "+bitexact", "-f", "webm"})
            args.push_back(a);
        break;
    case VideoFormat::Gif:
        // One palette for the whole clip, so colours do not flicker from frame to frame;
        // ffmpeg holds the frames until the palette is known.
        for (const char* a :
             {"-filter_complex",
              "[0:v]split[a][b];[a]palettegen=stats_mode=full[p];[b][p]paletteuse", "-loop", "0"})
            args.push_back(a);
        // Each frame's delay is the difference of its start and the next one's, so the
        // delays add up to the clip's length exactly; but ffmpeg rounds the last frame's
        // duration on its own (8.33 cs at 12 fps became 9, and an 8 s loop 8.01 s), so it
        // is given here.
        if (frames > 0) {
            args.push_back("-final_delay");
            args.push_back(fmt::format("{}", gifFinalDelay(fps, frames)));
        }
        args.push_back("-f");
        args.push_back("gif");
        break;
    }
    args.push_back(output);
    return args;
}

VideoWriter::VideoWriter(const std::string& ffmpeg, const std::string& path, VideoFormat format,
                         int width, int height, double fps, int64_t frames)
    : path_(path), width_(width), height_(height) {
    temp_ = temporaryBeside(path);
    int in[2], err[2];
    // Close-on-exec, so that no other child inherits a copy of the pipe (ffmpeg would then
    // never see the end of its input).
    if (::pipe2(in, O_CLOEXEC) != 0)
        throw IoError(fmt::format("cannot start ffmpeg: {}", std::strerror(errno)));
    if (::pipe2(err, O_CLOEXEC) != 0) {
        int e = errno;
        ::close(in[0]), ::close(in[1]);
        throw IoError(fmt::format("cannot start ffmpeg: {}", std::strerror(e)));
    }
    std::vector<std::string> args = ffmpegArguments(format, width, height, fps, frames, temp_);
    std::vector<char*> argv;
    std::string program = ffmpeg;
    argv.push_back(program.data());
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, in[0], 0);
    posix_spawn_file_actions_addopen(&actions, 1, "/dev/null", O_WRONLY, 0);
    posix_spawn_file_actions_adddup2(&actions, err[1], 2);
    posix_spawnattr_t attr;
    posix_spawnattr_init(&attr);
    // Its own process group: a Ctrl-C at the terminal reaches moire alone, which then
    // decides what becomes of the video, instead of ffmpeg finishing it on its own.
    sigset_t none, defaults;
    sigemptyset(&none);
    sigemptyset(&defaults);
    for (int s : {SIGINT, SIGTERM, SIGPIPE}) sigaddset(&defaults, s);
    posix_spawnattr_setpgroup(&attr, 0);
    posix_spawnattr_setsigmask(&attr, &none);
    posix_spawnattr_setsigdefault(&attr, &defaults);
    posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGMASK |
                                        POSIX_SPAWN_SETSIGDEF);
    int rc = posix_spawn(&pid_, program.c_str(), &actions, &attr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    posix_spawnattr_destroy(&attr);
    ::close(in[0]);
    ::close(err[1]);
    if (rc != 0) {
        ::close(in[1]);
        ::close(err[0]);
        pid_ = -1;
        throw IoError(fmt::format("cannot start {}: {}", program, std::strerror(rc)));
    }
    stdin_ = in[1];
    stderr_ = err[0];
    // Drain ffmpeg's stderr as it comes, so that it never blocks on a full pipe, keeping the
    // end of it for a failure message.
    errReader_ = std::thread([this] {
        char buf[4096];
        for (;;) {
            ssize_t n = ::read(stderr_, buf, sizeof buf);
            if (n < 0 && errno == EINTR) continue;
            if (n <= 0) break;
            errTail_.append(buf, static_cast<size_t>(n));
            if (errTail_.size() > 16384) errTail_.erase(0, errTail_.size() - 8192);
        }
    });
    buffer_.resize(static_cast<size_t>(width) * height * 4);
}

VideoWriter::~VideoWriter() {
    if (!done_) discard();
}

void VideoWriter::write(const Image& image) {
    if (done_ || stdin_ < 0) throw IoError("internal: writing to a finished video");
    if (image.width != width_ || image.height != height_ || image.channels < 4)
        throw IoError("internal: a video frame of the wrong size");
    // 8 bits a channel, rounded as the 8-bit PNG writer rounds.
    unsigned char* dst = buffer_.data();
    for (int y = 0; y < height_; ++y) {
        const float* src = image.row(y);
        for (int x = 0; x < width_; ++x)
            for (int c = 0; c < 4; ++c) *dst++ = toByte(src[x * image.channels + c]);
    }
    size_t off = 0;
    while (off < buffer_.size()) {
        ssize_t n = ::write(stdin_, buffer_.data() + off, buffer_.size() - off);
        if (n < 0 && errno == EINTR) continue;
        // EPIPE (SIGPIPE is ignored while a clip runs): ffmpeg has stopped reading.
        if (n < 0) throw IoError(failure("ffmpeg stopped taking frames"));
        off += static_cast<size_t>(n);
    }
}

int VideoWriter::wait() {
    if (stdin_ >= 0) ::close(stdin_), stdin_ = -1;
    // ffmpeg is waited for once; later calls (finish() reporting through failure()) read the
    // status kept then, where a second waitpid would find no child and report success.
    if (pid_ > 0) {
        int status = 0;
        pid_t got;
        while ((got = ::waitpid(pid_, &status, 0)) < 0 && errno == EINTR) {
        }
        pid_ = -1;
        if (got < 0)
            status_ = -SIGKILL; // no child to ask: never read that as success
        else
            status_ = WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
    }
    if (errReader_.joinable()) errReader_.join();
    if (stderr_ >= 0) ::close(stderr_), stderr_ = -1;
    return status_;
}

std::string VideoWriter::failure(const std::string& what) {
    int status = wait();
    std::error_code ec;
    fs::remove(temp_, ec);
    done_ = true;
    // The last few lines of what ffmpeg said, on one line each.
    std::string tail = errTail_;
    while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r')) tail.pop_back();
    size_t from = tail.size();
    for (int lines = 0; lines < 4 && from != std::string::npos && from > 0; ++lines)
        from = tail.rfind('\n', from - 1);
    if (from != std::string::npos && from < tail.size()) tail = tail.substr(from + 1);
    // ffmpeg names the temporary it was writing: name the user's file instead.
    for (size_t at; !temp_.empty() && (at = tail.find(temp_)) != std::string::npos;)
        tail.replace(at, temp_.size(), path_);
    std::string how =
        status >= 0 ? fmt::format("exit status {}", status) : fmt::format("signal {}", -status);
    return fmt::format("cannot write '{}': {} ({}){}{}", path_, what, how,
                       tail.empty() ? "" : "; ffmpeg said:\n", tail);
}

void VideoWriter::finish() {
    if (done_) throw IoError("internal: finishing a finished video");
    int status = wait();
    if (status != 0) throw IoError(failure("ffmpeg failed"));
    done_ = true;
    commitTemporary(temp_, path_); // removes the temporary when it throws
}

void VideoWriter::discard() {
    if (done_) return;
    if (pid_ > 0) ::kill(pid_, SIGKILL);
    wait();
    std::error_code ec;
    fs::remove(temp_, ec);
    done_ = true;
}

ClipOutput::ClipOutput(std::function<std::string(int64_t)> nameOf, WriteOptions options,
                       int inFlight)
    : nameOf_(std::move(nameOf)), options_(options),
      inFlight_(static_cast<size_t>(std::max(1, inFlight))) {}

ClipOutput::ClipOutput(std::unique_ptr<VideoWriter> video) : video_(std::move(video)) {}

ClipOutput::~ClipOutput() {
    abandon();
}

int ClipOutput::defaultInFlight() {
    // Measured at 1080p (bench/clip_bench.cpp): writing a PNG takes one core about 0.25 s,
    // while the default scene's frame takes about 1.4 s of core time to render, so one
    // writer for every four or five cores keeps writing off the critical path; lighter
    // scenes want a little more, hence four.
    return std::clamp(static_cast<int>(std::thread::hardware_concurrency()) / 4, 1, 8);
}

void ClipOutput::waitOldest() {
    std::future<void> f = std::move(pending_.front());
    pending_.pop_front();
    f.get(); // rethrows the write's IoError
}

void ClipOutput::add(int64_t n, Image image) {
    while (pending_.size() >= inFlight_) waitOldest();
    // A video takes its frames in order, so it has one write in flight at a time.
    if (video_)
        pending_.push_back(std::async(
            std::launch::async, [v = video_.get(), img = std::move(image)] { v->write(img); }));
    else
        pending_.push_back(std::async(
            std::launch::async, [name = nameOf_(n), options = options_, img = std::move(image)] {
                writeImage(name, img, options);
            }));
}

void ClipOutput::finish() {
    std::exception_ptr first;
    while (!pending_.empty()) {
        try {
            waitOldest();
        } catch (...) {
            if (!first) first = std::current_exception();
        }
    }
    if (first) std::rethrow_exception(first);
    if (video_) video_->finish();
}

std::string ClipOutput::abandon() {
    std::string error;
    while (!pending_.empty()) {
        try {
            waitOldest();
        } catch (const std::exception& e) {
            if (error.empty()) error = e.what();
        }
    }
    if (video_) video_->discard();
    return error;
}

} // namespace moire

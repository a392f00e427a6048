// Writing a video by piping raw 8-bit RGBA frames to an installed ffmpeg:
//   .mp4   H.264 (libx264), yuv420p: even width and height only
//   .webm  VP9 (libvpx-vp9), yuv420p, constant quality
//   .gif   a palette computed over the whole clip (palettegen, then paletteuse)
// ffmpeg writes to a temporary name beside the target, renamed into place only when it has
// finished successfully: a reader never sees half a video, and a clip that fails or is
// interrupted leaves any earlier file of that name untouched. Video carries no alpha.
#pragma once

#include "runtime/Image.h"
#include "runtime/output/ImageIO.h"

#include <csignal>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <sys/types.h>
#include <thread>
#include <vector>

namespace moire {

enum class VideoFormat { Mp4, WebM, Gif };

// The video format named by a path's extension, if it names one.
std::optional<VideoFormat> videoFormatOf(const std::string& path);
const char* extensionOf(VideoFormat format); // ".mp4", ".webm", ".gif"

// `name` found on $PATH as an executable file, or "" when it is not there.
std::string findOnPath(const std::string& name);

// Why `format` cannot hold a width x height picture, or "" when it can.
std::string videoSizeProblem(VideoFormat format, int width, int height);

// ffmpeg's arguments (after the program name) for `frames` raw RGBA frames on stdin to
// `output` (frames < 1: a count not known in advance).
std::vector<std::string> ffmpegArguments(VideoFormat format, int width, int height, double fps,
                                         int64_t frames, const std::string& output);
// The last frame's delay in a GIF of `frames` frames, in centiseconds: the clip's end less
// the last frame's start, both rounded as ffmpeg rounds frame times, so that the delays of a
// GIF add up to its length exactly.
int64_t gifFinalDelay(double fps, int64_t frames);

class VideoWriter {
  public:
    // Starts `ffmpeg` (a path) writing `frames` frames to a temporary beside `path` (frames
    // < 1: not known in advance). Throws IoError.
    VideoWriter(const std::string& ffmpeg, const std::string& path, VideoFormat format, int width,
                int height, double fps, int64_t frames = 0);
    // Discards the video unless finish() succeeded.
    ~VideoWriter();
    VideoWriter(const VideoWriter&) = delete;
    VideoWriter& operator=(const VideoWriter&) = delete;

    // Sends one frame (straight sRGB RGBA, the writer's size). Throws IoError if ffmpeg has
    // failed, with the end of what it printed.
    void write(const Image& image);
    // Ends the stream, waits for ffmpeg and moves the video into place. Throws IoError.
    void finish();
    // Stops ffmpeg and removes the temporary; the target is not touched. Never throws.
    void discard();

  private:
    // Waits for ffmpeg (once: later calls return the status kept); returns its exit status,
    // or -signal.
    int wait();
    std::string failure(const std::string& what);

    std::string path_, temp_;
    int width_, height_;
    pid_t pid_ = -1;
    int status_ = -SIGKILL; // ffmpeg's status once waited for
    int stdin_ = -1, stderr_ = -1;
    std::thread errReader_;
    std::string errTail_; // the end of ffmpeg's stderr, filled by errReader_
    std::vector<unsigned char> buffer_;
    bool done_ = false;
};

// Where a clip's frames go, written in the background while later frames render: numbered
// images, several at once (PNG compression is single-threaded and, on many cores, slower
// than rendering a frame), or one video, fed in order. Every image is complete once written
// (writeImage renames it into place).
class ClipOutput {
  public:
    // Numbered images, frame n to nameOf(n), at most `inFlight` being written at any time.
    ClipOutput(std::function<std::string(int64_t)> nameOf, WriteOptions options, int inFlight);
    explicit ClipOutput(std::unique_ptr<VideoWriter> video);
    // Waits for writes in progress; discards a video that was not finished.
    ~ClipOutput();
    ClipOutput(const ClipOutput&) = delete;
    ClipOutput& operator=(const ClipOutput&) = delete;

    // Queues frame n; first waits for the oldest write when `inFlight` are going. Throws
    // the IoError of any earlier write that failed.
    void add(int64_t n, Image image);
    // Waits for every write and moves a video into place. Throws IoError.
    void finish();
    // Stops: lets the image writes in progress complete, discards a video. Never throws;
    // returns the first write's error, or "" when every frame queued was written.
    std::string abandon();

    // Image writes in flight by default: enough to keep up with rendering on every core.
    static int defaultInFlight();

  private:
    void waitOldest();

    std::function<std::string(int64_t)> nameOf_;
    WriteOptions options_;
    size_t inFlight_ = 1;
    std::unique_ptr<VideoWriter> video_;
    std::deque<std::future<void>> pending_;
};

} // namespace moire

// `moire clip`: the recorder of spec §8.5. It is the clock rather than an observer of it:
// frame n is evaluated at exactly from + n / fps, rendered, written, and only then does the
// clock advance, so the same range recorded twice is the same files twice.
#include "compiler/lower/ClipClock.h"
#include "runtime/cli/ClipNames.h"
#include "runtime/cli/Commands.h"
#include "runtime/cli/Shared.h"
#include "runtime/cli/StopSignals.h"
#include "runtime/FloorNote.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/OutputFile.h"
#include "runtime/output/Render.h"
#include "runtime/output/VideoWriter.h"
#include "runtime/TileExecutor.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <optional>
#include <unistd.h>

namespace moire::cli {

namespace fs = std::filesystem;

namespace {

std::string clockTime(double seconds) {
    long s = std::lround(std::max(0.0, seconds));
    return s >= 3600 ? fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
                     : fmt::format("{}:{:02}", s / 60, s % 60);
}

// The progress line: a bar, frames done of the range, frames a second and time left.
void showProgress(double done, int64_t total, double elapsed) {
    constexpr int kBar = 24;
    int filled = static_cast<int>(kBar * done / static_cast<double>(total));
    double rate = elapsed > 0 ? done / elapsed : 0.0;
    std::string left = rate > 0 ? clockTime((static_cast<double>(total) - done) / rate) : "?";
    fmt::print(stderr, "\rmoire: [{:<{}}] {}/{} frames, {:.2f} fps, {} left ",
               std::string(static_cast<size_t>(std::clamp(filled, 0, kBar)), '#'), kBar,
               static_cast<int64_t>(done), total, rate, left);
    std::fflush(stderr);
}

int usage(const std::string& message) {
    fmt::print(stderr, "moire: error: {}\n", message);
    return kExitUsage;
}

} // namespace

int clip(const ClipArgs& args) {
    // Everything the command line alone can get wrong is reported before any work is done.
    if (!(std::isfinite(args.fps) && args.fps > 0 && args.fps <= 1000))
        return usage(fmt::format("--fps must be a number of frames a second above 0 and at most "
                                 "1000, not {:g}",
                                 args.fps));
    if (!std::isfinite(args.from)) return usage("--from must be a finite time in seconds");
    if (args.hasTo && !(std::isfinite(args.to) && args.to > args.from))
        return usage(fmt::format("--to ({:g}) must come after --from ({:g})", args.to, args.from));
    int w = 0, h = 0;
    if (!args.size.empty() && !parseSize(args.size, w, h, kMaxFrameSide))
        return usage(fmt::format("--size must be WIDTHxHEIGHT in pixels (1 to {}), not '{}'",
                                 kMaxFrameSide, args.size));
    PixelDepth depth;
    if (!parseDepth(args.depth, depth))
        return usage(fmt::format("--depth must be 8, 16, half or float, not '{}'", args.depth));
    std::string why;
    std::optional<FrameRange> given;
    if (!args.frames.empty() && !(given = parseFrames(args.frames, why))) return usage(why);
    if (!checkBackendArgs(args.backend, args.device)) return kExitUsage;
    CompileOptions compileOptions{.defines = args.defines};
    if (!checkFilterOption(args.filter, compileOptions)) return kExitUsage;
    if (args.output.empty() && !args.plan)
        return usage("clip needs -o: a numbered image name like frames/f_%04d.png, or a video "
                     "(.mp4, .webm, .gif)");

    if (args.output == kStdoutPath)
        return usage("clip writes files (numbered images, or a video renamed into place when "
                     "complete), not standard output");
    const std::optional<VideoFormat> video = videoFormatOf(args.output);
    NamePattern pattern;
    std::string ffmpeg;
    if (!args.output.empty()) {
        std::optional<NamePattern> p = parseNamePattern(args.output, why);
        if (!p) return usage(why);
        pattern = *p;
        if (video && pattern.numbered)
            return usage(
                fmt::format("'{}' is one video file: it takes no frame number", args.output));
        if (video && !args.depth.empty())
            return usage("--depth applies to image frames; video frames are 8-bit");
        if (!video && imageFormatOf(args.output).empty())
            return usage(fmt::format("cannot write '{}': unknown format; use .png, .tif, .exr "
                                     "or .jpg for numbered frames, .mp4, .webm or .gif for a "
                                     "video",
                                     args.output));
        if (video && w > 0) {
            std::string problem = videoSizeProblem(*video, w, h);
            if (!problem.empty()) return usage(problem);
        }
        if (video && !args.plan) {
            ffmpeg = findOnPath("ffmpeg");
            if (ffmpeg.empty()) {
                fmt::print(stderr,
                           "moire: error: writing {} needs ffmpeg (Debian package "
                           "'ffmpeg')\n",
                           extensionOf(*video));
                return kExitIo;
            }
        }
    }

    // From here on a Ctrl-C is answered with status 130 and nothing half-written, whether
    // it comes while the scene compiles or while frame n renders.
    StopSignals signals;
    std::unique_ptr<Backend> backend = openBackend(args.backend, args.device);
    if (!backend) return kExitMachine;
    const auto start = std::chrono::steady_clock::now();
    Stages stages(args.verbosity);
    Source src;
    if (!readScene(args.scene, src)) return kExitIo;
    auto program = compileOrReport(src, compileOptions);
    if (!program) return kExitScene;
    stages.done(fmt::format("compiled {}", src.path));
    FrameValues first;
    std::string diags;
    if (!evaluateFrame(*program, FrameRequest{args.from, w, h, nullptr, kMaxFrameSide}, first,
                       diags)) {
        fmt::print(stderr, "{}", diags);
        return kExitScene;
    }

    // Which frames: as asked, or the timings' loop.
    FrameRange range;
    std::vector<std::string> notes;
    if (given) {
        range = *given;
    } else if (args.hasTo) {
        range = {0, std::max<int64_t>(1, clip::framesBefore(args.from, args.to, args.fps)) - 1};
    } else {
        clip::Motion motion{first.timings, clip::readsClock(*program),
                            clip::movesWithClock(*program)};
        clip::Length length = clip::defaultLength(motion, args.from, args.fps);
        if (!length.error.empty()) return usage(length.error);
        range = {0, length.frames - 1};
        notes = length.notes;
    }
    if (args.plan) {
        for (const std::string& n : notes) fmt::print("note: {}\n", n);
        fmt::print("frames {}..{} ({} frame{}, t = {:.17g} to {:.17g} s, {}x{})\n", range.first,
                   range.last, range.count(), range.count() == 1 ? "" : "s",
                   clip::frameTime(args.from, range.first, args.fps),
                   clip::frameTime(args.from, range.last, args.fps), first.width, first.height);
        return kExitOk;
    }
    if (!args.verbosity.quiet) {
        for (const std::string& n : notes) fmt::print(stderr, "moire: note: {}\n", n);
        fmt::print(stderr, "{}",
                   strokeFloorNotes(*program, compileOptions.filter, first.pixelSize));
    }
    if (!video && !pattern.numbered && range.count() > 1)
        return usage(fmt::format(
            "the clip has {} frames but '{}' names one file: put a frame "
            "number in it, like {}_%04d{}",
            range.count(), args.output,
            (fs::path(args.output).parent_path() / fs::path(args.output).stem()).string(),
            fs::path(args.output).extension().string()));
    if (video) { // the scene's own size (a --size was checked above)
        std::string problem = videoSizeProblem(*video, first.width, first.height);
        if (!problem.empty()) {
            fmt::print(stderr, "moire: error: {}\n", problem);
            return kExitUsage;
        }
    }
    FrameFootprint footprint;
    footprint.width = first.width;
    footprint.height = first.height;
    footprint.channels = program->kernel.numOutputs;
    footprint.sink = video ? FrameSink::Video : FrameSink::ImageFile;
    footprint.format = video ? std::string() : imageFormatOf(args.output);
    // While a frame renders, earlier ones are being written (ClipOutput's writes in flight).
    footprint.queued = video ? 1 : ClipOutput::defaultInFlight();
    footprint.gpu = args.backend == "vulkan";
    if (!checkMemory(footprint)) return kExitMachine;
    // A missing output directory is created, as a shard of a longer clip is usually written
    // to a fresh one; something else in its place is an error. Temporaries that clips killed
    // there earlier left behind go.
    try {
        prepareOutputDirectory(pattern.name(range.first));
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    removeStaleTemporaries(pattern.name(range.first));

    std::unique_ptr<CompiledKernel> kernel;
    std::unique_ptr<ClipOutput> output;
    WriteOptions wo;
    wo.depth = depth;
    // Frames at render's level: frame n is byte for byte the still `render` makes of it.
    wo.threads = args.threads;
    try {
        kernel = backend->compile(program->kernel);
        output =
            video ? std::make_unique<ClipOutput>(
                        std::make_unique<VideoWriter>(ffmpeg, args.output, *video, first.width,
                                                      first.height, args.fps, range.count()))
                  : std::make_unique<ClipOutput>([pattern](int64_t n) { return pattern.name(n); },
                                                 wo, ClipOutput::defaultInFlight());
    } catch (const BackendError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitMachine;
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }

    stages.done(fmt::format("compiled the kernel for {}", describe(*backend)));
    const bool tty = isatty(fileno(stderr)) && !args.verbosity.quiet;
    const auto loopStart = std::chrono::steady_clock::now();
    bool shown = false;
    int64_t done = 0;
    ExecOptions exec;
    exec.threads = args.threads;
    if (tty)
        exec.progress = [&](double fraction) {
            double elapsed = secondsSince(loopStart);
            if (elapsed < 1.0 && !shown) return; // quick clips get no progress line
            showProgress(static_cast<double>(done) + std::min(fraction, 0.999), range.count(),
                         elapsed);
            shown = true;
        };
    auto endLine = [&] {
        if (shown) fmt::print(stderr, "\n");
        shown = false;
    };
    for (int64_t n = range.first; n <= range.last && StopSignals::received() == 0; ++n) {
        FrameValues frame;
        if (!evaluateFrame(
                *program,
                FrameRequest{clip::frameTime(args.from, n, args.fps), w, h, nullptr, kMaxFrameSide},
                frame, diags)) {
            endLine();
            fmt::print(stderr, "{}moire: error: frame {} (t = {:.17g}) cannot be rendered\n", diags,
                       n, clip::frameTime(args.from, n, args.fps));
            return kExitScene;
        }
        try {
            KernelFrame kf{frame.uniforms.data(), frame.width, frame.height};
            output->add(n, runKernel(*kernel, kf, exec));
        } catch (const BackendError& e) {
            endLine();
            fmt::print(stderr, "moire: error: {}\n", e.what());
            return kExitMachine;
        } catch (const IoError& e) {
            endLine();
            fmt::print(stderr, "moire: error: {}\n", e.what());
            return kExitIo;
        }
        ++done;
        if (tty && (shown || secondsSince(loopStart) >= 1.0)) {
            showProgress(static_cast<double>(done), range.count(), secondsSince(loopStart));
            shown = true;
        }
    }
    endLine();

    if (StopSignals::received() != 0) {
        const int status = 128 + StopSignals::received();
        // The frames being written are completed, a video is discarded.
        std::string failed = output->abandon();
        if (!failed.empty()) {
            fmt::print(stderr, "moire: error: {}\n", failed);
            return kExitIo;
        }
        if (video) {
            fmt::print(stderr, "moire: interrupted: {} was not written\n", args.output);
        } else if (done == 0) {
            fmt::print(stderr, "moire: interrupted before the first frame; nothing written\n");
        } else {
            fmt::print(stderr, "moire: interrupted: frames {} to {} are complete ({})\n",
                       range.first, range.first + done - 1, args.output);
        }
        return status;
    }
    try {
        output->finish();
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    stages.done(
        fmt::format("rendered and wrote {} frame{}", range.count(), range.count() == 1 ? "" : "s"));
    if (!args.verbosity.quiet) {
        double seconds = secondsSince(start);
        std::string what =
            video || range.count() == 1
                ? pattern.name(range.first)
                : fmt::format("{} to {}", pattern.name(range.first), pattern.name(range.last));
        fmt::print(stderr,
                   "moire: wrote {} ({} frame{} of {}x{} at {:g} fps, {}, {:.1f} s, "
                   "{:.2f} frames/s)\n",
                   what, range.count(), range.count() == 1 ? "" : "s", first.width, first.height,
                   args.fps, describe(*backend), seconds,
                   static_cast<double>(range.count()) / secondsSince(loopStart));
    }
    return kExitOk;
}

} // namespace moire::cli

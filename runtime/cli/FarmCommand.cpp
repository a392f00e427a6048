// `moire farm clip|render`: the request is checked and the scene compiled here, as a local
// render would, so that a mistake is reported before anything reaches the queue; then the
// work is cut into shards (runtime/farm/FarmPlan.h) and the scripts go to the work
// directory and to sbatch. `moire farm encode` is the join of a video: the shards render
// 8-bit PNG frames, and this feeds them to ffmpeg through the same VideoWriter, with the
// same arguments, as `moire clip` feeds the frames it renders, so the video's bytes are
// those a local clip writes.
#include "runtime/cli/FarmCommand.h"

#include "compiler/lower/ClipClock.h"
#include "runtime/cli/ClipNames.h"
#include "runtime/cli/DefineOption.h"
#include "runtime/cli/Shared.h"
#include "runtime/farm/FarmPlan.h"
#include "runtime/FrameEval.h"
#include "runtime/output/OutputFile.h"
#include "runtime/output/VideoWriter.h"

#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <optional>
#include <spawn.h>
#include <sys/wait.h>

extern char** environ;

namespace moire::cli {

namespace fs = std::filesystem;

namespace {

int usage(const std::string& message) {
    fmt::print(stderr, "moire: error: {}\n", message);
    return kExitUsage;
}

std::string number(double v) {
    return fmt::format("{}", v); // the shortest text that reads back as the same double
}

// What the shards and the join need to know of the request, found as a local run finds it.
struct Request {
    Source source;
    int width = 0, height = 0;
    FrameRange range; // clips
};

// Compiles the scene and evaluates its first frame; for a clip, also decides its frames.
// Prints the reason and returns the exit status when the request cannot be rendered.
int resolve(const FarmArgs& args, Request& out) {
    int w = 0, h = 0;
    if (!args.size.empty() && !parseSize(args.size, w, h))
        return usage(fmt::format("--size must be WIDTHxHEIGHT in pixels (1 to {}), not '{}'",
                                 kMaxImageSide, args.size));
    if (!checkBackendArgs(args.backend, args.device)) return kExitUsage;
    CompileOptions compileOptions{.defines = args.defines};
    if (!checkFilterOption(args.filter, compileOptions)) return kExitUsage;
    if (!readScene(args.scene, out.source)) return kExitIo;
    auto program = compileOrReport(out.source, compileOptions);
    if (!program) return kExitScene;
    const double t = args.mode == FarmArgs::Mode::Clip ? args.from : args.time;
    FrameValues first;
    std::string diags;
    if (!evaluateFrame(*program, FrameRequest{t, w, h}, first, diags)) {
        fmt::print(stderr, "{}", diags);
        return kExitScene;
    }
    out.width = first.width;
    out.height = first.height;
    if (args.mode != FarmArgs::Mode::Clip) return kExitOk;
    std::string why;
    if (!args.frames.empty()) {
        std::optional<FrameRange> given = parseFrames(args.frames, why);
        if (!given) return usage(why);
        out.range = *given;
    } else if (args.hasTo) {
        out.range = {0, std::max<int64_t>(1, clip::framesBefore(args.from, args.to, args.fps)) - 1};
    } else {
        clip::Motion motion{first.timings, clip::readsClock(*program),
                            clip::movesWithClock(*program)};
        clip::Length length = clip::defaultLength(motion, args.from, args.fps);
        if (!length.error.empty()) return usage(length.error);
        out.range = {0, length.frames - 1};
    }
    return kExitOk;
}

// The options every shard passes on as they were given.
std::vector<std::string> sharedOptions(const FarmArgs& args,
                                       const std::vector<std::string>& rawDefines) {
    std::vector<std::string> out;
    if (!args.size.empty()) out.insert(out.end(), {"--size", args.size});
    for (const std::string& d : rawDefines) out.insert(out.end(), {"-D", d});
    if (!args.backend.empty()) out.insert(out.end(), {"--backend", args.backend});
    if (args.device >= 0) out.insert(out.end(), {"--device", fmt::format("{}", args.device)});
    if (args.threads > 0) out.insert(out.end(), {"--threads", fmt::format("{}", args.threads)});
    if (!args.filter.empty()) out.insert(out.end(), {"--filter", args.filter});
    out.insert(out.end(), args.shardArgs.begin(), args.shardArgs.end());
    return out;
}

std::string jobName(const std::string& output) {
    std::string name = "moire-";
    for (char c : fs::path(output).stem().string())
        name += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_' ? c : '_';
    return name;
}

// Runs `bash script`, passing its output through; its exit status.
int runScript(const std::string& script) {
    std::vector<std::string> words = {"bash", script};
    std::vector<char*> argv;
    for (std::string& w : words) argv.push_back(w.data());
    argv.push_back(nullptr);
    pid_t pid = -1;
    int rc = posix_spawnp(&pid, "bash", nullptr, nullptr, argv.data(), environ);
    if (rc != 0) {
        fmt::print(stderr, "moire: error: cannot run bash: {}\n", std::strerror(rc));
        return kExitIo;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// Prints the scripts (--plan), or writes them and the scene into the work directory and
// runs the submission.
int submit(const FarmArgs& args, const farm::FarmJob& job, const Request& request) {
    farm::FarmScripts scripts = farm::makeScripts(job);
    const fs::path dir = job.workdir;
    const std::pair<const char*, const std::string*> files[] = {
        {"shard.sh", &scripts.shard}, {"join.sh", &scripts.join}, {"submit.sh", &scripts.submit}};
    if (args.plan) {
        for (const auto& [name, text] : files)
            fmt::print("==> {} <==\n{}\n", (dir / name).string(), *text);
        return kExitOk;
    }
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_empty(dir, ec))
        return usage(fmt::format("the work directory '{}' is not empty: give each request a "
                                 "new one",
                                 dir.string()));
    if (findOnPath("sbatch").empty()) {
        fmt::print(stderr, "moire: error: sbatch is not on PATH: moire farm submits to Slurm "
                           "(docs/farm.md); --plan prints the scripts without it\n");
        return kExitMachine;
    }
    try {
        fs::create_directories(dir / "logs");
        for (const auto& [name, text] : files) {
            writeFileAtomically((dir / name).string(), text->data(), text->size());
            fs::permissions(dir / name, fs::perms::owner_exec | fs::perms::group_exec,
                            fs::perm_options::add);
        }
        if (!args.scene.empty())
            writeFileAtomically((dir / "scene.moire").string(), request.source.text.data(),
                                request.source.text.size());
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    } catch (const fs::filesystem_error& e) {
        fmt::print(stderr, "moire: error: cannot make the work directory '{}': {}\n", dir.string(),
                   e.code().message());
        return kExitIo;
    }
    if (!args.verbosity.quiet)
        fmt::print(stderr, "moire farm: {} shards; scripts and logs in {}\n", job.shards.size(),
                   dir.string());
    if (args.verbosity.verbose)
        for (size_t i = 0; i < job.shards.size(); ++i)
            fmt::print(stderr, "moire farm: shard {}: {}\n", i, farm::shellCommand(job.shards[i]));
    int status = runScript((dir / "submit.sh").string());
    return status == 0 ? kExitOk : kExitIo;
}

// The parts of a job that clip and render share.
farm::FarmJob baseJob(const FarmArgs& args) {
    farm::FarmJob job;
    job.name = jobName(args.output);
    job.workdir = fs::absolute(args.workdir).lexically_normal().string();
    while (job.workdir.size() > 1 && job.workdir.back() == '/') job.workdir.pop_back();
    job.partition = args.partition;
    job.sbatchArgs = args.sbatchArgs;
    job.wait = args.wait;
    return job;
}

// The scene as the shards read it: the copy in the work directory.
std::vector<std::string> sceneArgument(const FarmArgs& args, const farm::FarmJob& job) {
    if (args.scene.empty()) return {};
    return {job.workdir + "/scene.moire"};
}

std::string moireOnNodes(const FarmArgs& args) {
    // A bare name is looked up on the nodes' PATH; a relative path is made absolute, as the
    // jobs run in the work directory.
    if (!args.moire.empty())
        return args.moire.find('/') == std::string::npos
                   ? args.moire
                   : fs::absolute(args.moire).lexically_normal().string();
    std::error_code ec;
    fs::path self = fs::read_symlink("/proc/self/exe", ec);
    return ec ? std::string("moire") : self.string();
}

int checkFarmOptions(const FarmArgs& args) {
    if (args.shards < 1) return usage("--shards must be 1 or more");
    if (args.output.empty()) return usage("farm needs -o: the file the joined result goes to");
    return kExitOk;
}

int farmClip(const FarmArgs& args, const std::vector<std::string>& rawDefines) {
    if (int rc = checkFarmOptions(args)) return rc;
    if (!(std::isfinite(args.fps) && args.fps > 0 && args.fps <= 1000))
        return usage(fmt::format("--fps must be a number of frames a second above 0 and at most "
                                 "1000, not {:g}",
                                 args.fps));
    std::string why;
    std::optional<NamePattern> pattern = parseNamePattern(args.output, why);
    if (!pattern) return usage(why);
    const std::optional<VideoFormat> video = videoFormatOf(args.output);
    if (video && pattern->numbered)
        return usage(fmt::format("'{}' is one video file: it takes no frame number", args.output));
    if (!video && !pattern->numbered)
        return usage(fmt::format("farm clip writes a video (.mp4, .webm, .gif) or numbered "
                                 "images (frame_%04d.png), not '{}'",
                                 args.output));
    if (video && !args.depth.empty())
        return usage("--depth applies to image frames; video frames are 8-bit");
    Request request;
    if (int rc = resolve(args, request)) return rc;
    if (video) {
        std::string problem = videoSizeProblem(*video, request.width, request.height);
        if (!problem.empty()) return usage(problem);
    }

    farm::FarmJob job = baseJob(args);
    const std::string moire = moireOnNodes(args);
    const std::string output = fs::absolute(args.output).lexically_normal().string();
    // A video's shards render lossless 8-bit frames, which the join encodes in one pass.
    const std::string frames = video ? job.workdir + "/frames/f_%09d.png" : output;
    for (const farm::FrameShard& s :
         farm::splitFrames(request.range.first, request.range.last, args.shards)) {
        std::vector<std::string> cmd = {moire, "clip"};
        for (const std::string& a : sceneArgument(args, job)) cmd.push_back(a);
        cmd.insert(cmd.end(), {"--fps", number(args.fps), "--from", number(args.from), "--frames",
                               fmt::format("{}..{}", s.first, s.last)});
        for (const std::string& a : sharedOptions(args, rawDefines)) cmd.push_back(a);
        if (video)
            cmd.insert(cmd.end(), {"--depth", "8"});
        else if (!args.depth.empty())
            cmd.insert(cmd.end(), {"--depth", args.depth});
        cmd.insert(cmd.end(), {"-o", frames, "-q"});
        job.shards.push_back(cmd);
    }
    const std::string all = fmt::format("{}..{}", request.range.first, request.range.last);
    if (video) {
        job.join.push_back({moire, "farm", "encode", frames, "--frames", all, "--fps",
                            number(args.fps), "-o", output, "-q"});
        job.join.push_back({"rm", "-rf", "--", job.workdir + "/frames"});
    } else {
        // Every shard succeeded, so every frame is in place: nothing is left to join.
        job.join.push_back({"echo", fmt::format("frames {} written to {}", all, output)});
    }
    return submit(args, job, request);
}

int farmRender(const FarmArgs& args, const std::vector<std::string>& rawDefines) {
    if (int rc = checkFarmOptions(args)) return rc;
    const std::string format = imageFormatOf(args.output);
    if (format.empty())
        return usage(fmt::format("cannot write '{}': unknown format; use .png, .tif, .exr or .jpg",
                                 args.output));
    if (!std::isfinite(args.time)) return usage("--time must be a finite time in seconds");
    Request request;
    if (int rc = resolve(args, request)) return rc;

    farm::FarmJob job = baseJob(args);
    const std::string moire = moireOnNodes(args);
    const std::string output = fs::absolute(args.output).lexically_normal().string();
    if (args.dpi != 0.0 && !checkDpi(args.dpi)) return kExitUsage;
    // A JPEG cannot record a tile's place: its tiles are 8-bit PNGs, whose pixels are the
    // bytes the JPEG encoder is given either way.
    const bool jpeg = format == "jpeg";
    const std::string ext = jpeg ? ".png" : fs::path(args.output).extension().string();
    std::vector<std::string> assemble = {moire, "assemble"};
    const std::vector<farm::Region> regions =
        farm::splitRegions(request.width, request.height, args.shards);
    for (size_t i = 0; i < regions.size(); ++i) {
        const farm::Region& r = regions[i];
        std::string tile = fmt::format("{}/tiles/tile_{}{}", job.workdir, i, ext);
        std::vector<std::string> cmd = {moire, "render"};
        for (const std::string& a : sceneArgument(args, job)) cmd.push_back(a);
        cmd.insert(cmd.end(), {"--time", number(args.time)});
        for (const std::string& a : sharedOptions(args, rawDefines)) cmd.push_back(a);
        if (jpeg)
            cmd.insert(cmd.end(), {"--depth", "8"});
        else if (!args.depth.empty())
            cmd.insert(cmd.end(), {"--depth", args.depth});
        if (args.dpi != 0.0) cmd.insert(cmd.end(), {"--dpi", number(args.dpi)});
        cmd.insert(cmd.end(), {"--region", fmt::format("{},{},{},{}", r.x0, r.y0, r.x1, r.y1), "-o",
                               tile, "-q"});
        job.shards.push_back(cmd);
        assemble.push_back(tile);
    }
    if (args.compression >= 0)
        assemble.insert(assemble.end(), {"--compression", fmt::format("{}", args.compression)});
    if (jpeg && !args.depth.empty()) assemble.insert(assemble.end(), {"--depth", args.depth});
    assemble.insert(assemble.end(), {"-o", output, "-q"});
    job.join.push_back(assemble);
    job.join.push_back({"rm", "-rf", "--", job.workdir + "/tiles"});
    return submit(args, job, request);
}

// The join of a video: frames A..B of the numbered PNGs, encoded as `moire clip` encodes.
int farmEncode(const FarmArgs& args) {
    const std::optional<VideoFormat> video = videoFormatOf(args.output);
    if (!video) return usage("farm encode writes a video: -o must end in .mp4, .webm or .gif");
    if (!(std::isfinite(args.fps) && args.fps > 0 && args.fps <= 1000))
        return usage("--fps must be a number of frames a second above 0 and at most 1000");
    std::string why;
    std::optional<NamePattern> pattern = parseNamePattern(args.scene, why);
    if (!pattern) return usage(why);
    if (!pattern->numbered)
        return usage(
            fmt::format("'{}' names one file: give the frames' numbered name", args.scene));
    std::optional<FrameRange> range = parseFrames(args.frames, why);
    if (!range) return usage(args.frames.empty() ? "farm encode needs --frames A..B" : why);
    const std::string ffmpeg = findOnPath("ffmpeg");
    if (ffmpeg.empty()) {
        fmt::print(stderr, "moire: error: writing {} needs ffmpeg (Debian package 'ffmpeg')\n",
                   extensionOf(*video));
        return kExitIo;
    }
    // A write to an ffmpeg that has stopped must fail with EPIPE and be reported, not kill us.
    std::signal(SIGPIPE, SIG_IGN);
    try {
        Image frame = readImage(pattern->name(range->first));
        std::string problem = videoSizeProblem(*video, frame.width, frame.height);
        if (!problem.empty()) return usage(problem);
        prepareOutputDirectory(args.output);
        VideoWriter writer(ffmpeg, args.output, *video, frame.width, frame.height, args.fps,
                           range->count());
        const int width = frame.width, height = frame.height;
        for (int64_t n = range->first; n <= range->last; ++n) {
            if (n != range->first) frame = readImage(pattern->name(n));
            if (frame.width != width || frame.height != height) {
                fmt::print(stderr, "moire: error: '{}' is {}x{}, not {}x{} as the first frame\n",
                           pattern->name(n), frame.width, frame.height, width, height);
                return kExitIo;
            }
            writer.write(frame);
        }
        writer.finish();
    } catch (const IoError& e) {
        fmt::print(stderr, "moire: error: {}\n", e.what());
        return kExitIo;
    }
    if (!args.verbosity.quiet)
        fmt::print(stderr, "moire: wrote {} ({} frames)\n", args.output, range->count());
    return kExitOk;
}

} // namespace

CLI::App* addFarmCommand(CLI::App& app, FarmArgs& args, std::vector<std::string>& rawDefines) {
    CLI::App* farmCmd = app.add_subcommand(
        "farm", "Render a clip or a poster as shards on a Slurm cluster (docs/farm.md)");
    farmCmd->require_subcommand(1);
    const std::string footer =
        "The scripts Slurm runs are written to --workdir and run from there; docs/farm.md\n"
        "describes them. Exit status: 0 submitted (with --wait: done); 1 the scene has errors;\n"
        "2 a wrong command line; 3 a file cannot be written, or a job failed; 4 no sbatch.";
    auto addFarmOptions = [&](CLI::App* cmd) {
        cmd->add_option("--shards", args.shards, "How many pieces: frame ranges or tiles")
            ->required();
        cmd->add_option("--workdir", args.workdir,
                        "A new directory on the filesystem every node shares, for the scripts, "
                        "the pieces and the logs")
            ->required();
        cmd->add_option("--partition", args.partition,
                        "The Slurm partition (default: the cluster's default)");
        cmd->add_option("--moire", args.moire,
                        "The moire binary as the nodes see it (default: this one's path)");
        cmd->add_option("--sbatch-arg", args.sbatchArgs,
                        "An extra sbatch option for every job, as --sbatch-arg=--time=10 "
                        "(repeatable)");
        cmd->add_flag("--plan", args.plan, "Print the job scripts; write and submit nothing");
        cmd->add_flag("--wait", args.wait, "Return when the join has finished, with its status");
        cmd->add_option("--backend", args.backend, "jit (default), interp or vulkan, on the nodes");
        cmd->add_option("--device", args.device, "Vulkan device index on the nodes")
            ->check(CLI::NonNegativeNumber);
        cmd->add_option("--threads", args.threads, "Worker threads per shard (default: all cores)");
        cmd->add_option("--size", args.size, "Frame size WIDTHxHEIGHT, replacing the scene's");
        cmd->add_option("--filter", args.filter, filterHelp());
        cmd->add_option("--shard-arg", args.shardArgs,
                        "An extra option for every shard's moire, as --shard-arg=--view=envelope "
                        "(repeatable)");
        addDefineOption(cmd, rawDefines);
        CLI::Option* q =
            cmd->add_flag("-q,--quiet", args.verbosity.quiet, "Print nothing but errors");
        cmd->add_flag("-v,--verbose", args.verbosity.verbose, "Also print each shard's command")
            ->excludes(q);
        cmd->footer(footer);
    };

    CLI::App* clipCmd = farmCmd->add_subcommand(
        "clip", "A clip as frame ranges, joined into the video (byte for byte `moire clip`'s)");
    clipCmd->add_option("scene", args.scene, "The .moire scene (default: the embedded one)");
    clipCmd->add_option("-o,--output", args.output,
                        "A video (.mp4, .webm, .gif) or numbered images (frame_%04d.png)");
    clipCmd->add_option("--fps", args.fps, "Frames per second")->required();
    clipCmd->add_option("--from", args.from, "Clock time of frame 0 in seconds (default 0)");
    CLI::Option* toOpt = clipCmd->add_option("--to", args.to, "End time in seconds, not included");
    CLI::Option* framesOpt = clipCmd->add_option(
        "--frames", args.frames, "N frames, or frames A..B (default: as moire clip)");
    toOpt->excludes(framesOpt);
    clipCmd->add_option("--depth", args.depth, "Bits per channel of image frames");
    addFarmOptions(clipCmd);
    clipCmd->callback([&args, toOpt] {
        args.mode = FarmArgs::Mode::Clip;
        args.hasTo = toOpt->count() > 0;
    });

    CLI::App* renderCmd = farmCmd->add_subcommand(
        "render", "A poster as tiles, assembled into the image (byte for byte `moire render`'s)");
    renderCmd->add_option("scene", args.scene, "The .moire scene (default: the embedded one)");
    renderCmd->add_option("-o,--output", args.output, "The image: .png, .tif, .exr or .jpg");
    renderCmd->add_option("--time", args.time, "Clock time t in seconds (default 0)");
    renderCmd->add_option("--depth", args.depth, "Bits per channel: 8, 16, half or float");
    renderCmd->add_option("--dpi", args.dpi, "Print resolution to record in the file");
    renderCmd->add_option("--compression", args.compression, "PNG's zlib level, 0 to 9")
        ->check(CLI::Range(0, 9));
    addFarmOptions(renderCmd);
    renderCmd->callback([&args] { args.mode = FarmArgs::Mode::Render; });

    CLI::App* encodeCmd = farmCmd->add_subcommand(
        "encode", "The video join: numbered 8-bit PNG frames encoded as moire clip encodes");
    encodeCmd->add_option("frames", args.scene, "The frames' numbered name (f_%04d.png)")
        ->required();
    encodeCmd->add_option("--frames", args.frames, "Frames A..B")->required();
    encodeCmd->add_option("--fps", args.fps, "Frames per second")->required();
    encodeCmd->add_option("-o,--output", args.output, "The video")->required();
    encodeCmd->add_flag("-q,--quiet", args.verbosity.quiet, "Print nothing but errors");
    encodeCmd->footer("Exit status: 0 done; 2 a wrong command line; 3 a frame cannot be read or "
                      "the video\ncannot be written.");
    encodeCmd->callback([&args] { args.mode = FarmArgs::Mode::Encode; });
    farmCmd->footer(footer);
    return farmCmd;
}

int farm(const FarmArgs& args, const std::vector<std::string>& rawDefines) {
    switch (args.mode) {
    case FarmArgs::Mode::Clip:
        return farmClip(args, rawDefines);
    case FarmArgs::Mode::Render:
        return farmRender(args, rawDefines);
    case FarmArgs::Mode::Encode:
        return farmEncode(args);
    case FarmArgs::Mode::None:
        break;
    }
    return usage("farm needs a subcommand: clip, render or encode");
}

} // namespace moire::cli

// The memory estimate before a render and the memory the process may have: the figures
// counted by hand from the buffers a render holds, and the limits read back as they were set.
#include "runtime/output/MemoryBudget.h"
#include "tests/support/Skip.h"

#include <doctest/doctest.h>
#include <fstream>
#include <string>
#include <sys/resource.h>

using namespace moire;

namespace {

// VmSize of this process, in bytes, read independently of MemoryBudget.cpp.
uint64_t mappedBytes() {
    std::ifstream in("/proc/self/status");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("VmSize:", 0) == 0) return std::stoull(line.substr(7)) * 1024;
    return 0;
}

} // namespace

TEST_CASE("memory budget: the estimate counts the frame and each copy of it") {
    // 32768x32768: 2^30 pixels of four float channels is 16 GiB for the frame, the writer's
    // float copy as much again, and the encoded file at most as much again; the rest (the
    // process, a 64 MB chunk) is under 1 GB.
    FrameFootprint png;
    png.width = png.height = 32768;
    const double frame = double(uint64_t{1} << 30) * 16;
    const double pngBytes = double(estimateFrameBytes(png));
    CHECK(pngBytes >= 3 * frame);
    CHECK(pngBytes <= 3 * frame + 1e9);
    // JPEG keeps three channels in its copy and its encoded file.
    FrameFootprint jpeg = png;
    jpeg.format = "jpeg";
    CHECK(double(estimateFrameBytes(jpeg)) ==
          doctest::Approx(pngBytes - 2 * frame / 4).epsilon(1e-3));
    // Layer fields are more channels of the frame.
    FrameFootprint fields = png;
    fields.channels = 10;
    CHECK(double(estimateFrameBytes(fields)) == doctest::Approx(pngBytes + frame * 6 / 4));
    // Each frame queued for writing is a frame and its writer's copy.
    FrameFootprint clip = png;
    clip.queued = 3;
    CHECK(double(estimateFrameBytes(clip)) >= 8 * frame);
    // A video frame goes out as 8-bit RGBA; a window keeps several 8-bit copies.
    FrameFootprint video = png;
    video.sink = FrameSink::Video;
    CHECK(double(estimateFrameBytes(video)) >= frame + frame / 4);
    CHECK(double(estimateFrameBytes(video)) < frame + frame / 4 + 1e9);
    // A small frame costs about the process alone.
    FrameFootprint small;
    small.width = small.height = 16;
    CHECK(estimateFrameBytes(small) < 400'000'000u);
}

TEST_CASE("memory budget: a streamed image holds no frame, only the bands (and the file to "
          "standard output)") {
    // 32768x32768 PNG at 8 bits to standard output: 4 GiB of samples, counted twice (the
    // compressed bands and the file made of them, each at most the samples when nothing
    // compresses); 16 GiB of float frame that is never made; a step of 8 rows a thread, 4 MiB
    // of floats here, and a band of 64 rows of samples filtered and compressed.
    FrameFootprint png;
    png.width = png.height = 32768;
    png.sink = FrameSink::Streamed;
    png.threads = 4;
    const double samples = double(uint64_t{1} << 30) * 4;
    const double bytes = double(estimateFrameBytes(png));
    CHECK(bytes >= 2 * samples + 4 * (8 * 32768.0 * 16 + 2 * 64 * 32768.0 * 4));
    CHECK(bytes <= 2 * samples + 1e9);
    CHECK(bytes < double(uint64_t{1} << 30) * 16); // less than the float frame alone
    // 16-bit samples double the file; more threads, more bands in flight.
    FrameFootprint deep = png;
    deep.depth = PixelDepth::U16;
    CHECK(double(estimateFrameBytes(deep)) == doctest::Approx(bytes + 2 * samples).epsilon(1e-2));
    FrameFootprint more = png;
    more.threads = 8;
    CHECK(estimateFrameBytes(more) > estimateFrameBytes(png));
    // Streamed to a file, only the bands waiting for those above them (runKernelInBands lets
    // a worker run `threads` bands ahead: two a thread) and a thread's own, never the file.
    FrameFootprint streamed = png;
    streamed.streamed = true;
    const double row = 32768.0 * 4 + 1;
    const double perThread = 8 * 32768.0 * 16 + 2 * 64 * row;
    CHECK(double(estimateFrameBytes(streamed)) >= 4 * (perThread + 2 * 64 * row));
    CHECK(double(estimateFrameBytes(streamed)) <= 4 * (perThread + 2 * 64 * row) + 4e8);
    // Every format alike: a 131072-pixel-wide 16-bit TIFF or float EXR is bounded by its
    // bands (a band of 64 rows: 64 MiB of 16-bit samples), hundreds of megabytes, not the
    // 275 GB of its float frame.
    for (const auto& [format, depth] :
         {std::pair{"tiff", PixelDepth::U16}, std::pair{"exr", PixelDepth::Float},
          std::pair{"jpeg", PixelDepth::U8}}) {
        FrameFootprint big;
        big.width = big.height = 131072;
        big.sink = FrameSink::Streamed;
        big.streamed = true;
        big.format = format;
        big.depth = depth;
        big.threads = 2;
        INFO(format);
        CHECK(estimateFrameBytes(big) < 2'000'000'000u);
        FrameFootprint wider = big;
        wider.width *= 2;
        CHECK(estimateFrameBytes(wider) > estimateFrameBytes(big)); // the bands are wider
        FrameFootprint taller = big;
        taller.height *= 2;
        CHECK(estimateFrameBytes(taller) == estimateFrameBytes(big)); // the height is free
    }
}

TEST_CASE("memory budget: the address space limit lowers what is available") {
    std::optional<MemoryAvailable> free = availableMemory();
    REQUIRE(free); // /proc/meminfo is there on Linux
    CHECK(free->bytes > 0);

    rlimit saved{};
    REQUIRE(getrlimit(RLIMIT_AS, &saved) == 0);
    const uint64_t headroom = 48ull << 20;
    const uint64_t mapped = mappedBytes();
    REQUIRE(mapped > 0);
    if (saved.rlim_max != RLIM_INFINITY && saved.rlim_max < mapped + headroom) {
        test::skip("the hard address space limit is already below what the test sets");
        return;
    }
    rlimit tight = saved;
    tight.rlim_cur = mapped + headroom;
    REQUIRE(setrlimit(RLIMIT_AS, &tight) == 0);
    std::optional<MemoryAvailable> limited = availableMemory();
    FrameFootprint frame;
    frame.width = frame.height = 4096; // 268 MB of frame alone
    const std::string problem = memoryProblem(frame);
    REQUIRE(setrlimit(RLIMIT_AS, &saved) == 0);

    REQUIRE(limited);
    // What is left under the limit: the headroom, less what the calls above mapped.
    CHECK(limited->bytes <= headroom);
    CHECK(limited->bytes + (16u << 20) >= headroom);
    CHECK(limited->limit.find("ulimit -v") != std::string::npos);
    CHECK(problem.find("a 4096x4096 image needs about ") == 0);
    CHECK(problem.find(" of memory; there is ") != std::string::npos);
    CHECK(problem.find("available under the address space limit (ulimit -v)") != std::string::npos);
}

TEST_CASE("memory budget: figures as the system's tools print them") {
    CHECK(formatBytes(21'500'000'000ull) == "21.5 GB");
    CHECK(formatBytes(512'300'000ull) == "512 MB");
    CHECK(formatBytes(4'000ull) == "4 kB");
}

// moire render streams every format from every backend (ImageStream, runKernelInBands): the
// file is the one the whole-frame writer makes of the same render (byte for byte, but the
// time it was written), a render's peak memory is
// bounded by its bands, not the image, and sizes past a format's own limit are refused with
// the format named.
#include "compiler/backend/Backend.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/MemoryBudget.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cerrno>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

const char* kScene = "scene { size = (48, 32) }\n"
                     "layer { family = circles; spacing = 3 }\n"
                     "layer { family = lines; spacing = 2.5; angle = 20deg; color = #c03070 }\n";

// `moire ARGS` run in `dir`, its peak memory measured (test::runMeasured).
test::Measured runMoire(const test::TempDir& dir, const std::vector<std::string>& args) {
    return test::runMeasured(args, dir);
}

} // namespace

TEST_CASE("render streams every format from every backend: the whole-frame writer's file") {
    // An odd size, so that the last band is short; 200 rows are four bands of 64 and a part.
    test::TempDir dir("streamed");
    dir.write("s.moire", kScene);
    auto program = test::compileOk(kScene);
    const int w = 173, h = 200;
    struct Case {
        const char* ext;
        const char* depth;
        PixelDepth pixelDepth;
    };
    for (const std::string name : {"jit", "interp", "vulkan"}) {
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) {
            MESSAGE("skipped: the ", name, " backend is not available here");
            continue;
        }
        const Image img = test::renderScene(*program, *backend, w, h);
        for (const Case c :
             {Case{"tif", "8", PixelDepth::U8}, Case{"tif", "16", PixelDepth::U16},
              Case{"exr", "half", PixelDepth::Half}, Case{"exr", "float", PixelDepth::Float},
              Case{"jpg", "8", PixelDepth::U8}, Case{"png", "16", PixelDepth::U16}}) {
            CAPTURE(name);
            CAPTURE(c.ext);
            CAPTURE(c.depth);
            WriteOptions wo;
            wo.depth = c.pixelDepth;
            wo.dpi = 150;
            const std::string whole = dir.file(std::string("whole.") + c.ext);
            writeImage(whole, img, wo);
            const std::string out = std::string("out.") + c.ext;
            const test::Measured r = runMoire(dir, {"render", "s.moire", "-q", "--backend", name,
                                                    "--size", fmt::format("{}x{}", w, h), "--depth",
                                                    c.depth, "--dpi", "150", "-o", out});
            REQUIRE_MESSAGE(r.status == 0, r.err);
            CHECK(test::imageBytesWithoutTime(dir.file(out)) == test::imageBytesWithoutTime(whole));
            const Image a = readImage(whole), b = readImage(dir.file(out));
            CHECK(a.pixels == b.pixels);
            fs::remove(whole);
            fs::remove(dir.file(out));
        }
    }
    CHECK(dir.names() == std::vector<std::string>{"s.moire"});
}

TEST_CASE("a 20000x20000 render's peak memory is bounded by its bands, not the image") {
    if (test::skipUnderAddressSanitizer()) return;
    // 400 Mpx: 6.4 GB of float pixels, 1.6 GB of 8-bit samples. The PNG goes, uncompressed
    // (fast), into /dev/null through a link, so the test costs the kernel's time and no disk.
    test::TempDir dir("rss");
    dir.write("s.moire", "scene { size = (48, 32) }\nlayer { family = lines; spacing = 3 }\n");
    fs::create_symlink("/dev/null", dir.file("big.png"));
    const test::Measured r =
        runMoire(dir, {"render", "s.moire", "-q", "--size", "20000x20000", "--compression", "0",
                       "--threads", "2", "-o", "big.png"});
    REQUIRE_MESSAGE(r.status == 0, r.err);
    // docs/cli.md's bound: the process (under 100 MB without OpenImageIO) and a few bands,
    // which MemoryBudget estimates from above; 20000 pixels wide, a band is a few megabytes.
    FrameFootprint f;
    f.width = f.height = 20000;
    f.sink = FrameSink::Streamed;
    f.threads = 2;
    f.streamed = true;
    MESSAGE("20000x20000 PNG: peak RSS ", formatBytes(r.maxRss), ", estimate ",
            formatBytes(estimateFrameBytes(f)));
    CHECK(r.maxRss < estimateFrameBytes(f));
    CHECK(r.maxRss < 256'000'000u);
    CHECK(dir.names() == std::vector<std::string>{"big.png", "s.moire"});
}

TEST_CASE("sizes past a format's limit are refused, naming the format and what holds more") {
    test::TempDir dir("limits");
    dir.write("s.moire", kScene);
    struct Case {
        std::vector<std::string> args;
        std::string message;
    };
    for (const Case& c : {
             Case{{"render", "s.moire", "--size", "65501x16", "-o", "x.jpg"},
                  "moire: error: cannot write 'x.jpg': JPEG holds at most 65500 pixels a side, "
                  "not 65501x16; use .tif or .exr for larger images\n"},
             Case{{"render", "s.moire", "--size", "16x1000001", "-o", "x.png"},
                  "moire: error: cannot write 'x.png': a PNG over 1000000 pixels a side is "
                  "refused by libpng's readers, not 16x1000001; use .tif or .exr for larger "
                  "images\n"},
             Case{{"render", "s.moire", "--size", "1048577x16", "-o", "x.tif"},
                  "moire: error: --size must be WIDTHxHEIGHT in pixels (1 to 1048576), not "
                  "'1048577x16'\n"},
             Case{{"watch", "s.moire", "--once", "--size", "32769x16", "-o", "x.tif"},
                  "moire: error: --size must be WIDTHxHEIGHT in pixels (1 to 32768), not "
                  "'32769x16'\n"},
             Case{{"clip", "s.moire", "--size", "32769x16", "--fps", "1", "--frames", "1", "-o",
                   "f%d.png"},
                  "moire: error: --size must be WIDTHxHEIGHT in pixels (1 to 32768), not "
                  "'32769x16'\n"},
             Case{{"view", "s.moire", "--size", "32769x16"},
                  "moire: error: --size must be WIDTHxHEIGHT in screen units (1 to 32768), not "
                  "'32769x16'\n"},
         }) {
        CAPTURE(fmt::format("{}", fmt::join(c.args, " ")));
        const test::Measured r = runMoire(dir, c.args);
        CHECK(r.status == 2);
        CHECK(r.err == c.message);
    }
    // A scene whose own size is past the format's limit: the same message.
    dir.write("wide.moire", "scene { size = (70000, 10) }\nlayer { family = circles }\n");
    const test::Measured r = runMoire(dir, {"render", "wide.moire", "-o", "x.jpg"});
    CHECK(r.status == 2);
    CHECK(r.err.find("JPEG holds at most 65500 pixels a side, not 70000x10") != std::string::npos);
    CHECK(dir.names() == std::vector<std::string>{"s.moire", "wide.moire"});
}

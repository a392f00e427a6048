// The command line's input, through the real binary: sizes parsed with range checks, times
// and resolutions that must be finite, scene files read only when they are regular files of
// at most 4 MiB (or standard input), and frames too large for the memory the process may
// have refused before anything is drawn, with the estimate checked against the peak
// resident memory of a real render.
#include "runtime/output/ImageIO.h"
#include "runtime/output/MemoryBudget.h"
#include "runtime/TextFile.h"
#include "tests/support/Support.h"

#include <cstring>
#include <doctest/doctest.h>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace moire;
namespace fs = std::filesystem;

namespace {

const char* kTiny = "scene { size = (40, 30) }\n"
                    "layer a { family = circles; spacing = 5; stroke = 1.2 }\n";

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

test::CommandResult run(const std::string& args) {
    return test::runCommand(quoted(test::moireBinary()) + " " + args);
}

using test::Measured;
using test::runMeasured;

} // namespace

TEST_CASE("input: --size takes only digits, each side 1 to 1048576 (render)") {
    test::TempDir dir("size");
    dir.write("s.moire", kTiny);
    const std::string scene = quoted(dir.file("s.moire"));
    const std::string out = dir.file("out.png");
    // Each of these wrapped, was read in part or was let through by sscanf's %d.
    for (const char* bad : {"4294967297x1",
                            "1x4294967297",
                            "2147483648x1",
                            "4294967296x4294967296",
                            "99999999999999999999x1",
                            "-1x5",
                            "5x-1",
                            "+5x5",
                            "5x+5",
                            " 5x5",
                            "5 x5",
                            "5x 5",
                            "5x5 ",
                            "5x5x",
                            "5x5x5",
                            "5x",
                            "x5",
                            "x",
                            "5",
                            "0x5",
                            "5x0",
                            "1048577x1",
                            "1x1048577",
                            "5e2x5",
                            "5.0x5",
                            "0x10",
                            "5x5junk",
                            "５x5",
                            "5×5"}) {
        CAPTURE(bad);
        test::CommandResult r =
            run("render " + scene + " -q -o " + quoted(out) + " --size " + quoted(bad));
        CHECK(r.status == 2);
        CHECK(
            r.err.find("moire: error: --size must be WIDTHxHEIGHT in pixels (1 to 1048576), not '" +
                       std::string(bad) + "'") != std::string::npos);
        CHECK(!fs::exists(out));
        // clip and view (no window is opened for a bad size) parse it the same way: a few of
        // the cases are enough (each run costs the process's start).
        const std::string some = bad;
        if (some != "4294967297x1" && some != "-1x5" && some != "5x5 " && some != "1048577x1")
            continue;
        r = run("clip " + scene + " --fps 1 --frames 1 -o " + quoted(dir.file("f%d.png")) +
                " --size " + quoted(bad));
        CHECK(r.status == 2);
        CHECK(r.err.find("--size must be WIDTHxHEIGHT") != std::string::npos);
        r = run("view " + scene + " --size " + quoted(bad));
        CHECK(r.status == 2);
        CHECK(r.err.find("--size must be WIDTHxHEIGHT") != std::string::npos);
    }
    // The bounds themselves are sizes.
    for (auto [size, w, h] :
         {std::tuple{"1x1", 1, 1}, std::tuple{"32768x1", 32768, 1}, std::tuple{"1x32768", 1, 32768},
          std::tuple{"7X3", 7, 3}, std::tuple{"0040x0030", 40, 30}}) {
        INFO("size ", std::string(size));
        test::CommandResult r =
            run("render " + scene + " -q --backend interp -o " + quoted(out) + " --size " + size);
        REQUIRE_MESSAGE(r.status == 0, r.err);
        Image img = readImage(out);
        CHECK(img.width == w);
        CHECK(img.height == h);
        fs::remove(out);
    }
}

TEST_CASE("input: --time must be finite and --dpi positive, finite and at most 1000000") {
    test::TempDir dir("time");
    dir.write("s.moire", kTiny);
    const std::string scene = quoted(dir.file("s.moire"));
    const std::string out = quoted(dir.file("out.png"));
    for (const char* t : {"nan", "inf", "-inf", "NaN"}) {
        CAPTURE(t);
        for (const std::string& cmd : {"render " + scene + " -o " + out,
                                       "watch " + scene + " --once -o " + out, "view " + scene}) {
            CAPTURE(cmd);
            test::CommandResult r = run(cmd + " --time " + t);
            CHECK(r.status == 2);
            CHECK(r.err.find("moire: error: --time must be a finite time in seconds") !=
                  std::string::npos);
        }
        test::CommandResult r = run("clip " + scene + " --fps 1 --frames 1 -o f%d.png --from " + t);
        CHECK(r.status == 2);
        CHECK(r.err.find("moire: error: --from must be a finite time") != std::string::npos);
    }
    CHECK(!fs::exists(dir.file("out.png")));
    for (const char* dpi : {"nan", "inf", "-5", "-0.001", "1e7", "1e39"}) {
        CAPTURE(dpi);
        test::CommandResult r = run("render " + scene + " -o " + out + " --dpi " + dpi);
        CHECK(r.status == 2);
        CHECK(r.err.find("moire: error: --dpi must be a number of dots per inch above 0 and at "
                         "most 1000000 (or 0: none recorded)") != std::string::npos);
        CHECK(!fs::exists(dir.file("out.png")));
    }
    for (const char* dpi : {"0", "300", "1000000"}) {
        CAPTURE(dpi);
        test::CommandResult r =
            run("render " + scene + " -q --backend interp -o " + out + " --dpi " + dpi);
        CHECK_MESSAGE(r.status == 0, r.err);
    }
    CHECK(run("render " + scene + " -q --backend interp -o " + out + " --time 1e300").status == 0);
}

TEST_CASE("input: a scene is a regular file of at most 4 MiB, or standard input") {
    test::TempDir dir("source");
    auto check = [&](const std::string& path) { return run("check " + quoted(path)).err; };
    // A device never ends: refused without reading it.
    test::CommandResult r = run("check /dev/zero");
    CHECK(r.status == 3);
    CHECK(r.err == "moire: error: cannot read '/dev/zero': it is a device, not a file\n");
    // A FIFO with no writer: refused at once rather than waited on (timeout says 124).
    const std::string fifo = dir.file("pipe.moire");
    REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    r = test::runCommand("timeout 20 " + quoted(test::moireBinary()) + " check " + quoted(fifo));
    CHECK(r.status == 3);
    CHECK(r.err.find("it is a FIFO, not a file") != std::string::npos);
    // The other commands read scenes the same way.
    r = test::runCommand("timeout 20 " + quoted(test::moireBinary()) + " render -q " +
                         quoted(fifo) + " -o " + quoted(dir.file("o.png")));
    CHECK(r.status == 3);
    CHECK(r.err.find("it is a FIFO, not a file") != std::string::npos);
    CHECK(check(dir.path()).find("cannot read '" + dir.path() + "': it is a directory") !=
          std::string::npos);
    CHECK(check(dir.file("missing.moire")).find("No such file or directory") != std::string::npos);

    // Exactly 4 MiB is read; one byte more is refused.
    std::string atCap = kTiny;
    atCap += "//";
    atCap += std::string(kMaxSourceBytes - atCap.size() - 1, 'x');
    atCap += "\n";
    REQUIRE(atCap.size() == 4u << 20);
    dir.write("at.moire", atCap);
    r = run("check " + quoted(dir.file("at.moire")));
    CHECK_MESSAGE(r.status == 0, r.err);
    dir.write("over.moire", atCap + "\n");
    r = run("check " + quoted(dir.file("over.moire")));
    CHECK(r.status == 3);
    CHECK(r.err.find("cannot read '" + dir.file("over.moire") +
                     "': it is longer than 4 MiB, the most a scene may be") != std::string::npos);

    // `-` is standard input: read to its end, bounded the same way, named <stdin>.
    dir.write("s.moire", kTiny);
    r = test::runCommand(quoted(test::moireBinary()) + " check - < " + quoted(dir.file("s.moire")));
    CHECK_MESSAGE(r.status == 0, r.err);
    r = test::runCommand("cd " + quoted(dir.path()) + " && cat s.moire | " +
                         quoted(test::moireBinary()) + " render - -q --backend interp");
    CHECK_MESSAGE(r.status == 0, r.err);
    CHECK(readImage(dir.file("stdin.png")).width == 40);
    r = test::runCommand("printf 'layer a { family = circels }\\n' | " +
                         quoted(test::moireBinary()) + " check -");
    CHECK(r.status == 1);
    CHECK(r.err.find("<stdin>:1:") == 0);
    r = test::runCommand("timeout 20 " + quoted(test::moireBinary()) + " check - < /dev/zero");
    CHECK(r.status == 3);
    CHECK(r.err.find("cannot read the scene from standard input: it is longer than 4 MiB") !=
          std::string::npos);
    // watch and view follow a file; standard input is not one.
    for (const char* cmd : {"watch - --once -o x.png", "view -"}) {
        CAPTURE(cmd);
        r = run(cmd);
        CHECK(r.status == 2);
        CHECK(r.err.find("standard input ('-') cannot be watched") != std::string::npos);
    }
}

TEST_CASE("input: a frame larger than the memory the process may have is refused at once") {
    if (test::skipUnderAddressSanitizer()) return;
    test::TempDir dir("memory");
    dir.write("s.moire", kTiny);
    const std::string scene = dir.file("s.moire");
    // 3 GB of address space: the process runs (it maps about a gigabyte before a frame), but a
    // 32768x32768 frame, 17 GB of float pixels alone, cannot be had. (render streams a file
    // band by band and needs no frame, but a PNG to standard output is kept whole until the
    // end: 4 GB of samples at most, twice.)
    const uint64_t limit = 3ull << 30;
    FrameFootprint big;
    big.width = big.height = 32768;
    big.sink = FrameSink::Streamed;
    const std::string need = "a 32768x32768 image needs about " +
                             formatBytes(estimateFrameBytes(big)) + " of memory; there is ";
    Measured m = runMeasured({"render", scene, "--size", "32768x32768", "-o", "-"}, dir, limit);
    CHECK(m.status == 4);
    INFO(m.err);
    CHECK(m.err.find("moire: error: " + need) == 0);
    CHECK(m.err.find(" available under the address space limit (ulimit -v)\n") !=
          std::string::npos);
    // Refused before the frame: nothing near its size was ever resident.
    CHECK(m.maxRss < (1ull << 30));
    CHECK(dir.names() == std::vector<std::string>{"s.moire"});

    // The same for a clip's frames, watch and a window of that size (refused before a window
    // is opened, so no display is needed).
    m = runMeasured({"clip", scene, "--size", "32768x32768", "--fps", "1", "--frames", "1", "-o",
                     dir.file("f%d.png")},
                    dir, limit);
    CHECK(m.status == 4);
    CHECK(m.err.find("moire: error: a 32768x32768 image needs about ") == 0);
    CHECK(m.maxRss < (1ull << 30));
    m = runMeasured({"watch", scene, "--once", "--size", "32768x32768", "-o", dir.file("w.png")},
                    dir, limit);
    CHECK(m.status == 4);
    CHECK(m.err.find("moire: error: a 32768x32768 image needs about ") == 0);
    CHECK(m.maxRss < (1ull << 30));
    m = runMeasured({"view", scene, "--size", "32768x32768"}, dir, limit);
    CHECK(m.status == 4);
    CHECK(m.err.find("moire: error: a 32768x32768 window needs about ") == 0);
    CHECK(dir.names() == std::vector<std::string>{"s.moire"});
}

TEST_CASE("input: the memory estimate bounds a real render's peak from above, within 2x") {
    if (test::skipUnderAddressSanitizer()) return;
    test::TempDir dir("peak");
    dir.write("s.moire", kTiny);
    for (auto [size, w, h, out] : {std::tuple{"2400x1600", 2400, 1600, "out.png"},
                                   std::tuple{"1600x1200", 1600, 1200, "out.exr"}}) {
        INFO("size ", std::string(size));
        Measured m = runMeasured({"render", dir.file("s.moire"), "-q", "--size", size, "--backend",
                                  "jit", "-o", dir.file(out)},
                                 dir);
        REQUIRE_MESSAGE(m.status == 0, m.err);
        FrameFootprint f;
        f.width = w;
        f.height = h;
        f.format = imageFormatOf(out);
        // render streams every format band by band as the workers finish them
        // (runKernelInBands into an ImageStream).
        f.sink = FrameSink::Streamed;
        f.streamed = true;
        const uint64_t estimate = estimateFrameBytes(f);
        MESSAGE(std::string(size), " ", std::string(out), ": estimate ", formatBytes(estimate),
                ", peak RSS ", formatBytes(m.maxRss));
        CHECK(estimate >= m.maxRss);
        CHECK(estimate <= 2 * m.maxRss);
    }
}

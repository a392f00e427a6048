// `moire render`'s PNG: encoded in bands on every thread at a zlib level --compression
// chooses. The level and the thread count change how the file is compressed, never a pixel;
// the bands are independent, so any number of threads writes the same bytes.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <string>

using namespace moire;
namespace fs = std::filesystem;

namespace {

test::CommandResult render(const test::TempDir& d, const std::string& args) {
    return test::runCommand("cd '" + d.path() + "' && '" + test::moireBinary() +
                            "' render -q s.moire " + args);
}

} // namespace

TEST_CASE("render's PNG holds the same pixels at every level and thread count") {
    test::TempDir d("render_encode");
    // 150 rows: two whole bands of 64 and part of a third; half-transparent strokes.
    d.write("s.moire", "scene { size = (203, 150) }\n"
                       "layer a { family = circles; spacing = 3; origin = (-20, 0) }\n"
                       "layer b { family = circles; spacing = 4; color = #80204060 }\n");
    REQUIRE(render(d, "-o ref.tif --depth 16").status == 0);
    const Image reference = readImage(d.file("ref.tif"));
    const std::pair<const char*, const char*> runs[] = {{"c0", "--compression 0"},
                                                        {"c9", "--compression 9"},
                                                        {"t1", "--threads 1"},
                                                        {"t3", "--threads 3"},
                                                        {"default", ""}};
    for (const char* depth : {"8", "16"}) {
        CAPTURE(depth);
        auto name = [&](const char* run) { return std::string(run) + "_" + depth + ".png"; };
        for (const auto& [run, args] : runs) {
            CAPTURE(args);
            REQUIRE(
                render(d, std::string(args) + " --depth " + depth + " -o " + name(run)).status ==
                0);
            // Against the 16-bit TIFF that OpenImageIO's writer made of the same frame:
            // within half a step of the PNG's depth; and every run of the PNG the same.
            const Image got = readImage(d.file(name(run)));
            const double step = depth[0] == '8' ? 1.0 / 255 : 1.0 / 65535;
            CHECK(test::compareImages(reference, got, 0.5 * step + 1.0 / 65535).over == 0);
            CHECK(test::compareImages(readImage(d.file(name("c0"))), got, 0.0).over == 0);
        }
        // More threads share out the bands; they do not change them: the same bytes.
        CHECK(test::readFile(d.file(name("t1"))) == test::readFile(d.file(name("t3"))));
        CHECK(fs::file_size(d.file(name("c0"))) > fs::file_size(d.file(name("c9"))));
        CHECK(fs::file_size(d.file(name("c0"))) > fs::file_size(d.file(name("default"))));
    }
}

TEST_CASE("render refuses a --compression that is no zlib level, or not for a PNG") {
    test::TempDir d("render_encode_errors");
    d.write("s.moire", "scene { size = (16, 16) }\nlayer { family = circles; spacing = 3 }\n");
    test::CommandResult r = render(d, "--compression 10 -o a.png");
    CHECK(r.status == 2);
    CHECK(r.err == "moire: error: --compression must be a zlib level from 0 (none) to 9 "
                   "(smallest), not 10\n");
    r = render(d, "--compression 5 -o a.exr");
    CHECK(r.status == 2);
    CHECK(r.err == "moire: error: --compression sets a PNG's zlib level; 'a.exr' is not a PNG\n");
    CHECK(!fs::exists(d.file("a.png")));
    CHECK(!fs::exists(d.file("a.exr")));
}

TEST_CASE("render's PNG, encoded band by band as they are rendered, is the frame's PNG") {
    // The command encodes each band as a worker finishes it, without an image of the whole
    // frame; writeImage's encoder here takes the frame rendered whole. The same bytes.
    test::TempDir d("render_encode_pipeline");
    const std::string scene = "scene { size = (97, 203) }\n"
                              "layer a { family = circles; spacing = 3; origin = (-20, 0) }\n"
                              "layer b { family = circles; spacing = 4; color = #80204060 }\n";
    d.write("s.moire", scene);
    auto program = test::compileOk(scene);
    auto jit = test::makeBackendOrSkip("jit");
    const Image frame = test::renderScene(*program, *jit);
    for (const char* depth : {"8", "16"}) {
        CAPTURE(depth);
        REQUIRE(render(d, std::string("--threads 2 --depth ") + depth + " -o p.png").status == 0);
        WriteOptions wo;
        wo.depth = depth[0] == '8' ? PixelDepth::U8 : PixelDepth::U16;
        const std::vector<unsigned char> whole = encodeImage("p.png", "png", frame, wo);
        CHECK(test::readFile(d.file("p.png")) == std::string(whole.begin(), whole.end()));
    }
}

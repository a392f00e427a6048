// `render --region` and `moire assemble`, run as a user runs them: a region is the very
// window of the whole frame (every backend), it records its place in the file, and tiles that
// cover a frame assemble into the very file a render of the whole makes.
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/OiioCodec.h"
#include "runtime/output/Render.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <string>
#include <vector>

using namespace moire;
namespace fs = std::filesystem;

namespace {

// Half-transparent strokes on two layers, so that every channel varies.
const char* kScene = "scene { size = (203, 150) }\n"
                     "layer a { family = circles; spacing = 3; origin = (-20, 0) }\n"
                     "layer b { family = circles; spacing = 4; rotation = 7deg; "
                     "color = #80204060 }\n";

struct Dir : test::TempDir {
    Dir() : test::TempDir("regions") { write("s.moire", kScene); }
    test::CommandResult moire(const std::string& args) const {
        return test::runCommand("cd '" + path() + "' && '" + test::moireBinary() + "' " + args);
    }
    test::CommandResult render(const std::string& args) const {
        return moire("render -q s.moire " + args);
    }
};

struct Rect {
    int x0, y0, x1, y1;
    std::string arg() const {
        return std::to_string(x0) + "," + std::to_string(y0) + "," + std::to_string(x1) + "," +
               std::to_string(y1);
    }
};

// The pixels of `whole` under `r`, `channels` channels, compared exactly.
int differences(const Image& whole, const Rect& r, const Image& window, int channels = 4) {
    int wrong = 0;
    for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x)
            for (int c = 0; c < channels; ++c) {
                const float a = whole.at(x, y, c), b = window.at(x - r.x0, y - r.y0, c);
                wrong += !(a == b);
            }
    return wrong;
}

ImageFileInfo infoOf(const std::string& path) {
    return oiioCodec().openRows(path)->info();
}

} // namespace

// The executor's region, in process (every channel, as floats), on every backend: windows of
// odd sizes, across the 64-pixel tiles' edges, touching every edge of the frame.
TEST_CASE("a region is the same window of the whole frame, bit for bit, on every backend") {
    auto program = test::compileOk(kScene);
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(*program, FrameRequest{}, frame, diags));
    const Rect rects[] = {{37, 11, 166, 97},
                          {0, 0, 1, 150},
                          {150, 100, 203, 150},
                          {64, 64, 129, 65},
                          {0, 0, 203, 150}};
    for (const std::string& name : test::availableBackends()) {
        CAPTURE(name);
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        const Image whole = renderFrame(*program, *backend, frame);
        REQUIRE(whole.width == 203);
        for (const Rect& r : rects) {
            CAPTURE(r.arg());
            ExecOptions options;
            options.region = TileRect{r.x0, r.y0, r.x1, r.y1};
            options.tileSize = 16 + r.x0 % 7; // tiles that start anywhere
            const Image window = renderFrame(*program, *backend, frame, options);
            REQUIRE(window.width == r.x1 - r.x0);
            REQUIRE(window.height == r.y1 - r.y0);
            REQUIRE(window.channels == whole.channels);
            CHECK(differences(whole, r, window, whole.channels) == 0);
        }
    }
}

// The same through the command line: float EXR keeps the kernel's floats (through one fixed
// sRGB decode), and the PNG path (bands encoded as the CPU kernel finishes them) too.
TEST_CASE("render --region writes the same window of the whole frame on every backend") {
    Dir d;
    const Rect r{37, 11, 166, 97};
    for (const std::string& backend : test::availableBackends()) {
        CAPTURE(backend);
        const std::string on = " --backend " + backend;
        for (const char* ext : {".exr", ".png"}) {
            auto whole = d.render(std::string("-o whole") + ext + on);
            INFO(whole.err);
            REQUIRE(whole.status == 0);
            auto part = d.render(std::string("-o part") + ext + " --region " + r.arg() + on);
            INFO(part.err);
            REQUIRE(part.status == 0);
            const Image window = readImage(d.file(std::string("part") + ext));
            REQUIRE(window.width == r.x1 - r.x0);
            REQUIRE(window.height == r.y1 - r.y0);
            CHECK(differences(readImage(d.file(std::string("whole") + ext)), r, window) == 0);
        }
    }
}

TEST_CASE("a region records its place in the frame, and a whole frame records none") {
    Dir d;
    for (const std::string name : {"r.png", "r.tif", "r.exr"}) {
        CAPTURE(name);
        auto r = d.render(std::string("-o ") + name + " --dpi 300 --region 40,30,131,97");
        INFO(r.err);
        REQUIRE(r.status == 0);
        const ImageFileInfo i = infoOf(d.file(name));
        CHECK(i.width == 91);
        CHECK(i.height == 67);
        CHECK(i.x == 40);
        CHECK(i.y == 30);
        CHECK(i.fullWidth == 203);
        CHECK(i.fullHeight == 150);
        CHECK(i.dpi == doctest::Approx(300).epsilon(1e-5));
        // A region that is the whole frame is the whole frame's file.
        REQUIRE(d.render(std::string("-o all_") + name + " --region 0,0,203,150").status == 0);
        REQUIRE(d.render(std::string("-o plain_") + name).status == 0);
        if (name != "r.exr") // an EXR records when it was written
            CHECK(test::readFile(d.file("all_" + name)) == test::readFile(d.file("plain_" + name)));
        CHECK(readImage(d.file("all_" + name)).pixels == readImage(d.file("plain_" + name)).pixels);
        const ImageFileInfo whole = infoOf(d.file("all_" + name));
        CHECK(whole.x == 0);
        CHECK(whole.y == 0);
        CHECK(whole.fullWidth == 203);
        CHECK(whole.fullHeight == 150);
    }
}

TEST_CASE("assembled tiles are the whole render's file, byte for byte") {
    Dir d;
    // Uneven splits of the 203x150 frame: 2 x 2 and 3 x 1, none on a multiple of 64 rows.
    const std::vector<std::vector<Rect>> splits = {
        {{0, 0, 90, 71}, {90, 0, 203, 71}, {0, 71, 90, 150}, {90, 71, 203, 150}},
        {{0, 0, 203, 13}, {0, 13, 203, 100}, {0, 100, 203, 150}}};
    struct Kind {
        const char* ext;
        const char* options;
        size_t split;
    };
    const Kind kinds[] = {{"png", "--depth 8", 0},
                          {"png", "--depth 8", 1},
                          {"png", "--depth 16 --dpi 300", 1},
                          {"tif", "--depth 16", 0},
                          {"tif", "--depth 8 --dpi 150", 1},
                          {"exr", "--depth half", 0}};
    for (const auto& [ext, options, s] : kinds) {
        CAPTURE(ext);
        CAPTURE(options);
        const std::string whole = std::string("whole.") + ext;
        REQUIRE(d.render("-o " + whole + " " + options).status == 0);
        {
            CAPTURE(s);
            std::string tiles;
            for (size_t i = 0; i < splits[s].size(); ++i) {
                const std::string tile = "t" + std::to_string(i) + "." + ext;
                auto r = d.render("-o " + tile + " " + options + " --region " + splits[s][i].arg());
                INFO(r.err);
                REQUIRE(r.status == 0);
                tiles = " " + tile + tiles; // in any order
            }
            const std::string joined = std::string("joined.") + ext;
            auto a = d.moire("assemble -q" + tiles + " -o " + joined);
            INFO(a.err);
            REQUIRE(a.status == 0);
            CHECK(a.err.empty());
            if (std::string(ext) == "exr") {
                const Image x = readImage(d.file(whole)), y = readImage(d.file(joined));
                CHECK(x.pixels == y.pixels);
            } else {
                CHECK(test::readFile(d.file(joined)) == test::readFile(d.file(whole)));
            }
        }
    }
}

TEST_CASE("render --region and assemble refuse what cannot be done, and say why") {
    Dir d;
    // Tiles of the 203x150 frame: a and b cover it; c overlaps a, e leaves a gap, f is of
    // another frame, g is a TIFF, h is 16-bit.
    for (const char* tile :
         {"a.png --region 0,0,100,150", "b.png --region 100,0,203,150",
          "c.png --region 90,0,203,150", "e.png --region 100,0,203,140",
          "f.png --size 300x150 --region 100,0,203,150", "g.tif --depth 8 --region 100,0,203,150",
          "h.png --depth 16 --region 100,0,203,150"}) {
        CAPTURE(tile);
        REQUIRE(d.render(std::string("-o ") + tile).status == 0);
    }
    struct Refusal {
        const char* args;
        int status;
        const char* says;
    };
    const Refusal refusals[] = {
        {"render s.moire -o x.png --region 0,0,204,150", 2,
         "--region 0,0,204,150 reaches past the 203x150 frame"},
        {"render s.moire -o x.png --size 100x100 --region 0,90,100,101", 2,
         "reaches past the 100x100 frame"},
        {"render s.moire -o x.png --region 10,0,10,5", 2, "--region '10,0,10,5' is empty"},
        {"render s.moire -o x.png --region 1,2,3", 2, "--region must be X0,Y0,X1,Y1"},
        {"render s.moire -o x.jpg --region 0,0,10,10", 2, "a JPEG cannot record where"},
        {"assemble a.png -o out.png", 2,
         "no tile covers pixel 100,0 of the 203x150 frame, beside 'a.png' (100x150 at 0,0)"},
        {"assemble a.png e.png -o out.png", 2, "no tile covers pixel 100,140 of the 203x150 frame"},
        {"assemble a.png c.png -o out.png", 2,
         "'a.png' (100x150 at 0,0) and 'c.png' (113x150 at 90,0) overlap"},
        {"assemble a.png f.png -o out.png", 2,
         "'a.png' is a region of a 203x150 frame, 'f.png' of a 300x150 frame"},
        {"assemble a.png h.png -o out.png", 2, "'a.png' holds 8-bit samples, 'h.png' 16-bit"},
        {"assemble a.png missing.png -o out.png", 3, "cannot read 'missing.png': no such file"},
        {"assemble a.png b.png -o out.png --size 200x150", 2,
         "the tiles make a 203x150 frame, not the 200x150 of --size"},
        {"assemble a.png b.png -o out.bmp", 2, "unknown image format"},
    };
    for (const Refusal& refusal : refusals) {
        CAPTURE(refusal.args);
        auto r = d.moire(refusal.args);
        INFO(r.err);
        CHECK(r.status == refusal.status);
        CHECK(r.err.find(refusal.says) != std::string::npos);
        CHECK(r.err.rfind("moire: error: ", 0) == 0);
    }
    CHECK_FALSE(fs::exists(d.file("x.png")));
    CHECK_FALSE(fs::exists(d.file("x.jpg")));
    CHECK_FALSE(fs::exists(d.file("out.png")));
    // Tiles of one frame in different formats join: the output takes the first one's depth.
    auto mixed = d.moire("assemble -q a.png g.tif -o mixed.png");
    INFO(mixed.err);
    CHECK(mixed.status == 0);
    REQUIRE(d.render("-o whole.png").status == 0);
    CHECK(test::readFile(d.file("mixed.png")) == test::readFile(d.file("whole.png")));
}

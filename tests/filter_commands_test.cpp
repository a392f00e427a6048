// --filter on every command that draws a scene (docs/filtering.md, docs/cli.md): each one's
// picture of circles finer than the pixels is what `moire render --filter` draws, the light
// grey of their mean ink under `mean` and solid ink under `point`, and a name other than
// these two is the same error everywhere, with nothing written. The pages of serve and export
// are read in a browser (tests/web/serve_input.test.js, tests/web/export.test.js).
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"
#include "tests/support/ViewerHarness.h"

#include <doctest/doctest.h>
#include <filesystem>

using namespace moire;
namespace fs = std::filesystem;

namespace {

// Circles 0.7 apart and 0.1 wide at a world unit a pixel: 1.43 members a pixel, 14% ink.
const char* kFine = "scene { size = (160, 120) }\n"
                    "layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n";

double meanInk(const Image& img) {
    double sum = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) sum += 1.0 - img.at(x, y, 0);
    return sum / (static_cast<double>(img.width) * img.height);
}

struct Dir : test::TempDir {
    Dir() : test::TempDir("filter-commands") { write("fine.moire", kFine); }
    test::CommandResult moire(const std::string& args) const {
        return test::runCommand("cd '" + path() + "' && '" + test::moireBinary() + "' " + args);
    }
    // render --filter NAME of the scene, as the other commands must draw it.
    Image rendered(const std::string& filter) const {
        auto r = moire("render fine.moire -q --backend jit --filter " + filter + " -o render-" +
                       filter + ".png");
        INFO(r.err);
        REQUIRE(r.status == 0);
        return readImage(file("render-" + filter + ".png"));
    }
};

// The mean filter's grey and the point rule's black, each the image render draws.
void checkPair(const Dir& dir, const Image& mean, const Image& point) {
    CHECK(meanInk(mean) < 0.3); // ~0.14, the centre's fold and 8-bit rounding aside
    CHECK(meanInk(point) > 0.9);
    for (const char* filter : {"mean", "point"}) {
        CAPTURE(filter);
        const Image want = dir.rendered(filter);
        test::ImageDiff d =
            test::compareImages(want, std::string(filter) == "mean" ? mean : point, 1.0 / 255);
        CHECK(d.fractionWithin() == 1.0);
    }
}

// The note the fine circles' stroke gives when point-sampled at a world unit a pixel: at the
// stroke's value, line 2, column 53, with the source line and a caret under it.
const char* kFloorNote =
    "fine.moire:2:53: note: the stroke of layer 'a', 0.1 wide, is 0.1 pixels at this size, "
    "under the stroke floor: it is drawn 2.3 pixels (2.3 units) wide, darker than written; "
    "filter = mean keeps the stroke's tone\n"
    "    2 | layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n"
    "      |                                                     ^~~\n";

size_t count(const std::string& text, const std::string& what) {
    size_t n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

// The error a bad name gives, with the command's status, on every command.
void checkBadName(const test::CommandResult& r) {
    CHECK(r.status == 2);
    CHECK(r.err.find("moire: error: --filter must be point or mean, not 'blur'") !=
          std::string::npos);
}

} // namespace

TEST_CASE("filter: clip --filter draws each frame as render --filter draws it") {
    Dir dir;
    for (const char* filter : {"mean", "point"}) {
        auto r = dir.moire(std::string("clip fine.moire -q --fps 1 --frames 1 --filter ") + filter +
                           " -o " + filter + "/f_%04d.png");
        INFO(r.err);
        REQUIRE(r.status == 0);
    }
    checkPair(dir, readImage(dir.file("mean/f_0000.png")), readImage(dir.file("point/f_0000.png")));
    auto bad = dir.moire("clip fine.moire --fps 1 --frames 1 --filter blur -o bad/f_%04d.png");
    checkBadName(bad);
    CHECK_FALSE(fs::exists(dir.file("bad")));
}

TEST_CASE("filter: watch --once --filter writes what render --filter draws") {
    Dir dir;
    for (const char* filter : {"mean", "point"}) {
        auto r = dir.moire(std::string("watch fine.moire --once -q --filter ") + filter +
                           " -o watch-" + filter + ".png");
        INFO(r.err);
        REQUIRE(r.status == 0);
    }
    checkPair(dir, readImage(dir.file("watch-mean.png")), readImage(dir.file("watch-point.png")));
    checkBadName(dir.moire("watch fine.moire --once --filter blur -o bad.png"));
    CHECK_FALSE(fs::exists(dir.file("bad.png")));
}

TEST_CASE("filter: print --filter draws the sheet's pixels with the filter asked") {
    // 40 x 30 mm at 101.6 dpi: 160 x 120 pixels, the frame fitted to the trim, so a pixel is
    // a world unit as in render.
    Dir dir;
    for (const char* filter : {"mean", "point"}) {
        auto r = dir.moire(std::string("print fine.moire -q --paper 40x30mm --dpi 101.6 "
                                       "--filter ") +
                           filter + " -o print-" + filter + ".png");
        INFO(r.err);
        REQUIRE(r.status == 0);
    }
    const Image mean = readImage(dir.file("print-mean.png"));
    const Image point = readImage(dir.file("print-point.png"));
    REQUIRE(mean.width == 160);
    REQUIRE(mean.height == 120);
    checkPair(dir, mean, point);
    checkBadName(dir.moire("print fine.moire --paper 40x30mm --dpi 100 --filter blur -o bad.png"));
    CHECK_FALSE(fs::exists(dir.file("bad.png")));
}

TEST_CASE("filter: export, serve and view refuse a bad --filter before anything is opened") {
    Dir dir;
    auto r = dir.moire("export fine.moire --filter blur -o bad.html");
    checkBadName(r);
    CHECK_FALSE(fs::exists(dir.file("bad.html")));
    // Both names make a page, and the two pages differ (the kernel's sampling is in them).
    REQUIRE(dir.moire("export fine.moire -q --filter point -o point.html").status == 0);
    REQUIRE(dir.moire("export fine.moire -q --filter mean -o mean.html").status == 0);
    CHECK(test::readFile(dir.file("point.html")) != test::readFile(dir.file("mean.html")));
    checkBadName(dir.moire("serve fine.moire --filter blur"));
    checkBadName(dir.moire("view fine.moire --filter blur"));
}

TEST_CASE("filter: farm passes --filter to every shard, and refuses a bad one") {
    Dir dir;
    auto r = dir.moire("farm render fine.moire --shards 2 --workdir w -o poster.png --moire "
                       "/opt/moire --filter point --plan");
    INFO(r.err);
    REQUIRE(r.status == 0);
    // Each of the two tiles' renders takes it, with the options every shard shares.
    CHECK(count(r.out, " --filter point --region ") == 2);
    checkBadName(dir.moire("farm render fine.moire --shards 2 --workdir w -o poster.png "
                           "--filter blur --plan"));
    CHECK_FALSE(fs::exists(dir.file("w")));
}

TEST_CASE("filter: view --filter shows what render --filter draws") {
    using namespace moire::test::xview;
    SKIP_WITHOUT_X();
    for (const char* filter : {"mean", "point"}) {
        CAPTURE(filter);
        Session session;
        if (!session.start(kFine, true, 160, 120, {"--filter", filter})) return;
        Rgb expect = offline(session.dir, kFine, "160x120", std::string("--filter ") + filter);
        CHECK(differing(windowMatching(session.screen, session.origin, expect), expect) == 0);
    }
}

TEST_CASE("filter: a point-sampled stroke under the floor is noted once, where it is written") {
    Dir dir;
    // render, clip, print and watch under --filter point: the note, once.
    for (const std::string& cmd :
         {std::string("render fine.moire --filter point -o r.png"),
          std::string("clip fine.moire --fps 1 --frames 1 --filter point -o c/f_%04d.png"),
          std::string("print fine.moire --paper 40x30mm --dpi 101.6 --filter point -o p.png"),
          std::string("watch fine.moire --once --filter point -o w.png")}) {
        CAPTURE(cmd);
        auto r = dir.moire(cmd);
        REQUIRE(r.status == 0);
        CHECK(r.err.find(kFloorNote) != std::string::npos);
        CHECK(count(r.err, "note: the stroke of") == 1);
    }
    // The scene's own `filter = point` too.
    dir.write("own.moire", "scene { size = (160, 120); filter = point }\n"
                           "layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n");
    CHECK(dir.moire("render own.moire -o own.png").err.find("own.moire:2:53: note: the stroke") !=
          std::string::npos);
    // Not under the mean, not with -q, not for a stroke at or over the floor (2.3 units at a
    // unit a pixel), nor one that is not a plain number.
    CHECK(dir.moire("render fine.moire -o m.png").err.find("note:") == std::string::npos);
    CHECK(dir.moire("render fine.moire -q --filter point -o q.png").err.empty());
    dir.write("thick.moire", "scene { size = (160, 120) }\n"
                             "layer a { family = circles; spacing = 8; stroke = 2.4 }\n"
                             "layer b { family = lines; spacing = 8; stroke = 0.5 * 2 }\n");
    CHECK(dir.moire("render thick.moire --filter point -o t.png").err.find("note:") ==
          std::string::npos);
    // Twice as large a frame halves the pixel: 2.4 is then 4.8 pixels, and a 2-unit stroke,
    // 4 pixels, stands clear of the floor too, while at half the size it is 1 pixel.
    dir.write("two.moire", "scene { size = (160, 120) }\n"
                           "layer a { family = circles; spacing = 8; stroke = 2 }\n");
    CHECK(
        dir.moire("render two.moire --filter point --size 320x240 -o big.png").err.find("note:") ==
        std::string::npos);
    auto small = dir.moire("render two.moire --filter point --size 80x60 -o small.png");
    CHECK(small.err.find("two.moire:2:51: note: the stroke of layer 'a', 2 wide, is 1 pixels at "
                         "this size") != std::string::npos);
}

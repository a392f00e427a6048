// `moire print` end to end, and the separations it rests on: each layer's sheet, laid over
// the paper in layer order with straight-alpha `over` (docs/print.md), gives back the whole
// picture on every backend, in memory and through 16-bit files; the sheet's size, bleed and
// marks as the layout says; a stated scale; and the errors of its options.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>
#include <vector>

using namespace moire;

namespace {

// Three layers: an opaque ink, a translucent coloured one (alpha and opacity both below 1),
// and a third over both, on a tinted opaque paper.
const char* const kScene =
    "scene { size = (60, 40); background = rgba(0.9, 0.85, 0.75, 1) }\n"
    "layer rings { family = circles; spacing = 3; stroke = 1.1; origin = (-5, 2) }\n"
    "layer bars { family = lines; spacing = 3.2; stroke = 0.9; angle = 30deg;\n"
    "             color = rgba(0.8, 0.1, 0.2, 0.8); opacity = 0.7 }\n"
    "layer dots { family = circles; spacing = 2.6; stroke = 0.7; origin = (6, -1);\n"
    "             color = #1840a0 }\n";
const float kPaper[4] = {0.9f, 0.85f, 0.75f, 1.0f};

// The documented rule: start from the paper, lay each sheet over it in layer order with
// straight-alpha `over` (a = as + ad (1 - as), c = (cs as + cd ad (1 - as)) / a), in double.
Image composite(const std::vector<Image>& sheets, const float paper[4]) {
    const Image& first = sheets.at(0);
    Image out(first.width, first.height, 4);
    for (int y = 0; y < first.height; ++y)
        for (int x = 0; x < first.width; ++x) {
            double c[3] = {paper[0], paper[1], paper[2]}, a = paper[3];
            for (const Image& s : sheets) {
                const double as = s.at(x, y, 3), na = as + a * (1 - as);
                for (int k = 0; k < 3; ++k)
                    c[k] = na > 0 ? (s.at(x, y, k) * as + c[k] * a * (1 - as)) / na : 0.0;
                a = na;
            }
            float* p = out.row(y) + x * 4;
            for (int k = 0; k < 3; ++k) p[k] = static_cast<float>(c[k]);
            p[3] = static_cast<float>(a);
        }
    return out;
}

test::CommandResult runIn(const test::TempDir& dir, const std::string& args) {
    return test::runCommand("cd '" + dir.path() + "' && '" + test::moireBinary() + "' " + args);
}

} // namespace

// The stacking rule is the renderer's own under the point filter. Under the mean filter (the
// default) the whole sheet also counts where two layers' strokes meet within a pixel
// (lower/StrokePairs.h), which sheets laid over one another as images cannot: on paper the
// separations' inks meet where they fall, and give the whole sheet's picture (docs/print.md).
TEST_CASE("separations laid over the paper in order give the whole picture on every backend") {
    auto whole = test::compileOk(kScene, {.filter = sema::FilterMode::Point});
    std::vector<std::unique_ptr<SceneProgram>> layers;
    for (int i = 0; i < 3; ++i) {
        CompileOptions options;
        options.filter = sema::FilterMode::Point;
        options.separateLayer = i;
        layers.push_back(test::compileOk(kScene, options));
    }
    for (const std::string& name : test::availableBackends()) {
        CAPTURE(name);
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        const Image want = test::renderScene(*whole, *backend, 90, 60);
        std::vector<Image> sheets;
        for (auto& p : layers) sheets.push_back(test::renderScene(*p, *backend, 90, 60));
        // A sheet is the layer's colour where it has ink, and clear elsewhere.
        const Image& bars = sheets[1];
        int inked = 0, clear = 0;
        for (int y = 0; y < bars.height; ++y)
            for (int x = 0; x < bars.width; ++x) {
                const float a = bars.at(x, y, 3);
                CHECK(a <= 0.8f * 0.7f + 1e-6f);
                if (a > 0.01f) {
                    ++inked;
                    CHECK(bars.at(x, y, 0) == doctest::Approx(0.8).epsilon(1e-5));
                    CHECK(bars.at(x, y, 2) == doctest::Approx(0.2).epsilon(1e-5));
                } else if (a == 0.0f) {
                    ++clear;
                }
            }
        CHECK(inked > 200);
        CHECK(clear > 200);
        // The sheets are the kernel's own floats, so the only difference is rounding: the
        // interpreter's doubles stored as floats, the float backends' own arithmetic.
        const double tolerance = name == "interp" ? 1e-6 : 2e-5;
        const test::ImageDiff d = test::compareImages(composite(sheets, kPaper), want, tolerance);
        CHECK(d.over == 0);
        CHECK(d.maxAbs <= tolerance);
    }
}

TEST_CASE("print --separate writes sheets that stack to the printed sheet, through 16-bit TIFF") {
    test::TempDir dir("print");
    dir.write("s.moire", kScene);
    const std::string common = "s.moire --paper 30x20mm --dpi 127 --filter point -q";
    auto full = runIn(dir, "print " + common + " -o full.tif");
    REQUIRE_MESSAGE(full.status == 0, full.err);
    auto sep = runIn(dir, "print " + common + " --separate -o out/sheet.tif");
    REQUIRE_MESSAGE(sep.status == 0, sep.err);
    std::vector<Image> sheets;
    for (const char* layer : {"rings", "bars", "dots"})
        sheets.push_back(readImage(dir.file(fmt::format("out/sheet-{}.tif", layer))));
    const Image want = readImage(dir.file("full.tif"));
    CHECK(want.width == 150); // 30 mm at 127 dpi: 5 pixels a millimetre
    CHECK(want.height == 100);
    // Each file rounds its samples to 1/65535 (half a step either way); the composite of
    // three sheets over an opaque paper carries at most a step from each and half a step
    // from the whole sheet: 3.5 steps. Four is the bound checked.
    const double step = 1.0 / 65535.0;
    const test::ImageDiff d = test::compareImages(composite(sheets, kPaper), want, 4 * step);
    CHECK(d.over == 0);
    CHECK(d.maxAbs <= 4 * step);
}

TEST_CASE("print: a sheet's size, its bleed as more of the world, and marks in the margin") {
    test::TempDir dir("print");
    dir.write("s.moire", kScene);
    // A6 (105 x 148 mm) at 50 dpi, turned to the scene's wide frame: 291 x 207 pixels
    // (148 / 25.4 * 50 = 291.3, 105 / 25.4 * 50 = 206.7); bleed 2 mm is 4 pixels, the marks'
    // 12 mm margin 24.
    auto plain = runIn(dir, "print s.moire --paper A6 --dpi 50 --depth 16 -o plain.png -q");
    REQUIRE_MESSAGE(plain.status == 0, plain.err);
    auto marked = runIn(
        dir, "print s.moire --paper a6 --dpi 50 --bleed 2 --marks --depth 16 -o marked.png -q");
    REQUIRE_MESSAGE(marked.status == 0, marked.err);
    const Image a = readImage(dir.file("plain.png"));
    const Image b = readImage(dir.file("marked.png"));
    CHECK(a.width == 291);
    CHECK(a.height == 207);
    const int border = 4 + 24;
    REQUIRE(b.width == 291 + 2 * border);
    REQUIRE(b.height == 207 + 2 * border);
    // The trim of the marked sheet is the plain sheet, pixel for pixel: the bleed adds world
    // around it at the same scale rather than shrinking the picture.
    int differ = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x)
            for (int c = 0; c < 4; ++c) differ += a.at(x, y, c) != b.at(x + border, y + border, c);
    CHECK(differ == 0);
    // The bleed is drawn: not the margin's white.
    int inkInBleed = 0;
    for (int x = 24; x < b.width - 24; ++x) inkInBleed += b.at(x, 25, 0) < 0.9f;
    CHECK(inkInBleed > 10);
    // The margin is white but for the marks: black crop marks on the trim's edges, in line
    // with the trim's corner (x = 28), and a target in the middle of the top margin.
    CHECK(b.at(10, 10, 0) == 1.0f);
    CHECK(b.at(border, 5, 0) < 0.6f);
    CHECK(b.at(border - 1, 5, 0) < 0.6f);
    CHECK(b.at(border + 4, 5, 0) == 1.0f);
    CHECK(b.at(b.width / 2, 12, 0) < 0.5f);
}

TEST_CASE("print --scale draws a stated number of world units a millimetre") {
    // 0.5 units a millimetre at 254 dpi (10 pixels a millimetre) is 0.05 units a pixel, on a
    // 40 x 30 mm (400 x 300 pixel) sheet: what `render` draws of a scene framed 20 x 15 at
    // that size. The scene's own frame and zoom are set aside.
    test::TempDir dir("print");
    const std::string layers = "layer a { family = circles; spacing = 1.3; stroke = 0.4 }\n"
                               "layer b { family = lines; spacing = 1.1; stroke = 0.3; "
                               "angle = 10deg }\n";
    dir.write("s.moire", "scene { size = (300, 100) }\ncamera { zoom = 3 }\n" + layers);
    dir.write("framed.moire", "scene { size = (20, 15) }\n" + layers);
    auto p =
        runIn(dir, "print s.moire --paper 40x30mm --landscape --dpi 254 --scale 0.5 -o p.png -q");
    REQUIRE_MESSAGE(p.status == 0, p.err);
    auto r = runIn(dir, "render framed.moire --size 400x300 -o r.png -q");
    REQUIRE_MESSAGE(r.status == 0, r.err);
    // The JIT reaches the same pixel size by other float operations: a rounding apart.
    const test::ImageDiff d =
        test::compareImages(readImage(dir.file("p.png")), readImage(dir.file("r.png")), 1.5 / 255);
    CHECK(d.over == 0);
}

TEST_CASE("print's options are checked, each with a clear message") {
    test::TempDir dir("print");
    struct Case {
        const char* args;
        const char* message;
    };
    const Case cases[] = {
        {"--paper B5 --dpi 300", "moire: error: --paper: unknown paper 'B5'; the papers are A0 "
                                 "to A6, letter, legal, tabloid, or a size such as 610x406mm"},
        {"--paper 0x10mm --dpi 300", "'0x10mm' is not a size on paper"},
        {"--paper A4 --dpi 0", "moire: error: --dpi must be a number of dots per inch above 0"},
        {"--paper A4 --dpi -5", "--dpi must be a number of dots per inch above 0"},
        {"--paper A4 --dpi 300 --bleed -1",
         "moire: error: --bleed must be a width in millimetres from 0 to 1000, not -1"},
        {"--paper A4 --dpi 300 --scale 0",
         "moire: error: --scale must be a number of world units per millimetre above 0"},
        {"--paper A4 --dpi 300 --scale -2", "--scale must be a number of world units"},
        {"--paper A0 --dpi 40000", "pixels, more than"},
        {"--paper 1x1mm --dpi 1", "is less than a pixel a side; raise --dpi"},
        {"--paper A4 --dpi 300 --separate -o s.jpg", "JPEG cannot hold"},
    };
    for (const Case& c : cases) {
        const std::string args = c.args;
        CAPTURE(args);
        auto r = runIn(dir, std::string("print ") + c.args + " -o x.tif");
        if (std::string(c.args).find("-o s.jpg") != std::string::npos)
            r = runIn(dir, std::string("print ") + c.args);
        CHECK(r.status == 2);
        CHECK_MESSAGE(r.err.find(c.message) != std::string::npos, r.err);
    }
    CHECK(dir.names().empty()); // nothing written
    auto render = runIn(dir, "render --size 61x40.6cm -o r.png");
    CHECK(render.status == 2);
    CHECK(render.err.find("needs --dpi") != std::string::npos);
    render = runIn(dir, "render --size 61x40.6cm --dpi 10 -o r.png -q");
    CHECK_MESSAGE(render.status == 0, render.err);
    CHECK(readImage(dir.file("r.png")).width == 240); // 610 / 25.4 * 10 = 240.2
}

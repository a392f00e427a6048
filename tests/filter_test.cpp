// The stroke filter (docs/filtering.md): the mean of the stroke as written over the pixel, at
// every size, against the point rule's floored strokes, and the switch between them in the
// scene and on the command line.
#include "runtime/output/ImageIO.h"
#include "runtime/output/Render.h"
#include "tests/support/ExactWindow.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <doctest/doctest.h>
#include <filesystem>
#include <fmt/format.h>

using namespace moire;
using test::downsampled;
using test::exactField;
using test::inkAgainst;
using test::InkAgainst;

namespace {

// Circles 0.7 apart, 0.1 wide, at the default zoom (1 pixel a world unit): 1.43 members a
// pixel, each inking 0.1 / 0.7 of its period.
const char* kFineCircles = "layer a { family = circles; spacing = 0.7; stroke = 0.1 }\n";
constexpr double kFineCirclesInk = 0.1 / 0.7;

// The mean ink (1 - red, on white paper) of an image.
double meanInk(const Image& img) {
    double sum = 0.0;
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) sum += 1.0 - img.at(x, y, 0);
    return sum / (static_cast<double>(img.width) * img.height);
}

// A window of the scene at its own size away from the centre, where the circles' index runs
// evenly (at the centre it folds: r = |p|).
Image fineWindow(const SceneProgram& program, Backend& backend) {
    return test::renderWindow(program, backend, 800, 560, 160, 120);
}

CompileOptions withFilter(sema::FilterMode mode) {
    CompileOptions options;
    options.filter = mode;
    return options;
}

} // namespace

TEST_CASE("filter: circles finer than the pixels read their mean ink, not solid black") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    auto mean = test::compileOk(kFineCircles); // the default filter
    Image img = fineWindow(*mean, *interp);
    CHECK(meanInk(img) == doctest::Approx(kFineCirclesInk).epsilon(0.05));
    // Point-sampled, the floored strokes (2.3 pixels wide every 0.7) merge into solid ink.
    auto point = test::compileOk(kFineCircles, withFilter(sema::FilterMode::Point));
    CHECK(meanInk(fineWindow(*point, *interp)) > 0.95);
    // The scene's switch does the same as the option.
    auto written = test::compileOk(std::string("scene { filter = point }\n") + kFineCircles);
    test::ImageDiff same =
        test::compareImages(fineWindow(*written, *interp), fineWindow(*point, *interp), 0.0);
    CHECK(same.maxAbs == 0.0);
}

TEST_CASE("filter: a turned camera turns the pixel's footprint with it") {
    // Fine lines at 30 degrees seen straight, and lines at 0 degrees under a camera turned by
    // -30 degrees: the same picture, so the footprint must follow the pixel's sides (a
    // footprint that kept to the world's axes would read the second one's lines as crossing
    // the pixel at 30 degrees).
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    const char* kLines = "layer a { family = lines; spacing = 0.8; stroke = 0.15; angle = ";
    auto straight = test::compileOk(std::string(kLines) + "30deg }\n");
    auto turned =
        test::compileOk(std::string("camera { rotation = -30deg }\n") + kLines + "0deg }\n");
    auto unturned = test::compileOk(std::string(kLines) + "0deg }\n");
    const Image want = fineWindow(*straight, *interp);
    test::ImageDiff same = test::compareImages(want, fineWindow(*turned, *interp), 2.0 / 255.0);
    CHECK(same.fractionWithin() >= 0.999);
    // And the angle matters: upright lines fill the square pixel's footprint otherwise.
    test::ImageDiff other = test::compareImages(want, fineWindow(*unturned, *interp), 2.0 / 255.0);
    CHECK(other.fractionWithin() < 0.9);
}

// Lines three ways given by their distance: the triangle lattice's lines, `spacing` apart.
const std::string kDistanceThreeWays =
    "family tri {\n let v = 0.5 * x + 0.8660254037844386 * y\n let w = 0.5 * x - "
    "0.8660254037844386 * y\n distance = min(abs(x - spacing * round(x / spacing)), "
    "min(abs(v - spacing * round(v / spacing)), abs(w - spacing * round(w / spacing))))\n}\n";

TEST_CASE("filter: the JIT and the GPU draw the mean the interpreter draws") {
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    // Lines at a slant over two scales, some resolved, some not, the fine circles, and two
    // resolved families nearly parallel in two colours (their strokes meet within pixels:
    // lower/StrokePairs.h).
    const std::string scenes[] = {
        kFineCircles,
        "camera { zoom = 0.3 }\nlayer a { family = lines; spacing = 4; stroke = 0.5; "
        "rotation = 17deg }\nlayer b { family = circles; spacing = 9; stroke = 2 }\n",
        "layer a { family = lines; spacing = 6; stroke = 1.6; rotation = 31deg }\n"
        "layer b { family = lines; spacing = 6.3; stroke = 1.6; rotation = 33deg; "
        "color = #a02020; opacity = 0.8 }\n",
        // A pencil by its winding index, with its disc, and lattices handing over to their
        // cells' share (their rows about a pixel apart, where the hand-over is partial).
        "layer a { family = pencil; lines = 120; stroke = 0.8; start = 30; origin = (250, "
        "-200) }\n",
        "layer a { family = hex_lattice; spacing = 1.1; stroke = 0.2; edges = 1 }\n"
        "layer b { family = triangle_lattice; spacing = 1.3; stroke = 0.35; scale = (1, 1.4); "
        "color = #a02020 }\n",
        // Fine lines whose members meet a resolved circle's strokes as periodic strokes
        // (StrokePairs.h, stripesCovariance), in two colours.
        "layer a { family = lines; spacing = 0.6; stroke = 0.2; rotation = 10deg }\n"
        "layer b { family = circles; spacing = 5; stroke = 1.2; color = #a02020; opacity = 0.8 "
        "}\n",
        // Two fine lattices' lines beating (FineUnion.h's strands), and a resolved triangle
        // lattice's lines meeting at its points (StrokePairs.h).
        "layer a { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1 }\n"
        "layer b { family = triangle_lattice; spacing = 0.55; stroke = 0.1; edges = 1; rotation "
        "= 3deg; color = #a02020 }\n",
        "layer a { family = triangle_lattice; spacing = 5; stroke = 1.2; edges = 1; rotation = "
        "7deg }\n"
        "layer b { family = lines; spacing = 4; stroke = 0.8; opacity = 0.7 }\n",
        // Dots about a pixel wide, as discs over the pixel (LatticeCrowd.h): the honeycomb's
        // nearest, and a square lattice's nine.
        "layer a { family = hex_lattice; spacing = 2.3; stroke = 0.84 }\n"
        "layer b { family = square_lattice; spacing = 1.6; stroke = 0.9; rotation = 10deg; "
        "color = #a02020; opacity = 0.8 }\n",
        // Two dot screens beating (LatticeUnion.h): triangle screens, and honeycombs' corners.
        "layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.3 }\n"
        "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 4deg; "
        "color = #a02020; opacity = 0.8 }\n",
        "layer a { family = hex_lattice; spacing = 0.35; stroke = 0.2 }\n"
        "layer b { family = hex_lattice; spacing = 0.35; stroke = 0.2; rotation = 3deg }\n",
        // Two honeycombs' edges by their cells (LatticeUnion.h, cellCorrelation).
        "layer a { family = hex_lattice; spacing = 0.35; stroke = 0.1; edges = 1 }\n"
        "layer b { family = hex_lattice; spacing = 0.35; stroke = 0.1; edges = 1; rotation = "
        "3deg; color = #a02020 }\n",
        // A honeycomb's edges over the pixel by two rings of its hexagons
        // (HoneycombInPixel.h), under resolved lines.
        "layer a { family = hex_lattice; spacing = 0.5; stroke = 0.1; edges = 1; rotation = "
        "7deg }\n"
        "layer b { family = lines; spacing = 3; stroke = 0.4; rotation = 20deg; color = "
        "#a02020 }\n",
        // A honeycomb's edges under fine lines (LatticeUnion.h, hexLineCorrelation).
        "layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n"
        "layer b { family = lines; spacing = 0.6; stroke = 0.1; angle = 32deg; color = "
        "#a02020 }\n",
        // A honeycomb's edges under a fine triangle screen along its rows of centres
        // (LatticeUnion.h, hexDotCorrelation).
        "layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n"
        "layer b { family = triangle_lattice; spacing = 0.693; stroke = 0.3; rotation = 2deg; "
        "color = #a02020 }\n",
        // A honeycomb's dots under fine lines (LatticeUnion.h, dotLineCorrelation).
        "layer a { family = hex_lattice; spacing = 0.35; stroke = 0.2 }\n"
        "layer b { family = lines; spacing = 0.525; stroke = 0.15; angle = 92deg; color = "
        "#a02020 }\n",
        // A resolved honeycomb under a stretched triangle screen whose dots tie on the
        // pixels' grid: the nearest dot's stroke meets the edges (StrokePairs.h), weighed to 0
        // at a tie, where double and float picked different dots (1.6% of pixels apart).
        "layer a { family = hex_lattice; spacing = 2.2; stroke = 0.6; edges = 1; rotation = 7deg "
        "}\n"
        "layer b { family = triangle_lattice; spacing = 3; stroke = 2.4; scale = (1, 1.4); color "
        "= #a02020 }\n",
        // Families given by their distance (DistanceFamily.h): a grid's crossings read in
        // parts under resolved circles, and rings five a pixel read in the finer parts, under
        // a turned camera.
        "family grid { distance = min(abs(x - spacing * round(x / spacing)), abs(y - spacing * "
        "round(y / spacing))) }\n"
        "layer a { family = grid; spacing = 1.3; stroke = 0.3; rotation = 10deg }\n"
        "layer b { family = circles; spacing = 3; stroke = 0.6; color = #a02020 }\n",
        "family rings { distance = abs(r - spacing * round(r / spacing)) }\n"
        "camera { rotation = 25deg }\n"
        "layer a { family = rings; spacing = 0.2; stroke = 0.05; origin = (30, 10) }\n",
        // Two such rings crowding and beating, by the index each crowd runs by
        // (DistanceFamily.h, runs), under a turned camera.
        "family rings { distance = abs(r - spacing * round(r / spacing)) }\n"
        "camera { rotation = 25deg }\n"
        "layer a { family = rings; spacing = 0.2; stroke = 0.05; origin = (30, 10) }\n"
        "layer b { family = rings; spacing = 0.21; stroke = 0.06; origin = (30, 10); color = "
        "#a02020 }\n",
        // Squares turned and circles about a centre in the window, under a turned camera:
        // their index folds along the squares' corners and bends about the centre, where
        // the pixel is read in parts (Prefilter.h, bentIndexMean).
        "camera { rotation = 20deg }\n"
        "layer a { family = squares; spacing = 5; stroke = 1.2; rotation = 10deg; origin = (338, "
        "-111) }\n"
        "layer b { family = circles; spacing = 3; stroke = 0.8; origin = (338, -111); color = "
        "#a02020; opacity = 0.8 }\n",
        // A hyperbola about its centre and along its asymptotes, read in parts below its
        // first member and where its index bends (Prefilter.h, belowFirstMean), under a
        // turned camera.
        "camera { rotation = 20deg }\n"
        "layer a { family = hyperbola; spacing = 2; stroke = 0.4; rotation = 10deg; origin = "
        "(338, -111) }\n",
        // A fork: lines encoding the angle about a point of the window, read in parts where
        // the index folds, the field read again at each part (LayerLowering::fieldAt), and
        // circles encoding a slope, under a turned camera.
        "camera { rotation = 20deg }\n"
        "layer a { family = lines; spacing = 2; stroke = 0.5; rotation = 10deg; field = "
        "atan2(y + 111, x - 338) / tau; gain = 5 }\n"
        "layer b { family = circles; spacing = 3; stroke = 0.8; origin = (338, -111); field = "
        "(x - 338) * (x - 338) / 200; gain = 1; color = #a02020; opacity = 0.8 }\n",
        // A square screen with a triangle one whose rows stand as far apart, turned 2 degrees:
        // their first harmonics beat (LatticeUnion.cpp, harmonicCovariance).
        "layer a { family = square_lattice; spacing = 0.52; stroke = 0.26 }\n"
        "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 2deg; "
        "color = #a02020 }\n",
        // Dots eight a pixel, read as a dot screen (DistanceDots.h), under a turned camera.
        "family dots { distance = hypot(x - spacing * round(x / spacing), y - spacing * "
        "round(y / spacing)) }\n"
        "camera { rotation = 25deg }\n"
        "layer a { family = dots; spacing = 0.125; stroke = 0.0625; rotation = 10deg }\n",
        // Square dots a pixel apart, a Chebyshev distance: past each square's diagonal a
        // part's stroke is cut by its neighbour's (DistanceFamily.cpp, boundedBy).
        "family cheb { distance = max(abs(x - spacing * round(x / spacing)), abs(y - spacing * "
        "round(y / spacing))) }\n"
        "layer a { family = cheb; spacing = 1; stroke = 0.5; rotation = 10deg }\n",
        // A triangle lattice's edges over the pixel (TriangleInPixel.h): rows 0.7 to 1.4 a
        // pixel (the 3 x 3 cells about the pixel's) and rows a few pixels apart (the 2 x 2
        // nearest it), under lines.
        "layer a { family = triangle_lattice; spacing = 1.2; stroke = 0.3; edges = 1; rotation = "
        "10deg }\n"
        "layer b { family = triangle_lattice; spacing = 5; stroke = 1; edges = 1; rotation = 3deg; "
        "color = #a02020; opacity = 0.8 }\n",
    };
    // Every backend's window of `program` against the interpreter's, drawn by `window`.
    auto holdToInterpreter = [&](const SceneProgram& program, auto window) {
        const Image ref = window(program, *interp);
        for (const char* name : {"jit", "vulkan"}) {
            CAPTURE(name);
            auto backend = test::makeBackendOrSkip(name);
            if (!backend) continue;
            const test::ImageDiff d =
                test::compareImages(ref, window(program, *backend), 2.0 / 255);
            if (std::getenv("MOIRE_FILTER_REPORT"))
                MESSAGE(std::string(name), ": ", d.fractionWithin(), " within 2/255, mean ",
                        d.meanAbs * 255);
            CHECK(d.fractionWithin() >= 0.999);
            CHECK(d.meanAbs <= 0.5 / 255.0);
        }
    };
    for (const std::string& text : scenes) {
        CAPTURE(text);
        holdToInterpreter(*test::compileOk(text), fineWindow);
    }
    // Rings about a lattice's points four a pixel, read as two dot screens' difference
    // (DistanceRings.h), in a smaller window (the interpreter reads them slowly). Read by
    // their tubes, whose probes branch on bounds a float may take the other way from a double,
    // 0.08% of this window's pixels were off by more than 2/255 on the JIT and lavapipe; with
    // the rings' centres of curvature alone, 400 units out from the frame's centre, 2.3%
    // (float's rounding spoiled the centre by a percent, and the roundness check failed),
    // before the centre was moved to the distance's peak: 0.016%. Laid over lines 3 degrees
    // off (their beat, a ring screen in the union of fine layers, LatticeUnion.h), the pixels
    // by the corner four rings' cells share, whose centres of curvature a float read from
    // other rings (and left to the tubes), were 0.078% off (the union's correlation lost
    // there); read half-way to the ring, none is.
    const std::string rings =
        "family ringdots { distance = abs(hypot(x - spacing * round(x / spacing), y - spacing * "
        "round(y / spacing)) - 0.25 * spacing) }\n"
        "layer a { family = ringdots; spacing = 0.25; stroke = 0.025; rotation = 10deg }\n"
        "layer b { family = lines; spacing = 0.25; stroke = 0.06; rotation = 13deg }\n";
    holdToInterpreter(*test::compileOk(rings), [](const SceneProgram& program, Backend& backend) {
        return test::renderWindow(program, backend, 800, 560, 80, 60);
    });
    // Lines three ways given by their distance, four a pixel each way, read in closed form
    // with their excess over independent inks (DistanceGrid.h), beating with lines 3 degrees
    // off one of their ways (a third strand in the union of fine layers).
    const std::string threeWays =
        kDistanceThreeWays +
        "layer a { family = tri; spacing = 0.25; stroke = 0.04; rotation = 10deg }\n"
        "layer b { family = lines; spacing = 0.25; stroke = 0.06; rotation = 13deg }\n";
    holdToInterpreter(*test::compileOk(threeWays),
                      [](const SceneProgram& program, Backend& backend) {
                          return test::renderWindow(program, backend, 800, 560, 80, 60);
                      });
    // Two layers of lines three ways 3 degrees apart: the meeting points' harmonics, a loop
    // in the kernel (MeetingBeat.h).
    const std::string bothThree =
        kDistanceThreeWays +
        "layer a { family = tri; spacing = 0.25; stroke = 0.04; rotation = 10deg }\n"
        "layer b { family = tri; spacing = 0.25; stroke = 0.04; rotation = 13deg }\n";
    holdToInterpreter(*test::compileOk(bothThree),
                      [](const SceneProgram& program, Backend& backend) {
                          return test::renderWindow(program, backend, 800, 560, 80, 60);
                      });
}

TEST_CASE("filter: --filter on render, and a bad value named") {
    test::TempDir dir("filter");
    dir.write("fine.moire", std::string("scene { size = (160, 120) }\n") + kFineCircles);
    auto render = [&](const std::string& args, const std::string& out) {
        return test::runCommand(test::moireBinary() + " render " + dir.file("fine.moire") +
                                " --backend interp -o " + dir.file(out) + " " + args);
    };
    REQUIRE(render("", "mean.png").status == 0);
    REQUIRE(render("--filter point", "point.png").status == 0);
    REQUIRE(render("--filter mean", "asked.png").status == 0);
    const double meanShown = meanInk(readImage(dir.file("mean.png")));
    CHECK(meanShown < 0.3); // the centre's fold and 8-bit quantising aside, ~0.14
    CHECK(meanInk(readImage(dir.file("point.png"))) > 0.9);
    CHECK(meanInk(readImage(dir.file("asked.png"))) == doctest::Approx(meanShown));
    test::CommandResult bad = render("--filter blur", "bad.png");
    CHECK(bad.status != 0);
    CHECK(bad.err.find("--filter must be point or mean, not 'blur'") != std::string::npos);
    CHECK_FALSE(std::filesystem::exists(dir.file("bad.png")));
}

// The window of an example the exact-field tests compare (96 x 64, off the frame's centre),
// and the backend they draw with (the JIT, else the interpreter).
struct ExampleWindow {
    std::string rel, name, text;
    int x0, y0;
};
constexpr int kWindowW = 96, kWindowH = 64, kExactSamples = 8;

// Every example but the walking ones: inside a stroke their solver reports the first member it
// accepts (§7.1), not always the nearest, and walking_triangles piles members closer than a
// pixel, where the nearest member alone is not the pixel's ink; experiments/tone_resolution
// measures them.
std::vector<ExampleWindow> exampleWindows() {
    std::vector<ExampleWindow> out;
    for (const std::string& rel : test::exampleScenes()) {
        const std::string name = std::filesystem::path(rel).stem().string();
        if (name.find("walk") != std::string::npos) continue;
        const std::string text = test::readFile(test::sourcePath(rel));
        auto scene = test::compileOk(text, {}, rel);
        FrameValues fv;
        std::string diags;
        REQUIRE(evaluateFrame(*scene, FrameRequest{}, fv, diags));
        out.push_back(
            {rel, name, text, (fv.width - kWindowW) / 2 + 37, (fv.height - kWindowH) / 2 - 23});
    }
    return out;
}

// The declarations `decls` in a 160 x 120 frame drawn one sample a pixel, and their exact field
// at 32 x 32 samples a pixel, at `time`, over the window (x0, y0, width, height): the two
// images.
std::pair<Image, Image> layerAndExact(const std::string& decls, Backend& backend, int x0, int y0,
                                      int width, int height, double time = 0.0) {
    const std::string text = "scene { size = (160, 120) }\n" + decls;
    auto drawn = test::compileOk(text);
    auto field = test::compileOk(text, exactField({}));
    // 32 x 32 samples: the exact field's antialias band, 0.7 of a sample, widens a dot of
    // radius r by a share of about (0.7 / 32 / r)^2 / 3 (a few percent at a lattice's dots).
    return {downsampled(*drawn, backend, x0, y0, width, height, 1, 0, 1, time),
            downsampled(*field, backend, x0, y0, width, height, 32, 0, 1, time)};
}

// The window drawn one sample a pixel by `drawn` and kExactSamples^2 by the exact field, its
// outputs [c0, c0 + channels): the two images.
std::pair<Image, Image> drawnAndExact(const ExampleWindow& w, const CompileOptions& options,
                                      Backend& backend, int c0, int channels) {
    auto drawn = test::compileOk(w.text, options, w.rel);
    auto field = test::compileOk(w.text, exactField(options), w.rel);
    return {
        downsampled(*drawn, backend, w.x0, w.y0, kWindowW, kWindowH, 1, c0, channels),
        downsampled(*field, backend, w.x0, w.y0, kWindowW, kWindowH, kExactSamples, c0, channels)};
}

// Every layer of every example alone, under the default filter, against an independent
// expectation: the exact field's stroke (as written, no floor) point-sampled 8 x 8 times a
// pixel and averaged. The mean is exact for phase families whose index runs evenly over a
// pixel and for members apart by more than a pixel, so the tone of a preview is the tone of
// a print (docs/filtering.md; experiments/tone_resolution measures the whole frames).
TEST_CASE("filter: each layer of the examples reads the box-filtered ink of its exact field") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    int compared = 0;
    for (const ExampleWindow& w : exampleWindows()) {
        auto scene = test::compileOk(w.text, {}, w.rel);
        for (int l = 0; l < static_cast<int>(scene->checked.layers.size()); ++l) {
            CAPTURE(w.name);
            CAPTURE(l);
            CompileOptions mean;
            mean.separateLayer = l;
            const auto [got, want] = drawnAndExact(w, mean, *backend, 3, 1);
            double sq = 0.0, sum = 0.0, gotInk = 0.0, wantInk = 0.0;
            for (size_t i = 0; i < got.pixels.size(); ++i) {
                const double e = got.pixels[i] - want.pixels[i];
                sq += e * e;
                sum += e;
                gotInk += got.pixels[i];
                wantInk += want.pixels[i];
            }
            const double n = static_cast<double>(got.pixels.size());
            INFO("ink ", gotInk / n, " against ", wantInk / n);
            CHECK(std::sqrt(sq / n) <= 0.03);  // the pixel's tone
            CHECK(std::abs(sum / n) <= 0.005); // the window's tone
            ++compared;
        }
    }
    CHECK(compared >= 25);
}

// A pencil's lines crowd towards its centre: 90 lines are 1 pixel apart 29 pixels out and a
// tenth of a pixel 3 pixels out. Counted by its nearest line alone, that core was drawn light
// where its lines merge; averaged by their winding index (PencilFamily.cpp), every line the
// pixel holds counts. Against the exact field (the stroke as written, 8 x 8 samples a pixel),
// in a window from 6 to about 90 pixels out, without the open disc and with one (whose edge
// is drawn from the distance): the whole window's RMSE and its mean ink.
TEST_CASE("filter: a pencil's crowded core reads its mean ink, counted by its winding index") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    for (const char* start : {"0", "24"}) {
        CAPTURE(start);
        const std::string text = std::string("scene { size = (200, 200) }\n"
                                             "layer a { family = pencil; lines = 90; stroke = "
                                             "0.6; start = ") +
                                 start + " }\n";
        auto drawn = test::compileOk(text);
        auto field = test::compileOk(text, exactField({}));
        // Right of the centre and above it: 6 to 88 pixels out along x, up to 40 across.
        const Image got = downsampled(*drawn, *backend, 106, 60, 80, 40, 1, 0, 1);
        const Image want = downsampled(*field, *backend, 106, 60, 80, 40, kExactSamples, 0, 1);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE("pencil, start ", std::string(start), ": RMSE ", d.rmse, ", ink ", d.ink,
                    " against ", d.exact);
        CHECK(d.rmse <= 0.04);
        CHECK(std::abs(d.ink - d.exact) <= 0.01);
    }
}

// Lattices finer than the pixels: the three kinds, points and edges, one of each stretched,
// their rows 0.45 to 0.65 pixel apart, and two lattices of edges about a cell a pixel. A lattice
// gives the distance to its nearest point or edge alone, and counted by it the pixel held one
// member's ink; the share of the plane the strokes cover (LatticeCrowd.cpp) is what the exact
// field's samples read: within 5% of its ink, and 0.05 RMSE.
TEST_CASE("filter: lattices finer than the pixels read their mean ink") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const char* kLayers[] = {
        "family = square_lattice; spacing = 0.55; stroke = 0.2",
        "family = square_lattice; spacing = 0.5; stroke = 0.08; edges = 1; scale = (1, 1.3)",
        "family = triangle_lattice; spacing = 0.6; stroke = 0.2",
        "family = triangle_lattice; spacing = 0.7; stroke = 0.06; edges = 1",
        "family = hex_lattice; spacing = 0.4; stroke = 0.15; scale = (1.2, 1)",
        "family = hex_lattice; spacing = 0.5; stroke = 0.06; edges = 1",
        // The square's and the triangle's edges are whole lines, averaged as phase families
        // at every scale: about a cell a pixel, and turned.
        "family = square_lattice; spacing = 1.1; stroke = 0.2; edges = 1; rotation = 20deg",
        "family = triangle_lattice; spacing = 1.3; stroke = 0.15; edges = 1; scale = (1.2, 1)",
    };
    for (const char* layer : kLayers) {
        CAPTURE(layer);
        const auto [got, want] =
            layerAndExact(std::string("layer a { ") + layer + " }\n", *backend, 20, 20, 64, 48);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE(std::string(layer), ": RMSE ", d.rmse, ", ink ", d.ink, " against ", d.exact);
        CHECK(std::abs(d.ink - d.exact) <= 0.05 * d.exact);
        CHECK(d.rmse <= 0.05);
    }
}

// Whole pictures of the examples with two layers or more, against the exact field's colour
// (each stroke as written, no floor) point-sampled 8 x 8 times a pixel and averaged. Laid over
// one another as independent, strokes that run nearly parallel through a pixel (a moiré's
// fringes) were off by 0.02-0.045 RMSE in these windows; the pairs' covariance
// (lower/StrokePairs.h) is what brings them to the layers' own tone.
TEST_CASE("filter: whole pictures read the box-filtered colour of their exact field") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    int compared = 0;
    for (const ExampleWindow& w : exampleWindows()) {
        if (test::compileOk(w.text, {}, w.rel)->checked.layers.size() < 2) continue;
        CAPTURE(w.name);
        const auto [got, want] = drawnAndExact(w, {}, *backend, 0, 3);
        double sq = 0.0;
        for (size_t i = 0; i < got.pixels.size(); ++i) {
            const double e = got.pixels[i] - want.pixels[i];
            sq += e * e;
        }
        const double rmse = std::sqrt(sq / static_cast<double>(got.pixels.size()));
        // Measured 0.001-0.0104 (0.0067-0.045 before the pairs' covariance); hyperbolae 0.0086
        // (0.031 before the pairs' covariance, 0.020 before its first members and asymptotes
        // were read in parts, 0.0128 before the pairs read each member's neighbours; each layer
        // alone 0.024 -> 0.0014): its window holds the first members' vertices and the
        // asymptotes, where its two layers' strokes meet.
        if (std::getenv("MOIRE_FILTER_REPORT")) MESSAGE(w.name, ": RMSE ", rmse);
        CHECK(rmse <= 0.012);
        ++compared;
    }
    CHECK(compared >= 12);
}

// The exact field's spread over a window: the RMSE of an even grey of its mean ink.
double spreadOf(const Image& img) {
    double mean = 0.0, sq = 0.0;
    for (float v : img.pixels) mean += v / double(img.pixels.size());
    for (float v : img.pixels) sq += (v - mean) * (v - mean) / double(img.pixels.size());
    return std::sqrt(sq);
}

// One lattice (or a pair) drawn one sample a pixel against the exact field at 32 x 32 samples
// a pixel, in a 64 x 48 window of a 160 x 120 frame.
InkAgainst latticeAgainstExact(const std::string& layers, Backend& backend, double& spread,
                               int samples = 32) {
    const std::string text = std::string("scene { size = (160, 120) }\n") + layers;
    auto drawn = test::compileOk(text);
    auto field = test::compileOk(text, exactField({}));
    const Image got = downsampled(*drawn, backend, 20, 20, 64, 48, 1, 0, 1);
    const Image want = downsampled(*field, backend, 20, 20, 64, 48, samples, 0, 1);
    spread = spreadOf(want);
    const InkAgainst d = inkAgainst(got, want);
    if (std::getenv("MOIRE_FILTER_REPORT"))
        MESSAGE(layers, "RMSE ", d.rmse, ", ink ", d.ink, " against ", d.exact,
                ", the exact field's spread ", spread);
    return d;
}

// One lattice against the exact field: within `rmse`, and its ink within `inkShare` of the
// exact ink.
void checkLatticeAgainstExact(const char* layers, Backend& backend, double rmse, double inkShare) {
    CAPTURE(layers);
    double spread = 0.0;
    const InkAgainst d = latticeAgainstExact(layers, backend, spread);
    CHECK(d.rmse <= rmse);
    CHECK(std::abs(d.ink - d.exact) <= inkShare * d.exact);
}

// Two lattices of edges whose lines are finer than the pixels and whose beat is not: a square
// lattice turned 3 degrees on another (the beat 0.5 / (2 sin 1.5deg) = 9.5 pixels), two
// triangle lattices 4 degrees apart, square lattices of pitches 0.5 and 0.53 (a beat of 8.8
// pixels along both axes), a square lattice beating with fine lines (either on top); and two
// resolved square lattices whose strokes cross within pixels. Laid as independent inks the fine
// pairs were an even grey (RMSE 0.034-0.057, each the exact field's own spread) and the
// resolved pair 0.032 off; each line beats with the other lattice's nearest in direction
// (FineUnion.h, strandCorrelation; two triangle lattices by their cells, LatticeUnion.h), and
// resolved lines meet as strokes (StrokePairs.h). A square lattice with lines about twice or
// half as fine beats by one layer's second harmonic with the other's first: read by the first
// harmonics alone those pairs were an even grey too (0.040 and 0.033 against spreads of
// 0.037), 0.0025 and 0.0074 since. An even grey's error is the field's spread: the drawn pair
// must be within a quarter of it.
TEST_CASE("filter: two lattices finer than the pixels show their beat") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    struct Case {
        const char* layers;
        double share; // of the exact field's spread
    };
    const Case kPairs[] = {
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1 }\n"
         "layer b { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1; rotation = "
         "3deg }\n",
         0.25},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.1; edges = 1 }\n"
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.1; edges = 1; rotation "
         "= 4deg; color = #a02020 }\n",
         0.25},
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.12; edges = 1 }\n"
         "layer b { family = square_lattice; spacing = 0.53; stroke = 0.12; edges = 1 }\n",
         0.25},
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1; rotation = "
         "10deg }\n"
         "layer b { family = lines; spacing = 0.5; stroke = 0.15; angle = 97deg }\n",
         0.25},
        {"layer a { family = lines; spacing = 0.5; stroke = 0.15; angle = 97deg }\n"
         "layer b { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1; rotation = "
         "10deg }\n",
         0.25},
        {"layer a { family = square_lattice; spacing = 6; stroke = 1.5; edges = 1 }\n"
         "layer b { family = square_lattice; spacing = 6.2; stroke = 1.5; edges = 1; rotation = "
         "5deg }\n",
         0.05},
        // A lattice's lines and lines about twice as fine, or half as fine: the beat is of one
        // layer's second harmonic with the other's first (strandCorrelation, kHarmonicPairs).
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1 }\n"
         "layer b { family = lines; spacing = 0.245; stroke = 0.08; rotation = 3deg }\n",
         0.25},
        {"layer a { family = square_lattice; spacing = 0.3; stroke = 0.08; edges = 1; rotation = "
         "20deg }\n"
         "layer b { family = lines; spacing = 0.62; stroke = 0.15; rotation = 24deg }\n",
         0.25},
        // A faint fine grid under two fine line families whose beat is coarse: the lines' beat
        // is correlated by the second pair of the run (Compose.cpp hands the pair's last layer
        // on).
        {"layer g { family = square_lattice; spacing = 0.45; stroke = 0.05; edges = 1; opacity = "
         "0.4 }\n"
         "layer a { family = lines; spacing = 0.5; stroke = 0.15 }\n"
         "layer b { family = lines; spacing = 0.525; stroke = 0.15 }\n",
         0.25},
    };
    for (const Case& c : kPairs) {
        CAPTURE(c.layers);
        double spread = 0.0;
        const InkAgainst d = latticeAgainstExact(c.layers, *backend, spread);
        CHECK(spread >= 0.03); // the exact field holds the beat
        CHECK(d.rmse <= c.share * spread);
    }
}

// A pair of layers against the exact field: within a quarter of the exact field's spread (an
// even grey is as far off as the spread), or of 1.25 times the two layers' own errors together
// where those are larger; its ink within 2% of the exact ink. `families` declares the families
// the layers draw that are not built in; the exact field is read at `samples` x `samples` a
// pixel.
void checkPairAgainstExact(const char* first, const char* second, Backend& backend,
                           const std::string& families = "", int samples = 32) {
    const std::string layers = families + first + second;
    CAPTURE(layers);
    double spread = 0.0, alone = 0.0;
    for (const char* one : {first, second}) {
        double own = 0.0;
        const double e = latticeAgainstExact(families + one, backend, own, samples).rmse;
        alone += e * e;
    }
    const InkAgainst d = latticeAgainstExact(layers, backend, spread, samples);
    CHECK(spread >= 0.03); // the exact field holds the beat
    CHECK(d.rmse <= std::max(0.25 * spread, 1.25 * std::sqrt(alone)));
    CHECK(std::abs(d.ink - d.exact) <= 0.02 * d.exact);
}

// Two dot screens whose dots are finer than the pixels and whose beat is not: square
// screens turned 3 degrees (a beat of 9.5 pixels), or of pitches 0.5 and 0.53 with one turned
// a quarter; triangle screens 0.5 to 4 degrees apart (down to a beat of 69 pixels), or at 30
// and 92 degrees; honeycombs' corners turned 2 and 3 degrees. Laid as independent inks the
// beat was lost, an even grey as far off as the exact field's spread (RMSE 0.035-0.068); with
// the screens' overlap (LatticeUnion.h) the pair is within a quarter of the spread of the exact
// field, or of the error each screen makes alone (0.0025 for the triangle screen 0.4 apart,
// 0.0023 for the honeycomb 0.35 on a side, with the box filter's ripple about their shares;
// 0.008 and 0.014 without it): the pair's error is then theirs together.
TEST_CASE("filter: two dot screens finer than the pixels show their beat") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.25 }\n",
         "layer b { family = square_lattice; spacing = 0.5; stroke = 0.25; rotation = 3deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.3 }\n",
         "layer b { family = square_lattice; spacing = 0.53; stroke = 0.3; rotation = 90deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.25 }\n",
         "layer b { family = square_lattice; spacing = 0.5; stroke = 0.25; rotation = 8deg }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.5; stroke = 0.25 }\n",
         "layer b { family = triangle_lattice; spacing = 0.5; stroke = 0.25; rotation = 12deg }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.3 }\n",
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 4deg; "
         "color = #a02020 }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.3 }\n",
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 0.5deg "
         "}\n"},
        {"layer a { family = triangle_lattice; spacing = 0.4; stroke = 0.2 }\n",
         "layer b { family = triangle_lattice; spacing = 0.4; stroke = 0.2; rotation = 3deg }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 30deg }\n",
         "layer b { family = triangle_lattice; spacing = 0.62; stroke = 0.35; rotation = 92deg "
         "}\n"},
        {"layer a { family = hex_lattice; spacing = 0.35; stroke = 0.2 }\n",
         "layer b { family = hex_lattice; spacing = 0.35; stroke = 0.2; rotation = 3deg }\n"},
        {"layer a { family = hex_lattice; spacing = 0.25; stroke = 0.14 }\n",
         "layer b { family = hex_lattice; spacing = 0.25; stroke = 0.14; rotation = 2deg }\n"},
    };
    for (const auto& [first, second] : kPairs) checkPairAgainstExact(first, second, *backend);
}

// A lattice past resolved reads its share of the plane, which is the box-filtered field's
// mean but not its ripple: the pixel's square passes each of the lattice's harmonics as
// sin(pi f) / (pi f) along each side (f its cycles a pixel), and the exact field's pixels
// swing about the share by that. Dot screens 3 to 4 rows a pixel and a honeycomb's edges past
// 3.4 were 0.0084 to 0.022 RMSE off the exact field (a pixel up to 0.047 off); their harmonics
// to the second order added (LatticeCrowd.cpp, latticeRipple), 0.0023 to 0.0038, most of it the
// exact field's own antialias band, which widens its strokes (its ink stands 0.002 to 0.004
// over the share).
TEST_CASE("filter: a lattice finer than the pixels reads the box filter's ripple about its share") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    for (const char* layer : {
             "family = triangle_lattice; spacing = 0.4; stroke = 0.2",
             "family = square_lattice; spacing = 0.3; stroke = 0.15; rotation = 5deg",
             "family = hex_lattice; spacing = 0.35; stroke = 0.2",
             "family = hex_lattice; spacing = 0.25; stroke = 0.14; rotation = 2deg",
             "family = hex_lattice; spacing = 0.25; stroke = 0.15; edges = 1; rotation = 7deg",
             "family = hex_lattice; spacing = 0.2; stroke = 0.1; edges = 1; rotation = 7deg",
         }) {
        CAPTURE(layer);
        const auto [got, want] =
            layerAndExact(std::string("layer a { ") + layer + " }\n", *backend, 20, 20, 64, 48);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE(std::string(layer), ": RMSE ", d.rmse, ", worst ", d.worst);
        CHECK(d.rmse <= 0.005);
        CHECK(d.worst <= 0.008);
    }
}

// Dot screens of different kinds, or turned past their rows' match, share no offset that
// moves one onto the other, so the screens' overlap (dotCorrelation's matched rows) cannot
// read them: laid as independent, a square screen 0.52 apart with a triangle screen 0.6 apart
// (whose rows stand as far apart, a harmonic of each cancelling the other's) read 11% too
// dark, RMSE 0.039 and 0.038 (turned 0 and 30 degrees), and turned 2 and 32 degrees lost their
// beat, 0.026 and 0.027; a square and a triangle screen 0.5 apart turned 12 degrees, 0.011.
// Their first harmonics' products over the pixel (LatticeUnion.cpp, harmonicCovariance):
// 0.0033 to 0.0043, the ink within 0.5%.
TEST_CASE("filter: dot screens of different kinds show their beat") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const char* kSquare = "layer a { family = square_lattice; spacing = 0.52; stroke = 0.26 }\n";
    const std::pair<std::string, std::string> kPairs[] = {
        {kSquare, "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3 }\n"},
        {kSquare,
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 30deg }\n"},
        {kSquare,
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 2deg }\n"},
        {kSquare,
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.3; rotation = 32deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.25 }\n",
         "layer b { family = triangle_lattice; spacing = 0.5; stroke = 0.25; rotation = 12deg }\n"},
    };
    for (const auto& [first, second] : kPairs)
        checkLatticeAgainstExact((first + second).c_str(), *backend, 0.006, 0.01);
}

// Two lattices of edges of one kind by their cells (LatticeUnion.h, cellCorrelation): the paper
// each leaves is its cells shrunk by its strokes, and the two papers' overlap at the offset
// the beat carries is a closed form (cellArea). Honeycombs, whose edges are no whole lines
// and were laid as independent (RMSE 0.035-0.039, the exact field's spread), turned on one
// another or of two pitches, and triangle lattices, whose strands' pairs are not independent
// where their lines meet (0.0136). Triangle lattices of two pitches, 0.5 and 0.52 and 0.5 and
// 0.53 turned 2 degrees: 0.0124 and 0.0148 with the second's cells stepped at the first's
// period, 0.0077 and 0.0076 with its pattern taken at that period.
TEST_CASE("filter: two lattices of edges of one kind show their beat by their cells") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = hex_lattice; spacing = 0.35; stroke = 0.1; edges = 1 }\n",
         "layer b { family = hex_lattice; spacing = 0.35; stroke = 0.1; edges = 1; rotation = "
         "3deg; color = #a02020 }\n"},
        {"layer a { family = hex_lattice; spacing = 0.3; stroke = 0.08; edges = 1; rotation = "
         "10deg }\n",
         "layer b { family = hex_lattice; spacing = 0.31; stroke = 0.1; edges = 1; rotation = "
         "71deg }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.1; edges = 1 }\n",
         "layer b { family = triangle_lattice; spacing = 0.6; stroke = 0.1; edges = 1; rotation "
         "= 4deg; color = #a02020 }\n"},
        {"layer a { family = hex_lattice; spacing = 0.3; stroke = 0.08; edges = 1 }\n",
         "layer b { family = hex_lattice; spacing = 0.315; stroke = 0.08; edges = 1 }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.5; stroke = 0.1; edges = 1 }\n",
         "layer b { family = triangle_lattice; spacing = 0.52; stroke = 0.1; edges = 1 }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.5; stroke = 0.1; edges = 1 }\n",
         "layer b { family = triangle_lattice; spacing = 0.53; stroke = 0.12; edges = 1; rotation "
         "= 2deg }\n"},
    };
    for (const auto& [first, second] : kPairs) checkPairAgainstExact(first, second, *backend);
}

// A dot screen and fine lines whose beat is coarse, either on top: lines beside a square
// screen's rows turned 3 degrees, a triangle screen's and a honeycomb's rows 1.5 and 2 degrees
// off theirs, and a square screen under a square grid of edges turned 3 degrees (each of the
// grid's lines beats with a row). Laid as independent, an even grey (0.031-0.051 off); each
// line beating with the screen's row nearest its direction (LatticeUnion.h, dotLineCorrelation),
// as the dot screens above.
TEST_CASE("filter: a dot screen and fine lines show their beat") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.25 }\n",
         "layer b { family = lines; spacing = 0.5; stroke = 0.15; rotation = 3deg }\n"},
        {"layer a { family = lines; spacing = 0.5; stroke = 0.15; rotation = 3deg }\n",
         "layer b { family = square_lattice; spacing = 0.5; stroke = 0.25 }\n"},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.3 }\n",
         "layer b { family = lines; spacing = 0.52; stroke = 0.15; angle = 31.5deg; color = "
         "#a02020 }\n"},
        {"layer a { family = hex_lattice; spacing = 0.35; stroke = 0.2 }\n",
         "layer b { family = lines; spacing = 0.525; stroke = 0.15; angle = 92deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.5; stroke = 0.25 }\n",
         "layer b { family = square_lattice; spacing = 0.5; stroke = 0.1; edges = 1; rotation = "
         "3deg }\n"},
    };
    for (const auto& [first, second] : kPairs) checkPairAgainstExact(first, second, *backend);
}

// A honeycomb's edges and fine lines (LatticeUnion.h, hexLineCorrelation): lines that run
// with a row of the honeycomb's centres (0.6 apart for hexagons 0.4 on a side) or of the lines
// its sides lie on, turned 2 degrees, a square grid's lines the same, and lines beneath the
// honeycomb; hexagons 0.3 on a side, finer than its polygons are measured (3.8 rows a pixel:
// its share, alone 0.016 off). Laid as independent inks the beat was lost, 0.019-0.042 off
// against spreads of 0.032-0.046; with the hexagons' paper less the strokes across them at
// the offset the beat carries, 0.0047-0.014.
TEST_CASE("filter: a honeycomb's edges and fine lines show their beat") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n",
         "layer b { family = lines; spacing = 0.6; stroke = 0.1; angle = 32deg }\n"},
        {"layer a { family = lines; spacing = 0.6; stroke = 0.1; angle = 92deg }\n",
         "layer b { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n"},
        {"layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n",
         "layer b { family = square_lattice; spacing = 0.6; stroke = 0.1; edges = 1; rotation = "
         "2deg }\n"},
        {"layer a { family = hex_lattice; spacing = 0.3; stroke = 0.08; edges = 1 }\n",
         "layer b { family = lines; spacing = 0.46; stroke = 0.14; angle = 33deg }\n"},
    };
    for (const auto& [first, second] : kPairs) checkPairAgainstExact(first, second, *backend);
}

// A honeycomb's edges and a dot screen (LatticeUnion.h, hexDotCorrelation): a triangle screen
// whose rows run with the honeycomb's rows of centres (0.693 apart for hexagons 0.4 on a side),
// turned 2 degrees, either on top; and a honeycomb's own corners as dots, turned 3 degrees.
TEST_CASE("filter: a honeycomb's edges and a dot screen show their beat") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n",
         "layer b { family = triangle_lattice; spacing = 0.693; stroke = 0.3; rotation = 2deg "
         "}\n"},
        {"layer a { family = triangle_lattice; spacing = 0.7; stroke = 0.34; rotation = 1deg }\n",
         "layer b { family = hex_lattice; spacing = 0.4; stroke = 0.1; edges = 1 }\n"},
        {"layer a { family = hex_lattice; spacing = 0.4; stroke = 0.08; edges = 1 }\n",
         "layer b { family = hex_lattice; spacing = 0.4; stroke = 0.2; rotation = 3deg }\n"},
    };
    for (const auto& [first, second] : kPairs) checkPairAgainstExact(first, second, *backend);
}

// One lattice's own lines crossing within the pixels: the triangle lattice's three meet at
// its points, which their union laid as independent drew light (resolved: 0.018 and 0.022
// RMSE; finer than the pixels: 3.5% light, 0.018); the square lattice's two are laid as
// independent, near exact over a pixel facing them and turned.
TEST_CASE("filter: a lattice's lines that cross within a pixel read the exact field's ink") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    // The triangle lattice's edges read over the pixel where two of its families' strokes
    // reach it (TriangleInPixel.h) to 1.4 rows a pixel: exact but for the float's rounding.
    // Finer, the share with the pairs' covariances.
    const std::pair<const char*, double> kLattices[] = {
        {"layer a { family = triangle_lattice; spacing = 6; stroke = 1.5; edges = 1 }\n", 0.002},
        {"layer a { family = triangle_lattice; spacing = 4; stroke = 0.6; edges = 1; rotation = "
         "10deg }\n",
         0.002},
        {"layer a { family = triangle_lattice; spacing = 1.2; stroke = 0.3; edges = 1; rotation = "
         "10deg }\n",
         0.002},
        {"layer a { family = triangle_lattice; spacing = 0.6; stroke = 0.1; edges = 1 }\n", 0.02},
        {"layer a { family = square_lattice; spacing = 6; stroke = 1.5; edges = 1 }\n", 0.02},
        {"layer a { family = square_lattice; spacing = 5; stroke = 1.2; edges = 1; rotation = "
         "25deg }\n",
         0.02},
    };
    for (const auto& [layers, rmse] : kLattices)
        checkLatticeAgainstExact(layers, *backend, rmse, 0.01);
}

// Dots about a pixel wide, short of crowding (rows 1.4 to 4 pixels apart): drawn from the
// nearest point's distance as a stroke across its normal, a dot narrower than the pixel
// covered the band that stroke would; the nearest dot over the pixel (LatticeCrowd.h,
// discInSquare) is its own area.
TEST_CASE("filter: dots about a pixel wide read their exact ink") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const char* kLattices[] = {
        "layer a { family = hex_lattice; spacing = 2.3; stroke = 0.84 }\n",
        "layer a { family = square_lattice; spacing = 2; stroke = 0.8; rotation = 10deg }\n",
        "layer a { family = triangle_lattice; spacing = 3; stroke = 1.5 }\n",
        "layer a { family = hex_lattice; spacing = 4; stroke = 2.5; scale = (1.2, 1) }\n",
        "layer a { family = square_lattice; spacing = 1.6; stroke = 1 }\n",
        "layer a { family = square_lattice; spacing = 8; stroke = 5 }\n",
        "layer a { family = square_lattice; spacing = 1.2; stroke = 0.4 }\n",
        "layer a { family = triangle_lattice; spacing = 1.1; stroke = 0.35; rotation = 15deg }\n",
        "layer a { family = hex_lattice; spacing = 1.5; stroke = 0.4 }\n",
        "layer a { family = hex_lattice; spacing = 1.4; stroke = 0.9; rotation = 20deg }\n",
        "layer a { family = hex_lattice; spacing = 1; stroke = 0.5; scale = (1, 1.3) }\n",
    };
    for (const char* layers : kLattices) checkLatticeAgainstExact(layers, *backend, 0.02, 0.03);
}

// A morph of families of different kinds interpolates their distances, D = (1 - w) d1 + w d2,
// which the distance form read as a distance to its nearest member's centre line: where the
// members crowd, one member's ink (0.12 here, whatever the families), and resolved, 0.08 off
// half-way through a change. Crowded, the morph reads the chance that D < h from its families'
// shares of the plane within a distance, with the beat of two lines of the families that run
// together added (MorphBeat.h); resolved, the blend sampled over the pixel from each family's
// nearest lines or dot (MorphFamily.cpp). Against the exact field at 32 x 32 samples a pixel,
// the distance form -> the families independent -> with their beat:
//   a square grid to circles, 0.6 apart, half-way: 0.055 -> 0.043 -> 0.0128 (the circles'
//     centre is in the window, where their members run along the grid's lines), the other way
//     round 0.043 -> 0.0132, and with the centre far off 0.029 -> 0.015 -> 0.0086; at the
//     change's start, 0.241 -> 0.0014 -> 0.0017; 0.45 apart, 70% of the way, 0.0084 -> 0.0027;
//   lines to a square grid that holds them, half-way: 0.082 (ink 0.138 against 0.220) ->
//     0.0102; turned 2 degrees, 30% of the way, 0.0185 -> 0.0039, and at the change's start
//     exact, as the families alone are (the beat adds nothing where D is one family's);
//   a square grid to a triangle grid, half-way: 0.0288 -> 0.028 -> 0.024 with the triangle's
//     other two lines meeting on the line of the pair (ink 0.360 against 0.350). The rest is
//     the lattices' common period: the grid's lines run through every other column of the
//     triangle's points, and the exact ink over the plane goes from 0.34 to 0.39 as one
//     lattice is shifted across the other (0.36 on average, what the model reads);
//   circles to a honeycomb's dots, 0.5 apart, a third of the way: 0.019 -> 0.013 (ink 0.100
//     -> 0.090 against 0.086; the honeycomb's dots have no lines);
//   lines to a triangle grid at the change's end: 0.356 -> 0.0072;
//   a square grid to circles 7 apart (resolved), half-way: 0.078 -> 0.0074.
TEST_CASE("filter: a morph across kinds reads the ink of its exact field") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    struct Case {
        const char* morph;
        double time;      // of a change from 0 to 1 s
        double rmse, ink; // the most RMSE, and the most error in ink as a share of the exact ink
    };
    const char* kGridCircles =
        "morph(change, square_lattice, circles); edges = 1; spacing = 0.6; stroke = 0.12";
    const char* kLinesGrid =
        "morph(change, lines, square_lattice); edges = 1; spacing = 0.6; stroke = 0.12";
    const char* kGridTriangle =
        "morph(change, square_lattice, triangle_lattice); edges = 1; spacing = 0.6; stroke = 0.12";
    const char* kLinesGridTurned = "morph(change, lines, square_lattice); edges = 1; spacing = "
                                   "0.6; stroke = 0.12; rotation = 2deg";
    const Case kCases[] = {
        {kGridCircles, 0.5, 0.016, 0.03},
        {kGridCircles, 0.0, 0.005, 0.01},
        {"morph(change, square_lattice, circles); edges = 1; spacing = 0.6; stroke = 0.12; "
         "origin = (300, 200)",
         0.5, 0.011, 0.03},
        {"morph(change, circles, square_lattice); edges = 1; spacing = 0.6; stroke = 0.12", 0.5,
         0.016, 0.035},
        {"morph(change, square_lattice, circles); edges = 1; spacing = 0.45; stroke = 0.1", 0.7,
         0.004, 0.01},
        {kLinesGrid, 0.5, 0.013, 0.025},
        {kLinesGridTurned, 0.3, 0.006, 0.015},
        {kLinesGridTurned, 0.0, 0.001, 0.005},
        {kGridTriangle, 0.5, 0.027, 0.035},
        // Near either end of the change (w = 0.99 and 0.06) the blend is all but one family:
        // read in one integral over the family of the larger weight, 0.0168 (ink 2.6% heavy)
        // and 0.0049; split in two, each family's share stepped over its own range, 0.0088
        // and 0.0028, where the triangle grid alone reads 0.0089.
        {kGridTriangle, 0.85, 0.011, 0.01},
        {kGridTriangle, 0.25, 0.004, 0.006},
        {"morph(change, circles, hex_lattice); spacing = 0.5; stroke = 0.1", 0.33, 0.016, 0.06},
        {"morph(change, lines, triangle_lattice); edges = 1; spacing = 0.55; stroke = 0.08", 1.0,
         0.01, 0.02},
        {"morph(change, square_lattice, circles); edges = 1; spacing = 7; stroke = 1.5", 0.5, 0.012,
         0.02},
    };
    for (const Case& c : kCases) {
        CAPTURE(c.morph);
        CAPTURE(c.time);
        const std::string text =
            std::string("scene { size = (160, 120) }\ntiming change { period = 2 }\n"
                        "layer a { family = ") +
            c.morph + "; morph_time = 1 }\n";
        auto drawn = test::compileOk(text);
        auto field = test::compileOk(text, exactField({}));
        const Image got = downsampled(*drawn, *backend, 20, 20, 64, 48, 1, 0, 1, c.time);
        const Image want = downsampled(*field, *backend, 20, 20, 64, 48, 32, 0, 1, c.time);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE(std::string(c.morph), " at ", c.time, ": RMSE ", d.rmse, ", ink ", d.ink,
                    " against ", d.exact);
        CHECK(d.rmse <= c.rmse);
        CHECK(std::abs(d.ink - d.exact) <= c.ink * d.exact);
        // The JIT and the GPU draw what the interpreter draws.
        auto interp = test::makeBackendOrSkip("interp");
        REQUIRE(interp);
        const Image ref = downsampled(*drawn, *interp, 20, 20, 64, 48, 1, 0, 4, c.time);
        for (const char* name : {"jit", "vulkan"}) {
            CAPTURE(name);
            auto other = test::makeBackendOrSkip(name);
            if (!other) continue;
            test::ImageDiff same = test::compareImages(
                ref, downsampled(*drawn, *other, 20, 20, 64, 48, 1, 0, 4, c.time), 2.0 / 255);
            CHECK(same.fractionWithin() >= 0.999);
        }
    }
}

// A honeycomb's edges over the pixel (HoneycombInPixel.h): 1 less the paper its shrunk hexagons
// leave there, from rows of edges 0.4 to 2.9 pixels apart, turned, stretched and under a
// turned camera. Read from the nearest edge's distance, a pixel that reached a corner, or two
// edges, counted one stroke, and from a row a pixel on it handed over to the edges' share: 0.0095
// to 0.102 RMSE against the exact field (0.102 with rows 1.04 pixels apart, the spread of the
// exact field itself), the ink up to 16% light. Finer than kTwoRingsRows the share stands,
// exact now where the three directions' strokes laid as independent were 5% light.
TEST_CASE("filter: a honeycomb's edges read the exact field's ink over the pixel at every scale") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    for (const char* spacing : {"3", "1.5", "1.2", "1", "0.8", "0.6", "0.45"})
        for (const char* stroke : {"0.08", "0.2"}) {
            const std::string layers = std::string("layer a { family = hex_lattice; spacing = ") +
                                       spacing + "; stroke = " + stroke +
                                       "; edges = 1; rotation = 7deg }\n";
            checkLatticeAgainstExact(layers.c_str(), *backend, 0.002, 0.01);
        }
    const char* kStretched[] = {
        "layer a { family = hex_lattice; spacing = 0.9; stroke = 0.25; edges = 1; scale = (1.3, "
        "1) }\n",
        "layer a { family = hex_lattice; spacing = 0.5; stroke = 0.1; edges = 1; scale = (1, 1.2); "
        "rotation = 20deg }\n",
        "camera { rotation = 25deg }\nlayer a { family = hex_lattice; spacing = 2; stroke = 0.6; "
        "edges = 1 }\n",
    };
    for (const char* layers : kStretched) checkLatticeAgainstExact(layers, *backend, 0.002, 0.01);
    // Past two rings' reach, the share: the even grey of the exact field's own ink.
    double spread = 0.0;
    const char* fine =
        "layer a { family = hex_lattice; spacing = 0.25; stroke = 0.15; edges = 1 }\n";
    const InkAgainst d = latticeAgainstExact(fine, *backend, spread);
    CHECK(std::abs(d.ink - d.exact) <= 0.01 * d.exact);
    CHECK(d.rmse <= 1.1 * spread);
}

// Rings, a square grid's lines and a square screen's dots, each given by its distance alone.
const char* kDistanceRings = "family rings { distance = abs(r - spacing * round(r / spacing)) }\n";
const char* kDistanceGrid = "family grid { distance = min(abs(x - spacing * round(x / spacing)), "
                            "abs(y - spacing * round(y / spacing))) }\n";
const char* kDistanceDots = "family dots { distance = hypot(x - spacing * round(x / spacing), "
                            "y - spacing * round(y / spacing)) }\n";

// A family given by its distance gives nothing of its members but the nearest's distance, so
// the distance form read every pixel as that member's straight stroke: one member where
// several crowd into the pixel, one side of a ridge between two (a grid's crossings, a dot's
// neighbours), and the distance as a Euclidean one where |grad d| is not 1. It is read now to
// first order in the distance's own units where the pixel's corners agree with its centre,
// and in 4 x 4 (then 8 x 8) parts where they read another member whose stroke may reach in,
// an 8 x 8 part holding its neighbour's member's stroke too (DistanceFamily.h). Against the exact
// field at 32 x 32 samples a pixel, before and after (the window's RMSE; docs/filtering.md,
// "Families given by their distance"), each case failing before; the resolved rings, which read
// their nearest member alone either way, hold the parts to the form they replace.
TEST_CASE("filter: a family given by its distance reads the ink of its exact field") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::string rings = kDistanceRings, grid = kDistanceGrid, dots = kDistanceDots;
    const std::string cheb = "family cheb { distance = max(abs(x - spacing * round(x / spacing)), "
                             "abs(y - spacing * round(y / spacing))) }\n";
    struct Case {
        std::string layers;
        double rmse, ink; // the most RMSE, and the most error in ink as a share of the exact ink
    };
    const Case kCases[] = {
        // Resolved rings, 3 apart (the window holds their centre): 0.0025 -> 0.0018.
        {rings + "layer a { family = rings; spacing = 3; stroke = 0.8 }\n", 0.003, 0.002},
        // A ring a pixel: 0.037 -> 0.00006; five a pixel: 0.195 -> 0.0005 (ink 0.055 -> 0.250).
        {rings + "layer a { family = rings; spacing = 1; stroke = 0.2 }\n", 0.002, 0.005},
        {rings + "layer a { family = rings; spacing = 0.2; stroke = 0.05 }\n", 0.002, 0.005},
        // 1.4 a pixel about a centre off the window, under a camera turned 25 degrees:
        // 0.051 -> 0.0001 (ink 0.104 -> 0.143 against 0.143).
        {rings + "camera { rotation = 25deg }\nlayer a { family = rings; spacing = 0.7; stroke "
                 "= 0.1; origin = (30, 10) }\n",
         0.002, 0.005},
        // A grid's lines crossing, turned 20 degrees under the camera's 25: 0.108 ->
        // 0.0002; and 1.7 lines a pixel, 0.206 -> 0.0007 (ink 0.100 -> 0.305 against 0.304;
        // 0.0022 and 0.0145, 0.291, where a part read its nearest line alone).
        {grid + "camera { rotation = 25deg }\nlayer a { family = grid; spacing = 2; stroke = 0.4; "
                "rotation = 20deg }\n",
         0.001, 0.005},
        {grid + "layer a { family = grid; spacing = 0.6; stroke = 0.1 }\n", 0.002, 0.01},
        // Dots 0.7 apart: 0.159 -> 0.008 with each part reading its dot's edge as straight
        // (ink 0.275 -> 0.153 against 0.145), 0.0008 with the edge's curvature (0.1444).
        // Dots 0.4 apart, 0.024 (ink 12% heavy) -> 0.0026 (0.0018 in parts alone, where the
        // tubes took a little), 0.0008 where the dot screen's closed form takes a little
        // (DistanceDots.h); 1.5 apart, 0.0018 -> 0.0003; all but touching a pixel apart,
        // 0.0052 -> 0.0017 (0.0015 with a square's corner read in parts where it reads
        // further than the centre says).
        {dots + "layer a { family = dots; spacing = 0.7; stroke = 0.3; rotation = 10deg }\n",
         0.0015, 0.01},
        {dots + "layer a { family = dots; spacing = 0.4; stroke = 0.2; rotation = 10deg }\n", 0.003,
         0.01},
        {dots + "layer a { family = dots; spacing = 1.5; stroke = 0.8; rotation = 10deg }\n", 0.001,
         0.005},
        {dots + "layer a { family = dots; spacing = 1; stroke = 0.9; rotation = 10deg }\n", 0.003,
         0.005},
        // Square dots, a Chebyshev distance max(|dx|, |dy|): past a square's diagonal the
        // distance is the greater of two, whose stroke is two first-order strokes'
        // intersection, not their union (boundedBy), and a pixel whose corner reads further
        // than its centre says is read in parts. 4 apart: 0.015 -> 0.0011 (ink 0.256 ->
        // 0.250 against 0.250); a pixel apart, 0.083 -> 0.0038 (0.333 -> 0.252); 0.7 apart,
        // 0.168 -> 0.0057 (0.418 -> 0.255). With a neighbour level with the part's reading
        // taken as bounding it too where it reads further than the part's first-order reading
        // puts it (greaterOrLevel): 0.0008, 0.0003 and 0.0008, every ink within 0.04%.
        {cheb + "layer a { family = cheb; spacing = 4; stroke = 2; rotation = 10deg }\n", 0.0015,
         0.005},
        {cheb + "layer a { family = cheb; spacing = 1; stroke = 0.5; rotation = 10deg }\n", 0.001,
         0.005},
        {cheb + "layer a { family = cheb; spacing = 0.7; stroke = 0.35; rotation = 10deg }\n",
         0.0015, 0.005},
        // Distances whose gradient is not 1: waves 0.5 apart (|grad d| to 1.17), 0.092 ->
        // 0.0001 (ink 0.108 -> 0.200); petals (to 1.4), one member resolved, 0.0117 -> 0.0009.
        {"family waves {\n let f = y - 3 * sin(x / 5)\n distance = abs(f - spacing * round(f / "
         "spacing))\n}\nlayer a { family = waves; spacing = 0.5; stroke = 0.1 }\n",
         0.002, 0.005},
        {"family petals { distance = abs(r - 20 - 4 * sin(theta * 5)) }\nlayer a { family = "
         "petals; stroke = 0.7 }\n",
         0.002, 0.02},
    };
    for (const Case& c : kCases)
        checkLatticeAgainstExact(c.layers.c_str(), *backend, c.rmse, c.ink);
}

// Members given by their distance finer than the 8 x 8 parts: a part held several members, or a
// dot smaller than itself, and read its nearest to first order (dots five a pixel read 0.525
// ink against their share of 0.196, rings twenty a pixel 0.160 against 0.250). They are read by
// their tubes (DistanceTubes.h): the mean over points of the pixel of the share of each point's
// ray, from its member to the ridge, that the stroke covers. Against the exact field at 64 x 64
// samples a pixel (the window's RMSE), and the window's mean ink against the share of the
// plane the strokes cover, pi h^2 / L^2 for dots, 2h / L for rings, 1 - (1 - 2h / L)^2 for a
// grid (which the 64 x 64 reference itself misses by up to 2% at 8 a pixel). Before, and now:
//   dots 4 a pixel:   RMSE 0.106 (ink 0.302) -> 0.0036 (0.1964 against 0.1963); as a dot
//     screen in closed form (DistanceDots.h) 0.0012 (0.1964)
//   dots 8 a pixel:   0.480 (0.681) -> 0.0062 (0.1964); as a dot screen 0.0048 (0.1963),
//     what is left mostly the 64 x 64 reference's own aliasing
//   rings 12 a pixel: 0.039 (0.222) -> 0.0004 (0.2500 against 0.250)
//   a grid 6 a pixel: 0.024 (0.333) -> 0.0066 (0.360 against 0.360); in closed form by its
//     two ways' indices (DistanceGrid.h) 0.0034 (0.360)
//   a grid 8 a pixel: 0.085 (0.269) -> 0.019 (0.358); in closed form 0.0063 (0.360), what
//     is left mostly the 64 x 64 reference's own aliasing (tests/distance_grid_test.cpp holds
//     the closed form to a finer one)
// and where the reference aliases, the share alone: dots 12.5 a pixel (0.446 before), rings 20
// and 50 a pixel (0.160, 0.060 before).
TEST_CASE("filter: members given by their distance finer than the parts read their share") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::string rings = kDistanceRings, grid = kDistanceGrid, dots = kDistanceDots;
    enum Kind { Dots, Rings, Grid };
    struct Case {
        Kind kind;
        double spacing, stroke;
        double rmse; // against the 64 x 64 reference; 0: the share alone
        double ink;  // the most error in ink as a share of the share
    };
    const Case kCases[] = {
        // The dots' ink within half a percent (by their tubes, 1% heavy where a sample near
        // where four dots' cells meet read its ray as a straight member's: DistanceTubes.cpp,
        // kNearerTurnStep); read as a dot screen (DistanceDots.h) where they are round.
        {Dots, 0.25, 0.125, 0.003, 0.005},
        {Dots, 0.125, 0.0625, 0.008, 0.005},
        {Dots, 0.08, 0.04, 0.0, 0.005},
        {Rings, 1.0 / 12, 1.0 / 48, 0.01, 0.005},
        {Rings, 0.05, 0.0125, 0.0, 0.01},
        {Rings, 0.02, 0.005, 0.0, 0.01},
        {Grid, 1.0 / 6, 1.0 / 30, 0.006, 0.01},
        {Grid, 0.125, 0.025, 0.01, 0.01},
        // Over the hand-over, where straight members stay with the parts longer than dots:
        // with a straight member's ray counted once as the parts see it, a grid four a pixel
        // read 0.013 and rings six a pixel 0.0012, by the tubes; now 0.0015 and 0.0001.
        {Grid, 0.25, 0.05, 0.004, 0.01},
        {Rings, 1.0 / 6, 1.0 / 24, 0.0005, 0.005},
    };
    for (const Case& c : kCases) {
        const double h = c.stroke / 2, L = c.spacing;
        const double pi = 3.14159265358979323846;
        const double share = c.kind == Dots    ? pi * h * h / (L * L)
                             : c.kind == Rings ? 2 * h / L
                                               : 1 - (1 - 2 * h / L) * (1 - 2 * h / L);
        const std::string layer =
            (c.kind == Dots    ? dots + "layer a { family = dots; "
             : c.kind == Rings ? rings + "layer a { family = rings; origin = (30, 10); "
                               : grid + "layer a { family = grid; ") +
            fmt::format("spacing = {}; stroke = {}{} }}\n", L, c.stroke,
                        c.kind == Rings ? "" : "; rotation = 10deg");
        CAPTURE(layer);
        const std::string text = std::string("scene { size = (160, 120) }\n") + layer;
        auto drawn = test::compileOk(text);
        const Image got = downsampled(*drawn, *backend, 20, 20, 64, 48, 1, 0, 1);
        double ink = 0.0;
        for (float v : got.pixels) ink += (1.0 - v) / double(got.pixels.size()); // paper is 1
        if (std::getenv("MOIRE_FILTER_REPORT")) MESSAGE(layer, "ink ", ink, " against ", share);
        CHECK(std::abs(ink - share) <= c.ink * share);
        if (c.rmse == 0.0) continue;
        auto field = test::compileOk(text, exactField({}));
        const Image want = downsampled(*field, *backend, 20, 20, 64, 48, 64, 0, 1);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT")) MESSAGE("RMSE ", d.rmse);
        CHECK(d.rmse <= c.rmse);
    }
}

// Two families given by their distance whose members crowd and run parallel over the pixel,
// and whose beat is coarse: rings 0.2 and 0.21 apart about one centre (a beat of 4.2 pixels),
// rings 0.2 apart about two centres 2 apart, lines given by their distance with a phase
// family's lines turned 3 degrees (a beat of 3.8 pixels; either on top), waves whose
// distance's gradient is not 1, and the lines under a square lattice's edges turned 3 degrees.
// Laid as independent inks the beat was lost, an even grey as far off as the exact field's
// spread (RMSE 0.067 to 0.099, against spreads of 0.044 to 0.090); each now reads the index its
// crowd runs by (DistanceFamily.cpp, runsRead) and beats as a phase family does (FineUnion.h):
// 0.0026 to 0.0097. A grid given by its distance, 0.2 apart, with a phase family's lines,
// with another such grid, and under a square lattice's edges, each 3 degrees off it: read by
// its two ways' strands (DistanceGrid.h; FineUnion.cpp), 0.0029 to 0.0042, where the pixel
// centre's way alone read 0.032 and 0.037 (spreads 0.041 to 0.044). Dots given by their
// distance, 0.2 apart turned 10 degrees, with a phase family's lines, under a square lattice's
// dots, and with the same dots, each 3 degrees off: read as a dot screen (DistanceDots.h) and
// correlated as a lattice's dots are (LatticeUnion.h), 0.0031 to 0.0037, where laid as
// independent they read 0.038 to 0.040 (spreads 0.038 to 0.040). Rings about a lattice's
// points given by their distance, 0.2 apart turned 10 degrees, radius 0.05, stroke 0.05, with
// a phase family's lines, under a square lattice's dots, with the same rings and with dots
// given by their distance, each 3 degrees off: read as two dot screens' difference
// (DistanceRings.h) and correlated as the outer discs' screen less the inner discs'
// (LatticeShape::inner), 0.0026 to 0.0037, where laid as independent they read 0.038 to
// 0.043 (spreads 0.038 to 0.043). The exact field is read at
// 64 x 64 samples a pixel: at 32 x 32 it aliases with members five a pixel (the same pictures
// read 0.010 to 0.024 off it).
TEST_CASE("filter: two families given by their distance show their beat where they crowd") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::string families =
        std::string(kDistanceRings) + kDistanceGrid + kDistanceDots +
        "family bands { distance = abs(x - spacing * round(x / spacing)) }\n"
        "family waves {\n let f = y - 3 * sin(x / 5)\n distance = abs(f - spacing * round(f / "
        "spacing))\n}\n"
        "family rings_on {\n let dx = x - spacing * round(x / spacing)\n let dy = y - spacing * "
        "round(y / spacing)\n distance = abs(hypot(dx, dy) - 0.25 * spacing)\n}\n" +
        kDistanceThreeWays;
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = rings; spacing = 0.2; stroke = 0.05; origin = (30, 10) }\n",
         "layer b { family = rings; spacing = 0.21; stroke = 0.06; origin = (30, 10) }\n"},
        {"layer a { family = rings; spacing = 0.2; stroke = 0.05; origin = (30, 10) }\n",
         "layer b { family = rings; spacing = 0.2; stroke = 0.05; origin = (32, 10) }\n"},
        {"layer a { family = bands; spacing = 0.2; stroke = 0.05 }\n",
         "layer b { family = lines; spacing = 0.2; stroke = 0.06; rotation = 3deg }\n"},
        {"layer a { family = lines; spacing = 0.2; stroke = 0.06; rotation = 3deg }\n",
         "layer b { family = bands; spacing = 0.2; stroke = 0.05 }\n"},
        {"layer a { family = waves; spacing = 0.25; stroke = 0.06 }\n",
         "layer b { family = waves; spacing = 0.26; stroke = 0.06 }\n"},
        {"layer a { family = bands; spacing = 0.2; stroke = 0.05 }\n",
         "layer b { family = square_lattice; spacing = 0.2; stroke = 0.04; edges = 1; rotation = "
         "3deg }\n"},
        {"layer a { family = grid; spacing = 0.2; stroke = 0.04; rotation = 10deg }\n",
         "layer b { family = lines; spacing = 0.2; stroke = 0.05; rotation = 13deg }\n"},
        {"layer a { family = grid; spacing = 0.2; stroke = 0.04; rotation = 10deg }\n",
         "layer b { family = grid; spacing = 0.2; stroke = 0.04; rotation = 13deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.2; stroke = 0.04; edges = 1; rotation = "
         "13deg }\n",
         "layer b { family = grid; spacing = 0.2; stroke = 0.04; rotation = 10deg }\n"},
        {"layer a { family = dots; spacing = 0.2; stroke = 0.1; rotation = 10deg }\n",
         "layer b { family = lines; spacing = 0.2; stroke = 0.05; rotation = 13deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.2; stroke = 0.1; rotation = 13deg }\n",
         "layer b { family = dots; spacing = 0.2; stroke = 0.1; rotation = 10deg }\n"},
        {"layer a { family = dots; spacing = 0.2; stroke = 0.1; rotation = 10deg }\n",
         "layer b { family = dots; spacing = 0.2; stroke = 0.1; rotation = 13deg }\n"},
        {"layer a { family = rings_on; spacing = 0.2; stroke = 0.05; rotation = 10deg }\n",
         "layer b { family = lines; spacing = 0.2; stroke = 0.05; rotation = 13deg }\n"},
        {"layer a { family = square_lattice; spacing = 0.2; stroke = 0.1; rotation = 13deg }\n",
         "layer b { family = rings_on; spacing = 0.2; stroke = 0.05; rotation = 10deg }\n"},
        {"layer a { family = rings_on; spacing = 0.2; stroke = 0.05; rotation = 10deg }\n",
         "layer b { family = rings_on; spacing = 0.2; stroke = 0.05; rotation = 13deg }\n"},
        {"layer a { family = rings_on; spacing = 0.2; stroke = 0.05; rotation = 10deg }\n",
         "layer b { family = dots; spacing = 0.2; stroke = 0.1; rotation = 13deg }\n"},
        // Lines three ways (DistanceGrid.h) with lines 3 degrees off one way: 0.0077 against
        // a spread of 0.034, the three ways' third strand paired with the lines.
        {"layer a { family = tri; spacing = 0.2; stroke = 0.04; rotation = 10deg }\n",
         "layer b { family = lines; spacing = 0.2; stroke = 0.06; rotation = 13deg }\n"},
    };
    for (const auto& [first, second] : kPairs)
        checkPairAgainstExact(first, second, *backend, families, 64);
}

// Two layers of lines three ways given by their distance, each read in closed form with its
// meeting points' excess (DistanceGrid.h). Their pairs of lines beat, and the pairs are not
// independent of one another: within each layer the three indices sum to a slow c, so the
// pairs' product holds harmonics of c (MeetingBeat.h). Against the exact field at 64 x 64
// samples a pixel, RMSE with the pairs taken as independent and with the meeting harmonics
// (the exact field's spread; most of what is left is each layer's own ink, 0.005 over):
//   3 degrees apart, strokes 0.04:          0.0130 -> 0.0066 (0.026)
//   spacings 0.2 and 0.21, strokes 0.05:    0.0176 -> 0.0062 (0.029)
//   2 degrees apart, strokes 0.06 and 0.04: 0.0185 -> 0.0054 (0.029)
// Either layer alone is 0.0050 to 0.0055 off, so the pairs taken as independent were
// further off than both layers' own errors together.
TEST_CASE("filter: two layers of lines three ways keep the beat of their meeting points") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::pair<const char*, const char*> kPairs[] = {
        {"layer a { family = tri; spacing = 0.2; stroke = 0.04; rotation = 10deg }\n",
         "layer b { family = tri; spacing = 0.2; stroke = 0.04; rotation = 13deg }\n"},
        {"layer a { family = tri; spacing = 0.2; stroke = 0.05; rotation = 10deg }\n",
         "layer b { family = tri; spacing = 0.21; stroke = 0.05; rotation = 10deg }\n"},
        {"layer a { family = tri; spacing = 0.2; stroke = 0.06; rotation = 10deg }\n",
         "layer b { family = tri; spacing = 0.2; stroke = 0.04; rotation = 12deg }\n"},
    };
    for (const auto& [first, second] : kPairs) {
        CAPTURE(first);
        CAPTURE(second);
        double spread = 0.0, own = 0.0, alone = 0.0;
        for (const char* one : {first, second}) {
            const double e = latticeAgainstExact(kDistanceThreeWays + one, *backend, own, 64).rmse;
            alone += e * e;
        }
        const InkAgainst d =
            latticeAgainstExact(kDistanceThreeWays + first + second, *backend, spread, 64);
        CHECK(spread >= 0.02); // the exact field holds the beat
        CHECK(d.rmse <= std::max(0.25 * spread, 1.25 * std::sqrt(alone)));
        CHECK(std::abs(d.ink - d.exact) <= 0.02 * d.exact);
    }
}

// The closed form takes a phase family's index as linear across the pixel. Where it folds (a
// polygon's support function along its corners, where a stroke turns its corner inside the
// pixel) or bends within the pixel (about the circles' centre, a spiral's core, a parabola's
// vertex), the pixel is read in 2 x 2 to 8 x 8 parts, each by the closed form over its own
// index (Prefilter.h, bentIndexMean). Against the exact field at 32 x 32 samples a pixel, over
// 24 x 24 pixels about the family's centre, before and now (RMSE; the worst pixel):
//   circles 1 apart:              0.0101 (0.103)  -> 0.0003 (0.0011)
//   squares 4 apart:              0.0510 (0.250)  -> 0.0000 (0.0000)
//   triangles 3 apart, turned:    0.0197 (0.260)  -> 0.0004 (0.0046)
//   hexagons 2.5 apart, turned:   0.0205 (0.169)  -> 0.0003 (0.0025)
//   a spiral of three arms:       0.0074 (0.090)  -> 0.0003 (0.0033)
//   parabolas, bend 30:           0.0133 (0.028)  -> 0.0020 (0.0089)
//   squares to circles, half-way: 0.0189 (0.127)  -> 0.0009 (0.0019)
// and lines, whose index is linear, read the same (0.0002).
TEST_CASE("filter: an index that bends or folds within the pixel is read in parts") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const char* kLayers[] = {
        "family = circles; spacing = 1; stroke = 0.3",
        "family = squares; spacing = 4; stroke = 1",
        "family = triangles; spacing = 3; stroke = 0.8; rotation = 10deg",
        "family = hexagons; spacing = 2.5; stroke = 0.6; rotation = 7deg; origin = (0.3, 0.2)",
        "family = spiral; arms = 3; spacing = 1; stroke = 0.3",
        "family = parabola; bend = 30; spacing = 2; stroke = 0.5",
        "family = lines; spacing = 2; stroke = 0.6",
        // Half-way through a morph of squares to circles (at 0.5 s of a 2 s loop).
        "family = morph(change, squares, circles); spacing = 3; stroke = 0.8; morph_time = 1",
    };
    for (const char* layer : kLayers) {
        CAPTURE(layer);
        // About the family's centre, the frame's.
        const auto [got, want] =
            layerAndExact(std::string("timing change { period = 2 }\nlayer a { ") + layer + " }\n",
                          *backend, 68, 48, 24, 24, 0.5);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT")) MESSAGE("RMSE ", d.rmse, ", worst ", d.worst);
        CHECK(d.rmse <= 0.003);
        CHECK(d.worst <= 0.012);
    }
}

TEST_CASE("filter: a layer encoding a field is read in parts where its index bends") {
    // A layer encoding a field (§10.1) moves its members by the field: its index is the
    // carrier's less gain s f / s, which bends wherever either does, and folds where the field
    // does (a fork's defect, theta / tau at the origin). Taken as linear across the pixel, as
    // the closed form takes it, these windows about the centre were 0.0031 to 0.028 RMSE off
    // the exact field (a pixel up to 0.22), and a hyperbola's 0.198 (0.97); read in parts
    // where the index bends, the field read again at each part (LayerLowering::fieldAt),
    // 0.0003 to 0.0022 (0.0099). The hyperbola read so was still 0.020 (0.10) off while the
    // field was subtracted from its phase, which its first member's reading takes for the
    // square root of a smooth function: the point rule drew the member it leaves out as a
    // hairline along its asymptotes. The field moves its members' level instead (phaseFields):
    // 0.0019 (0.026).
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    struct Case {
        const char* layer;
        double rmse, worst;
    };
    const Case kCases[] = {
        {"family = lines; spacing = 2; stroke = 0.6; field = theta / tau; gain = 5", 0.003, 0.012},
        {"family = lines; spacing = 1; stroke = 0.3; field = theta / tau; gain = 3", 0.003, 0.012},
        {"family = circles; spacing = 1; stroke = 0.3; field = x * x / 40; gain = 1", 0.003, 0.012},
        {"family = circles; spacing = 2; stroke = 0.5; field = theta / tau; gain = 2", 0.003,
         0.012},
        {"family = lines; spacing = 1.5; stroke = 0.4; field = sin(x / 3); gain = 0.5", 0.003,
         0.012},
        {"family = lines; spacing = 2; stroke = 0.6; field = r / 4; gain = 1", 0.003, 0.012},
        // Half-way through a morph of squares to circles (at 0.5 s of a 2 s loop).
        {"family = morph(change, squares, circles); spacing = 3; stroke = 0.8; morph_time = 1; "
         "field = theta / tau; gain = 2",
         0.003, 0.012},
        // A first member: the field moves its level, not the hyperbola's phase (phaseFields).
        // Read in its phase squared, where the field's level is added back (0.0019, 0.026
        // before: "Members crowding into a fold").
        {"family = hyperbola; spacing = 2; stroke = 0.5; field = x / 20; gain = 1", 0.0015, 0.012},
    };
    for (const Case& c : kCases) {
        CAPTURE(c.layer);
        const auto [got, want] = layerAndExact(std::string("timing change { period = 2 }\n"
                                                           "layer a { ") +
                                                   c.layer + " }\n",
                                               *backend, 68, 48, 24, 24, 0.5);
        const InkAgainst d = inkAgainst(got, want);
        if (std::getenv("MOIRE_FILTER_REPORT"))
            MESSAGE(std::string(c.layer), ": RMSE ", d.rmse, ", worst ", d.worst);
        CHECK(d.rmse <= c.rmse);
        CHECK(d.worst <= c.worst);
    }
}

TEST_CASE("filter: a family with a first member is read in parts below it and where it bends") {
    // The hyperbola's phase folds along its asymptotes (its member 0, excluded): beside them
    // the index runs as the square root of the distance, the first member's two sides lie
    // either side of each asymptote, and the members after it crowd towards it away from the
    // centre. Drawn by the nearest member's distance alone below the first member and the
    // closed form elsewhere, the asymptotes were light lines (RMSE 0.016 to 0.155 over the
    // windows below, a pixel up to 0.78 off; 0.0080 about the centre of the one family whose
    // strokes there are thin and far apart); read in 8 x 8 parts there and where the index
    // bends (Prefilter.h, belowFirstMean), 0.0005 to 0.0061 (worst 0.044), and each part read
    // in the phase squared (FoldMean.h), in which the members crowding into the asymptotes
    // stand evenly, 0.0002 to 0.0014 (worst 0.014). About the centre, and along an asymptote
    // away from it.
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    for (const char* layer : {"family = hyperbola; spacing = 2; stroke = 0.5",
                              "family = hyperbola; spacing = 2; stroke = 0.2",
                              "family = hyperbola; spacing = 6; stroke = 0.5",
                              "family = hyperbola; spacing = 8; stroke = 2.2",
                              "family = hyperbola; spacing = 4; stroke = 1.1"})
        for (const auto& [x0, y0] : {std::pair{68, 48}, std::pair{20, 0}}) {
            CAPTURE(layer);
            CAPTURE(x0);
            const auto [got, want] =
                layerAndExact(std::string("layer a { ") + layer + " }\n", *backend, x0, y0, 24, 24);
            const InkAgainst d = inkAgainst(got, want);
            if (std::getenv("MOIRE_FILTER_REPORT")) MESSAGE("RMSE ", d.rmse, ", worst ", d.worst);
            CHECK(d.rmse <= 0.003);
            CHECK(d.worst <= 0.02);
        }
}

TEST_CASE("filter: hyperbolas crowding into their asymptotes draw their merged strokes") {
    // Hyperbolas 0.125 pixels apart: beside each asymptote their members crowd in without
    // end and their strokes merge into a dark band, which parts taking the index as linear
    // (and the nearest member's distance where the fold crossed a part) drew grey: 0.028 RMSE
    // over this window across an asymptote, against 0.009 read in the phase squared
    // (FoldMean.h). The exact field is taken at 128 x 128 samples a pixel: at 64 x 64 its
    // antialias band greys the gaps between strokes that all but merge (the asymptote's pixel
    // 0.90 of ink there, 0.96 at 128 x 128, 0.97 at 256 x 256; the filter 0.977).
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    const std::string text = "scene { size = (48, 36) }\ncamera { zoom = 0.5 }\n"
                             "layer a { family = hyperbola; spacing = 0.25; stroke = 0.05 }\n";
    auto drawn = test::compileOk(text);
    auto field = test::compileOk(text, exactField({}));
    const Image got = downsampled(*drawn, *backend, 33, 0, 8, 8, 1, 0, 1);
    const Image want = downsampled(*field, *backend, 33, 0, 8, 8, 128, 0, 1);
    const InkAgainst d = inkAgainst(got, want);
    if (std::getenv("MOIRE_FILTER_REPORT")) MESSAGE("RMSE ", d.rmse, ", worst ", d.worst);
    CHECK(d.rmse <= 0.012);
    CHECK(std::abs(d.ink - d.exact) <= 0.01);
}

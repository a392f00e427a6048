// Layers' strokes meeting within the pixel under the mean filter where a pixel holds more
// than one member's stroke of a layer (docs/filtering.md, "Strokes that meet within a pixel";
// compiler/lower/StrokePairs.h): a crowded layer's members against a resolved layer's strokes
// (stripesCovariance), and members a pixel or two apart with their neighbours
// (strokeCovariance), against the exact field.
#include "tests/support/ExactWindow.h"
#include "tests/support/Support.h"

#include <cmath>
#include <cstdlib>
#include <doctest/doctest.h>
#include <string>

using namespace moire;

namespace {

struct Window {
    int x0, y0, width, height;
};

// A window of `frame` + `scene` drawn one sample a pixel under the mean filter against the
// same window of its exact field at 64 x 64 samples a pixel: within `rmse`, its ink within 1%.
void checkWindow(Backend& backend, const char* frame, const char* scene, Window w, double rmse) {
    CAPTURE(scene);
    const std::string text = std::string(frame) + scene;
    auto drawn = test::compileOk(text);
    auto field = test::compileOk(text, test::exactField({}));
    const Image got = test::downsampled(*drawn, backend, w.x0, w.y0, w.width, w.height, 1, 0, 1);
    const Image want = test::downsampled(*field, backend, w.x0, w.y0, w.width, w.height, 64, 0, 1);
    const test::InkAgainst d = test::inkAgainst(got, want);
    if (std::getenv("MOIRE_FILTER_REPORT"))
        MESSAGE(std::string(scene), "RMSE ", d.rmse, ", ink ", d.ink, " against ", d.exact);
    CHECK(d.rmse <= rmse);
    CHECK(std::abs(d.ink - d.exact) <= 0.01 * d.exact);
}

} // namespace

// A layer whose members crowd at a member a pixel or more, laid with a layer whose strokes are
// resolved: the crowded layer's strokes no longer meet as its nearest alone (StrokePairs.h,
// its weight gone at a member a pixel), nor do its members beat with the other layer's (the
// union of fine layers wants both crowded), so the two were laid as independent inks over
// every pixel the resolved stroke crosses. The crowded layer's members read as periodic
// strokes against the resolved stroke (stripesCovariance) carry what the two share there.
// Scenes found by drawing random pairs against their exact field, each a 40 x 30 window of a
// 160 x 120 frame, against the exact field at 64 x 64 samples a pixel (their strokes are
// thick: 32 x 32 samples' antialias band takes ink from the cells' corners). RMSE, laid as
// independent -> read as periodic strokes (experiments/filter_random measures 300 random
// scenes):
//   squares 1.1 pixels apart and parabolas 2.1 apart: 0.055 -> 0.0084 (0.0023 since the
//     nearest strokes are read with their neighbours, below);
//   waves crowding where they steepen, and lines 2.2 pixels apart: 0.028 -> 0.0053;
//   waves 1.2 pixels apart, parabolas 1.9 apart: 0.032 -> 0.0070;
//   lines 0.34 pixels apart, hexagons 1.9 apart: 0.021 -> 0.0040;
//   hyperbolas finer than the pixel, pentagons 5.4 pixels apart: 0.023 -> 0.0015;
//   circles warped by a field, 0.78 pixels apart, under spirals warped by another: 0.029 ->
//     0.0034;
//   squares 0.49 pixels apart and triangles 2.3 apart: 0.0165 -> 0.0003;
// and families given by their distance, crowding one way, by the index they run by:
//   rings 0.6 pixels apart under lines 5 apart: 0.0133 -> 0.0015;
//   rings 0.7 pixels apart under circles 4 apart: 0.0200 -> 0.0031;
//   lines 0.55 pixels apart under parabolas 2.5 apart: 0.0099 -> 0.0012;
//   circles 3.6 pixels apart under lines 0.72 apart: 0.0186 -> 0.0016.
TEST_CASE("filter: a crowded layer's members meet a resolved layer's strokes") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    struct Case {
        const char* scene;
        int x0, y0;
        double rmse;
    };
    const Case kCases[] = {
        {"camera { zoom = 1.439; rotation = 18.23deg }\n"
         "layer a { family = squares; spacing = 0.7567; stroke = 0.4333; rotation = 41.83deg; "
         "origin = (-8.048, 20.39) }\n"
         "layer b { family = parabola; bend = 0.1348; spacing = 1.482; stroke = 0.5102; "
         "rotation = 7.19deg; origin = (9.012, 7.379) }\n",
         100, 62, 0.004},
        {"camera { zoom = 0.3615; rotation = 12.51deg }\n"
         "layer a { family = wave; amplitude = 5.199; spacing = 3.374; stroke = 0.7905; "
         "rotation = 19.98deg; origin = (24.92, -19.54) }\n"
         "layer b { family = lines; angle = 44.19deg; spacing = 6.184; stroke = 2.157; "
         "rotation = 42.09deg; origin = (24.68, -21.2) }\n",
         7, 83, 0.008},
        {"camera { zoom = 0.6827; rotation = 17.46deg }\n"
         "layer a { family = parabola; bend = 0.1838; spacing = 2.831; stroke = 0.3505; "
         "rotation = 84.92deg; origin = (-13.71, 10.49) }\n"
         "layer b { family = wave; amplitude = 5.516; spacing = 1.841; stroke = 0.8691; "
         "rotation = 39.5deg; origin = (-26.93, -16.76) }\n",
         6, 69, 0.01},
        {"camera { zoom = 0.9233; rotation = 19.5deg }\n"
         "layer a { family = hexagons; spacing = 2.071; stroke = 1.056; rotation = 45.64deg; "
         "origin = (-5.887, -19.83) }\n"
         "layer b { family = lines; angle = 49.73deg; spacing = 0.3634; stroke = 0.21; "
         "rotation = 56.98deg; origin = (-24.25, 23.79) }\n",
         67, 44, 0.006},
        {"camera { zoom = 1.961; rotation = 28.45deg }\n"
         "layer a { family = hyperbola; spacing = 0.4045; stroke = 0.1808; rotation = 14.83deg; "
         "origin = (16.69, -2.945) }\n"
         "layer b { family = ngon; sides = 5; spacing = 2.778; stroke = 0.4413; "
         "rotation = 81.71deg; origin = (8.018, 10.74) }\n",
         94, 19, 0.004},
        {"camera { zoom = 0.9973; rotation = 1.311deg }\n"
         "layer a { family = circles; spacing = 0.7795; stroke = 0.3155; rotation = 0.9704deg; "
         "origin = (-7.578, -18.98); field = ripple }\n"
         "layer b { family = spiral; arms = -1; spacing = 3.589; stroke = 1.608; "
         "rotation = 17.77deg; origin = (6.63, -22.83); field = saddle }\n",
         67, 79, 0.006},
        {"camera { zoom = 0.3918; rotation = 16.04deg }\n"
         "layer a { family = squares; spacing = 1.254; stroke = 0.1691; rotation = 59.23deg; "
         "origin = (22.86, -19.39) }\n"
         "layer b { family = triangles; spacing = 5.945; stroke = 0.9645; rotation = 31.46deg; "
         "origin = (-23.55, -3.207) }\n",
         15, 1, 0.002},
        // Families given by their distance whose members crowd running one way, read by the
        // index they run by (DistanceFamily.h, runs).
        {"family rings { distance = abs(r - spacing * round(r / spacing)) }\n"
         "layer a { family = rings; spacing = 0.6; stroke = 0.15; origin = (-30, 10) }\n"
         "layer b { family = lines; spacing = 5; stroke = 1.2; rotation = 20deg }\n",
         60, 40, 0.003},
        {"family rings { distance = abs(r - spacing * round(r / spacing)) }\n"
         "layer a { family = rings; spacing = 0.7; stroke = 0.2; origin = (-50, 40) }\n"
         "layer b { family = circles; spacing = 4; stroke = 1.5; origin = (20, -10) }\n",
         60, 40, 0.005},
        {"family dlines { distance = abs(x - spacing * round(x / spacing)) }\n"
         "layer a { family = dlines; spacing = 0.55; stroke = 0.15; rotation = 10deg }\n"
         "layer b { family = parabola; spacing = 2.5; stroke = 0.8; rotation = 30deg }\n",
         60, 40, 0.003},
        {"family dlines { distance = abs(x - spacing * round(x / spacing)) }\n"
         "camera { zoom = 0.6 }\n"
         "layer a { family = circles; spacing = 6; stroke = 1.5 }\n"
         "layer b { family = dlines; spacing = 1.2; stroke = 0.4; rotation = 70deg }\n",
         60, 40, 0.003},
    };
    for (const Case& c : kCases)
        checkWindow(*backend, "scene { size = (160, 120) }\n", c.scene, {c.x0, c.y0, 40, 30},
                    c.rmse);
}

// Two layers whose members stand one to two pixels apart: each pixel holds the edges of two
// members' strokes of a layer, not one, and the pair's covariance read from the nearest
// stroke of each alone took it from one edge, as far off as independence and of either sign
// (StrokePairs.h, strokeCovariance: the next member either side is read with the nearest).
// Scenes from experiments/filter_random, each whole in its own 48 x 36 frame against the
// exact field at 64 x 64 samples a pixel. RMSE, the nearest strokes alone -> with their
// neighbours:
//   waves 4 pixels apart over a pencil's rays 1.2 apart: 0.0231 -> 0.0092;
//   lines 1.9 pixels apart over a spiral's arms 2.0 apart: 0.0076 -> 0.0024;
//   waves 1.2 pixels apart over waves 3.0 apart, warped by a swirl: 0.0103 -> 0.0059.
TEST_CASE("filter: layers whose members stand a pixel or two apart meet with every stroke") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) backend = test::makeBackendOrSkip("interp");
    REQUIRE(backend);
    struct Case {
        const char* scene;
        double rmse;
    };
    const Case kCases[] = {
        {"camera { zoom = 3.484; rotation = 5.468deg; center = (-18.11, -10.24) }\n"
         "layer a { family = wave; amplitude = 5.567; spacing = 1.153; stroke = 0.3936; "
         "rotation = 87.47deg; origin = (21.15, 25.92) }\n"
         "layer b { family = pencil; lines = 92; spacing = 1.248; stroke = 0.2841; "
         "rotation = 15.4deg; origin = (-10.61, -18.44) }\n",
         0.012},
        {"camera { zoom = 0.3006; rotation = 11.09deg; center = (20.89, 31.84) }\n"
         "layer a { family = lines; angle = 5.997deg; spacing = 6.177; stroke = 2.989; "
         "rotation = 6.154deg; origin = (-20.64, -21.99) }\n"
         "layer b { family = spiral; arms = 1; spacing = 6.724; stroke = 3.942; "
         "rotation = 32.23deg; origin = (4.677, -6.691) }\n",
         0.0035},
        {"camera { zoom = 0.6504; rotation = 18.87deg; center = (8.683, 4.047) }\n"
         "layer a { family = wave; amplitude = 5.105; spacing = 1.847; stroke = 0.988; "
         "rotation = 20.66deg; origin = (-9.349, -17.45) }\n"
         "layer b { family = wave; amplitude = 5.452; spacing = 4.636; stroke = 1.272; "
         "rotation = 67.58deg; origin = (-1.627, 3.028); field = swirl }\n",
         0.0075},
    };
    for (const Case& c : kCases)
        checkWindow(*backend, "scene { size = (48, 36) }\n", c.scene, {0, 0, 48, 36}, c.rmse);
}

// The viewer's camera maths against a brute-force copy of the kernel's camera formula, and
// against the compiled kernel itself: zoom about the cursor, pans, layer drags and turns keep
// what was under the cursor under it.
#include "compiler/backend/interp/Interpreter.h"
#include "runtime/FrameEval.h"
#include "runtime/view/ViewCamera.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <random>

using namespace moire;
using namespace moire::view;

namespace {

// LowerScene.cpp's camera, written out term by term: s = (px - W/2, H/2 - py), world =
// centre + pan + Rot(turn) s * max(sw / W, sh / H) / (zoom * zoomFactor).
Vec2 kernelWorld(const SceneCamera& c, const ViewAdjust& v, int w, int h, Vec2 p) {
    double sx = p.x - w * 0.5, sy = h * 0.5 - p.y;
    double fit = std::max(c.sceneWidth / w, c.sceneHeight / h);
    double pixel = fit / (c.zoom * v.zoomFactor);
    double rx = std::cos(c.turn) * sx - std::sin(c.turn) * sy;
    double ry = std::sin(c.turn) * sx + std::cos(c.turn) * sy;
    return {c.centerX + v.panX + rx * pixel, c.centerY + v.panY + ry * pixel};
}

// The layer's own point that the motion m carries to world point p: Rot(-turn) (p - d).
Vec2 unmove(const LayerMotion& m, Vec2 p) {
    double x = p.x - m.dx, y = p.y - m.dy, c = std::cos(m.turn), s = std::sin(m.turn);
    return {c * x + s * y, -s * x + c * y};
}

double dist(Vec2 a, Vec2 b) {
    return std::hypot(a.x - b.x, a.y - b.y);
}

SceneCamera turnedCamera() {
    SceneCamera c;
    c.centerX = 12.5;
    c.centerY = -7.0;
    c.turn = 0.35;
    c.zoom = 1.7;
    c.sceneWidth = 1200;
    c.sceneHeight = 800;
    return c;
}

ViewAdjust someView() {
    ViewAdjust v;
    v.panX = -3.25;
    v.panY = 8.5;
    v.zoomFactor = 2.3;
    v.layerRef(1) = {4.0, -6.0, 0.6};
    return v;
}

} // namespace

TEST_CASE("view camera: pixel to world is the kernel's formula, and toPixel inverts it") {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 200; ++i) {
        SceneCamera c;
        c.centerX = (u(rng) - 0.5) * 400;
        c.centerY = (u(rng) - 0.5) * 400;
        c.turn = (u(rng) - 0.5) * 8;
        c.zoom = 0.1 + 4 * u(rng);
        c.sceneWidth = 100 + 2000 * u(rng);
        c.sceneHeight = 100 + 2000 * u(rng);
        ViewAdjust v;
        v.panX = (u(rng) - 0.5) * 100;
        v.panY = (u(rng) - 0.5) * 100;
        v.zoomFactor = 0.2 + 5 * u(rng);
        int w = 1 + static_cast<int>(u(rng) * 1999), h = 1 + static_cast<int>(u(rng) * 1999);
        Vec2 p{u(rng) * w, u(rng) * h};
        ViewCamera cam(c, v, w, h);
        Vec2 world = cam.toWorld(p), expect = kernelWorld(c, v, w, h, p);
        CHECK(dist(world, expect) < 1e-9 * (1 + std::hypot(expect.x, expect.y)));
        Vec2 back = cam.toPixel(world);
        CHECK(dist(back, p) < 1e-7);
    }
}

TEST_CASE("view camera: the wheel zooms about the cursor") {
    SceneCamera c = turnedCamera();
    ViewAdjust v = someView();
    const int w = 640, h = 360;
    for (Vec2 at : {Vec2{10.5, 20.5}, Vec2{320, 180}, Vec2{639.5, 300.25}}) {
        for (double factor : {1.1, 1.0 / 1.1, 3.0, 0.25}) {
            ViewAdjust after = v;
            zoomAbout(c, after, w, h, at, factor);
            CHECK(after.zoomFactor == doctest::Approx(v.zoomFactor * factor));
            // The point under the cursor stays; a pixel away moves by 1/factor as much.
            CHECK(dist(kernelWorld(c, after, w, h, at), kernelWorld(c, v, w, h, at)) < 1e-9);
            Vec2 near{at.x + 1, at.y};
            CHECK(dist(kernelWorld(c, after, w, h, near), kernelWorld(c, after, w, h, at)) ==
                  doctest::Approx(dist(kernelWorld(c, v, w, h, near), kernelWorld(c, v, w, h, at)) /
                                  factor));
            CHECK(after.layer(1).dx == v.layer(1).dx); // layers are not the camera's
        }
    }
}

TEST_CASE("view camera: a drag pans the world point under the cursor along with it") {
    SceneCamera c = turnedCamera();
    ViewAdjust v = someView();
    const int w = 500, h = 300;
    Vec2 from{100.5, 80.5}, to{260.25, 40.75};
    ViewAdjust after = v;
    panDrag(c, after, w, h, from, to);
    CHECK(dist(kernelWorld(c, after, w, h, to), kernelWorld(c, v, w, h, from)) < 1e-9);
    CHECK(after.zoomFactor == v.zoomFactor);
    // The centre moved by the drag, in world units, against it.
    double pixel = std::max(c.sceneWidth / w, c.sceneHeight / h) / (c.zoom * v.zoomFactor);
    CHECK(std::hypot(after.panX - v.panX, after.panY - v.panY) ==
          doctest::Approx(dist(from, to) * pixel));
    // In pieces, the same.
    ViewAdjust steps = v;
    Vec2 prev = from;
    for (int i = 1; i <= 10; ++i) {
        Vec2 next{from.x + (to.x - from.x) * i / 10, from.y + (to.y - from.y) * i / 10};
        panDrag(c, steps, w, h, prev, next);
        prev = next;
    }
    CHECK(steps.panX == doctest::Approx(after.panX));
    CHECK(steps.panY == doctest::Approx(after.panY));
}

TEST_CASE("view camera: a dragged layer follows the cursor, whatever the turns") {
    SceneCamera c = turnedCamera();
    const int w = 400, h = 400;
    for (double layerTurn : {0.0, 0.6, -2.0}) {
        ViewAdjust v = someView();
        v.layerRef(1).turn = layerTurn;
        Vec2 from{150, 210}, to{90.5, 330.5};
        // The layer's own point under the cursor when the drag starts.
        Vec2 q = unmove(v.layer(1), kernelWorld(c, v, w, h, from));
        ViewAdjust after = v;
        moveLayer(c, after, w, h, 1, from, to);
        CHECK(dist(after.layer(1).apply(q), kernelWorld(c, after, w, h, to)) < 1e-9);
        CHECK(after.layer(1).turn == layerTurn);
        CHECK(after.panX == v.panX); // the camera stays
        CHECK(after.layer(0).identity());
    }
    // A layer past the end of the list is added to it.
    ViewAdjust v;
    moveLayer(c, v, w, h, 3, {0, 0}, {10, 0});
    CHECK(v.layers.size() == 4);
    CHECK_FALSE(v.layer(3).identity());
}

TEST_CASE("view camera: alt-drag turns a layer about the world origin") {
    SceneCamera c = turnedCamera();
    c.centerX = 40; // the origin on screen, off the centre
    const int w = 600, h = 400;
    ViewAdjust v = someView();
    ViewCamera cam(c, v, w, h);
    Vec2 from{450, 120};
    Vec2 a = cam.toWorld(from);
    for (double beta : {0.3, -1.1, 2.5}) {
        // The cursor moves to where the world point under it goes when turned by beta about
        // the origin: the layer turns by beta, and its point under the cursor comes along.
        Vec2 b{std::cos(beta) * a.x - std::sin(beta) * a.y,
               std::sin(beta) * a.x + std::cos(beta) * a.y};
        Vec2 to = cam.toPixel(b);
        ViewAdjust after = v;
        turnLayer(c, after, w, h, 1, from, to);
        CHECK(after.layer(1).turn == doctest::Approx(v.layer(1).turn + beta));
        Vec2 q = unmove(v.layer(1), a);
        CHECK(dist(after.layer(1).apply(q), b) < 1e-9);
        // Whatever sat on the origin turns in place: the offset turned with the layer.
        Vec2 o = unmove(v.layer(1), {0, 0});
        CHECK(dist(after.layer(1).apply(o), {0, 0}) < 1e-9);
    }
    // Farther from the origin along the same ray sweeps no angle.
    ViewAdjust after = v;
    Vec2 origin = cam.toPixel({0, 0});
    turnLayer(c, after, w, h, 1, from,
              {origin.x + 2 * (from.x - origin.x), origin.y + 2 * (from.y - origin.y)});
    CHECK(after.layer(1).turn == doctest::Approx(v.layer(1).turn));
}

TEST_CASE("view camera: a preview's pixels cover blocks of the full frame exactly") {
    SceneCamera c = turnedCamera();
    ViewAdjust v = someView();
    for (auto [w, h, d] : {std::tuple{640, 360, 4}, std::tuple{641, 359, 4}, std::tuple{97, 33, 8},
                           std::tuple{320, 200, 2}}) {
        Preview p = previewOf(c, v, w, h, d);
        CHECK(p.width == (w + d - 1) / d);
        CHECK(p.height == (h + d - 1) / d);
        for (Vec2 u : {Vec2{0, 0}, Vec2{0.5, 0.5}, Vec2{3.25, 7.5}, Vec2{double(p.width), 1.0}}) {
            Vec2 full = kernelWorld(c, v, w, h, {u.x * d, u.y * d});
            CHECK(dist(kernelWorld(c, p.view, p.width, p.height, u), full) < 1e-9);
        }
    }
}

TEST_CASE("view camera: the compiled kernel places the world and the layers the same way") {
    // Two layers whose distance fields are |x| and |y| in their own coordinates (one member,
    // far from the others), so the kernel's layer fields reveal where it put each pixel.
    auto program = test::compileOk(
        "scene { size = (300, 200) }\n"
        "camera { center = (12.5, -7); zoom = 1.7; rotation = 20deg }\n"
        "layer a { family = x; spacing = 100000 }\n"
        "layer b { family = y; spacing = 100000 }\n",
        CompileOptions{.mode = CompileOptions::Mode::Interactive, .layerFields = true});
    REQUIRE(program->viewSlot >= 0);
    ViewAdjust v;
    v.panX = -3.25;
    v.panY = 8.5;
    v.zoomFactor = 2.3;
    v.layerRef(0) = {4.0, -6.0, 0.6};
    v.layerRef(1) = {-10.0, 2.0, -1.2};
    std::vector<double> literals = program->literals;
    v.write(literals, program->viewSlot, 2);

    const int w = 240, h = 180;
    FrameRequest req;
    req.width = w;
    req.height = h;
    req.literals = &literals;
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(*program, req, frame, diags));
    SceneCamera c = SceneCamera::from(frame);
    CHECK(c.centerX == doctest::Approx(12.5));
    CHECK(c.turn == doctest::Approx(20 * std::numbers::pi / 180));
    CHECK(c.sceneWidth == 300);

    Interpreter kernel(program->kernel);
    const lower::OutputLayout& layout = program->layout;
    for (Vec2 p : {Vec2{0.5, 0.5}, Vec2{120.5, 90.5}, Vec2{17.5, 160.5}, Vec2{230.5, 4.5}}) {
        const std::vector<double> out = kernel.atPixel(frame.uniforms, p.x, p.y, w, h);
        Vec2 world = ViewCamera(c, v, w, h).toWorld(p);
        Vec2 qa = unmove(v.layer(0), world), qb = unmove(v.layer(1), world);
        CHECK(std::fabs(out[layout.distanceSlot(0)]) == doctest::Approx(std::fabs(qa.x)));
        CHECK(std::fabs(out[layout.distanceSlot(1)]) == doctest::Approx(std::fabs(qb.y)));
    }
}

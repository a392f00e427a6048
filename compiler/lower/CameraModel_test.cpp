// The camera template (CameraModel.h): its inverse and its displacements agree with its
// forward map; instantiated over IR values it builds a function that computes, on the
// interpreter, exactly what the double instantiation computes; and the compiled scene's
// kernel places its pixels where the double instantiation says.
#include "compiler/backend/interp/Interpreter.h"
#include "compiler/ir/BuiltValue.h"
#include "compiler/lower/CameraModel.h"
#include "runtime/FrameEval.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <numbers>
#include <random>

using namespace moire;
using lower::CameraT;
using V = ir::Vec2T<double>;

namespace {

CameraT<double> randomCamera(std::mt19937& rng, bool turned, bool centred) {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    CameraT<double> c;
    c.width = 64 + std::floor(500 * (u(rng) + 1));
    c.height = 48 + std::floor(300 * (u(rng) + 1));
    const double turn = std::numbers::pi * u(rng);
    c.cosTurn = std::cos(turn);
    c.sinTurn = std::sin(turn);
    c.pixel = std::exp(3 * u(rng));
    c.center = {100 * u(rng), 100 * u(rng)};
    c.turned = turned;
    c.centred = centred;
    return c;
}

} // namespace

TEST_CASE("camera model: toPixel undoes toWorld, and deltaToWorld is the difference of two") {
    std::mt19937 rng(13);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 200; ++k) {
        const CameraT<double> cam = randomCamera(rng, k % 3 != 0, k % 2 == 0);
        const V p{cam.width * (u(rng) + 1) / 2, cam.height * (u(rng) + 1) / 2};
        const V w = lower::toWorld(cam, p);
        const V back = lower::toPixel(cam, w);
        CHECK(back.x == doctest::Approx(p.x).epsilon(1e-12).scale(cam.width));
        CHECK(back.y == doctest::Approx(p.y).epsilon(1e-12).scale(cam.height));
        const V d{7.0 * u(rng), 7.0 * u(rng)};
        const V w2 = lower::toWorld(cam, V{p.x + d.x, p.y + d.y});
        const V dw = lower::deltaToWorld(cam, d);
        const double reach = 1e-12 * (std::hypot(w.x, w.y) + cam.pixel * cam.width);
        CHECK(std::fabs(w2.x - w.x - dw.x) <= reach);
        CHECK(std::fabs(w2.y - w.y - dw.y) <= reach);
    }
}

TEST_CASE("camera model: the forward map is the written formula") {
    // An independent copy of world = C + Rot(turn) (px - W/2, H/2 - py) * pixel, on purpose.
    std::mt19937 rng(7);
    for (int k = 0; k < 50; ++k) {
        const CameraT<double> cam = randomCamera(rng, true, true);
        const double px = 0.5 + k * 3.1, py = 0.5 + k * 1.7;
        const double sx = px - cam.width / 2, sy = cam.height / 2 - py;
        const V w = lower::toWorld(cam, V{px, py});
        CHECK(w.x ==
              doctest::Approx(cam.center.x + (cam.cosTurn * sx - cam.sinTurn * sy) * cam.pixel));
        CHECK(w.y ==
              doctest::Approx(cam.center.y + (cam.sinTurn * sx + cam.cosTurn * sy) * cam.pixel));
    }
}

TEST_CASE("camera model: the IR instantiation computes what the double instantiation does") {
    // The function: params 0-5 are the centre, the turn's cosine and sine, the scene's size;
    // param 6 the zoom. Outputs: the world point, then the pixel back from it.
    for (bool turned : {false, true})
        for (bool centred : {false, true}) {
            ir::Function f;
            ir::Builder b(f);
            auto built = [&](ir::ValueId v) { return ir::BuiltValue(b, v); };
            CameraT<ir::BuiltValue> cam;
            cam.width = built(b.leaf(ir::Op::ImageW));
            cam.height = built(b.leaf(ir::Op::ImageH));
            cam.center = {built(b.param(0)), built(b.param(1))};
            cam.cosTurn = built(b.param(2));
            cam.sinTurn = built(b.param(3));
            cam.pixel =
                lower::fitScale(built(b.param(4)), built(b.param(5)), cam.width, cam.height) /
                built(b.param(6));
            cam.turned = turned;
            cam.centred = centred;
            const ir::Vec2T<ir::BuiltValue> w =
                lower::toWorld(cam, {built(b.leaf(ir::Op::PixelX)), built(b.leaf(ir::Op::PixelY))});
            const ir::Vec2T<ir::BuiltValue> back = lower::toPixel(cam, w);
            b.output(0, w.x.id);
            b.output(1, w.y.id);
            b.output(2, back.x.id);
            b.output(3, back.y.id);
            f.numOutputs = 4;
            ir::verify(f);

            const double turn = 0.7;
            const std::vector<double> params = {12.5, -3.25, std::cos(turn), std::sin(turn), 1200,
                                                800,  1.9};
            CameraT<double> d;
            d.width = 300;
            d.height = 170;
            d.center = {params[0], params[1]};
            d.cosTurn = params[2];
            d.sinTurn = params[3];
            d.pixel = lower::fitScale(params[4], params[5], d.width, d.height) / params[6];
            d.turned = turned;
            d.centred = centred;
            Interpreter interp(f);
            for (double px : {0.5, 17.5, 150.0, 299.5})
                for (double py : {0.5, 85.0, 169.5}) {
                    const std::vector<double> out =
                        interp.atPixel({}, px, py, 300, 170, 0.0, &params);
                    const V w = lower::toWorld(d, V{px, py});
                    const V back = lower::toPixel(d, w);
                    CHECK(out[0] == w.x);
                    CHECK(out[1] == w.y);
                    CHECK(out[2] == back.x);
                    CHECK(out[3] == back.y);
                }
        }
}

TEST_CASE("camera model: a compiled scene's pixels lie where the double instantiation says") {
    // Layers whose phase is x and y with spacing 1: their index fields are the world point.
    auto program = test::compileOk(
        "scene { size = (400, 300) }\ncamera { center = (3, -2); zoom = 1.7; rotation = 25deg }\n"
        "layer { family = x; spacing = 1 }\nlayer { family = y; spacing = 1 }\n",
        {.layerFields = true});
    FrameValues fv;
    std::string diags;
    FrameRequest req;
    req.width = 160; // another aspect than the scene's: the frame is fitted
    req.height = 90;
    REQUIRE(evaluateFrame(*program, req, fv, diags));
    CameraT<double> cam;
    cam.width = 160;
    cam.height = 90;
    cam.center = {3, -2};
    cam.cosTurn = std::cos(25 * std::numbers::pi / 180);
    cam.sinTurn = std::sin(25 * std::numbers::pi / 180);
    cam.pixel = lower::fitScale(400.0, 300.0, 160.0, 90.0) / 1.7;
    Interpreter interp(program->kernel);
    for (double px : {0.5, 40.5, 159.5})
        for (double py : {0.5, 60.5, 89.5}) {
            const std::vector<double> out = interp.atPixel(fv.uniforms, px, py, 160, 90);
            const V w = lower::toWorld(cam, V{px, py});
            CHECK(out[program->layout.indexSlot(0)] == doctest::Approx(w.x).epsilon(1e-12));
            CHECK(out[program->layout.indexSlot(1)] == doctest::Approx(w.y).epsilon(1e-12));
        }
}

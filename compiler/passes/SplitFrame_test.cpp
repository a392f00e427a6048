// SplitFrame: the frame program and the kernel together compute what the scene function
// computes, with every per-frame value (time, params, anything not depending on the pixel)
// moved to the frame; and the kernel's structure, hence its hash and the JIT's cache entry,
// does not depend on the scene's numbers, only on its shape.
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "compiler/passes/Simplify.h"
#include "compiler/passes/SplitFrame.h"

#include <doctest/doctest.h>

using namespace moire;
using namespace moire::ir;

namespace {

using Vals = std::vector<ValueId>;

size_t count(const Function& f, Op op) {
    size_t n = 0;
    for (const Block& blk : f.blocks)
        for (const Inst& inst : blk.insts) n += inst.op == op;
    return n;
}

// Two per-pixel outputs and two settings, mixing per-frame and per-pixel work: a per-frame
// `if`, a per-frame bool and int used per pixel, and a per-pixel loop that reads time and
// a param inside its body.
Function sceneFunction() {
    Function f;
    f.name = "scene";
    f.numOutputs = 4;
    Builder b(f);
    ValueId t = b.leaf(Op::Time), p0 = b.param(0), p1 = b.param(1);
    ValueId k = b.add(b.mul(b.sin(t), p0), b.constF(1.0));
    ValueId px = b.leaf(Op::PixelX), py = b.sub(b.leaf(Op::ImageH), b.leaf(Op::PixelY));
    ValueId frameBool = b.lt(p0, p1);
    ValueId frameInt = b.emit(Op::FToI, {b.mul(p1, b.constF(2.0))});
    ValueId frameIf = b.ifThenElse(
        frameBool, [&] { return Vals{b.mul(p0, b.constF(2.0))}; }, [&] { return Vals{p1}; })[0];
    auto loop = b.loop(
        {b.constI(0), px},
        [&](std::span<const ValueId> p) {
            return Vals{b.emit(Op::ILt, {p[0], frameInt})};
        },
        [&](std::span<const ValueId> p) {
            ValueId step = b.mul(b.param(1), b.leaf(Op::Time)); // read inside the per-pixel region
            return Vals{b.emit(Op::IAdd, {p[0], b.constI(1)}),
                        b.add(b.mul(p[1], b.constF(0.5)), step)};
        });
    b.output(0, b.add(b.mul(px, k), b.select(frameBool, py, b.leaf(Op::ImageW))));
    b.output(1, b.add(loop[1], frameIf));
    b.output(2, b.mul(p0, b.constF(10.0))); // settings: frame outputs after the uniforms
    b.output(3, t);
    verify(f);
    return f;
}

} // namespace

TEST_CASE("frame program and kernel together compute the scene function, on every backend") {
    Function scene = sceneFunction();
    passes::FrameSplit split = passes::splitFrame(scene, 2);
    for (Op op : {Op::Time, Op::Param}) CHECK(count(split.kernel, op) == 0);
    for (Op op : {Op::PixelX, Op::PixelY, Op::ImageW, Op::ImageH})
        CHECK(count(split.frame, op) == 0);
    CHECK(count(split.kernel, Op::Loop) == 1);
    CHECK(count(split.frame, Op::If) == 1);
    CHECK(split.numSettings == 2);
    CHECK(split.frame.numOutputs == split.numUniforms + 2);

    auto backends = optest::allBackends();
    std::vector<std::unique_ptr<CompiledKernel>> kernels;
    for (auto& backend : backends) kernels.push_back(backend->compile(split.kernel));
    const int w = 5, h = 3;
    for (auto [p0, p1, t] : {std::tuple{0.5, 1.6, 0.25}, {2.0, 1.2, 1.5}, {-1.0, 2.9, 0.0}}) {
        CAPTURE(p0);
        CAPTURE(p1);
        optest::InterpInputs frameIn;
        frameIn.params = {p0, p1};
        frameIn.time = t;
        std::vector<double> frame = optest::interpret(split.frame, frameIn);
        std::vector<double> uniforms(frame.begin(), frame.begin() + split.numUniforms);
        for (size_t i = 0; i < backends.size(); ++i) {
            CAPTURE(backends[i]->name());
            std::vector<float> out(w * h * 2);
            kernels[i]->runTile(KernelFrame{uniforms.data(), w, h}, TileRect{0, 0, w, h},
                                out.data(), w * 2);
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x) {
                    optest::InterpInputs in = frameIn;
                    in.pixelX = x + 0.5;
                    in.pixelY = y + 0.5;
                    in.imageW = w;
                    in.imageH = h;
                    std::vector<double> want = optest::interpret(scene, in);
                    CHECK(frame[split.numUniforms] == want[2]);
                    CHECK(frame[split.numUniforms + 1] == want[3]);
                    for (int k = 0; k < 2; ++k)
                        CHECK(out[(y * w + x) * 2 + k] == doctest::Approx(want[k]).epsilon(1e-5));
                }
        }
    }
}

TEST_CASE("a scene whose numbers change keeps its kernel, a change of shape does not") {
    auto hashOf = [](const std::string& text) { return test::compileOk(text)->kernelHash; };
    const std::string base =
        "layer { family = circles; spacing = 7; stroke = 1.5; color = #203040 }";
    const uint64_t h = hashOf(base);
    // Numbers only: spacing, stroke, colour, the scene size. (Setting a size at all is a
    // change of shape, so the sizes are compared among themselves.)
    CHECK(hashOf("layer { family = circles; spacing = 8; stroke = 1.5; color = #203040 }") == h);
    CHECK(hashOf("layer { family = circles; spacing = 7; stroke = 3; color = #a01010 }") == h);
    CHECK(hashOf("scene { size = (300, 200) }\n" + base) ==
          hashOf("scene { size = (1200, 900) }\n" + base));
    // Shape: another family, another layer, another power.
    CHECK(hashOf("layer { family = lines; spacing = 7; stroke = 1.5; color = #203040 }") != h);
    CHECK(hashOf(base + "\n" + base) != h);
    const uint64_t square = hashOf("layer { family = x ^ 2 + y; spacing = 7 }");
    CHECK(hashOf("layer { family = x ^ 2 + y; spacing = 9 }") == square);
    CHECK(hashOf("layer { family = x ^ 3 + y; spacing = 7 }") != square);
    CHECK(hashOf("layer { family = x ^ 2 - y; spacing = 7 }") != square);
}

TEST_CASE("the JIT compiles a kernel once for scenes that differ only in numbers") {
    auto backend = test::makeBackendOrSkip("jit");
    if (!backend) return;
    auto* jit = dynamic_cast<LlvmJitBackend*>(backend.get());
    REQUIRE(jit);
    auto interp = test::makeBackendOrSkip("interp");
    REQUIRE(interp);
    auto a = test::compileOk("layer { family = circles; spacing = 7; color = #203040 }");
    auto b = test::compileOk("layer { family = circles; spacing = 4; color = #c02020 }");
    REQUIRE(a->kernelHash == b->kernelHash);
    Image ia = test::renderScene(*a, *jit, 48, 32);
    const int afterFirst = jit->compileCount();
    CHECK(afterFirst >= 1);
    Image ib = test::renderScene(*b, *jit, 48, 32);
    CHECK(jit->compileCount() == afterFirst); // a cache hit
    // ...which still draws the second scene, not the first: it matches the interpreter.
    CHECK(test::compareImages(ib, test::renderScene(*b, *interp, 48, 32), 2e-3).fractionWithin() >
          0.99);
    CHECK(test::compareImages(ia, ib, 2e-3).fractionWithin() < 0.9);
    // A change of shape compiles anew.
    test::renderScene(*test::compileOk("layer { family = lines; spacing = 7 }"), *jit, 48, 32);
    CHECK(jit->compileCount() == afterFirst + 1);
}

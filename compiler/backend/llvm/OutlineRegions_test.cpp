// Which arms of a kernel share one function: the key of an arm is its structure, whatever
// uniforms, pixel values or shared constants it reads. Then the JIT with arms outlined against
// the same JIT with every arm in place: the same pixels, bit for bit, with fewer instructions
// compiled.
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/backend/llvm/OutlineRegions.h"
#include "compiler/Compile.h"
#include "compiler/ir/Builder.h"
#include "runtime/FrameEval.h"

#include <algorithm>
#include <cstring>
#include <doctest/doctest.h>
#include <sstream>

using namespace moire;
using namespace moire::llvmbackend;

namespace {

// A layer's worth of an arm: reads uniforms [slot, slot + 1], the pixel, a shared constant
// and `outside`, and loops (a loop is what makes an arm worth a function).
std::vector<ir::ValueId> layerArm(ir::Builder& b, int slot, ir::ValueId outside, ir::ValueId shared,
                                  double step) {
    ir::ValueId u = b.uniform(slot), v = b.uniform(slot + 1);
    ir::ValueId x = b.add(b.leaf(ir::Op::PixelX), b.mul(u, outside));
    std::vector<ir::ValueId> r = b.loop(
        {x, shared}, [&](std::span<const ir::ValueId> c) { return std::vector{b.lt(c[0], v)}; },
        [&](std::span<const ir::ValueId> c) {
            return std::vector{b.add(c[0], b.constF(step)), b.add(c[1], shared)};
        });
    return {b.mul(r[0], r[1])};
}

struct TwoLayers {
    ir::Function f;
    ir::BlockId arm[2] = {0, 0};
};

// Two `if`s whose else-arms are layerArm at `slots` with `steps`.
TwoLayers twoLayers(int slot0, int slot1, double step0, double step1) {
    TwoLayers t;
    t.f.numOutputs = 2;
    ir::Builder b(t.f);
    ir::ValueId shared = b.constF(0.5), outside = b.leaf(ir::Op::PixelY);
    int slots[2] = {slot0, slot1};
    double steps[2] = {step0, step1};
    for (int k = 0; k < 2; ++k) {
        ir::ValueId c = b.lt(b.uniform(20 + k), shared);
        std::vector<ir::ValueId> r = b.ifThenElse(
            c, [&] { return std::vector{shared}; },
            [&] { return layerArm(b, slots[k], outside, shared, steps[k]); });
        t.arm[k] = t.f.blocks[0].insts.back().regions[1]; // the if just built
        b.output(k, r[0]);
    }
    return t;
}

} // namespace

TEST_CASE("outlined arms: the same structure over other uniforms is one key") {
    TwoLayers t = twoLayers(3, 9, 1.0, 1.0);
    RegionSignature a = regionSignature(t.f, t.arm[0]), b = regionSignature(t.f, t.arm[1]);
    CHECK(a.key == b.key);
    // Uniforms and the pixel are read as inputs, passed by the caller, in the order first read.
    REQUIRE(a.leaves.size() == 3);
    CHECK(a.leaves[0]->op == ir::Op::Uniform);
    CHECK(a.leaves[0]->iimm == 3);
    CHECK(b.leaves[0]->iimm == 9);
    CHECK(a.leaves[2]->op == ir::Op::PixelX);
    // The shared constant is made inside, not passed: the inputs are the leaves and `outside`.
    CHECK(a.inputs.size() == 4);
    REQUIRE(a.constants.size() == 1);
    CHECK(a.constants[0]->imm == 0.5);
    CHECK(outlinable(t.f, t.arm[0]));
    CHECK(regionSize(t.f, t.arm[0]) > 8);
}

TEST_CASE("outlined arms: another constant or another op is another key") {
    TwoLayers t = twoLayers(3, 9, 1.0, 2.0);
    CHECK(regionSignature(t.f, t.arm[0]).key != regionSignature(t.f, t.arm[1]).key);
    // -0 and +0 are different constants (1 / x tells them apart).
    TwoLayers z = twoLayers(3, 9, 0.0, -0.0);
    CHECK(regionSignature(z.f, z.arm[0]).key != regionSignature(z.f, z.arm[1]).key);
}

TEST_CASE("outlined arms: an arm that writes an output stays in place") {
    ir::Function f;
    f.numOutputs = 1;
    ir::Builder b(f);
    ir::ValueId c = b.lt(b.leaf(ir::Op::PixelX), b.constF(3));
    b.ifThenElse(
        c,
        [&] {
            b.output(0, b.constF(1));
            return std::vector<ir::ValueId>{};
        },
        [&] { return std::vector<ir::ValueId>{}; });
    CHECK_FALSE(outlinable(f, f.blocks[0].insts.back().regions[0]));
    CHECK(outlinable(f, f.blocks[0].insts.back().regions[1]));
}

namespace {

std::vector<float> render(LlvmJitBackend& jit, const SceneProgram& p) {
    FrameRequest req;
    req.width = 173; // not a whole number of lanes: the tile's last run is masked
    req.height = 61;
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(p, req, frame, diags));
    auto kernel = jit.compile(p.kernel);
    std::vector<float> out(size_t(frame.width) * frame.height * kernel->numOutputs());
    kernel->runTile({frame.uniforms.data(), frame.width, frame.height},
                    {0, 0, frame.width, frame.height}, out.data(),
                    size_t(frame.width) * kernel->numOutputs());
    return out;
}

int countOf(const std::string& text, const std::string& what) {
    int n = 0;
    for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
    return n;
}

} // namespace

TEST_CASE("outlined arms: the default scene's two walking layers share their solver, same "
          "pixels") {
    EmbeddedScene scene = defaultScene();
    CompileResult r = compileScene(scene.path, scene.text, {});
    REQUIRE(r.program);
    LlvmJitBackend::Options inPlace, outlined;
    inPlace.lanes = outlined.lanes = 8;
    inPlace.outlineInsts = 0;
    LlvmJitBackend a(inPlace), b(outlined);
    if (b.lanes() == 1) return; // a host without vectors runs scalar code, which outlines nothing
    std::vector<float> x = render(a, *r.program), y = render(b, *r.program);
    REQUIRE(x.size() == y.size());
    CHECK(std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0);

    // Each arm function is defined once and called; the second layer calls the first's.
    std::string text = b.dumpLlvm(r.program->kernel);
    std::vector<std::string> arms, calls;
    std::istringstream lines(text);
    for (std::string line; std::getline(lines, line);) {
        size_t at = line.find('@'), open = line.find('(', at);
        if (at == std::string::npos || open == std::string::npos) continue;
        std::string callee = line.substr(at, open - at);
        if (line.rfind("define {", 0) == 0) arms.push_back(callee);
        if (line.find(" call {") != std::string::npos) calls.push_back(callee);
    }
    REQUIRE(arms.size() > 1);
    int shared = 0;
    for (const std::string& arm : arms) {
        auto n = std::count(calls.begin(), calls.end(), arm);
        INFO(arm);
        CHECK(n >= 1);
        shared += n >= 2;
    }
    CHECK(shared >= 1);
    // Less code in all than with every arm in place.
    CHECK(countOf(text, "\n  ") < countOf(a.dumpLlvm(r.program->kernel), "\n  "));
}

// A kernel compiled in chunks computes exactly what it computes whole, and chunking keeps
// every function the JIT compiles bounded in size however many layers a scene has (which
// is what keeps LLVM's compile time linear in the layers).
#include "compiler/backend/llvm/KernelChunks.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "tests/support/Support.h"

#include <cmath>
#include <cstring>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <sstream>

using namespace moire;

namespace {

std::unique_ptr<SceneProgram> compiled(const std::string& text) {
    CompileResult r = compileScene("chunks.moire", text, {});
    INFO(r.diagnostics);
    REQUIRE(r.program);
    return std::move(r.program);
}

// The kernel's outputs over a tile 2 strips and a bit wide (so a short last strip too).
std::vector<float> runTile(LlvmJitBackend& jit, const SceneProgram& p) {
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(p, FrameRequest{}, frame, diags));
    auto kernel = jit.compile(p.kernel);
    TileRect tile{3, 5, 3 + 2 * llvmbackend::kStrip + 21, 9};
    int w = tile.x1 - tile.x0, h = tile.y1 - tile.y0, n = kernel->numOutputs();
    std::vector<float> out(static_cast<size_t>(w) * h * n, -7.0f);
    kernel->runTile({frame.uniforms.data(), frame.width, frame.height}, tile, out.data(),
                    static_cast<size_t>(w) * n);
    return out;
}

// Equal, bit for bit but for the last digits where a vectorised maths function and the
// scalar one may round apart.
int mismatches(const std::vector<float>& a, const std::vector<float>& b) {
    int bad = 0;
    for (size_t i = 0; i < a.size(); ++i) {
        if (std::memcmp(&a[i], &b[i], sizeof(float)) == 0) continue;
        if (std::fabs(a[i] - b[i]) <= 1e-5f * std::max(1.0f, std::fabs(a[i]))) continue;
        ++bad;
    }
    return bad;
}

std::string layers(int n) {
    // Families of every kind: lattice, walking (ifs and loops in the kernel), phase.
    const char* kinds[] = {"circles; spacing = 6; stroke = 1.7",
                           "squares; spacing = 9; offset = (1.1, 0.4); turn = 1.6deg",
                           "hyperbola; spacing = 5", "lines; spacing = 4; rotation = 20deg",
                           "hexagons; spacing = 12"};
    std::string text = "scene { size = (300, 200) }\n";
    for (int i = 0; i < n; ++i)
        text +=
            fmt::format("layer {{ family = {}; origin = ({}, {}) }}\n", kinds[i % 5], i * 3, -i);
    return text;
}

// Instructions in the largest function of the optimised module.
size_t largestFunction(const std::string& llvmText) {
    size_t largest = 0, current = 0;
    bool inside = false;
    std::istringstream in(llvmText);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("define ", 0) == 0) {
            inside = true;
            current = 0;
        } else if (inside && line == "}") {
            inside = false;
            largest = std::max(largest, current);
        } else if (inside && line.rfind("  ", 0) == 0) {
            ++current;
        }
    }
    return largest;
}

} // namespace

TEST_CASE("jit chunks: a kernel cut into chunks computes what it computes whole") {
    LlvmJitBackend whole(1u << 30), chunked(40);
    std::vector<std::string> scenes = {layers(12)};
    for (const char* name :
         {"walking_squares", "unwinding_walk", "morphing_shapes", "terrain_contours", "two_fields"})
        scenes.push_back(test::readFile(test::sourcePath(fmt::format("examples/{}.moire", name))));
    for (const std::string& text : scenes) {
        CAPTURE(text.substr(0, 120));
        auto p = compiled(text);
        llvmbackend::ChunkPlan plan = llvmbackend::planChunks(p->kernel, 40);
        CHECK(plan.chunks.size() > 1);
        CHECK(mismatches(runTile(whole, *p), runTile(chunked, *p)) == 0);
    }
}

TEST_CASE("jit chunks: no function grows with the number of layers") {
    // One function per kernel made LLVM's time superlinear in the layers (16 s for 500).
    LlvmJitBackend jit;
    size_t small = largestFunction(jit.dumpLlvm(compiled(layers(15))->kernel));
    size_t large = largestFunction(jit.dumpLlvm(compiled(layers(60))->kernel));
    CHECK(small > 0);
    CHECK(large <= small * 3 / 2);
}

TEST_CASE("jit chunks: every value a chunk reads comes from an earlier chunk's slot") {
    auto p = compiled(layers(10));
    llvmbackend::ChunkPlan plan = llvmbackend::planChunks(p->kernel, 30);
    REQUIRE(plan.chunks.size() > 3);
    // Replay the plan: the slot a chunk loads must still hold the value stored there.
    std::vector<ir::ValueId> slotHolds(plan.numSlots, ir::kNoValue);
    size_t next = 0;
    for (const llvmbackend::Chunk& c : plan.chunks) {
        CHECK(c.begin == next);
        next = c.end;
        for (auto [value, slot] : c.loads) CHECK(slotHolds.at(slot) == value);
        for (auto [value, slot] : c.stores) slotHolds.at(slot) = value;
    }
    CHECK(next == p->kernel.blocks[0].insts.size());
}

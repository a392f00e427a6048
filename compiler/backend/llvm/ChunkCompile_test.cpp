// How the JIT compiles a chunked kernel: each chunk runs whole strips (so its pixel loop is
// vectorised once, with no remainder loop or epilogue beside it: the time LLVM takes over a
// kernel of 1,000 layers is mostly code generation of those copies), in a module of its own
// compiled on several threads. Whatever the setting, the pixels are the same.
#include "compiler/backend/llvm/KernelChunks.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "compiler/Compile.h"
#include "runtime/FrameEval.h"

#include <cstdlib>
#include <cstring>
#include <doctest/doctest.h>
#include <fmt/format.h>
#include <sstream>

using namespace moire;

namespace {

constexpr float kUntouched = -7.0f;

std::unique_ptr<SceneProgram> compiled(const std::string& text) {
    CompileResult r = compileScene("chunk_compile.moire", text, {});
    INFO(r.diagnostics);
    REQUIRE(r.program);
    return std::move(r.program);
}

std::string circles(int n) {
    std::string text = "scene { size = (300, 200) }\n";
    for (int i = 0; i < n; ++i)
        text += fmt::format(
            "layer {{ family = circles; spacing = 6; stroke = 1.7; origin = ({}, {}) }}\n", i * 3,
            -i);
    // Walking and phase families too: loops and ifs inside a chunk's pixel loop.
    text += "layer { family = squares; spacing = 9; offset = (1.1, 0.4); turn = 1.6deg }\n"
            "layer { family = hexagons; spacing = 12 }\n";
    return text;
}

// The kernel over a tile that is not a whole number of strips, written into rows wider than
// the tile: every pixel outside the tile must keep kUntouched.
std::vector<float> runTile(LlvmJitBackend& jit, const SceneProgram& p, TileRect tile,
                           size_t rowFloats) {
    FrameValues frame;
    std::string diags;
    REQUIRE(evaluateFrame(p, FrameRequest{}, frame, diags));
    auto kernel = jit.compile(p.kernel);
    std::vector<float> out(rowFloats * static_cast<size_t>(tile.y1 - tile.y0), kUntouched);
    kernel->runTile({frame.uniforms.data(), frame.width, frame.height}, tile, out.data(),
                    rowFloats);
    return out;
}

bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// Lines of the optimised IR holding a loop's back edge, in the functions of chunks.
int chunkLoopBackEdges(const std::string& llvmText, int* chunkFunctions) {
    int edges = 0;
    bool inChunk = false;
    *chunkFunctions = 0;
    std::istringstream in(llvmText);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("define ", 0) == 0) {
            inChunk = line.find(".chunk") != std::string::npos;
            *chunkFunctions += inChunk;
        } else if (line == "}") {
            inChunk = false;
        } else if (inChunk && line.find("!llvm.loop") != std::string::npos) {
            ++edges;
        }
    }
    return edges;
}

} // namespace

TEST_CASE("jit chunks: whole strips write the tile's pixels and nothing past its edge") {
    auto p = compiled(circles(8));
    REQUIRE(llvmbackend::planChunks(p->kernel, 40).chunks.size() > 2);
    LlvmJitBackend::Options unchunked, chunked;
    unchunked.chunkInsts = 1u << 30;
    chunked.chunkInsts = 40;
    LlvmJitBackend whole(unchunked), cut(chunked);
    int n = cut.compile(p->kernel)->numOutputs();
    // 2 strips and 5 pixels from x = 7: the last strip is short; 11 pixels of spare row.
    TileRect tile{7, 3, 7 + 2 * llvmbackend::kStrip + 5, 6};
    size_t rowFloats = static_cast<size_t>(tile.x1 - tile.x0 + 11) * n;
    std::vector<float> a = runTile(whole, *p, tile, rowFloats);
    std::vector<float> b = runTile(cut, *p, tile, rowFloats);
    CHECK(sameBits(a, b));
    for (int y = 0; y < tile.y1 - tile.y0; ++y)
        for (size_t i = static_cast<size_t>(tile.x1 - tile.x0) * n; i < rowFloats; ++i)
            CHECK(b[y * rowFloats + i] == kUntouched);
}

TEST_CASE("jit chunks: compiled on several threads or as before, the pixels are the same") {
    auto p = compiled(circles(8));
    TileRect tile{0, 0, 3 * llvmbackend::kStrip + 9, 4};
    LlvmJitBackend::Options one, four, classic;
    one.chunkInsts = four.chunkInsts = classic.chunkInsts = 40;
    one.compileThreads = 1;
    four.compileThreads = 4;
    classic.classicChunks = true;
    LlvmJitBackend a(one), b(four), c(classic);
    size_t rowFloats = static_cast<size_t>(tile.x1) * a.compile(p->kernel)->numOutputs();
    std::vector<float> ref = runTile(a, *p, tile, rowFloats);
    CHECK(sameBits(ref, runTile(b, *p, tile, rowFloats)));
    CHECK(sameBits(ref, runTile(c, *p, tile, rowFloats)));
}

TEST_CASE("jit chunks: a chunk's pixel loop is compiled once") {
    // Looping to the tile's edge, each chunk was vectorised with a vectorised epilogue and a
    // scalar remainder loop beside the vector body: three copies of its code to compile.
    auto p = compiled(circles(40).substr(0, circles(40).find("layer { family = squares")));
    LlvmJitBackend jit;
    int chunks = 0;
    int edges = chunkLoopBackEdges(jit.dumpLlvm(p->kernel), &chunks);
    CHECK(chunks > 1);
    CHECK(edges <= chunks);
}

// The width of the float arithmetic in the chunks' optimised code (outputs are stored
// interleaved, in wider vectors): 0 where none is vectorised, -1 where two widths appear.
int chunkVectorWidth(const std::string& llvmText) {
    int width = 0;
    bool inChunk = false;
    std::istringstream in(llvmText);
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("define ", 0) == 0)
            inChunk = line.find(".chunk") != std::string::npos;
        else if (line == "}")
            inChunk = false;
        if (!inChunk) continue;
        for (const char* op : {" = fadd <", " = fsub <", " = fmul <", " = fdiv <"}) {
            size_t at = line.find(op);
            if (at == std::string::npos || line.find(" x float>", at) == std::string::npos)
                continue;
            int w = std::atoi(line.c_str() + at + std::strlen(op));
            width = width == 0 || width == w ? w : -1;
        }
    }
    return width;
}

TEST_CASE("jit chunks: the pixel loop is vectorised at the width it is given") {
    // The hint saves the vectoriser costing every width; 4 floats is legal on every x86-64
    // and no cost model would pick it on a host with AVX, so the width seen is the hint's.
    auto p = compiled(circles(40).substr(0, circles(40).find("layer { family = squares")));
    // (The hint is for scalar chunks: a chunk in lanes is vectors already.)
    LlvmJitBackend::Options four, none, scalar;
    four.chunkVectorWidth = 4;
    none.chunkVectorWidth = 0;
    four.lanes = none.lanes = scalar.lanes = 1;
    LlvmJitBackend hinted(four), unhinted(none), widest(scalar);
    CHECK(chunkVectorWidth(hinted.dumpLlvm(p->kernel)) == 4);
    // With no hint, or the default one, the cost model's width and the default agree.
    int chosen = chunkVectorWidth(unhinted.dumpLlvm(p->kernel));
    CHECK(chosen >= 4);
    CHECK(chunkVectorWidth(widest.dumpLlvm(p->kernel)) == chosen);
    // And the pixels do not depend on the width.
    TileRect tile{0, 0, 2 * llvmbackend::kStrip + 3, 3};
    size_t rowFloats = static_cast<size_t>(tile.x1) * widest.compile(p->kernel)->numOutputs();
    std::vector<float> ref = runTile(unhinted, *p, tile, rowFloats);
    CHECK(sameBits(ref, runTile(hinted, *p, tile, rowFloats)));
    CHECK(sameBits(ref, runTile(widest, *p, tile, rowFloats)));
}

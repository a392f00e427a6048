// Cutting a large kernel into chunks for the LLVM backend.
//
// LLVM's code generation is superlinear in the size of one function (instruction selection,
// scheduling and register allocation over one huge basic block): a scene of 1,000 layers
// took over a minute to compile as one function. A kernel past a number of instructions
// (LlvmJitBackend::kDefaultChunkInsts) is therefore cut, between instructions of its entry block,
// into chunks of about that size, each compiled as a function of its own with its own pixel loop
// (so each is still vectorised). The tile function runs every chunk over a strip of at most kStrip
// pixels in turn; a value one chunk computes and a later one reads passes through a per-strip carry
// buffer (one slot of kStrip words per value, slots reused once a value is read for the
// last time). Leaves (constants, uniforms, the pixel position) are computed again instead.
#pragma once

#include "compiler/ir/IR.h"

#include <cstddef>
#include <unordered_map>
#include <vector>

namespace moire::llvmbackend {

constexpr int kStrip = 64;

struct Chunk {
    size_t begin = 0, end = 0;                      // entry-block instructions [begin, end)
    std::vector<const ir::Inst*> rematerialise;     // leaves of earlier chunks, emitted again here
    std::vector<std::pair<ir::ValueId, int>> loads; // earlier chunks' values: value, slot
    std::unordered_map<ir::ValueId, int> stores;    // values later chunks read: slot
};

struct ChunkPlan {
    std::vector<Chunk> chunks; // one chunk: compile the kernel whole
    int numSlots = 0;
};

// With `outlineInsts`, the arms compiled as functions of their own (OutlineRegions.h) do not
// count towards their chunk's size.
ChunkPlan planChunks(const ir::Function& kernel, size_t maxInsts, size_t outlineInsts = 0);

} // namespace moire::llvmbackend

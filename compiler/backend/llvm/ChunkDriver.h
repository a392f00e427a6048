// The driver of a chunked kernel (KernelChunks.h): the one function a tile calls, which runs
// every chunk over each strip of the tile.
#pragma once

#include "compiler/ir/IR.h"

#include <llvm/IR/Function.h>
#include <llvm/IR/Module.h>
#include <string>
#include <vector>

namespace moire::llvmbackend {

// The tile function of a chunked kernel: for each row of the tile, for each strip of at most
// kStrip pixels of it, every chunk in turn, sharing one carry buffer. Chunks that run whole
// strips write their outputs to a strip buffer, of which the pixels inside the tile are copied
// out (writing past x1 could overwrite the next tile or run off the image).
void emitChunkDriver(llvm::Module& m, const std::string& name, const ir::Function& kernel,
                     const std::vector<llvm::Function*>& chunks, int numSlots, bool wholeStrip);

} // namespace moire::llvmbackend

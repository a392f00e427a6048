// Regions of a kernel compiled as functions of their own, once per structure. Private to the
// LLVM backend.
//
// LLVM's code generation costs more than the rest of the JIT together, and grows faster than
// the size of the function it compiles (register allocation over one huge body). A walking
// family lowers to a tree of `if`s, one arm per solver path (closed forms, the stepped walk),
// and a scene usually has several layers of one family: the default scene's two walking layers
// differ only in which uniforms they read. So, with lanes, a large arm of an `if` is compiled
// as a function of its own, called where the arm would have run: arms of the same structure
// (the same ops in the same order, reading their inputs in the same pattern) share one
// function, and the functions, packed into a few modules, compile in parallel with the rest.
//
// An outlined arm reads every value it does not define as an argument. The leaves it reads
// whose value depends on where it is called (a uniform's slot, the pixel, the image size) are
// evaluated by the caller and passed in too, so that two layers' arms differ in nothing but
// their arguments; constants, even those it shares with code outside, are part of its
// structure and made inside. Inputs the same in every lane (uniforms and what is computed
// from them alone) are passed as scalars.
#pragma once

#include "compiler/ir/IR.h"

#include <cstddef>
#include <string>
#include <vector>

namespace moire::llvmbackend {

// Instructions in a region, counting those of nested regions.
size_t regionSize(const ir::Function& f, ir::BlockId region);

// Whether a region can run as a function: it writes no output (a function returns values;
// outputs are the tile function's to store).
bool outlinable(const ir::Function& f, ir::BlockId region);

// An `if` arm as a function: what it reads and what it is.
struct RegionSignature {
    // The values it reads from outside, in the order first read: the function's arguments
    // after the execution mask. Includes the results of `leaves`.
    std::vector<ir::ValueId> inputs;
    // Instructions inside the region the caller evaluates and passes in (uniforms, the pixel,
    // the image size), in the order met.
    std::vector<const ir::Inst*> leaves;
    // Constants defined outside that it reads: made again inside the function.
    std::vector<const ir::Inst*> constants;
    // The region's structure with its values numbered by first definition and its inputs by
    // first use: equal keys, equal functions.
    std::string key;
};

RegionSignature regionSignature(const ir::Function& f, ir::BlockId region);

// Whether `region`, an arm of an `if`, is compiled as a function where arms of at least
// `minInsts` instructions are (0: none is).
bool outlinedArm(const ir::Function& f, ir::BlockId region, size_t minInsts);

// Instructions in a region that are compiled where it is: those of nested regions too, but
// not those of the arms in it compiled as functions of their own (each counts as one, a call).
size_t ownSize(const ir::Function& f, ir::BlockId region, size_t minInsts);

} // namespace moire::llvmbackend

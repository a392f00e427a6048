// A base for passes that rebuild a function instruction by instruction. The default copies
// everything (renumbering values densely and dropping unreferenced blocks); a pass
// overrides `visit` to replace, drop or fold instructions.
#pragma once

#include "compiler/ir/Builder.h"
#include "compiler/ir/IR.h"

namespace moire::passes {

// Whether a pass verifies what it built. A chain of passes (simplify) verifies its last
// result only: the verifier walks every instruction, and each pass of the chain would pay it.
enum class Check { Verify, Trust };

class Rewriter {
  public:
    explicit Rewriter(const ir::Function& src);
    virtual ~Rewriter() = default;

    // Rebuilds the function; verifies the result unless `check` says the caller will.
    ir::Function run(Check check = Check::Verify);

  protected:
    // Handles one instruction of the source. Return false to get the default copy.
    virtual bool visit(const ir::Inst& inst) { return false; }
    // Called when a region is entered or left (CSE uses it to scope its table).
    virtual void enterRegion() {}
    virtual void leaveRegion() {}
    // Called for a source value that has no mapping yet; the default is an internal error.
    virtual ir::ValueId mapMissing(ir::ValueId v);
    // Called after the entry block has been rebuilt, before verification.
    virtual void finish() {}

    // The new value standing for source value `v`.
    ir::ValueId map(ir::ValueId v);
    void bind(ir::ValueId oldValue, ir::ValueId newValue) { vmap_[oldValue] = newValue; }
    // Copies `inst` with mapped operands (recursing into regions); returns the new results.
    ir::IdList copy(const ir::Inst& inst);
    // Emits the body of a source block into the current block, returning the mapped yield.
    std::vector<ir::ValueId> inlineBlock(ir::BlockId b);

    const ir::Function& src_;
    ir::Function dst_;
    ir::Builder b_;

  private:
    std::vector<ir::ValueId> vmap_;
};

} // namespace moire::passes

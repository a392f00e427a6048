// The IR -> LLVM IR translator of one tile function. Private to the LLVM backend.
//
// One translation, two shapes. With one lane, a value is a float, an i32 or an i1 and the
// pixel loop steps one pixel at a time (LLVM's loop vectoriser may then widen the loop when
// it has no control flow). With W lanes, every value is a vector of W of them, one per pixel
// of a run of W neighbours, and each op becomes the same op on vectors: a tile function then
// evaluates W pixels per step whatever the kernel's control flow. Control flow runs under an
// execution mask (the lanes a region is evaluated for): an `if` runs each region only when
// one of its lanes takes it, and merges the two with a select; a `loop` runs while any lane
// is active and keeps a finished lane's values unchanged (TranslateControl.cpp).
#pragma once

#include "compiler/backend/llvm/KernelChunks.h"
#include "compiler/backend/llvm/LlvmTranslate.h"
#include "compiler/backend/llvm/OutlineRegions.h"
#include "compiler/ir/IR.h"

#include <functional>
#include <llvm/IR/IRBuilder.h>
#include <llvm/IR/Module.h>
#include <string>
#include <unordered_map>
#include <vector>

namespace moire::llvmbackend {

struct TranslatorShape {
    unsigned lanes = 1;       // pixels per step; 1: scalar values
    bool vectorMaths = false; // libm calls go to glibc's libmvec (4, 8 or 16 lanes)
};

// The arms of `if`s a kernel's translators compile as functions of their own
// (OutlineRegions.h), each once; shared by the translators of one kernel. Arms are packed
// into modules of up to about `binInsts` instructions, each into the first with room:
// modules compile in parallel, but each has a fixed cost (LLVM's code generation pipeline is
// built and run for it), so a module per arm would cost more than it saves.
struct Outliner {
    std::string prefix;                                         // the kernel's name
    size_t minInsts = 0;                                        // arms at least this big
    size_t binInsts = 0;                                        // instructions per module
    std::function<llvm::Module&(const std::string&)> newModule; // a module of that name
    std::unordered_map<std::string, std::string> names; // key (with lanes' invariance): name
    std::vector<std::pair<llvm::Module*, size_t>> bins; // modules and their instructions

    // The module for an arm of `insts` instructions.
    llvm::Module& moduleFor(size_t insts) {
        for (auto& [module, size] : bins)
            if (size + insts <= binInsts) {
                size += insts;
                return *module;
            }
        bins.emplace_back(&newModule(prefix + ".arms" + std::to_string(bins.size())), insts);
        return *bins.back().first;
    }
};

class Translator {
  public:
    Translator(const ir::Function& f, llvm::Module& m, TranslatorShape shape = {},
               Outliner* outliner = nullptr);

    // The tile function of the whole kernel, or with `chunk`, the function of one chunk: the
    // same loop over the tile's pixels, with a tenth parameter, the strip's carry buffer.
    // With `wholeStrip`, a chunk runs kStrip pixels from x0 whatever x1 is: a constant trip
    // count that the vectoriser divides exactly, so it emits neither a scalar remainder loop
    // nor a vectorised epilogue, each as big as the body (the driver clips the outputs).
    //
    // With `vectorWidth`, a whole-strip scalar chunk's pixel loop carries that width as a hint.
    // The vectoriser then plans that one width instead of costing every width the target
    // offers, which was a third of LLVM's optimisation time for a kernel of 1,000 layers; the
    // driver passes the width its cost model picks for these loops (the widest float vector).
    llvm::Function* run(const std::string& name, const Chunk* chunk = nullptr,
                        bool wholeStrip = false, bool external = false, unsigned vectorWidth = 0);

  private:
    // --- the pixel loop (LlvmTranslate.cpp)
    void loopMetadata(llvm::BranchInst* backEdge, const char* key, unsigned value);
    llvm::Value* carrySlot(ir::ValueId v, int slot);
    void storeCarry(ir::ValueId v, int slot);
    llvm::Value* loadCarry(ir::ValueId v, int slot);
    void beginOutputs(const Chunk* chunk);
    void output(const ir::Inst& inst);
    void flushOutputs();
    llvm::Value* runMask();

    // --- ops (TranslateOps.cpp)
    void instruction(const ir::Inst& inst);
    bool laneInvariant(const ir::Inst& inst) const;
    llvm::Constant* cf(double v);
    llvm::Value* v(ir::ValueId id);
    llvm::Value* intrinsic(llvm::Intrinsic::ID id, std::initializer_list<llvm::Value*> args);
    llvm::Value* libm(const char* name, std::initializer_list<llvm::Value*> args);
    llvm::Value* semMin(llvm::Value* a, llvm::Value* b);
    llvm::Value* semMax(llvm::Value* a, llvm::Value* b);
    llvm::Value* floorOf(llvm::Value* a);
    llvm::Value* hypot(llvm::Value* a, llvm::Value* b);
    llvm::Type* typeOf(ir::ValueId id) const;

    // --- control flow (TranslateControl.cpp)
    void block(ir::BlockId id);
    std::vector<llvm::Value*> yielded(ir::BlockId id);
    void ifInst(const ir::Inst& inst);
    void loopInst(const ir::Inst& inst);
    void maskedIf(const ir::Inst& inst);
    bool cheapRegion(ir::BlockId id, int& budget) const;
    llvm::Value* andMask(llvm::Value* mask, llvm::Value* cond);

    // --- arms run as functions of their own (TranslateOutline.cpp)
    bool outlines(ir::BlockId region) const;
    std::vector<llvm::Value*> callOutlined(ir::BlockId region);
    llvm::FunctionType* armType(ir::BlockId region, const RegionSignature& sig);
    void runRegion(const std::string& name, ir::BlockId region, const RegionSignature& sig,
                   const std::vector<char>& invariant);

    const ir::Function& f_;
    llvm::Module& m_;
    llvm::LLVMContext& ctx_;
    llvm::IRBuilder<> b_;
    std::vector<llvm::Value*> vals_;
    // With lanes: whether each value is the same in every lane (laneInvariant), and whether
    // every argument of the instruction being translated is.
    std::vector<char> invariant_;
    bool argsInvariant_ = false;
    TranslatorShape shape_;
    Outliner* outliner_ = nullptr;
    llvm::Type *sf_, *si32_, *i64_; // scalars
    llvm::Type *fTy_, *iTy_, *bTy_; // the types of IR values (vectors with lanes)
    llvm::Function* fn_ = nullptr;
    llvm::BasicBlock* entry_ = nullptr;
    llvm::Instruction* entryInsert_ = nullptr;
    llvm::Value *uniforms_ = nullptr, *imageW_ = nullptr, *imageH_ = nullptr;
    llvm::Value *pixelX_ = nullptr, *pixelY_ = nullptr, *row_ = nullptr, *pixelBase_ = nullptr;
    std::unordered_map<int64_t, llvm::Value*> uniformLoads_;
    llvm::Value *carry_ = nullptr, *lane_ = nullptr;
    bool callsLibm_ = false;

    // With lanes: the lanes the current region runs for (nullptr: all of them), the lanes of
    // the pixel run inside the tile (nullptr: all), and each output slot's vector, kept in an
    // alloca (promoted to registers by LLVM) until the run's pixels are stored together.
    llvm::Value* exec_ = nullptr;
    llvm::Value* tail_ = nullptr;
    llvm::Value* wholeRun_ = nullptr; // with tail_: every lane of the run is inside the tile
    int regionDepth_ = 0;
    std::vector<llvm::AllocaInst*> outSlots_;
    bool writesOutputs_ = false;
};

} // namespace moire::llvmbackend

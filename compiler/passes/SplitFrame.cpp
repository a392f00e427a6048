#include "compiler/passes/SplitFrame.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/passes/Rewriter.h"
#include "compiler/passes/Simplify.h"

#include <iterator>
#include <unordered_map>

namespace moire::passes {

using namespace ir;

namespace {

bool isPixelInput(Op op) {
    return op == Op::PixelX || op == Op::PixelY || op == Op::ImageW || op == Op::ImageH;
}

// varying[v]: v depends on the pixel. An If or Loop is varying when anything inside it is.
// Instructions are visited in program order, a region's before the If or Loop owning it, so
// one sweep settles everything but a loop's back edges; sweeping the blocks in their
// numbering instead took a sweep per If or Loop in a chain of them (one per layer).
std::vector<bool> varyingValues(const Function& f) {
    std::vector<bool> varying(f.numValues(), false);
    bool changed = true;
    std::function<bool(BlockId)> sweep = [&](BlockId b) {
        bool any = false;
        for (const Inst& inst : f.blocks[b].insts) {
            bool v = isPixelInput(inst.op);
            for (ValueId a : inst.args) v = v || varying[a];
            for (BlockId r : inst.regions) v = sweep(r) || v;
            any = any || v;
            if (!v) continue;
            for (ValueId r : inst.results)
                if (!varying[r]) varying[r] = changed = true;
            for (BlockId r : inst.regions)
                for (ValueId p : f.blocks[r].params)
                    if (!varying[p]) varying[p] = changed = true;
        }
        return any;
    };
    while (changed) {
        changed = false;
        sweep(0);
    }
    return varying;
}

// Leaves only the frame program can evaluate.
bool isFrameLeaf(Op op) {
    return op == Op::Time || op == Op::Param;
}

bool instVarying(const Inst& inst, const std::vector<bool>& varying) {
    if (isPixelInput(inst.op) || inst.op == Op::Tally) return true; // a tally counts per pixel
    for (ValueId r : inst.results)
        if (varying[r]) return true;
    for (ValueId a : inst.args)
        if (varying[a]) return true;
    return false;
}

// Builds the kernel: the varying instructions of the entry block (with everything inside
// their regions). A non-varying value the kernel uses becomes a uniform, or a constant.
class KernelBuilder : public Rewriter {
  public:
    KernelBuilder(const Function& scene, const std::vector<bool>& varying, int numOutputs)
        : Rewriter(scene), varying_(varying) {
        dst_.name = "kernel";
        dst_.numOutputs = numOutputs;
        for (const Block& blk : scene.blocks)
            for (const Inst& inst : blk.insts)
                for (ValueId r : inst.results) def_[r] = &inst;
    }
    std::vector<ValueId> uniformSources; // scene value behind each uniform slot

  private:
    bool visit(const Inst& inst) override {
        // Fix: time and param belong to the frame program even when they are read inside a
        // varying region, where everything else is copied; they used to be copied too, and
        // no kernel can evaluate them. Skipped here, their uses import them as uniforms.
        if (isFrameLeaf(inst.op)) return true;
        if (depth_ > 0) return false; // inside a kernel region: copy everything
        if (inst.op == Op::Output) return inst.iimm >= dst_.numOutputs; // settings go to the frame
        return !instVarying(inst, varying_);
    }
    void enterRegion() override { ++depth_; }
    void leaveRegion() override { --depth_; }

    ValueId mapMissing(ValueId v) override {
        // What the kernel takes from the frame goes at the top of its entry block, so it
        // dominates every use, including uses inside regions. It is set aside here and put
        // there once, in finish(): inserting each import at the top as it came cost a copy
        // of the whole entry block per uniform, quadratic in the size of the scene.
        BlockId saved = b_.block();
        b_.setBlock(0);
        auto& entry = dst_.blocks[0].insts;
        size_t at = entry.size();
        ValueId r = importValue(v);
        std::move(entry.begin() + at, entry.end(), std::back_inserter(imports_));
        entry.erase(entry.begin() + at, entry.end());
        b_.setBlock(saved);
        return r;
    }
    void finish() override {
        auto& entry = dst_.blocks[0].insts;
        std::move(entry.begin(), entry.end(), std::back_inserter(imports_));
        entry = std::move(imports_);
    }
    ValueId importValue(ValueId v) {
        const Inst* def = def_.at(v);
        if (def->op == Op::ConstF) return b_.constF(def->imm);
        if (def->op == Op::ConstI) return b_.constI(def->iimm);
        if (def->op == Op::ConstB) return b_.constB(def->iimm != 0);
        int slot = static_cast<int>(uniformSources.size());
        uniformSources.push_back(v);
        ValueId u = b_.uniform(slot);
        Type t = src_.type(v);
        if (t == Type::B) return b_.emit(Op::Ne, {u, b_.constF(0.0)});
        if (t == Type::I) return b_.emit(Op::FToI, {u});
        return u;
    }

    const std::vector<bool>& varying_;
    std::unordered_map<ValueId, const Inst*> def_;
    int depth_ = 0;
    std::vector<Inst> imports_; // the entry block's imports, in the order they were made
};

// Builds the frame program: the non-varying instructions, then one output per uniform and
// per setting.
class FrameBuilder : public Rewriter {
  public:
    FrameBuilder(const Function& scene, const std::vector<bool>& varying, int numKernelOutputs,
                 const std::vector<ValueId>& uniforms, int firstOptional)
        : Rewriter(scene), varying_(varying), numKernelOutputs_(numKernelOutputs),
          uniforms_(uniforms), firstOptional_(firstOptional) {
        dst_.name = "frame";
        for (const Block& blk : scene.blocks)
            for (const Inst& inst : blk.insts)
                if (isFrameLeaf(inst.op)) frameLeaves_[inst.results[0]] = &inst;
    }
    int numSettings = 0;
    std::vector<int> perPixel;

  private:
    // A uniform read from a time or param leaf inside a varying region (skipped here with
    // its region): the leaf is read again in the frame program.
    ValueId mapMissing(ValueId v) override {
        auto it = frameLeaves_.find(v);
        MOIRE_CHECK(it != frameLeaves_.end(), "frame program: %{} has no mapping", v);
        return b_.emit(it->second->op, {}, it->second->imm, it->second->iimm);
    }
    bool visit(const Inst& inst) override {
        if (inst.op == Op::Output) {
            if (inst.iimm >= numKernelOutputs_) settings_.push_back(&inst);
            return true;
        }
        return instVarying(inst, varying_);
    }
    ValueId asFloat(ValueId v) {
        Type t = dst_.type(v);
        if (t == Type::B) return b_.select(v, b_.constF(1.0), b_.constF(0.0));
        if (t == Type::I) return b_.emit(Op::IToF, {v});
        return v;
    }
    void finish() override {
        int slot = 0;
        numSettings = 0;
        for (const Inst* s : settings_)
            numSettings = std::max<int>(numSettings, s->iimm - numKernelOutputs_ + 1);
        dst_.numOutputs = static_cast<int>(uniforms_.size()) + numSettings;
        for (ValueId u : uniforms_) b_.output(slot++, asFloat(map(u)));
        for (const Inst* s : settings_) {
            const int setting = s->iimm - numKernelOutputs_;
            const int at = static_cast<int>(uniforms_.size()) + setting;
            if (varying_[s->args[0]]) {
                MOIRE_CHECK(setting >= firstOptional_, "a scene setting depends on the pixel");
                perPixel.push_back(setting);
                b_.output(at, b_.constF(0.0));
                continue;
            }
            b_.output(at, map(s->args[0]));
        }
    }

    const std::vector<bool>& varying_;
    int numKernelOutputs_;
    const std::vector<ValueId>& uniforms_;
    int firstOptional_;
    std::vector<const Inst*> settings_;
    std::unordered_map<ValueId, const Inst*> frameLeaves_;
};

} // namespace

FrameSplit splitFrame(const Function& scene, int numKernelOutputs, int firstOptional) {
    std::vector<bool> varying = varyingValues(scene);
    KernelBuilder kb(scene, varying, numKernelOutputs);
    FrameSplit out;
    out.kernel = eliminateDeadCode(kb.run());
    FrameBuilder fb(scene, varying, numKernelOutputs, kb.uniformSources, firstOptional);
    out.frame = simplify(fb.run());
    out.perPixelSettings = fb.perPixel;
    out.numUniforms = static_cast<int>(kb.uniformSources.size());
    out.numSettings = fb.numSettings;
    return out;
}

} // namespace moire::passes

#include "compiler/backend/llvm/KernelChunks.h"

#include "compiler/backend/llvm/OutlineRegions.h"

#include <algorithm>

namespace moire::llvmbackend {

using ir::Inst;
using ir::ValueId;

namespace {

// An instruction's size in the chunk that holds it: an arm compiled as a function of its own
// (outlineInsts, OutlineRegions.h) is a call there.
size_t sizeOf(const ir::Function& f, const Inst& inst, size_t outlineInsts) {
    size_t n = 1;
    for (ir::BlockId r : inst.regions)
        if (inst.op != ir::Op::If || !outlinedArm(f, r, outlineInsts))
            n += ownSize(f, r, outlineInsts);
    return n;
}

template <class Fn>
void forEachArg(const ir::Function& f, const Inst& inst, Fn&& fn) {
    for (ValueId a : inst.args) fn(a);
    for (ir::BlockId r : inst.regions)
        for (const Inst& i : f.blocks[r].insts) forEachArg(f, i, fn);
}

bool isLeaf(const Inst& inst) {
    return (ir::opInfo(inst.op).flags & ir::flags::Leaf) && inst.results.size() == 1;
}

} // namespace

ChunkPlan planChunks(const ir::Function& f, size_t maxInsts, size_t outlineInsts) {
    const std::vector<Inst>& insts = f.blocks[0].insts;
    ChunkPlan plan;
    std::vector<int> chunkOf(insts.size());
    size_t size = 0;
    plan.chunks.emplace_back();
    for (size_t i = 0; i < insts.size(); ++i) {
        if (size >= maxInsts) {
            plan.chunks.back().end = i;
            plan.chunks.emplace_back();
            plan.chunks.back().begin = i;
            size = 0;
        }
        size += sizeOf(f, insts[i], outlineInsts);
        chunkOf[i] = static_cast<int>(plan.chunks.size()) - 1;
    }
    plan.chunks.back().end = insts.size();
    if (plan.chunks.size() == 1) return plan;

    // Where each entry-block value is defined, and the last chunk that reads it.
    const int none = -1;
    std::vector<int> defChunk(f.numValues(), none), lastUse(f.numValues(), none);
    std::vector<const Inst*> def(f.numValues(), nullptr);
    for (size_t i = 0; i < insts.size(); ++i)
        for (ValueId r : insts[i].results) {
            defChunk[r] = chunkOf[i];
            def[r] = &insts[i];
        }
    // Each chunk's imports, in the order first read.
    std::vector<std::vector<ValueId>> imports(plan.chunks.size());
    std::vector<int> seenIn(f.numValues(), none);
    for (size_t i = 0; i < insts.size(); ++i) {
        int c = chunkOf[i];
        forEachArg(f, insts[i], [&](ValueId a) {
            if (defChunk[a] == none || defChunk[a] == c || seenIn[a] == c) return;
            seenIn[a] = c;
            imports[c].push_back(a);
            if (!isLeaf(*def[a])) lastUse[a] = std::max(lastUse[a], c);
        });
    }
    // Slots: taken by a value in the chunk that defines it, free again after its last reader.
    std::vector<int> slotOf(f.numValues(), none), freeSlots;
    std::vector<std::vector<int>> freedAt(plan.chunks.size() + 1);
    for (size_t c = 0; c < plan.chunks.size(); ++c) {
        Chunk& chunk = plan.chunks[c];
        for (int s : freedAt[c]) freeSlots.push_back(s);
        for (ValueId a : imports[c]) {
            if (isLeaf(*def[a]))
                chunk.rematerialise.push_back(def[a]);
            else
                chunk.loads.push_back({a, slotOf[a]});
        }
        for (size_t i = chunk.begin; i < chunk.end; ++i)
            for (ValueId r : insts[i].results) {
                if (lastUse[r] == none) continue;
                int slot = freeSlots.empty() ? plan.numSlots++ : freeSlots.back();
                if (!freeSlots.empty()) freeSlots.pop_back();
                slotOf[r] = slot;
                chunk.stores[r] = slot;
                freedAt[lastUse[r] + 1].push_back(slot);
            }
    }
    return plan;
}

} // namespace moire::llvmbackend

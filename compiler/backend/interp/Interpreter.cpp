#include "compiler/backend/interp/Interpreter.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/Semantics.h"

#include <algorithm>
#include <cmath>

namespace moire {

using ir::Op;

namespace {
thread_local uint64_t tOpCount = 0;
thread_local uint64_t tTallies[ir::kMaxTallies] = {};
} // namespace

uint64_t Interpreter::lastOpCount() {
    return tOpCount;
}

uint64_t Interpreter::lastTally(int counter) {
    return counter >= 0 && counter < ir::kMaxTallies ? tTallies[counter] : 0;
}

double Interpreter::meanTally(InterpEnv env, int first, int step, int counter) const {
    std::vector<double> regs;
    double total = 0, pixels = 0;
    for (int y = first; y < env.imageH; y += step)
        for (int x = first; x < env.imageW; x += step) {
            env.pixelX = x + 0.5;
            env.pixelY = y + 0.5;
            run(env, regs);
            total += static_cast<double>(lastTally(counter));
            ++pixels;
        }
    return pixels > 0 ? total / pixels : 0.0;
}

Interpreter::Interpreter(const ir::Function& f)
    : numOutputs_(f.numOutputs), numValues_(f.numValues()) {
    blocks_.resize(f.blocks.size());
    for (size_t bi = 0; bi < f.blocks.size(); ++bi) {
        const ir::Block& b = f.blocks[bi];
        PBlock& pb = blocks_[bi];
        pb.params = b.params;
        for (const ir::Inst& inst : b.insts) {
            if (inst.op == Op::Yield) {
                pb.firstYield = static_cast<uint32_t>(argPool_.size());
                pb.numYield = static_cast<uint32_t>(inst.args.size());
                argPool_.insert(argPool_.end(), inst.args.begin(), inst.args.end());
                continue;
            }
            PInst p;
            p.op = inst.op;
            p.result = inst.results.empty() ? 0 : inst.results[0];
            if (inst.args.size() > 0) p.a = inst.args[0];
            if (inst.args.size() > 1) p.b = inst.args[1];
            if (inst.args.size() > 2) p.c = inst.args[2];
            p.imm = inst.imm;
            p.iimm = inst.iimm;
            if (inst.op == Op::If || inst.op == Op::Loop) {
                p.region0 = inst.regions[0];
                p.region1 = inst.regions[1];
                p.firstArg = static_cast<uint32_t>(argPool_.size());
                p.numArgs = static_cast<uint32_t>(inst.args.size());
                argPool_.insert(argPool_.end(), inst.args.begin(), inst.args.end());
                p.firstRes = static_cast<uint32_t>(argPool_.size());
                p.numRes = static_cast<uint32_t>(inst.results.size());
                argPool_.insert(argPool_.end(), inst.results.begin(), inst.results.end());
            }
            pb.insts.push_back(p);
        }
    }
}

std::vector<double> Interpreter::atPixel(const std::vector<double>& uniforms, double px, double py,
                                         int w, int h, double time,
                                         const std::vector<double>* params) const {
    std::vector<double> out(static_cast<size_t>(numOutputs_)), regs;
    InterpEnv env;
    env.pixelX = px;
    env.pixelY = py;
    env.imageW = w;
    env.imageH = h;
    env.time = time;
    if (params) {
        env.params = params->data();
        env.numParams = params->size();
    }
    env.uniforms = uniforms.data();
    env.numUniforms = uniforms.size();
    env.outputs = out.data();
    run(env, regs);
    return out;
}

void Interpreter::run(const InterpEnv& env, std::vector<double>& regs) const {
    if (regs.size() < numValues_) regs.resize(numValues_);
    tOpCount = 0;
    std::fill(std::begin(tTallies), std::end(tTallies), 0);
    runBlock(0, env, regs.data());
}

void Interpreter::runBlock(uint32_t id, const InterpEnv& env, double* r) const {
    const PBlock& block = blocks_[id];
    tOpCount += block.insts.size();
    for (const PInst& p : block.insts) {
        switch (p.op) {
        case Op::ConstF:
            r[p.result] = p.imm;
            break;
        case Op::ConstI: // int32, as on every other backend: the immediate's low 32 bits
            r[p.result] = static_cast<double>(static_cast<int32_t>(static_cast<uint32_t>(p.iimm)));
            break;
        case Op::ConstB:
            r[p.result] = static_cast<double>(p.iimm);
            break;
        case Op::PixelX:
            r[p.result] = env.pixelX;
            break;
        case Op::PixelY:
            r[p.result] = env.pixelY;
            break;
        case Op::ImageW:
            r[p.result] = env.imageW;
            break;
        case Op::ImageH:
            r[p.result] = env.imageH;
            break;
        case Op::Time:
            r[p.result] = env.time;
            break;
        case Op::Param:
            MOIRE_CHECK(static_cast<size_t>(p.iimm) < env.numParams, "param slot {}", p.iimm);
            r[p.result] = env.params[p.iimm];
            break;
        case Op::Uniform:
            MOIRE_CHECK(static_cast<size_t>(p.iimm) < env.numUniforms, "uniform slot {}", p.iimm);
            r[p.result] = env.uniforms[p.iimm];
            break;
        case Op::Indep:
        case Op::Detach:
            r[p.result] = r[p.a];
            break;
        case Op::DerivX:
        case Op::DerivY:
            MOIRE_ICE("derivative markers must be removed by the AD pass");
        case Op::Select:
            r[p.result] = r[p.a] != 0.0 ? r[p.b] : r[p.c];
            break;
        case Op::Lt:
            r[p.result] = r[p.a] < r[p.b];
            break;
        case Op::Le:
            r[p.result] = r[p.a] <= r[p.b];
            break;
        case Op::Gt:
            r[p.result] = r[p.a] > r[p.b];
            break;
        case Op::Ge:
            r[p.result] = r[p.a] >= r[p.b];
            break;
        case Op::Eq:
            r[p.result] = r[p.a] == r[p.b];
            break;
        case Op::Ne:
            r[p.result] = r[p.a] != r[p.b];
            break;
        case Op::And:
            r[p.result] = (r[p.a] != 0.0) && (r[p.b] != 0.0);
            break;
        case Op::Or:
            r[p.result] = (r[p.a] != 0.0) || (r[p.b] != 0.0);
            break;
        case Op::Not:
            r[p.result] = r[p.a] == 0.0;
            break;
        case Op::IAdd:
            r[p.result] =
                static_cast<int32_t>(static_cast<int64_t>(r[p.a]) + static_cast<int64_t>(r[p.b]));
            break;
        case Op::ISub:
            r[p.result] =
                static_cast<int32_t>(static_cast<int64_t>(r[p.a]) - static_cast<int64_t>(r[p.b]));
            break;
        case Op::IMul:
            r[p.result] =
                static_cast<int32_t>(static_cast<int64_t>(r[p.a]) * static_cast<int64_t>(r[p.b]));
            break;
        case Op::ILt:
            r[p.result] = r[p.a] < r[p.b];
            break;
        case Op::ILe:
            r[p.result] = r[p.a] <= r[p.b];
            break;
        case Op::IEq:
            r[p.result] = r[p.a] == r[p.b];
            break;
        case Op::FToI:
            r[p.result] = ir::semFToI(r[p.a]);
            break;
        case Op::IToF:
            r[p.result] = r[p.a];
            break;
        case Op::Output:
            MOIRE_CHECK(p.iimm < numOutputs_, "output slot");
            env.outputs[p.iimm] = r[p.a];
            break;
        case Op::Tally:
            ++tTallies[p.iimm];
            break;
        case Op::If: {
            uint32_t region = r[argPool_[p.firstArg]] != 0.0 ? p.region0 : p.region1;
            runBlock(region, env, r);
            const PBlock& b = blocks_[region];
            for (uint32_t i = 0; i < p.numRes; ++i)
                r[argPool_[p.firstRes + i]] = r[argPool_[b.firstYield + i]];
            break;
        }
        case Op::Loop: {
            const PBlock& cond = blocks_[p.region0];
            const PBlock& body = blocks_[p.region1];
            // Carried values live in the loop's result registers between iterations.
            for (uint32_t i = 0; i < p.numRes; ++i)
                r[argPool_[p.firstRes + i]] = r[argPool_[p.firstArg + i]];
            for (;;) {
                for (uint32_t i = 0; i < p.numRes; ++i)
                    r[cond.params[i]] = r[argPool_[p.firstRes + i]];
                runBlock(p.region0, env, r);
                if (r[argPool_[cond.firstYield]] == 0.0) break;
                for (uint32_t i = 0; i < p.numRes; ++i)
                    r[body.params[i]] = r[argPool_[p.firstRes + i]];
                runBlock(p.region1, env, r);
                for (uint32_t i = 0; i < p.numRes; ++i)
                    r[argPool_[p.firstRes + i]] = r[argPool_[body.firstYield + i]];
            }
            break;
        }
        case Op::Yield:
            break;
        default: {
            double a[3] = {r[p.a], r[p.b], r[p.c]};
            r[p.result] = ir::evalFloat<double>(p.op, a, p.iimm);
            break;
        }
        }
    }
}

namespace {
class InterpKernel : public CompiledKernel {
  public:
    explicit InterpKernel(const ir::Function& f) : interp_(f) {}
    int numOutputs() const override { return interp_.numOutputs(); }
    void runTile(const KernelFrame& frame, TileRect tile, float* out,
                 size_t rowStride) const override {
        std::vector<double> regs(interp_.numValues());
        std::vector<double> outputs(interp_.numOutputs());
        InterpEnv env;
        env.imageW = frame.imageW;
        env.imageH = frame.imageH;
        env.uniforms = frame.uniforms;
        env.numUniforms = SIZE_MAX;
        env.outputs = outputs.data();
        const int n = interp_.numOutputs();
        for (int y = tile.y0; y < tile.y1; ++y) {
            float* row = out + static_cast<size_t>(y - tile.y0) * rowStride;
            for (int x = tile.x0; x < tile.x1; ++x) {
                env.pixelX = x + 0.5;
                env.pixelY = y + 0.5;
                // Outputs a kernel does not write stay 0, as in the caller's buffer on the JIT.
                std::fill(outputs.begin(), outputs.end(), 0.0);
                interp_.run(env, regs);
                for (int k = 0; k < n; ++k)
                    row[(x - tile.x0) * n + k] = static_cast<float>(outputs[k]);
            }
        }
    }

  private:
    Interpreter interp_;
};
} // namespace

std::unique_ptr<CompiledKernel> InterpBackend::compile(const ir::Function& kernel) {
    return std::make_unique<InterpKernel>(kernel);
}

} // namespace moire

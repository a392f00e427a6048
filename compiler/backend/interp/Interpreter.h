// The reference interpreter: evaluates IR in double precision, op by op. It is the oracle
// the other backends are tested against, and it runs each frame's parameter program.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/ir/IR.h"

#include <cstdint>
#include <vector>

namespace moire {

struct InterpEnv {
    double pixelX = 0.0, pixelY = 0.0;
    double imageW = 0.0, imageH = 0.0;
    double time = 0.0;
    const double* params = nullptr; // literal table (Param)
    size_t numParams = 0;
    const double* uniforms = nullptr; // Uniform
    size_t numUniforms = 0;
    double* outputs = nullptr; // Output
};

class Interpreter {
  public:
    explicit Interpreter(const ir::Function& f);

    // Runs the function once. `regs` is scratch space reused across calls.
    void run(const InterpEnv& env, std::vector<double>& regs) const;
    // Runs a kernel at one pixel (its centre is (px, py)) of a w x h image with the frame's
    // uniforms, and returns its outputs. A function that still reads the clock or the
    // literal table (a scene function before the frame split) is given `time` and `params`.
    std::vector<double> atPixel(const std::vector<double>& uniforms, double px, double py, int w,
                                int h, double time = 0.0,
                                const std::vector<double>* params = nullptr) const;
    int numOutputs() const { return numOutputs_; }
    size_t numValues() const { return numValues_; }
    // Number of instructions executed by the most recent run on this thread.
    static uint64_t lastOpCount();
    // How many times `tally [counter]` ran in the most recent run on this thread.
    static uint64_t lastTally(int counter);
    // The mean of tally `counter` a pixel over every `step`-th pixel of every `step`-th row
    // from (first, first) of env's image (the benchmarks' counts of solver work).
    double meanTally(InterpEnv env, int first, int step, int counter) const;

  private:
    struct PInst {
        ir::Op op;
        uint32_t result;
        uint32_t a = 0, b = 0, c = 0;
        double imm = 0.0;
        int64_t iimm = 0;
        uint32_t region0 = 0, region1 = 0;
        uint32_t firstArg = 0, numArgs = 0; // into argPool_ (If/Loop/Yield)
        uint32_t firstRes = 0, numRes = 0;  // into argPool_ (If/Loop results)
    };
    struct PBlock {
        std::vector<PInst> insts;
        std::vector<uint32_t> params;
        uint32_t firstYield = 0, numYield = 0; // the Yield's operands, into argPool_
    };
    void runBlock(uint32_t id, const InterpEnv& env, double* r) const;

    std::vector<PBlock> blocks_;
    std::vector<uint32_t> argPool_;
    int numOutputs_ = 0;
    size_t numValues_ = 0;
};

class InterpBackend : public Backend {
  public:
    std::string name() const override { return "interp"; }
    std::unique_ptr<CompiledKernel> compile(const ir::Function& kernel) override;
};

} // namespace moire

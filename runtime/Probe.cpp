#include "runtime/Probe.h"

#include "compiler/diag/Diagnostics.h"

namespace moire {

Prober::Prober(const SceneProgram& program, Backend* backend)
    : program_(program), literals_(program.literals), frame_(program.frame) {
    MOIRE_CHECK(program.probeSlot >= 0, "the program was not compiled for probing");
    if (backend)
        compiled_ = backend->compile(program.kernel);
    else
        exact_ = std::make_unique<Interpreter>(program.kernel);
}

void Prober::setLiteral(int slot, double value) {
    MOIRE_CHECK(slot >= 0 && slot < program_.probeSlot, "literal slot {} is not a scene number",
                slot);
    literals_[slot] = value;
}

std::vector<double> Prober::at(double x, double y, double t) {
    literals_[program_.probeSlot] = x;
    literals_[program_.probeSlot + 1] = y;
    std::vector<double> frameOut(program_.frame.numOutputs);
    InterpEnv fenv;
    fenv.time = t;
    fenv.params = literals_.data();
    fenv.numParams = literals_.size();
    fenv.outputs = frameOut.data();
    frame_.run(fenv, regs_);

    // A 1x1 image: its only pixel centre maps exactly onto the camera centre, the probe point.
    const int n = program_.kernel.numOutputs;
    std::vector<double> out(n);
    if (exact_) {
        InterpEnv env;
        env.pixelX = env.pixelY = 0.5;
        env.imageW = env.imageH = 1.0;
        env.uniforms = frameOut.data();
        env.numUniforms = program_.numUniforms;
        env.outputs = out.data();
        std::vector<double> regs;
        exact_->run(env, regs);
        return out;
    }
    std::vector<float> pixel(n);
    KernelFrame kf;
    kf.uniforms = frameOut.data();
    kf.imageW = kf.imageH = 1;
    compiled_->runTile(kf, TileRect{0, 0, 1, 1}, pixel.data(), n);
    for (int i = 0; i < n; ++i) out[i] = pixel[i];
    return out;
}

} // namespace moire

// Stage (d): the lowered scene -> forward-mode AD -> simplify -> the frame/kernel split, with
// the IR verifier after each pass. Then the passes are checked to keep the meaning: on the
// interpreter, at a few pixels, the differentiated scene, its simplified form, and the frame
// program feeding the kernel all compute the same outputs.
#include "compiler/lower/LowerScene.h"
#include "compiler/passes/AutoDiff.h"
#include "compiler/passes/Simplify.h"
#include "compiler/passes/SplitFrame.h"
#include "fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace moire;
    if (size > fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::guarded("autodiff", [&] {
        auto front = fuzz::runFront(text, /*check=*/true);
        if (!front->checkedOk) return;
        fuzz::LowerSetup setup = fuzz::lowerSetup(*front, data, size);
        lower::LoweredScene scene = fuzz::lowerWith(*front, setup);
        const lower::OutputLayout& layout = scene.layout;
        ir::Function lowered = passes::simplify(scene.function);
        ir::Function derived = passes::autoDiff(lowered);
        ir::verify(derived);
        ir::Function simplified = passes::simplify(derived);
        ir::verify(simplified);
        // As Compile.cpp splits it: a checked value may depend on the pixel (it is then not
        // checked per frame, and the frame outputs 0 for it).
        passes::FrameSplit split =
            passes::splitFrame(simplified, layout.numKernelOutputs, layout.firstCheckSetting());
        ir::verify(split.frame);
        ir::verify(split.kernel);
        ir::Function kernel = passes::simplify(split.kernel);
        ir::verify(kernel);

        const int w = 8, h = 8;
        const double t = 0.75;
        const size_t nk = layout.numKernelOutputs;
        std::vector<double> frameOut =
            fuzz::interpret(split.frame, setup.literals, {}, 0.0, 0.0, w, h, t);
        if (frameOut.size() < static_cast<size_t>(split.numUniforms + split.numSettings))
            fuzz::finding("the frame program has too few outputs");
        std::vector<double> uniforms(frameOut.begin(), frameOut.begin() + split.numUniforms);
        for (auto [px, py] : {std::pair{0.5, 0.5}, {5.5, 2.5}, {7.5, 7.5}}) {
            std::vector<double> a = fuzz::interpret(derived, setup.literals, {}, px, py, w, h, t);
            std::vector<double> b =
                fuzz::interpret(simplified, setup.literals, {}, px, py, w, h, t);
            fuzz::requireSame("simplify after AD", a, b, a.size());
            std::vector<double> k = fuzz::interpret(kernel, {}, uniforms, px, py, w, h, t);
            fuzz::requireSame("frame + kernel against the scene", a, k, nk);
            std::vector<double> settings(frameOut.begin() + split.numUniforms, frameOut.end());
            std::vector<double> tail(a.begin() + nk, a.end());
            for (int s : split.perPixelSettings)
                if (static_cast<size_t>(s) < settings.size() &&
                    static_cast<size_t>(s) < tail.size())
                    settings[s] = tail[s] = 0.0;
            fuzz::requireSame("frame settings against the scene", tail, settings, tail.size());
        }
    });
    return 0;
}

// Stage (c): checked scene -> IR lowering, then the IR verifier, then the simplify passes
// (constant folding, CSE, dead code) and the verifier again. The lowering options (layer
// fields, probe, interactive, tally) are picked from the input's bytes.
#include "compiler/lower/LowerScene.h"
#include "compiler/passes/Simplify.h"
#include "fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace moire;
    if (size > fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::guarded("lower", [&] {
        auto front = fuzz::runFront(text, /*check=*/true);
        if (!front->checkedOk) return;
        fuzz::LowerSetup setup = fuzz::lowerSetup(*front, data, size);
        lower::LoweredScene lowered = fuzz::lowerWith(*front, setup);
        const lower::OutputLayout& layout = lowered.layout;
        const ir::Function& scene = lowered.function;
        ir::verify(scene);
        if (layout.numKernelOutputs > scene.numOutputs)
            fuzz::finding("the layout has more kernel outputs than the scene function");
        ir::Function simplified = passes::simplify(scene);
        ir::verify(simplified);
        if (simplified.numOutputs != scene.numOutputs)
            fuzz::finding("simplify changed the number of outputs");
    });
    return 0;
}

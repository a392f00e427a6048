// Stage (e): a compiled kernel -> GLSL -> SPIR-V through glslang -> spirv-val. glslang
// rejecting the emitted GLSL is an internal error (compileSpirv raises it); SPIR-V that
// spirv-val rejects is a finding.
#include "compiler/backend/glsl/GlslKernel.h"
#include "fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace moire;
    if (size > fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::guarded("spirv", [&] {
        CompileOptions options;
        options.layerFields = size % 2; // the viewer's and `--dump` kernels carry layer fields
        CompileResult r = compileScene("fuzz.moire", text, options);
        if (!r.program) return;
        std::vector<uint32_t> spirv = glsl::compileSpirv(r.program->kernel);
        std::string message;
        if (!glsl::validateSpirv(spirv, &message))
            fuzz::finding("spirv-val rejects the kernel: " + message + "\n" +
                          glsl::emitGlsl(r.program->kernel));
    });
    return 0;
}

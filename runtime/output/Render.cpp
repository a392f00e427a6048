#include "runtime/output/Render.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/backend/llvm/LlvmJit.h"
#include "runtime/output/JitCache.h"
#include "runtime/vulkan/VulkanBackend.h"

namespace moire {

const std::vector<std::string>& backendNames() {
    static const std::vector<std::string> names = {"jit", "interp", "vulkan"};
    return names;
}

std::unique_ptr<Backend> makeBackend(const std::string& name, const BackendOptions& options) {
    if (name == "interp") return std::make_unique<InterpBackend>();
    if (name == "jit") {
        LlvmJitBackend::Options jit;
        if (options.cacheKernels) jit.objects = JitCache::forThisBuild();
        return std::make_unique<LlvmJitBackend>(jit);
    }
    if (name == "vulkan")
        return std::make_unique<VulkanBackend>(VulkanBackend::Options{.device = options.device});
    return nullptr;
}

Image renderFrame(const SceneProgram& program, Backend& backend, const FrameValues& frame,
                  const ExecOptions& options) {
    std::unique_ptr<CompiledKernel> kernel = backend.compile(program.kernel);
    KernelFrame kf;
    kf.uniforms = frame.uniforms.data();
    kf.imageW = frame.width;
    kf.imageH = frame.height;
    return runKernel(*kernel, kf, options);
}

} // namespace moire

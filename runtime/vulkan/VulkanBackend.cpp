#include "runtime/vulkan/VulkanBackend.h"

#include "compiler/backend/glsl/GlslKernel.h"
#include "runtime/vulkan/VulkanContext.h"

#include <algorithm>
#include <fmt/format.h>
#include <mutex>
#include <unordered_map>

namespace moire {

namespace {

// A compute pipeline, destroyed with the last kernel or backend that holds it; it holds its
// context, so the device outlives every pipeline made on it.
struct Pipeline {
    std::shared_ptr<vk::Context> context;
    VkPipeline pipeline = VK_NULL_HANDLE;
    int numUniforms = 0; // uniforms the kernel reads: its largest slot + 1
    Pipeline(std::shared_ptr<vk::Context> c, VkPipeline p, int u)
        : context(std::move(c)), pipeline(p), numUniforms(u) {}
    ~Pipeline() { context->destroyPipeline(pipeline); }
    Pipeline(const Pipeline&) = delete;
    Pipeline& operator=(const Pipeline&) = delete;
};

int uniformCount(const ir::Function& f) {
    int64_t n = 0;
    for (const ir::Block& b : f.blocks)
        for (const ir::Inst& inst : b.insts)
            if (inst.op == ir::Op::Uniform) n = std::max(n, inst.iimm + 1);
    return static_cast<int>(n);
}

class VulkanKernel : public CompiledKernel {
  public:
    VulkanKernel(std::shared_ptr<const Pipeline> p, int numOutputs, const VulkanOptions& options)
        : pipeline_(std::move(p)), numOutputs_(numOutputs) {
        run_.maxChunkBytes = options.maxChunkBytes;
        run_.staged = options.staged;
    }
    int numOutputs() const override { return numOutputs_; }
    bool wholeFrame() const override { return true; }
    void runTile(const KernelFrame& frame, TileRect t, float* out,
                 size_t rowStride) const override {
        if (t.x1 <= t.x0 || t.y1 <= t.y0) return;
        // The shader computes in single precision, like the JIT: the frame program's doubles
        // are rounded once here.
        std::vector<float> uniforms(pipeline_->numUniforms);
        for (int i = 0; i < pipeline_->numUniforms; ++i)
            uniforms[i] = static_cast<float>(frame.uniforms[i]);
        pipeline_->context->run(pipeline_->pipeline, uniforms, frame.imageW, frame.imageH, t,
                                numOutputs_, out, rowStride, run_);
    }

  private:
    std::shared_ptr<const Pipeline> pipeline_;
    int numOutputs_;
    vk::RunOptions run_;
};

} // namespace

struct VulkanBackend::Impl {
    Options options;
    std::shared_ptr<vk::Context> context;
    std::mutex mutex;
    std::unordered_map<uint64_t, std::shared_ptr<const Pipeline>> cache;
    int compiled = 0;
};

VulkanBackend::VulkanBackend(const Options& options) : impl_(std::make_unique<Impl>()) {
    impl_->options = options;
    impl_->context = vk::Context::open(options.device);
}

VulkanBackend::~VulkanBackend() = default;

int VulkanBackend::compileCount() const {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    return impl_->compiled;
}

std::string VulkanBackend::deviceName() const {
    const vk::DeviceInfo& d = impl_->context->info();
    return fmt::format("device {}: {}", d.index, d.name);
}

std::unique_ptr<CompiledKernel> VulkanBackend::compile(const ir::Function& kernel) {
    const uint64_t hash = ir::structuralHash(kernel);
    std::lock_guard<std::mutex> lock(impl_->mutex);
    auto it = impl_->cache.find(hash);
    if (it == impl_->cache.end()) {
        // The SPIR-V is not kept: the pipeline (and the driver's VkPipelineCache behind it)
        // is what a second compile of the same structure would produce.
        std::vector<uint32_t> spirv = glsl::compileSpirv(kernel);
        VkPipeline p = impl_->context->createPipeline(spirv);
        auto pipeline = std::make_shared<const Pipeline>(impl_->context, p, uniformCount(kernel));
        it = impl_->cache.emplace(hash, std::move(pipeline)).first;
        ++impl_->compiled;
    }
    return std::make_unique<VulkanKernel>(it->second, kernel.numOutputs, impl_->options);
}

} // namespace moire

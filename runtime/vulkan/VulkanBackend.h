// The GPU backend: kernels compiled to SPIR-V by compiler/backend/glsl and run as Vulkan
// compute pipelines (runtime/vulkan/VulkanContext). Pipelines are cached by the kernel's
// structural hash, as the JIT caches its functions, so a scene whose numbers change (an
// animation, a slider, a parameter sweep) reuses its pipeline and only uploads new uniforms.
#pragma once

#include "compiler/backend/Backend.h"

#include <cstdint>
#include <memory>
#include <string>

namespace moire {

namespace vk {
class Context;
}

struct VulkanOptions {
    int device = -1;            // physical device index; -1: first discrete GPU, else first
    uint64_t maxChunkBytes = 0; // output bytes per dispatch; 0: the device's own budget
    // Copy each output through a host-visible buffer on the device, as a discrete GPU must,
    // even where the device's memory is the host's (lavapipe): for tests of that path.
    bool staged = false;
};

class VulkanBackend : public Backend {
  public:
    using Options = VulkanOptions;
    // Opens the device. Throws BackendError (one line) when there is no Vulkan driver, no
    // usable device, or no device `options.device`.
    explicit VulkanBackend(const Options& options = {});
    ~VulkanBackend() override;

    std::string name() const override { return "vulkan"; }
    std::unique_ptr<CompiledKernel> compile(const ir::Function& kernel) override;

    // How many kernels were actually compiled to pipelines (cache misses).
    int compileCount() const;
    // The device in use: "device N: name".
    std::string deviceName() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

} // namespace moire

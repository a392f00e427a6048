// The Vulkan executor's device side: one instance and logical device per physical device,
// shared by every backend and kernel of the process that uses that device, with the objects
// all of moire's compute shaders have in common (their descriptor set and pipeline layouts,
// a VkPipelineCache) and the buffers a dispatch streams through.
//
// The shader interface is glsl::GlslKernel.h's: binding 0 the uniforms, binding 1 the
// outputs, push constants glsl::PushConstants. Standard Vulkan 1.2 only, no extensions and no
// layers, so lavapipe (CI) and any desktop GPU driver run it alike. Every failure the user
// can meet (no loader driver, no device, a bad index, device lost, out of memory) throws
// BackendError with a one-line message; nothing here aborts.
#pragma once

#include "compiler/backend/Backend.h"
#include "runtime/vulkan/Bands.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>
#include <vulkan/vulkan.h>

namespace moire::vk {

struct DeviceInfo {
    int index = 0;
    std::string name;
    std::string type; // discrete, integrated, virtual, cpu, other
    uint32_t apiVersion = 0;
    // Vulkan 1.2 (the SPIR-V is 1.5), a compute queue, and shaderSignedZeroInfNanPreserve-
    // Float32 (the shaders declare that mode: Semantics.h defines inf, NaN and -0)
    bool usable = false;
    std::string whyNot; // when not usable
};

// The physical devices, in the loader's order. Throws BackendError when there is no Vulkan
// driver at all; an empty list means a driver but no device.
std::vector<DeviceInfo> listDevices();
// The device a render uses unless told: the first usable discrete GPU, else the first usable
// device; -1 when none is usable.
int defaultDevice(const std::vector<DeviceInfo>& devices);
std::string versionString(uint32_t apiVersion);

class Context {
  public:
    // The context of device `index` (-1: defaultDevice), opened on first use and shared while
    // anything holds it. Throws BackendError.
    static std::shared_ptr<Context> open(int index);
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    const DeviceInfo& info() const { return info_; }

    // A compute pipeline for a SPIR-V module written to GlslKernel.h's interface (through
    // the context's VkPipelineCache). Thread-safe.
    VkPipeline createPipeline(const std::vector<uint32_t>& spirv);
    void destroyPipeline(VkPipeline pipeline);

    // Runs `pipeline` over `rect` of an imageW x imageH frame and writes its numOutputs
    // floats per pixel to out[(y - rect.y0) * rowStride + (x - rect.x0) * numOutputs + k].
    // The rectangle goes in chunks (planChunks) of at most `maxChunkBytes` of output (0: the
    // device's own budget), two in flight so that one is copied out while the next runs.
    // Calls are serialised: one queue, one set of buffers.
    void run(VkPipeline pipeline, const std::vector<float>& uniforms, int imageW, int imageH,
             TileRect rect, int numOutputs, float* out, size_t rowStride,
             uint64_t maxChunkBytes = 0);

    // The chunk limits run() uses for a given budget (for tests and reports).
    ChunkLimits chunkLimits(uint64_t maxChunkBytes = 0) const;

  private:
    struct Buffer {
        VkBuffer buffer = VK_NULL_HANDLE;
        VkDeviceMemory memory = VK_NULL_HANDLE;
        VkDeviceSize size = 0;
        void* mapped = nullptr; // host-visible buffers stay mapped
        bool coherent = true;
    };
    // A chunk's resources; two of them take turns. The output always comes back through a
    // copy into host memory, even on a device whose device-local memory the CPU can read
    // (lavapipe, integrated GPUs): one path, and the one a discrete GPU needs is the one CI
    // runs. The copy costs a memcpy next to the shading.
    struct Slot {
        Buffer device;   // the shader's output buffer, device-local where there is such memory
        Buffer readback; // host-visible copy of it
        VkCommandPool pool = VK_NULL_HANDLE;
        VkCommandBuffer commands = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        VkDescriptorSet descriptors = VK_NULL_HANDLE;
        bool busy = false;
        TileRect chunk;
    };

    explicit Context(int index);
    void release();
    void createDevice();
    void createShared();
    Buffer makeBuffer(VkDeviceSize size, VkBufferUsageFlags usage, bool hostVisible);
    void freeBuffer(Buffer& b);
    void reserve(Slot& slot, VkDeviceSize bytes);
    void submit(Slot& slot, VkPipeline pipeline, const TileRect& chunk, int imageW, int imageH,
                int numOutputs);
    void finish(Slot& slot, const TileRect& rect, int numOutputs, float* out, size_t rowStride);
    void check(VkResult r, const char* what);

    DeviceInfo info_;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    VkPhysicalDeviceMemoryProperties memory_{};
    VkPhysicalDeviceLimits limits_{};
    uint64_t budget_ = 0; // default bytes per chunk buffer
    VkPipelineCache pipelineCache_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;

    std::mutex mutex_; // guards everything below, and the queue
    Buffer uniforms_;
    VkDeviceSize uniformBytes_ = 0; // of this run's uniforms
    Slot slots_[2];
    std::atomic<bool> lost_{false}; // after VK_ERROR_DEVICE_LOST every call fails at once
};

} // namespace moire::vk

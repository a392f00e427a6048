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

// Where a run()'s time went, for benchmarks: host milliseconds spent recording and
// submitting command buffers, blocked on fences, and copying results out to the caller; and,
// where the queue has timestamps, device milliseconds in the shader and in the copy to
// host-visible memory (0 when the output needs none). Summed over the run's chunks.
struct RunTimes {
    double submitMs = 0, waitMs = 0, copyOutMs = 0;
    double kernelMs = 0, deviceCopyMs = 0;
    bool deviceTimes = false; // kernelMs and deviceCopyMs were measured
    int chunks = 0;
};

struct RunOptions {
    uint64_t maxChunkBytes = 0; // output bytes per chunk; 0: the device's own budget
    // Copy the output through a host-visible buffer on the device even where the shader could
    // write into memory the host reads (Context::Slot): the path a discrete GPU takes, for
    // tests on a device that does not need it.
    bool staged = false;
    RunTimes* times = nullptr; // where the time went, when given
};

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
    // The rectangle goes in chunks (planChunks) of at most `options.maxChunkBytes` of output,
    // two in flight so that one is copied out while the next runs. Calls are serialised: one
    // queue, one set of buffers.
    void run(VkPipeline pipeline, const std::vector<float>& uniforms, int imageW, int imageH,
             TileRect rect, int numOutputs, float* out, size_t rowStride,
             const RunOptions& options = {});

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
    // A chunk's resources; two of them take turns. On a device whose own memory the host
    // reads cached (direct_: lavapipe, integrated GPUs) the shader writes into mapped memory
    // and the host copies the rows out from there; elsewhere (or when staged) the device
    // first copies the output into a host-visible buffer. (On lavapipe that copy was a tenth
    // of a simple scene's frame.)
    struct Slot {
        bool direct = false; // the buffers are direct_'s kind (no readback)
        Buffer device;       // the shader's output buffer, device-local; mapped when direct
        Buffer readback;     // host-visible copy of it; none when direct
        VkCommandPool pool = VK_NULL_HANDLE;
        VkCommandBuffer commands = VK_NULL_HANDLE;
        VkFence fence = VK_NULL_HANDLE;
        VkDescriptorSet descriptors = VK_NULL_HANDLE;
        VkQueryPool timestamps = VK_NULL_HANDLE; // three: dispatch, shader done, copy done
        bool timed = false;                      // this submission wrote them
        bool busy = false;
        TileRect chunk;
    };

    explicit Context(int index);
    void release();
    void createDevice();
    void createShared();
    enum class Memory {
        Device,   // the device's own (VRAM on a discrete GPU)
        Readback, // host-visible, cached where offered
        Shared,   // device-local, host-visible and cached: both at once (direct_)
    };
    Buffer makeBuffer(VkDeviceSize size, VkBufferUsageFlags usage, Memory kind);
    void freeBuffer(Buffer& b);
    void reserve(Slot& slot, VkDeviceSize bytes, bool direct);
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
    bool timestamps_ = false; // the compute queue writes timestamps
    bool direct_ = false;     // the shader writes into memory the host reads (Slot)
    uint64_t budget_ = 0;     // default bytes per chunk buffer
    VkPipelineCache pipelineCache_ = VK_NULL_HANDLE;
    VkDescriptorSetLayout setLayout_ = VK_NULL_HANDLE;
    VkPipelineLayout pipelineLayout_ = VK_NULL_HANDLE;
    VkDescriptorPool descriptorPool_ = VK_NULL_HANDLE;

    std::mutex mutex_; // guards everything below, and the queue
    Buffer uniforms_;
    VkDeviceSize uniformBytes_ = 0; // of this run's uniforms
    Slot slots_[2];
    RunTimes* times_ = nullptr;     // of the run in progress, when asked for
    std::atomic<bool> lost_{false}; // after VK_ERROR_DEVICE_LOST every call fails at once
};

} // namespace moire::vk

#include "runtime/vulkan/VulkanContext.h"

#include "compiler/backend/glsl/GlslKernel.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fmt/format.h>
#include <map>

namespace moire::vk {

namespace {

// A Vulkan structure, zeroed, with its type set. (Brace-initialising sType alone makes GCC's
// -Wextra name every member left out.)
template <class T>
T vkStruct(VkStructureType type) {
    T v{};
    v.sType = type;
    return v;
}

const char* resultName(VkResult r) {
    switch (r) {
    case VK_ERROR_OUT_OF_HOST_MEMORY:
        return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY:
        return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED:
        return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST:
        return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED:
        return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT:
        return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT:
        return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT:
        return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER:
        return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS:
        return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_OUT_OF_POOL_MEMORY:
        return "VK_ERROR_OUT_OF_POOL_MEMORY";
    case VK_ERROR_INVALID_SHADER_NV:
        return "VK_ERROR_INVALID_SHADER_NV";
    case VK_TIMEOUT:
        return "VK_TIMEOUT";
    default:
        return "VkResult error";
    }
}

// An instance with no layers and no extensions: compute needs neither, and a layer the user
// has not installed must not stop the render.
VkInstance createInstance() {
    auto app = vkStruct<VkApplicationInfo>(VK_STRUCTURE_TYPE_APPLICATION_INFO);
    app.pApplicationName = "moire";
    app.pEngineName = "moire";
    app.apiVersion = VK_API_VERSION_1_2;
    auto ci = vkStruct<VkInstanceCreateInfo>(VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO);
    ci.pApplicationInfo = &app;
    VkInstance instance = VK_NULL_HANDLE;
    VkResult r = vkCreateInstance(&ci, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw BackendError("no Vulkan driver found (none installed, or VK_ICD_FILENAMES / "
                           "VK_DRIVER_FILES names none that loads)");
    if (r != VK_SUCCESS)
        throw BackendError(fmt::format("cannot create a Vulkan instance ({})", resultName(r)));
    return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    VkResult r = vkEnumeratePhysicalDevices(instance, &count, nullptr);
    std::vector<VkPhysicalDevice> devices(count);
    if (r == VK_SUCCESS && count) r = vkEnumeratePhysicalDevices(instance, &count, devices.data());
    if (r != VK_SUCCESS && r != VK_INCOMPLETE)
        throw BackendError(fmt::format("cannot list the Vulkan devices ({})", resultName(r)));
    devices.resize(count);
    return devices;
}

// The first queue family that can run compute shaders, or -1.
int computeFamily(VkPhysicalDevice pd) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(pd, &count, families.data());
    for (uint32_t i = 0; i < count; ++i)
        if ((families[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && families[i].queueCount > 0)
            return static_cast<int>(i);
    return -1;
}

// The generated shaders declare SignedZeroInfNanPreserve for 32-bit floats (the emitter's
// kFloatControls): a device that does not report support for it may not run them.
bool preservesInfNan(VkPhysicalDevice pd) {
    auto fc = vkStruct<VkPhysicalDeviceFloatControlsProperties>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES);
    auto p2 = vkStruct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    p2.pNext = &fc;
    vkGetPhysicalDeviceProperties2(pd, &p2);
    return fc.shaderSignedZeroInfNanPreserveFloat32;
}

DeviceInfo describe(VkPhysicalDevice pd, int index) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(pd, &p);
    DeviceInfo d;
    d.index = index;
    d.name = p.deviceName;
    switch (p.deviceType) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        d.type = "discrete";
        break;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        d.type = "integrated";
        break;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        d.type = "virtual";
        break;
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        d.type = "cpu";
        break;
    default:
        d.type = "other";
        break;
    }
    d.apiVersion = p.apiVersion;
    if (p.apiVersion < VK_API_VERSION_1_2)
        d.whyNot =
            fmt::format("it supports Vulkan {}; moire needs 1.2", versionString(p.apiVersion));
    else if (computeFamily(pd) < 0)
        d.whyNot = "it has no compute queue";
    else if (!preservesInfNan(pd))
        d.whyNot = "its shaders cannot keep infinities, NaN and signed zeros "
                   "(shaderSignedZeroInfNanPreserveFloat32)";
    d.usable = d.whyNot.empty();
    return d;
}

// The validation layer's best-practice threshold for a buffer of its own allocation (1 MiB):
// moire has five buffers a device, so it allocates each at least that large rather than
// sub-allocating.
constexpr VkDeviceSize kMinAllocation = 1 << 20;

constexpr VkMemoryPropertyFlags kSharedMemory = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT |
                                                VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                                VK_MEMORY_PROPERTY_HOST_CACHED_BIT;

struct InstanceGuard {
    VkInstance instance;
    ~InstanceGuard() { vkDestroyInstance(instance, nullptr); }
};

// A memory type allowed by `bits` with all of `flags`, or -1.
int memoryType(const VkPhysicalDeviceMemoryProperties& m, uint32_t bits,
               VkMemoryPropertyFlags flags) {
    for (uint32_t i = 0; i < m.memoryTypeCount; ++i)
        if ((bits & (1u << i)) && (m.memoryTypes[i].propertyFlags & flags) == flags)
            return static_cast<int>(i);
    return -1;
}

} // namespace

std::string versionString(uint32_t v) {
    return fmt::format("{}.{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v),
                       VK_API_VERSION_PATCH(v));
}

std::vector<DeviceInfo> listDevices() {
    InstanceGuard guard{createInstance()};
    std::vector<DeviceInfo> out;
    std::vector<VkPhysicalDevice> devices = physicalDevices(guard.instance);
    for (size_t i = 0; i < devices.size(); ++i)
        out.push_back(describe(devices[i], static_cast<int>(i)));
    return out;
}

int defaultDevice(const std::vector<DeviceInfo>& devices) {
    for (const DeviceInfo& d : devices)
        if (d.usable && d.type == "discrete") return d.index;
    for (const DeviceInfo& d : devices)
        if (d.usable) return d.index;
    return -1;
}

std::shared_ptr<Context> Context::open(int index) {
    // Weak references: a context lives while a backend or kernel holds it and is torn down
    // with the last of them, never by static destructors racing the driver's own at exit.
    static std::mutex mutex;
    static std::map<int, std::weak_ptr<Context>> contexts;
    std::lock_guard<std::mutex> lock(mutex);
    if (auto c = contexts[index].lock()) return c;
    std::shared_ptr<Context> c(new Context(index));
    contexts[index] = c;
    return c;
}

Context::Context(int index) {
    try {
        instance_ = createInstance();
        std::vector<VkPhysicalDevice> devices = physicalDevices(instance_);
        if (devices.empty()) throw BackendError("no Vulkan device found (the driver lists none)");
        std::vector<DeviceInfo> infos;
        for (size_t i = 0; i < devices.size(); ++i)
            infos.push_back(describe(devices[i], static_cast<int>(i)));
        if (index < 0) {
            index = defaultDevice(infos);
            if (index < 0)
                throw BackendError(fmt::format(
                    "no Vulkan device here can run moire: device 0 ({}): {}{}", infos[0].name,
                    infos[0].whyNot, infos.size() > 1 ? " (see 'moire devices')" : ""));
        }
        if (index >= static_cast<int>(devices.size()))
            throw BackendError(fmt::format(
                "there is no Vulkan device {}: this machine has {} ({}; see 'moire devices')",
                index, devices.size(),
                devices.size() == 1 ? std::string("device 0")
                                    : fmt::format("devices 0 to {}", devices.size() - 1)));
        info_ = infos[index];
        if (!info_.usable)
            throw BackendError(fmt::format("Vulkan device {} ({}) cannot run moire: {}", index,
                                           info_.name, info_.whyNot));
        physical_ = devices[index];
        createDevice();
        createShared();
    } catch (...) {
        release(); // whatever was created so far (null handles are skipped)
        throw;
    }
}

Context::~Context() {
    release();
}

void Context::release() {
    if (device_) {
        vkDeviceWaitIdle(device_);
        for (Slot& s : slots_) {
            freeBuffer(s.device);
            freeBuffer(s.readback);
            if (s.fence) vkDestroyFence(device_, s.fence, nullptr);
            if (s.timestamps) vkDestroyQueryPool(device_, s.timestamps, nullptr);
            s.timestamps = VK_NULL_HANDLE;
            // Destroying the pool frees the command buffer taken from it.
            if (s.pool) vkDestroyCommandPool(device_, s.pool, nullptr);
            s.fence = VK_NULL_HANDLE, s.pool = VK_NULL_HANDLE, s.commands = VK_NULL_HANDLE;
        }
        freeBuffer(uniforms_);
        // Destroying the pool frees the descriptor sets taken from it.
        if (descriptorPool_) vkDestroyDescriptorPool(device_, descriptorPool_, nullptr);
        if (pipelineLayout_) vkDestroyPipelineLayout(device_, pipelineLayout_, nullptr);
        if (setLayout_) vkDestroyDescriptorSetLayout(device_, setLayout_, nullptr);
        if (pipelineCache_) vkDestroyPipelineCache(device_, pipelineCache_, nullptr);
        vkDestroyDevice(device_, nullptr);
    }
    if (instance_) vkDestroyInstance(instance_, nullptr);
    descriptorPool_ = VK_NULL_HANDLE;
    pipelineLayout_ = VK_NULL_HANDLE, setLayout_ = VK_NULL_HANDLE;
    pipelineCache_ = VK_NULL_HANDLE, device_ = VK_NULL_HANDLE, instance_ = VK_NULL_HANDLE;
}

void Context::check(VkResult r, const char* what) {
    if (r == VK_SUCCESS) return;
    if (r == VK_ERROR_DEVICE_LOST) {
        lost_ = true;
        throw BackendError(
            fmt::format("the Vulkan device {} ({}) was lost: {}", info_.index, info_.name, what));
    }
    if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
        throw BackendError(
            fmt::format("Vulkan device {} ({}) is out of {} memory: {}", info_.index, info_.name,
                        r == VK_ERROR_OUT_OF_DEVICE_MEMORY ? "device" : "host", what));
    throw BackendError(fmt::format("Vulkan: {} failed ({})", what, resultName(r)));
}

void Context::createDevice() {
    queueFamily_ = static_cast<uint32_t>(computeFamily(physical_));
    const float priority = 1.0f;
    auto qci = vkStruct<VkDeviceQueueCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO);
    qci.queueFamilyIndex = queueFamily_;
    qci.queueCount = 1;
    qci.pQueuePriorities = &priority;
    auto dci = vkStruct<VkDeviceCreateInfo>(VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO);
    dci.queueCreateInfoCount = 1;
    dci.pQueueCreateInfos = &qci;
    check(vkCreateDevice(physical_, &dci, nullptr, &device_), "creating the logical device");
    vkGetDeviceQueue(device_, queueFamily_, 0, &queue_);
    uint32_t familyCount = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, nullptr);
    std::vector<VkQueueFamilyProperties> families(familyCount);
    vkGetPhysicalDeviceQueueFamilyProperties(physical_, &familyCount, families.data());
    timestamps_ = families[queueFamily_].timestampValidBits > 0;

    auto m3 = vkStruct<VkPhysicalDeviceMaintenance3Properties>(
        VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES);
    auto p2 = vkStruct<VkPhysicalDeviceProperties2>(VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2);
    p2.pNext = &m3;
    vkGetPhysicalDeviceProperties2(physical_, &p2);
    limits_ = p2.properties.limits;
    vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    uint64_t deviceHeap = 0, hostHeap = 0;
    for (uint32_t i = 0; i < memory_.memoryTypeCount; ++i) {
        uint64_t heap = memory_.memoryHeaps[memory_.memoryTypes[i].heapIndex].size;
        VkMemoryPropertyFlags f = memory_.memoryTypes[i].propertyFlags;
        if (f & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT) deviceHeap = std::max(deviceHeap, heap);
        if (f & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) hostHeap = std::max(hostHeap, heap);
    }
    if (!deviceHeap) deviceHeap = hostHeap;
    // Where the device's own memory is also the host's, cached (lavapipe, most integrated
    // GPUs), the shader writes its output straight into memory the host reads: no copy on
    // the device, and no second buffer. (Not for a discrete GPU's host-visible VRAM: host
    // reads of it are uncached and slow.)
    direct_ = memoryType(memory_, ~0u, kSharedMemory) >= 0;
    // 64 MiB a chunk (4M pixels of RGBA): large enough that a submission's fixed cost vanishes
    // in its work, small enough that the two slots' buffers (4 x 64 MiB at most) fit any
    // device and host beside what else runs there; never above what the device can bind.
    budget_ = std::min<uint64_t>({uint64_t{64} << 20, limits_.maxStorageBufferRange,
                                  m3.maxMemoryAllocationSize, deviceHeap / 16, hostHeap / 16});
}

void Context::createShared() {
    auto pcci = vkStruct<VkPipelineCacheCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO);
    check(vkCreatePipelineCache(device_, &pcci, nullptr, &pipelineCache_),
          "creating a pipeline cache");

    VkDescriptorSetLayoutBinding bindings[2] = {};
    for (uint32_t i = 0; i < 2; ++i) {
        bindings[i].binding = i;
        bindings[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        bindings[i].descriptorCount = 1;
        bindings[i].stageFlags = VK_SHADER_STAGE_COMPUTE_BIT;
    }
    auto slci = vkStruct<VkDescriptorSetLayoutCreateInfo>(
        VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO);
    slci.bindingCount = 2;
    slci.pBindings = bindings;
    check(vkCreateDescriptorSetLayout(device_, &slci, nullptr, &setLayout_),
          "creating the descriptor set layout");

    VkPushConstantRange push{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(glsl::PushConstants)};
    auto plci = vkStruct<VkPipelineLayoutCreateInfo>(VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO);
    plci.setLayoutCount = 1;
    plci.pSetLayouts = &setLayout_;
    plci.pushConstantRangeCount = 1;
    plci.pPushConstantRanges = &push;
    check(vkCreatePipelineLayout(device_, &plci, nullptr, &pipelineLayout_),
          "creating the pipeline layout");

    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 4};
    auto dpci = vkStruct<VkDescriptorPoolCreateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO);
    dpci.maxSets = 2;
    dpci.poolSizeCount = 1;
    dpci.pPoolSizes = &size;
    check(vkCreateDescriptorPool(device_, &dpci, nullptr, &descriptorPool_),
          "creating a descriptor pool");

    for (Slot& s : slots_) {
        auto dsai =
            vkStruct<VkDescriptorSetAllocateInfo>(VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO);
        dsai.descriptorPool = descriptorPool_;
        dsai.descriptorSetCount = 1;
        dsai.pSetLayouts = &setLayout_;
        check(vkAllocateDescriptorSets(device_, &dsai, &s.descriptors), "allocating descriptors");
        // A pool per slot, reset whole before each recording (cheaper than resetting
        // single command buffers, which needs a pool that tracks them one by one).
        auto cpci = vkStruct<VkCommandPoolCreateInfo>(VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO);
        cpci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
        cpci.queueFamilyIndex = queueFamily_;
        check(vkCreateCommandPool(device_, &cpci, nullptr, &s.pool), "creating a command pool");
        auto cbai =
            vkStruct<VkCommandBufferAllocateInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO);
        cbai.commandPool = s.pool;
        cbai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        cbai.commandBufferCount = 1;
        check(vkAllocateCommandBuffers(device_, &cbai, &s.commands), "allocating commands");
        auto fci = vkStruct<VkFenceCreateInfo>(VK_STRUCTURE_TYPE_FENCE_CREATE_INFO);
        check(vkCreateFence(device_, &fci, nullptr, &s.fence), "creating a fence");
        if (timestamps_) {
            auto qpci = vkStruct<VkQueryPoolCreateInfo>(VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO);
            qpci.queryType = VK_QUERY_TYPE_TIMESTAMP;
            qpci.queryCount = 3;
            check(vkCreateQueryPool(device_, &qpci, nullptr, &s.timestamps),
                  "creating a query pool");
        }
    }
}

ChunkLimits Context::chunkLimits(uint64_t maxChunkBytes) const {
    ChunkLimits l;
    l.maxBytes = maxChunkBytes ? std::min(maxChunkBytes, budget_) : budget_;
    l.maxGroupsX = limits_.maxComputeWorkGroupCount[0];
    l.maxGroupsY = limits_.maxComputeWorkGroupCount[1];
    l.localX = glsl::kLocalSizeX;
    l.localY = glsl::kLocalSizeY;
    return l;
}

VkPipeline Context::createPipeline(const std::vector<uint32_t>& spirv) {
    auto smci = vkStruct<VkShaderModuleCreateInfo>(VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO);
    smci.codeSize = spirv.size() * sizeof(uint32_t);
    smci.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    check(vkCreateShaderModule(device_, &smci, nullptr, &module), "creating a shader module");
    auto pci =
        vkStruct<VkComputePipelineCreateInfo>(VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO);
    pci.stage.sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    pci.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pci.stage.module = module;
    pci.stage.pName = "main";
    pci.layout = pipelineLayout_;
    VkPipeline pipeline = VK_NULL_HANDLE;
    VkResult r = vkCreateComputePipelines(device_, pipelineCache_, 1, &pci, nullptr, &pipeline);
    vkDestroyShaderModule(device_, module, nullptr);
    check(r, "creating a compute pipeline");
    return pipeline;
}

void Context::destroyPipeline(VkPipeline pipeline) {
    // A run() that used it has returned, and run() waits for its work: nothing is in flight.
    std::lock_guard<std::mutex> lock(mutex_);
    vkDestroyPipeline(device_, pipeline, nullptr);
}

Context::Buffer Context::makeBuffer(VkDeviceSize size, VkBufferUsageFlags usage, Memory kind) {
    const bool hostVisible = kind != Memory::Device;
    Buffer b;
    b.size = size;
    auto bci = vkStruct<VkBufferCreateInfo>(VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO);
    bci.size = size;
    bci.usage = usage;
    bci.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
    check(vkCreateBuffer(device_, &bci, nullptr, &b.buffer), "creating a buffer");
    try {
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(device_, b.buffer, &req);
        // Readback wants memory the CPU reads fast (cached); the shader's own buffer wants
        // device-local memory (VRAM on a discrete GPU; everything is, on lavapipe).
        int type = -1;
        if (kind == Memory::Shared) {
            type = memoryType(memory_, req.memoryTypeBits, kSharedMemory);
        } else if (hostVisible) {
            type = memoryType(memory_, req.memoryTypeBits,
                              VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT |
                                  VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
            if (type < 0)
                type = memoryType(memory_, req.memoryTypeBits, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
        } else {
            type = memoryType(memory_, req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
            if (type < 0) type = memoryType(memory_, req.memoryTypeBits, 0);
        }
        if (type < 0) throw BackendError("Vulkan: the device offers no memory for a buffer");
        b.coherent = memory_.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        auto mai = vkStruct<VkMemoryAllocateInfo>(VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO);
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = static_cast<uint32_t>(type);
        std::string what = fmt::format("allocating {:.1f} MiB", size / 1048576.0);
        check(vkAllocateMemory(device_, &mai, nullptr, &b.memory), what.c_str());
        check(vkBindBufferMemory(device_, b.buffer, b.memory, 0), "binding buffer memory");
        if (hostVisible)
            check(vkMapMemory(device_, b.memory, 0, VK_WHOLE_SIZE, 0, &b.mapped), "mapping memory");
    } catch (...) {
        freeBuffer(b);
        throw;
    }
    return b;
}

void Context::freeBuffer(Buffer& b) {
    if (b.buffer) vkDestroyBuffer(device_, b.buffer, nullptr);
    if (b.memory) vkFreeMemory(device_, b.memory, nullptr); // unmaps too
    b = Buffer{};
}

void Context::reserve(Slot& slot, VkDeviceSize bytes, bool direct) {
    if (slot.direct == direct && slot.device.size >= bytes &&
        (direct || slot.readback.size >= bytes))
        return;
    freeBuffer(slot.device);
    freeBuffer(slot.readback);
    slot.direct = direct;
    // A run's first chunk is its largest, so one allocation serves the whole run. The floor
    // keeps small renders and 1 x 1 probes from reallocating as their output count varies.
    VkDeviceSize size = std::max<VkDeviceSize>(bytes, kMinAllocation);
    if (direct) {
        slot.device = makeBuffer(size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Memory::Shared);
        return;
    }
    slot.device =
        makeBuffer(size, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                   Memory::Device);
    slot.readback = makeBuffer(size, VK_BUFFER_USAGE_TRANSFER_DST_BIT, Memory::Readback);
}

void Context::submit(Slot& slot, VkPipeline pipeline, const TileRect& chunk, int imageW, int imageH,
                     int numOutputs) {
    const int w = chunk.x1 - chunk.x0, h = chunk.y1 - chunk.y0;
    const VkDeviceSize bytes = static_cast<VkDeviceSize>(w) * h * numOutputs * sizeof(float);
    VkDescriptorBufferInfo uniforms{uniforms_.buffer, 0, uniformBytes_};
    VkDescriptorBufferInfo outputs{slot.device.buffer, 0, bytes};
    VkWriteDescriptorSet writes[2] = {};
    for (int i = 0; i < 2; ++i) {
        writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
        writes[i].dstSet = slot.descriptors;
        writes[i].dstBinding = static_cast<uint32_t>(i);
        writes[i].descriptorCount = 1;
        writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
        writes[i].pBufferInfo = i == 0 ? &uniforms : &outputs;
    }
    // The slot's last submission has completed (its fence was waited for), so its set and
    // command buffer are free to rewrite.
    vkUpdateDescriptorSets(device_, 2, writes, 0, nullptr);

    VkCommandBuffer cb = slot.commands;
    check(vkResetCommandPool(device_, slot.pool, 0), "resetting a command pool");
    auto begin = vkStruct<VkCommandBufferBeginInfo>(VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO);
    begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vkBeginCommandBuffer(cb, &begin), "recording commands");
    slot.timed = times_ && slot.timestamps;
    if (slot.timed) {
        vkCmdResetQueryPool(cb, slot.timestamps, 0, 3);
        vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, slot.timestamps, 0);
    }
    vkCmdBindPipeline(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
    vkCmdBindDescriptorSets(cb, VK_PIPELINE_BIND_POINT_COMPUTE, pipelineLayout_, 0, 1,
                            &slot.descriptors, 0, nullptr);
    glsl::PushConstants pc{imageW, imageH, chunk.x0, chunk.y0, w, h};
    vkCmdPushConstants(cb, pipelineLayout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof pc, &pc);
    vkCmdDispatch(cb, (w + glsl::kLocalSizeX - 1) / glsl::kLocalSizeX,
                  (h + glsl::kLocalSizeY - 1) / glsl::kLocalSizeY, 1);
    if (slot.timed)
        vkCmdWriteTimestamp(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, slot.timestamps, 1);
    // The shader's writes, then (on a device with memory of its own) the copy to host-visible
    // memory, then the host's reads.
    auto barrier = vkStruct<VkBufferMemoryBarrier>(VK_STRUCTURE_TYPE_BUFFER_MEMORY_BARRIER);
    barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    barrier.size = bytes;
    barrier.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
    barrier.buffer = slot.device.buffer;
    VkPipelineStageFlagBits written = VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT;
    if (!slot.direct) {
        barrier.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
        vkCmdPipelineBarrier(cb, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                             VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 1, &barrier, 0,
                             nullptr);
        VkBufferCopy region{0, 0, bytes};
        vkCmdCopyBuffer(cb, slot.device.buffer, slot.readback.buffer, 1, &region);
        barrier.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        barrier.buffer = slot.readback.buffer;
        written = VK_PIPELINE_STAGE_TRANSFER_BIT;
    }
    if (slot.timed) vkCmdWriteTimestamp(cb, written, slot.timestamps, 2);
    barrier.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
    vkCmdPipelineBarrier(cb, written, VK_PIPELINE_STAGE_HOST_BIT, 0, 0, nullptr, 1, &barrier, 0,
                         nullptr);
    check(vkEndCommandBuffer(cb), "recording commands");

    check(vkResetFences(device_, 1, &slot.fence), "resetting a fence");
    auto si = vkStruct<VkSubmitInfo>(VK_STRUCTURE_TYPE_SUBMIT_INFO);
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cb;
    check(vkQueueSubmit(queue_, 1, &si, slot.fence), "submitting a dispatch");
    slot.busy = true;
    slot.chunk = chunk;
}

void Context::finish(Slot& slot, const TileRect& rect, int numOutputs, float* out,
                     size_t rowStride) {
    // No timeout: a large chunk of an expensive scene on a CPU device legitimately takes long,
    // and work still in flight could not be abandoned safely anyway.
    auto t0 = std::chrono::steady_clock::now();
    check(vkWaitForFences(device_, 1, &slot.fence, VK_TRUE, UINT64_MAX), "running a dispatch");
    slot.busy = false;
    auto t1 = std::chrono::steady_clock::now();
    if (slot.timed) {
        uint64_t ticks[3];
        check(vkGetQueryPoolResults(device_, slot.timestamps, 0, 3, sizeof ticks, ticks,
                                    sizeof(uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
              "reading timestamps");
        const double msPerTick = limits_.timestampPeriod / 1e6;
        times_->kernelMs += (ticks[1] - ticks[0]) * msPerTick;
        times_->deviceCopyMs += (ticks[2] - ticks[1]) * msPerTick;
        times_->deviceTimes = true;
    }
    const Buffer& result = slot.direct ? slot.device : slot.readback;
    if (!result.coherent) {
        auto range = vkStruct<VkMappedMemoryRange>(VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE);
        range.memory = result.memory;
        range.size = VK_WHOLE_SIZE;
        check(vkInvalidateMappedMemoryRanges(device_, 1, &range), "reading back");
    }
    const TileRect& c = slot.chunk;
    const size_t rowFloats = static_cast<size_t>(c.x1 - c.x0) * numOutputs;
    const float* src = static_cast<const float*>(result.mapped);
    for (int y = c.y0; y < c.y1; ++y)
        std::memcpy(out + static_cast<size_t>(y - rect.y0) * rowStride +
                        static_cast<size_t>(c.x0 - rect.x0) * numOutputs,
                    src + static_cast<size_t>(y - c.y0) * rowFloats, rowFloats * sizeof(float));
    if (times_) {
        auto t2 = std::chrono::steady_clock::now();
        times_->waitMs += std::chrono::duration<double, std::milli>(t1 - t0).count();
        times_->copyOutMs += std::chrono::duration<double, std::milli>(t2 - t1).count();
    }
}

void Context::run(VkPipeline pipeline, const std::vector<float>& uniforms, int imageW, int imageH,
                  TileRect rect, int numOutputs, float* out, size_t rowStride,
                  const RunOptions& options) {
    std::lock_guard<std::mutex> lock(mutex_);
    RunTimes* const times = options.times;
    struct Clear {
        RunTimes*& times;
        ~Clear() { times = nullptr; }
    } clear{times_};
    times_ = times;
    const bool direct = direct_ && !options.staged;
    if (lost_)
        throw BackendError(
            fmt::format("the Vulkan device {} ({}) was lost earlier", info_.index, info_.name));
    const std::vector<TileRect> chunks =
        planChunks(rect, numOutputs, chunkLimits(options.maxChunkBytes));
    if (chunks.empty()) return;

    // A zero-sized buffer is not allowed: a kernel without uniforms still binds one float.
    uniformBytes_ = std::max<size_t>(uniforms.size(), 1) * sizeof(float);
    if (uniformBytes_ > limits_.maxStorageBufferRange)
        throw BackendError(fmt::format("the scene's {} uniforms exceed the device's storage "
                                       "buffer limit of {} bytes",
                                       uniforms.size(), limits_.maxStorageBufferRange));
    if (uniforms_.size < uniformBytes_) {
        freeBuffer(uniforms_);
        uniforms_ = makeBuffer(std::max<VkDeviceSize>(uniformBytes_, kMinAllocation),
                               VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Memory::Readback);
    }
    // Nothing is in flight between runs, so the buffer is free to overwrite.
    std::memset(uniforms_.mapped, 0, uniformBytes_);
    if (!uniforms.empty())
        std::memcpy(uniforms_.mapped, uniforms.data(), uniforms.size() * sizeof(float));
    if (!uniforms_.coherent) {
        auto range = vkStruct<VkMappedMemoryRange>(VK_STRUCTURE_TYPE_MAPPED_MEMORY_RANGE);
        range.memory = uniforms_.memory;
        range.size = VK_WHOLE_SIZE;
        check(vkFlushMappedMemoryRanges(device_, 1, &range), "writing uniforms");
    }

    try {
        // Two slots in turn: chunk i runs while chunk i - 1 is copied into `out`.
        for (size_t i = 0; i < chunks.size(); ++i) {
            Slot& slot = slots_[i % 2];
            if (slot.busy) finish(slot, rect, numOutputs, out, rowStride);
            const TileRect& c = chunks[i];
            reserve(slot,
                    static_cast<VkDeviceSize>(c.x1 - c.x0) * (c.y1 - c.y0) * numOutputs *
                        sizeof(float),
                    direct);
            auto t0 = std::chrono::steady_clock::now();
            submit(slot, pipeline, c, imageW, imageH, numOutputs);
            if (times) {
                times->submitMs +=
                    std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                        .count();
                ++times->chunks;
            }
        }
        for (size_t i = chunks.size() >= 2 ? chunks.size() - 2 : 0; i < chunks.size(); ++i)
            if (slots_[i % 2].busy) finish(slots_[i % 2], rect, numOutputs, out, rowStride);
    } catch (...) {
        // Nothing may still be running into these buffers (or be copied to `out`) once the
        // caller sees the error.
        vkQueueWaitIdle(queue_);
        for (Slot& s : slots_) s.busy = false;
        throw;
    }
}

} // namespace moire::vk

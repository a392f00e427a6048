// `moire view`: picks the backend (Vulkan on a hardware GPU, else the JIT) and opens the
// viewer (runtime/view/Viewer.h).
#include "runtime/cli/Commands.h"
#include "runtime/cli/Shared.h"
#include "runtime/FrameEval.h"
#include "runtime/output/Render.h"
#include "runtime/view/Viewer.h"
#include "runtime/vulkan/VulkanBackend.h"
#include "runtime/vulkan/VulkanContext.h"

#include <algorithm>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace moire::cli {

namespace {

// The first usable hardware GPU: discrete, then integrated, then a virtual one (a VM's GPU).
// Lavapipe (type "cpu") is Vulkan on the CPU, which the JIT beats on the same cores. -1 when
// there is none, or no Vulkan at all.
int hardwareGpu() {
    try {
        const std::vector<vk::DeviceInfo> devices = vk::listDevices();
        for (const char* type : {"discrete", "integrated", "virtual"})
            for (const vk::DeviceInfo& d : devices)
                if (d.usable && d.type == type) return d.index;
    } catch (const BackendError&) {
    }
    return -1;
}

} // namespace

int view(const ViewArgs& args) {
    if (args.scene == kStdinPath) {
        fmt::print(stderr, "moire: error: view follows a scene file as it is saved; standard "
                           "input ('-') cannot be watched\n");
        return kExitUsage;
    }
    if (!checkTime(args.time, "--time")) return kExitUsage;
    int w = 0, h = 0;
    if (!args.size.empty() && !parseSize(args.size, w, h, kMaxFrameSide)) {
        fmt::print(stderr,
                   "moire: error: --size must be WIDTHxHEIGHT in screen units (1 to {}), not "
                   "'{}'\n",
                   kMaxFrameSide, args.size);
        return kExitUsage;
    }
    if (!checkBackendArgs(args.backend, args.device)) return kExitUsage;
    CompileOptions filter;
    if (!checkFilterOption(args.filter, filter)) return kExitUsage;
    if (w > 0) {
        // Without --size the window opens at most the screen's size.
        FrameFootprint footprint;
        footprint.width = w;
        footprint.height = h;
        footprint.sink = FrameSink::Window;
        if (!checkMemory(footprint)) return kExitMachine;
    }

    std::unique_ptr<Backend> backend;
    if (args.backend.empty() && args.device < 0) {
        if (int gpu = hardwareGpu(); gpu >= 0) {
            try {
                backend = makeBackend("vulkan", BackendOptions{.device = gpu});
            } catch (const BackendError& e) {
                if (!args.verbosity.quiet)
                    fmt::print(stderr, "moire: note: {}; drawing with the JIT\n", e.what());
            }
        }
        if (!backend) backend = openBackend("jit", -1);
    } else {
        backend = openBackend(args.backend.empty() ? "vulkan" : args.backend, args.device);
    }
    if (!backend) return kExitMachine;
    if (args.verbosity.verbose)
        fmt::print(stderr, "moire: view: drawing with {}{}\n", describe(*backend),
                   args.backend.empty()
                       ? " (chosen: a hardware GPU when there is one, else the JIT)"
                       : "");

    view::ViewerOptions options;
    options.scenePath = args.scene;
    options.width = w;
    options.height = h;
    options.time = args.time;
    options.defines = args.defines;
    options.filter = filter.filter;
    options.paused = args.paused;
    options.threads = args.threads;
    options.debounceMs = args.debounceMs;
    options.trace = args.trace;
    options.backendLabel = backend->name();
    if (auto* vk = dynamic_cast<VulkanBackend*>(backend.get())) {
        // "device N: name" -> "vulkan: name"
        std::string device = vk->deviceName();
        size_t colon = device.find(": ");
        options.backendLabel +=
            ": " + (colon == std::string::npos ? device : device.substr(colon + 2));
    }
    return view::runViewer(*backend, options);
}

} // namespace moire::cli

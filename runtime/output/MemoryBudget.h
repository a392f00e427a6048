// How much memory a render will take, and how much this process may have: checked before a
// frame is started, so that a size too large for the machine is refused with the figure
// instead of ending in an allocation failure or the kernel's out-of-memory killer part way
// through (a 32768x32768 frame is 17 GB of float pixels before it is written).
#pragma once

#include "runtime/output/ImageIO.h"

#include <cstdint>
#include <optional>
#include <string>

namespace moire {

// Where the pixels of a frame go, which decides the buffers beside the frame itself.
enum class FrameSink {
    ImageFile, // writeImage: a float copy of the picture in the file's channels
    Video,     // ffmpeg's pipe: one 8-bit RGBA frame
    Window,    // the viewer: 8-bit copies for the window, the last frame and the texture
    // render's image, streamed band by band (runKernelInBands into an ImageStream): no frame,
    // a step of floats a worker, the bands waiting for those above them, the encoder's
    // buffers (imageStreamBytes), and, to standard output, the compressed file
    Streamed,
};

struct FrameFootprint {
    int width = 0, height = 0;
    int channels = 4; // the kernel's outputs a pixel (RGBA, more with layer fields)
    FrameSink sink = FrameSink::ImageFile;
    std::string format = "png"; // ImageFile: imageFormatOf(the output)
    // Frames held while the next one renders (clip: the writes in flight), each with its own
    // writer's buffers.
    int queued = 0;
    bool gpu = false;                       // the Vulkan executor: its staging buffers
    int threads = 0;                        // Streamed: the workers (0: one per hardware thread)
    PixelDepth depth = PixelDepth::Default; // Streamed: the file's samples
    bool streamed = false; // Streamed: written to a file as the bands come (not assembled)
};

// An upper bound, in bytes, of the memory the process holds at its peak while rendering and
// writing the frame described: the process itself (the JIT, the libraries) and every buffer
// that scales with the frame.
uint64_t estimateFrameBytes(const FrameFootprint& frame);

struct MemoryAvailable {
    uint64_t bytes = 0;
    std::string limit; // what sets it: "" (memory free for use), or the limit's name
};

// The memory this process can still take: the kernel's MemAvailable, lowered by the address
// space and data limits (ulimit -v, -d) less what is already mapped, and by every enclosing
// cgroup's limit less its use (v2 memory.max, v1 memory.limit_in_bytes). Empty when none of
// them can be read.
std::optional<MemoryAvailable> availableMemory();

// "about 21.5 GB", "about 512 MB": decimal units, as the system's tools print them.
std::string formatBytes(uint64_t bytes);

// Empty when the frame fits in what is available (or nothing could be learned about it);
// else the error to print: "a 32768x32768 image needs about 34.4 GB of memory; this machine
// has 18.2 GB available".
std::string memoryProblem(const FrameFootprint& frame);

} // namespace moire

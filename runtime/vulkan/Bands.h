// Splitting one dispatch into chunks a Vulkan device can take. A print-size frame (7200 x
// 4800 pixels, 4 floats each: 553 MB) exceeds every device's maxStorageBufferRange (128 MiB
// on lavapipe, 4 GiB at most anywhere) and is more than a renderer should hold on the device
// at once, so the executor runs it in rectangles whose output buffer fits a byte budget and
// whose workgroup counts fit maxComputeWorkGroupCount. Pure arithmetic, unit-tested without
// a device (Bands_test.cpp).
#pragma once

#include "compiler/backend/Backend.h"

#include <cstdint>
#include <vector>

namespace moire::vk {

struct ChunkLimits {
    uint64_t maxBytes = 0;                   // output bytes one chunk may fill
    uint32_t maxGroupsX = 0, maxGroupsY = 0; // maxComputeWorkGroupCount[0], [1]
    uint32_t localX = 8, localY = 8;         // the shader's local size
};

// Covers `rect` exactly once with chunks in row-major order (so consecutive chunks fill
// consecutive image rows). Each chunk is as wide as the limits allow, then as tall: whole
// rows where they fit, so a chunk's output is one contiguous run per row. Throws
// BackendError if not even one pixel fits (a budget below numOutputs * 4 bytes).
std::vector<TileRect> planChunks(TileRect rect, int numOutputs, const ChunkLimits& limits);

} // namespace moire::vk

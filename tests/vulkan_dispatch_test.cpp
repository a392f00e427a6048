// The Vulkan executor's dispatch held to values worked out here: every invocation of a
// workgroup that hangs past the rectangle's edge shades a pixel but stores nothing
// (GlslEmit.cpp's `inside`); the outputs land in the image's own interleaved layout whether
// the shader stores them four at a time (vec4) or one by one, whole or in chunks, written
// straight into host-visible memory or copied there; and hypot, written without branches,
// keeps its precision across the magnitudes its scaling switches between.
// Skipped where no Vulkan device is available.
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/ir/Builder.h"
#include "compiler/ir/OpTable_test.h"
#include "runtime/TileExecutor.h"
#include "runtime/vulkan/VulkanBackend.h"
#include "tests/support/Support.h"

#include <cmath>
#include <doctest/doctest.h>
#include <limits>

using namespace moire;
using namespace moire::ir;

namespace {

// Output k of pixel (x, y) in a w-wide frame: every term a small multiple of 1/8, so float
// holds it exactly and the shader must produce exactly this.
double expected(int x, int y, int w, int k) {
    return (x + 0.5) * 64.0 + (y + 0.5) + w * 8192.0 + k * 0.125;
}

// The kernel of `expected`, reading uniform k for its k * 0.125.
Function layoutKernel(int numOutputs) {
    return optest::build(numOutputs, [&](Builder& b) {
        ValueId pos = b.add(b.add(b.mul(b.leaf(Op::PixelX), b.constF(64.0)), b.leaf(Op::PixelY)),
                            b.mul(b.leaf(Op::ImageW), b.constF(8192.0)));
        for (int k = 0; k < numOutputs; ++k) b.output(k, b.add(pos, b.uniform(k)));
    });
}

std::vector<double> eighths(int n) {
    std::vector<double> u(n);
    for (int k = 0; k < n; ++k) u[k] = k * 0.125;
    return u;
}

} // namespace

TEST_CASE("vulkan dispatch: odd-sized frames, whole and in chunks, hold every pixel's own "
          "outputs and nothing past them") {
    if (!test::makeBackendOrSkip("vulkan")) return;
    // 37 x 23: neither side a multiple of the workgroup's, so the last workgroups of every
    // row and column hang past the edge. Five pixels a chunk: rows cut into eight pieces.
    const int w = 37, h = 23;
    for (int n : {1, 3, 4, 5, 8}) {
        CAPTURE(n);
        const Function f = layoutKernel(n);
        const std::vector<double> uniforms = eighths(n);
        const KernelFrame frame{uniforms.data(), w, h};
        // Into memory the host reads where the device offers it (lavapipe), and through a
        // copy on the device as a discrete GPU does.
        for (VulkanOptions options :
             {VulkanOptions{}, VulkanOptions{.staged = true},
              VulkanOptions{.maxChunkBytes = 5 * n * sizeof(float)},
              VulkanOptions{.maxChunkBytes = 5 * n * sizeof(float), .staged = true}}) {
            CAPTURE(options.maxChunkBytes);
            CAPTURE(options.staged);
            VulkanBackend backend(options);
            auto kernel = backend.compile(f);
            const Image img = runKernel(*kernel, frame);
            REQUIRE(img.channels == n);
            size_t wrong = 0;
            for (int y = 0; y < h; ++y)
                for (int x = 0; x < w; ++x)
                    for (int k = 0; k < n; ++k) wrong += img.at(x, y, k) != expected(x, y, w, k);
            CHECK(wrong == 0);

            // A window at an odd offset into a buffer with a padded row: the window's pixels
            // are the frame's, and the padding and the rows past it are left alone.
            const int x0 = 5, y0 = 3, ww = 19, wh = 11, pad = 3;
            const size_t stride = static_cast<size_t>(ww + pad) * n;
            std::vector<float> buf(stride * (wh + 1), -1.0f);
            kernel->runTile(frame, TileRect{x0, y0, x0 + ww, y0 + wh}, buf.data(), stride);
            size_t windowWrong = 0, touched = 0;
            for (int y = 0; y < wh + 1; ++y)
                for (int x = 0; x < ww + pad; ++x)
                    for (int k = 0; k < n; ++k) {
                        const float v = buf[y * stride + static_cast<size_t>(x) * n + k];
                        if (y < wh && x < ww)
                            windowWrong += v != expected(x0 + x, y0 + y, w, k);
                        else
                            touched += v != -1.0f;
                    }
            CHECK(windowWrong == 0);
            CHECK(touched == 0);
        }
    }
}

TEST_CASE("vulkan dispatch: hypot keeps its precision wherever its scaling changes, and its "
          "infinities and NaN") {
    auto vk = test::makeBackendOrSkip("vulkan");
    if (!vk) return;
    const Function f = optest::build(1, [](Builder& b) {
        b.output(0, b.emit(Op::Hypot, {b.uniform(0), b.uniform(1)}));
    });
    auto kernel = vk->compile(f);
    // Around 2^60 and 2^-60, where the shader scales both sides by 2^-80 or 2^100, at the
    // ends of float's range, where an unscaled square would overflow or vanish, and mixed.
    const double inf = std::numeric_limits<double>::infinity(), nan = std::nan("");
    std::vector<double> sides = {0.0,
                                 -0.0,
                                 1.0,
                                 3.0,
                                 0x1p60,
                                 0x1.000002p60,
                                 0x1.fffffep59,
                                 0x1p-60,
                                 0x1.000002p-60,
                                 0x1.fffffep-61,
                                 3.4e38,
                                 -2.5e38,
                                 1e-38,
                                 1e-44,
                                 1.5e19,
                                 -4e-20,
                                 inf,
                                 -inf,
                                 nan};
    for (double a : sides)
        for (double c : sides) {
            CAPTURE(a);
            CAPTURE(c);
            const float got = optest::runPixel(*kernel, {a, c})[0];
            CHECK(optest::withinVulkanPrecision(Op::Hypot, 0, static_cast<float>(a),
                                                static_cast<float>(c), got));
        }
}

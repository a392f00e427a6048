// The GPU backend's compiler half: the IR translated op by op to a GLSL 4.50 compute shader,
// then to SPIR-V by glslang, for the Vulkan executor (runtime/vulkan); and the same
// translation as a GLSL ES 3.00 fragment shader, for the WebGL2 page of `moire export`. The same IR
// the interpreter and the LLVM JIT run, so no per-pixel maths is written again for the GPU.
//
// The shader's interface, shared with the executor:
//   set 0, binding 0: readonly storage buffer, float uniforms[] (the frame program's outputs)
//   set 0, binding 1: writeonly storage buffer of the outputs: numOutputs floats per pixel,
//                     row-major over the dispatched rectangle of w x h pixels (the image's
//                     own layout); declared vec4 o[] when numOutputs is a multiple of 4
//                     (the same bytes, one store per four floats), else float o[]
//   push constants:   PushConstants below (std430, 24 bytes)
//   local size:       kLocalSizeX x kLocalSizeY x 1; dispatch ceil(w / kLocalSizeX) x
//                     ceil(h / kLocalSizeY)
//   execution mode:   SignedZeroInfNanPreserve for 32-bit floats (Semantics.h defines NaN,
//                     infinities and -0): the device must report
//                     shaderSignedZeroInfNanPreserveFloat32 (Vulkan 1.2 float controls)
#pragma once

#include "compiler/ir/IR.h"

#include <cstdint>
#include <string>
#include <vector>

namespace moire::glsl {

// 128 invocations, the most every Vulkan device must allow (maxComputeWorkGroupInvocations),
// 16 wide so that a workgroup's row of outputs is contiguous. On lavapipe, which runs each
// workgroup as one task, 8 x 8 cost about 5% more CPU time on the two ring families.
constexpr uint32_t kLocalSizeX = 16, kLocalSizeY = 8;

struct PushConstants {
    int32_t imageW, imageH; // the whole frame, in pixels
    int32_t x0, y0;         // the rectangle's first pixel
    int32_t w, h;           // the rectangle's size
};

// Which shader the kernel becomes: the Vulkan compute shader described above, or a GLSL ES
// 3.00 fragment shader for WebGL2 (`moire export`), whose interface is
//   uniform vec4 m_u[uniformVectors(kernel)]: uniform slot i in m_u[i / 4][i % 4]
//   uniform vec2 m_image:  the image's width and height in pixels
//   out vec4 m_color:      outputs 0-3 (straight sRGB-encoded RGBA), drawn over the whole
//                          canvas (a viewport of the image's size); the other outputs unused
enum class Dialect { Vulkan, WebGl };

// The shader's source.
std::string emitGlsl(const ir::Function& kernel, Dialect dialect = Dialect::Vulkan);
// The uniform slots the kernel reads (one past the highest), and the vec4s that hold them.
int uniformCount(const ir::Function& kernel);
int uniformVectors(const ir::Function& kernel);

// Whether glslang accepts `source` as a GLSL ES 3.00 fragment shader (as WebGL2 compiles it);
// otherwise `message` holds its log.
bool validateGlslEs(const std::string& source, std::string* message);

// SPIR-V for Vulkan 1.2 (glslang). A shader glslang rejects is a bug in the emitter: it
// raises an internal error carrying the source and glslang's log.
std::vector<uint32_t> compileSpirv(const ir::Function& kernel);
// The same for a shader's GLSL source (emitGlsl's, or a benchmark's hand-written kernel).
std::vector<uint32_t> compileGlsl(const std::string& source);

// spirv-val for the Vulkan 1.2 environment: true when valid; otherwise `message` says why.
bool validateSpirv(const std::vector<uint32_t>& spirv, std::string* message);

// Human-readable SPIR-V (`moire compile --dump=spirv`).
std::string disassembleSpirv(const std::vector<uint32_t>& spirv);

} // namespace moire::glsl

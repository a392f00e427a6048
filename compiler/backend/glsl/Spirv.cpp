// GLSL -> SPIR-V through glslang's library API, and SPIR-V validation and disassembly through
// SPIRV-Tools.
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/diag/Diagnostics.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <mutex>
#include <spirv-tools/libspirv.hpp>

namespace moire::glsl {

namespace {
void initialiseGlslangOnce() {
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });
}
} // namespace

std::vector<uint32_t> compileSpirv(const ir::Function& kernel) {
    initialiseGlslangOnce();
    const std::string source = emitGlsl(kernel);
    const char* text = source.c_str();
    glslang::TShader shader(EShLangCompute);
    shader.setStrings(&text, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    const EShMessages messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 450, false, messages))
        MOIRE_ICE("glslang rejected the generated shader:\n{}\n{}", shader.getInfoLog(), source);
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages))
        MOIRE_ICE("glslang could not link the generated shader:\n{}", program.getInfoLog());
    std::vector<uint32_t> spirv;
    glslang::SpvOptions options;
    options.validate = false;
    options.disableOptimizer = false; // glslang's own SPIR-V optimiser: smaller modules
    glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
    return spirv;
}

bool validateSpirv(const std::vector<uint32_t>& spirv, std::string* message) {
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
    std::string log;
    tools.SetMessageConsumer(
        [&](spv_message_level_t, const char*, const spv_position_t& pos, const char* msg) {
            log += "word " + std::to_string(pos.index) + ": " + msg + "\n";
        });
    bool ok = tools.Validate(spirv);
    if (message) *message = log;
    return ok;
}

std::string disassembleSpirv(const std::vector<uint32_t>& spirv) {
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
    std::string text;
    if (!tools.Disassemble(spirv, &text,
                           SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES |
                               SPV_BINARY_TO_TEXT_OPTION_INDENT))
        return "; (the module could not be disassembled)\n";
    return text;
}

} // namespace moire::glsl

// GLSL -> SPIR-V through glslang's library API, and SPIR-V validation and disassembly through
// SPIRV-Tools.
#include "compiler/backend/glsl/GlslKernel.h"
#include "compiler/diag/Diagnostics.h"

#include <cstring>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>
#include <mutex>
#include <spirv-tools/libspirv.hpp>
#include <string>
#include <unordered_set>

namespace moire::glsl {

namespace {
void initialiseGlslangOnce() {
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });
}
} // namespace

std::vector<uint32_t> compileSpirv(const ir::Function& kernel) {
    return compileGlsl(emitGlsl(kernel));
}

std::vector<uint32_t> compileGlsl(const std::string& source) {
    initialiseGlslangOnce();
    const char* text = source.c_str();
    glslang::TShader shader(EShLangCompute);
    shader.setStrings(&text, 1);
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangCompute, glslang::EShClientVulkan, 100);
    shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
    shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
    const EShMessages messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
    if (!shader.parse(GetDefaultResources(), 450, false, messages))
        MOIRE_ICE("glslang rejected the shader:\n{}\n{}", shader.getInfoLog(), source);
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages))
        MOIRE_ICE("glslang could not link the shader:\n{}", program.getInfoLog());
    std::vector<uint32_t> spirv;
    glslang::SpvOptions options;
    options.validate = false;
    options.disableOptimizer = false; // glslang's own SPIR-V optimiser: smaller modules
    glslang::GlslangToSpv(*program.getIntermediate(EShLangCompute), spirv, &options);
    return spirv;
}

bool validateGlslEs(const std::string& source, std::string* message) {
    initialiseGlslangOnce();
    const char* text = source.c_str();
    glslang::TShader shader(EShLangFragment);
    shader.setStrings(&text, 1);
    // No client API: glslang then holds the shader to the GLSL ES specification alone, as a
    // WebGL2 implementation's front end does.
    shader.setEnvInput(glslang::EShSourceGlsl, EShLangFragment, glslang::EShClientNone, 0);
    bool ok = shader.parse(GetDefaultResources(), 300, EEsProfile, false, false, EShMsgDefault);
    std::string log = shader.getInfoLog();
    if (ok) {
        glslang::TProgram program;
        program.addShader(&shader);
        ok = program.link(EShMsgDefault);
        log += program.getInfoLog();
    }
    if (message) *message = log;
    return ok;
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

namespace {
// The module with every repeated debug name made unique by its id ("param" -> "param_812").
// glslang names each temporary of a function call "param", thousands of them in a scene of
// many layers, and the disassembler's friendly names then search for a free "param_N" name
// by counting up from 0 each time: quadratic, minutes for a few hundred layers.
std::vector<uint32_t> uniqueNames(const std::vector<uint32_t>& spirv) {
    constexpr uint32_t kOpName = 5, kHeaderWords = 5;
    if (spirv.size() < kHeaderWords) return spirv;
    std::vector<uint32_t> out(spirv.begin(), spirv.begin() + kHeaderWords);
    std::unordered_set<std::string> seen;
    for (size_t at = kHeaderWords; at < spirv.size();) {
        uint32_t words = spirv[at] >> 16, op = spirv[at] & 0xffff;
        if (words == 0 || at + words > spirv.size()) return spirv; // malformed: leave it be
        if (op != kOpName || words < 3) {
            out.insert(out.end(), spirv.begin() + at, spirv.begin() + at + words);
            at += words;
            continue;
        }
        uint32_t target = spirv[at + 1];
        const char* chars = reinterpret_cast<const char*>(&spirv[at + 2]);
        std::string name(chars, strnlen(chars, (words - 2) * sizeof(uint32_t)));
        if (!seen.insert(name).second) name += "_" + std::to_string(target);
        std::vector<uint32_t> literal((name.size() + sizeof(uint32_t)) / sizeof(uint32_t), 0);
        std::memcpy(literal.data(), name.data(), name.size());
        out.push_back(static_cast<uint32_t>((2 + literal.size()) << 16) | kOpName);
        out.push_back(target);
        out.insert(out.end(), literal.begin(), literal.end());
        at += words;
    }
    return out;
}
} // namespace

std::string disassembleSpirv(const std::vector<uint32_t>& spirv) {
    spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
    std::string text;
    if (!tools.Disassemble(uniqueNames(spirv), &text,
                           SPV_BINARY_TO_TEXT_OPTION_FRIENDLY_NAMES |
                               SPV_BINARY_TO_TEXT_OPTION_INDENT))
        return "; (the module could not be disassembled)\n";
    return text;
}

} // namespace moire::glsl

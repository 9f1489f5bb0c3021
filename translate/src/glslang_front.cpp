// glslang as the front end of the shader targets (compilers.h): GLSL of
// every dialect checked with OpenGL semantics (what glslangValidator does
// without -V), GLSL 4.50 to SPIR-V for Vulkan with the relaxed rules of
// `glslangValidator -V -R --amb --aml` (default-block uniforms gathered
// into one block), and HLSL through its HLSL front end.
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <mutex>

#include "compilers.h"

namespace sg::translate::detail {

namespace {

EShLanguage language(ShaderStage stage) {
    switch (stage) {
    case ShaderStage::Vertex:
        return EShLangVertex;
    case ShaderStage::TessControl:
        return EShLangTessControl;
    case ShaderStage::TessEval:
        return EShLangTessEvaluation;
    case ShaderStage::Fragment:
        break;
    }
    return EShLangFragment;
}

// glslang's process-wide tables, made once (InitializeProcess is not
// thread-safe) and kept for the life of the process.
void initialiseOnce() {
    static std::once_flag once;
    std::call_once(once, [] { glslang::InitializeProcess(); });
}

// The compiler's log on one line (its lines joined by "; "), as errors are.
std::string logOf(glslang::TShader& shader, glslang::TProgram* program) {
    std::string log = shader.getInfoLog();
    if (program) log += program->getInfoLog();
    std::string line;
    for (char c : log) {
        if (c == '\n') {
            while (!line.empty() && line.back() == ' ') line.pop_back();
            if (!line.empty() && line.back() != ' ') line += "; ";
        } else {
            line += c;
        }
    }
    while (!line.empty() && (line.back() == ' ' || line.back() == ';')) line.pop_back();
    return line.empty() ? std::string("(no log)") : line;
}

} // namespace

std::vector<uint32_t> glslang(const std::string& text, ShaderStage stage, FrontEnd frontEnd,
                              const std::string& what) {
    initialiseOnce();
    const EShLanguage lang = language(stage);
    glslang::TShader shader(lang);
    // GlslForHlsl: SG_BIT_ARITHMETIC defined after the #version line.
    std::string withDefine;
    if (frontEnd == FrontEnd::GlslForHlsl) {
        const size_t eol = text.find('\n');
        withDefine = text.substr(0, eol + 1) + "#define SG_BIT_ARITHMETIC 1\n#line 2\n" +
                     (eol == std::string::npos ? std::string() : text.substr(eol + 1));
    }
    const char* source = frontEnd == FrontEnd::GlslForHlsl ? withDefine.c_str() : text.c_str();
    shader.setStrings(&source, 1);
    EShMessages messages = EShMsgDefault;
    if (frontEnd == FrontEnd::GlslVulkan || frontEnd == FrontEnd::GlslForHlsl) {
        shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientVulkan, 100);
        shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
        shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
        shader.setEnvInputVulkanRulesRelaxed();
        shader.setGlobalUniformBlockName("SgGlobals");
        shader.setGlobalUniformSet(0);
        shader.setGlobalUniformBinding(0);
        shader.setAutoMapBindings(true);
        shader.setAutoMapLocations(true);
        messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules);
    } else if (frontEnd == FrontEnd::HlslValidate) {
        shader.setEnvInput(glslang::EShSourceHlsl, lang, glslang::EShClientVulkan, 100);
        shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_1);
        shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_3);
        shader.setEntryPoint("main");
        shader.setAutoMapBindings(true);
        shader.setAutoMapLocations(true);
        messages = EShMessages(EShMsgSpvRules | EShMsgVulkanRules | EShMsgReadHlsl);
    }
    // 100: the version assumed without a #version line (every program here has one).
    if (!shader.parse(GetDefaultResources(), 100, false, messages))
        throw TranslateError(what + ": glslang: " + logOf(shader, nullptr));
    if (frontEnd == FrontEnd::GlslValidate) return {};
    glslang::TProgram program;
    program.addShader(&shader);
    if (!program.link(messages) || !program.mapIO())
        throw TranslateError(what + ": glslang (link): " + logOf(shader, &program));
    std::vector<uint32_t> spirv;
    glslang::SpvOptions options;
    options.validate = false; // the SPIR-V validator runs on the result (spirv_tools.cpp)
    glslang::GlslangToSpv(*program.getIntermediate(lang), spirv, &options);
    if (spirv.empty()) throw TranslateError(what + ": glslang: no SPIR-V generated");
    return spirv;
}

} // namespace sg::translate::detail

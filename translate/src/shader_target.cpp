// The shader targets' table and their chains (surfgrad/translate/shader_target.h):
// GLSL 4.50 as written; GLSL 3.30 and ES 3.00 by the dialect's header (the
// shared source adapts through sg/compat.glsl); SPIR-V by glslang; HLSL
// and MSL from that SPIR-V by SPIRV-Cross. Adding a target is one row here
// and its case in translateShader().
#include "surfgrad/translate/shader_target.h"

#include "compilers.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::translate {

namespace {

using detail::FrontEnd;
namespace sh = sg::shaders;

// The GLSL rows carry the shader library's name of their dialect
// (sg::shaders::targetName), so a dialect is named in one place.
ShaderTargetInfo glslRow(ShaderTarget target, sh::Target dialect, const char* language,
                         bool tessellation) {
    return {target, sh::targetName(dialect), language, ".glsl", "glslang", tessellation};
}

} // namespace

const char* shaderStageName(ShaderStage stage) {
    switch (stage) {
    case ShaderStage::Vertex:
        return "vert";
    case ShaderStage::TessControl:
        return "tesc";
    case ShaderStage::TessEval:
        return "tese";
    case ShaderStage::Fragment:
        return "frag";
    }
    return "?";
}

const std::vector<ShaderTargetInfo>& shaderTargets() {
    static const std::vector<ShaderTargetInfo> table = {
        glslRow(ShaderTarget::Glsl450, sh::Target::Glsl450, "GLSL 4.50 core (OpenGL 4.5)", true),
        glslRow(ShaderTarget::Glsl330, sh::Target::Glsl330, "GLSL 3.30 core (OpenGL 3.3)", false),
        glslRow(ShaderTarget::Es300, sh::Target::Es300, "GLSL ES 3.00 (WebGL2, OpenGL ES 3)",
                false),
        {ShaderTarget::Spirv, "spirv", "SPIR-V 1.3 (Vulkan 1.1)", ".spv",
         "glslang, SPIR-V validator", true},
        {ShaderTarget::Hlsl, "hlsl", "HLSL shader model 5.0 (D3D11, Unity, Unreal)", ".hlsl",
         "glslang's HLSL front end, SPIR-V validator", false},
        {ShaderTarget::Msl, "msl", "Metal Shading Language 2.2 (macOS 10.15)", ".metal", "", false},
    };
    return table;
}

const ShaderTargetInfo& shaderTargetInfo(ShaderTarget target) {
    return shaderTargets()[size_t(target)];
}

std::optional<ShaderTarget> findShaderTarget(std::string_view name) {
    for (const ShaderTargetInfo& t : shaderTargets())
        if (name == t.name) return t.target;
    return std::nullopt;
}

std::string shaderTargetNames() {
    std::string names;
    for (const ShaderTargetInfo& t : shaderTargets())
        names += (names.empty() ? "" : "|") + std::string(t.name);
    return names;
}

TranslatedShader translateShader(const std::string& glsl450, ShaderStage stage, ShaderTarget target,
                                 const std::string& name) {
    SG_EXPECTS(glsl450.rfind("#version 450", 0) == 0,
               "translateShader: the program starts with #version 450");
    const ShaderTargetInfo& info = shaderTargetInfo(target);
    const bool tessellation = stage == ShaderStage::TessControl || stage == ShaderStage::TessEval;
    SG_EXPECTS(!tessellation || info.tessellation,
               "translateShader: tessellation stages only to targets that have them");
    const std::string what = name + ": " + shaderStageName(stage) + " stage: " + info.name;
    TranslatedShader out;
    out.validatedBy = info.validator;
    switch (target) {
    case ShaderTarget::Glsl450:
    case ShaderTarget::Glsl330:
    case ShaderTarget::Es300:
        out.text = sh::inDialect(glsl450, target == ShaderTarget::Glsl450   ? sh::Target::Glsl450
                                          : target == ShaderTarget::Glsl330 ? sh::Target::Glsl330
                                                                            : sh::Target::Es300);
        detail::glslang(out.text, stage, FrontEnd::GlslValidate, what);
        return out;
    case ShaderTarget::Spirv:
        out.spirv = detail::glslang(glsl450, stage, FrontEnd::GlslVulkan, what);
        detail::validateSpirv(out.spirv, what);
        out.text = detail::disassembleSpirv(out.spirv);
        return out;
    case ShaderTarget::Hlsl:
    case ShaderTarget::Msl: {
        const bool hlsl = target == ShaderTarget::Hlsl;
        const std::vector<uint32_t> spirv = detail::glslang(
            glsl450, stage, hlsl ? FrontEnd::GlslForHlsl : FrontEnd::GlslVulkan, what);
        detail::validateSpirv(spirv, what);
        out.text = detail::spirvCross(
            spirv, hlsl ? detail::CrossLanguage::Hlsl : detail::CrossLanguage::Msl, what);
        if (hlsl) {
            // The HLSL read back by glslang's HLSL front end, its SPIR-V
            // validated: the text SPIRV-Cross wrote is a valid program.
            detail::validateSpirv(
                detail::glslang(out.text, stage, FrontEnd::HlslValidate, what + " (read back)"),
                what + " (read back)");
        }
        return out;
    }
    }
    SG_EXPECTS(false, "translateShader: a target of the table");
    return out;
}

} // namespace sg::translate

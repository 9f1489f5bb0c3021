// The compilers a shader target's chain runs (shader_target.cpp): glslang
// (GLSL and HLSL front ends, SPIR-V generation), the SPIR-V validator and
// disassembler (SPIRV-Tools) and SPIRV-Cross (SPIR-V to HLSL and MSL).
// Each returns its result or throws TranslateError with the compiler's log.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "surfgrad/translate/shader_target.h"

namespace sg::translate::detail {

// What glslang reads and what it makes of it.
enum class FrontEnd {
    GlslValidate, // GLSL of any version, OpenGL semantics: parse only
    GlslVulkan,   // GLSL 4.50 to SPIR-V for Vulkan 1.1, relaxed rules (shader_target.h)
    GlslForHlsl,  // the same, for SPIRV-Cross's HLSL: SG_BIT_ARITHMETIC (sg/compat.glsl)
    HlslValidate, // HLSL (entry "main", shader model 5.0 semantics) to SPIR-V, discarded
};

// Runs glslang on `text`; returns the SPIR-V module (empty for
// GlslValidate). `what` names the program in a TranslateError.
std::vector<uint32_t> glslang(const std::string& text, ShaderStage stage, FrontEnd frontEnd,
                              const std::string& what);

// The SPIR-V validator (Vulkan 1.1 environment) and the disassembler.
void validateSpirv(const std::vector<uint32_t>& spirv, const std::string& what);
std::string disassembleSpirv(const std::vector<uint32_t>& spirv);

// SPIRV-Cross: the SPIR-V module as HLSL (shader model 5.0) or MSL (2.0).
enum class CrossLanguage { Hlsl, Msl };
std::string spirvCross(const std::vector<uint32_t>& spirv, CrossLanguage language,
                       const std::string& what);

} // namespace sg::translate::detail

// Shader targets: one program of the shared GLSL source, written for GLSL
// 4.50 core, carried to the other languages engines take (the issue on
// shaders in every engine; docs/engines.md, "Scene programs per target").
//
// How each target is made, in one table (shader_target.cpp):
//  - glsl450: the text as written;
//  - glsl330, es300: the same text under the dialect's header as the
//    shader library writes it (sg::shaders::assemble: `#version 330 core`;
//    `#version 300 es` with highp defaults); sg/compat.glsl adapts the
//    library to the dialect from __VERSION__ and GL_ES (exponent arithmetic
//    from bit patterns), the renderer's programs through SG_DFDX / SG_DFDY /
//    SG_PRIMITIVE_ID (sg/render/surface_fs.glsl);
//  - spirv: glslang with Vulkan 1.1 rules, relaxed so that default-block
//    uniforms are gathered into one uniform block (`SgGlobals`, set 0,
//    binding 0) and samplers and varyings get bindings and locations in
//    declaration order (the vertex outputs and fragment inputs of the
//    renderer's programs are declared in the same order, so they match);
//  - hlsl, msl: that SPIR-V translated by SPIRV-Cross (HLSL shader model
//    5.0; MSL 2.2 for macOS). For HLSL the GLSL is compiled with
//    SG_BIT_ARITHMETIC (sg/compat.glsl: frexp, ldexp and imulExtended from
//    bit patterns, as in GLSL 3.30), because SPIRV-Cross's HLSL for them is
//    not valid HLSL.
// sg::shaders::Target names how the library's own text is spelled per
// dialect (the macro layers of sg/compat.glsl and sg/compat.hlsl); the
// targets here carry a complete program, which the renderer writes in GLSL
// 4.50, to every language, HLSL and MSL through SPIR-V.
// Every result is validated where this machine has a validator: glslang for
// GLSL and for HLSL (its HLSL front end), the SPIR-V validator for SPIR-V
// (Vulkan 1.1 environment). Metal source is not validated: no Metal
// compiler exists on Linux.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sg::translate {

// The stages of the renderer's programs (tessellation: adaptive patches).
enum class ShaderStage { Vertex, TessControl, TessEval, Fragment };
// "vert", "tesc", "tese", "frag": the stage's file extension as glslang
// reads it, and the name messages use.
const char* shaderStageName(ShaderStage stage);

enum class ShaderTarget { Glsl450, Glsl330, Es300, Spirv, Hlsl, Msl };

// One row of the target table.
struct ShaderTargetInfo {
    ShaderTarget target;
    const char* name;      // command-line name: "glsl450", "es300", ...
    const char* language;  // e.g. "GLSL ES 3.00 (WebGL2, OpenGL ES 3)"
    const char* extension; // file extension after the stage's ("frag.spv": ".spv")
    const char* validator; // what validates it here, or "" (none on this platform)
    // Whether programs with tessellation stages (the renderer's adaptive
    // patches) reach this target: GLSL 3.30 and ES 3.00 have no such stages
    // (nor the std430 buffers of the patch vertex stage); SPIRV-Cross writes
    // no HLSL hull or domain shaders, and Metal tessellates through compute
    // kernels and host code, which a shader translation cannot give.
    bool tessellation;
};

// Every target, in the order of the enum.
const std::vector<ShaderTargetInfo>& shaderTargets();
const ShaderTargetInfo& shaderTargetInfo(ShaderTarget target);
// The target named `name` (ShaderTargetInfo::name), or nullopt.
std::optional<ShaderTarget> findShaderTarget(std::string_view name);
// "glsl450|glsl330|es300|spirv|hlsl|msl", for help texts and messages.
std::string shaderTargetNames();

// A program that a compiler of the chain rejected. what() is
// "<name>: <stage> stage: <target>: <compiler>: <its log>" on one line (the
// log's lines joined by "; "); the log names the compiler's
// line numbers (of the text given, or of the intermediate text for hlsl).
class TranslateError : public std::runtime_error {
public:
    explicit TranslateError(const std::string& what) : std::runtime_error(what) {}
};

struct TranslatedShader {
    // The program in the target's language; for spirv the module's
    // disassembly (what `spirv-dis` prints).
    std::string text;
    // spirv: the module (little-endian words); empty for the other targets.
    std::vector<uint32_t> spirv;
    // The validator that accepted it (ShaderTargetInfo::validator), or ""
    // where none exists here (msl).
    std::string validatedBy;
};

// Carries one stage of a program to `target` and validates the result.
// `glsl450` is a complete program whose first line is `#version 450`
// (`#version 450 core`); everything else must be valid in the target
// dialects it is carried to. `name` labels messages (e.g. a scene's mesh):
// "<name>: <stage>: <target>: <compiler>: <log>".
// Contract: a tessellation stage only to a target with `tessellation`.
// Throws TranslateError when a compiler of the chain rejects the program.
// Thread-safe: glslang's process state is initialised once.
TranslatedShader translateShader(const std::string& glsl450, ShaderStage stage, ShaderTarget target,
                                 const std::string& name);

} // namespace sg::translate

// The HLSL round trip of the test suite (docs/engines.md, "HLSL"): an HLSL
// compute program of the shared source (assembled with
// sg::shaders::Target::Hlsl) is compiled by glslang's HLSL front end to
// SPIR-V (glslangValidator -D -V), validated (spirv-val), translated to
// GLSL 4.50 by SPIRV-Cross and linked on the OpenGL 4.5 context, so the
// parity harness runs what the HLSL spelling of the source computes. The
// tools are Debian's glslang-tools, spirv-tools and spirv-cross, found on
// PATH (scripts/setup-deps installs them).
#pragma once

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "cli.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

namespace sg::test {

// The GLSL 4.50 translation of HLSL compute program `hlsl` (entry `main`);
// throws naming the tool and its output when a step fails. `name` names the
// scratch files and the program in messages (letters, digits, '-', '_').
// Textures: SPIRV-Cross joins each Texture2D and the SamplerState it is
// sampled with into one `uniform sampler2D SPIRV_Cross_Combined<tex><state>`;
// with `samplersInheritBindings` that sampler2D takes the texture's binding
// ([[vk::binding(n)]]: texture unit n), so a harness binds its textures by
// unit without knowing the generated names.
inline std::string translateHlslCompute(const shaders::Assembled& hlsl, const std::string& name,
                                        bool samplersInheritBindings = false) {
    namespace fs = std::filesystem;
    const fs::path dir = processScratchDir("surfgrad_hlsl");
    const fs::path src = dir / (name + ".hlsl"), spv = dir / (name + ".spv"),
                   glsl = dir / (name + ".comp");
    std::ofstream(src) << hlsl.text;
    const std::string steps[] = {
        "glslangValidator -D -V --target-env vulkan1.1 -S comp -e main -o " + shellQuote(spv) +
            " " + shellQuote(src),
        "spirv-val --target-env vulkan1.1 " + shellQuote(spv),
        "spirv-cross --version 450 --no-es " +
            std::string(samplersInheritBindings ? "--combined-samplers-inherit-bindings " : "") +
            shellQuote(spv) + " --output " + shellQuote(glsl),
    };
    for (const std::string& step : steps) {
        const CommandResult r = runCommand(step);
        if (r.exitCode != 0) {
            throw std::runtime_error("HLSL round trip of " + name + ": `" + step +
                                     "` failed (exit " + std::to_string(r.exitCode) + "):\n" +
                                     r.output());
        }
    }
    std::ifstream in(glsl);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The translation as a compute program on the current (4.5) context.
inline gl::Program hlslComputeProgram(const shaders::Assembled& hlsl, const std::string& name,
                                      bool samplersInheritBindings = false) {
    shaders::Assembled glsl;
    glsl.text = translateHlslCompute(hlsl, name, samplersInheritBindings);
    glsl.files = {name + " (SPIRV-Cross GLSL of the HLSL)"};
    return gl::Program({{gl::Stage::Compute, glsl}});
}

} // namespace sg::test

// Shader targets (surfgrad/translate/shader_target.h): the table, each chain on a
// program of the shared library, and the errors of a rejected program.
// What the chains make is checked by other means than the code under test:
// the SPIR-V module's header words against the SPIR-V specification (magic
// number, version 1.3), the declarations the target languages require
// (HLSL's cbuffer of the gathered uniforms, Metal's entry point), and the
// command-line validators on the example scenes' programs
// (tests/examples/scenes_test.cpp, EveryShaderTargetIsWrittenAndValidated).
#include <gtest/gtest.h>

#include <set>

#include "surfgrad/shaders/shader_files.h"
#include "surfgrad/translate/shader_target.h"

namespace {

namespace st = sg::translate;

// A fragment program of the kind the renderer assembles: the shared
// library, default-block uniforms, a sampler, fine screen derivatives
// through the macro the legacy dialects replace.
std::string fragmentProgram() {
    const std::string body = R"(#include "sg/surfgrad.glsl"
#ifdef SG_GLSL_LEGACY
#define SG_DFDX(v) dFdx(v)
#else
#define SG_DFDX(v) dFdxFine(v)
#endif
in vec3 vRelPos;
in vec2 vUv0;
uniform vec4 uLayer;
uniform sampler2D uTex0;
layout(location = 0) out vec4 outValue;
void main() {
    vec3 dPdx = SG_DFDX(vRelPos);
    int e;
    float m = sgFrexp(uLayer.x, e);
    int hi;
    int lo;
    sgIMulExtended(int(uLayer.y), 3, hi, lo);
    outValue = vec4(dPdx * m, float(e + hi + lo)) + texture(uTex0, vUv0);
}
)";
    return sg::shaders::assemble(body, "test.frag").text;
}

TEST(ShaderTargets, TableNamesEveryTargetOnce) {
    std::set<std::string> names;
    for (const st::ShaderTargetInfo& t : st::shaderTargets()) {
        EXPECT_TRUE(names.insert(t.name).second) << t.name;
        EXPECT_EQ(st::findShaderTarget(t.name), t.target);
        EXPECT_EQ(&st::shaderTargetInfo(t.target), &t);
    }
    EXPECT_EQ(names.size(), 6u);
    EXPECT_EQ(st::findShaderTarget("glsl"), std::nullopt);
    EXPECT_EQ(st::findShaderTarget(""), std::nullopt);
    EXPECT_EQ(st::shaderTargetNames(), "glsl450|glsl330|es300|spirv|hlsl|msl");
}

TEST(ShaderTargets, GlslDialectsChangeOnlyTheHeader) {
    const std::string src = fragmentProgram();
    const std::string rest = src.substr(src.find('\n'));
    const std::pair<st::ShaderTarget, const char*> cases[] = {
        {st::ShaderTarget::Glsl450, "#version 450 core"},
        {st::ShaderTarget::Glsl330, "#version 330 core"},
        {st::ShaderTarget::Es300, "#version 300 es\nprecision highp float;\nprecision highp int;\n"
                                  "precision highp sampler2D;\nprecision highp usampler2D;"},
    };
    for (const auto& [target, version] : cases) {
        const st::TranslatedShader out =
            st::translateShader(src, st::ShaderStage::Fragment, target, "test");
        // The dialect's header, then the program after its #version line.
        EXPECT_EQ(out.text.rfind(std::string(version) + "\n", 0), 0u) << out.text.substr(0, 200);
        EXPECT_NE(out.text.find(rest.substr(1)), std::string::npos) << version;
        EXPECT_TRUE(out.spirv.empty());
        EXPECT_EQ(out.validatedBy, "glslang");
    }
}

TEST(ShaderTargets, SpirvIsAVulkanModule) {
    const st::TranslatedShader out = st::translateShader(
        fragmentProgram(), st::ShaderStage::Fragment, st::ShaderTarget::Spirv, "test");
    ASSERT_GE(out.spirv.size(), 5u);
    EXPECT_EQ(out.spirv[0], 0x07230203u); // SPIR-V specification 2.3: magic number
    EXPECT_EQ(out.spirv[1], 0x00010300u); // version 1.3 (Vulkan 1.1)
    // The default-block uniforms gathered into one block; the disassembly
    // names it and the fragment entry point.
    EXPECT_NE(out.text.find("SgGlobals"), std::string::npos);
    EXPECT_NE(out.text.find("OpEntryPoint Fragment"), std::string::npos);
    EXPECT_NE(out.validatedBy.find("SPIR-V validator"), std::string::npos);
}

TEST(ShaderTargets, HlslAndMslComeFromTheSpirv) {
    const std::string src = fragmentProgram();
    const st::TranslatedShader hlsl =
        st::translateShader(src, st::ShaderStage::Fragment, st::ShaderTarget::Hlsl, "test");
    EXPECT_NE(hlsl.text.find("cbuffer SgGlobals"), std::string::npos);
    EXPECT_NE(hlsl.text.find("ddx_fine"), std::string::npos); // dFdxFine, shader model 5.0
    // SG_BIT_ARITHMETIC: no frexp or mul-extended intrinsic reaches HLSL.
    EXPECT_EQ(hlsl.text.find("frexp("), std::string::npos);
    EXPECT_EQ(hlsl.text.find("imulExtended"), std::string::npos);
    EXPECT_NE(hlsl.validatedBy.find("HLSL front end"), std::string::npos);
    const st::TranslatedShader msl =
        st::translateShader(src, st::ShaderStage::Fragment, st::ShaderTarget::Msl, "test");
    EXPECT_NE(msl.text.find("#include <metal_stdlib>"), std::string::npos);
    EXPECT_NE(msl.text.find("fragment main0_out main0("), std::string::npos);
    EXPECT_EQ(msl.validatedBy, ""); // no Metal compiler on Linux
}

TEST(ShaderTargets, VertexStageToEveryTarget) {
    const std::string src = sg::shaders::assemble(R"(#include "sg/compat.glsl"
layout(location = 0) in vec3 aPosition;
uniform mat4 uViewProj;
out vec3 vRelPos;
void main() {
    vRelPos = aPosition;
    gl_Position = uViewProj * vec4(aPosition, 1.0);
}
)",
                                                  "test.vert")
                                .text;
    for (const st::ShaderTargetInfo& t : st::shaderTargets()) {
        const st::TranslatedShader out =
            st::translateShader(src, st::ShaderStage::Vertex, t.target, "test");
        EXPECT_FALSE(out.text.empty()) << t.name;
    }
}

// A program a dialect rejects: the error names the program, the stage,
// the target, the compiler and the compiler's line.
TEST(ShaderTargets, RejectedProgramNamesTargetCompilerAndLine) {
    // gl_PrimitiveID does not exist in GLSL ES 3.00; the rest is valid.
    const std::string src = "#version 450 core\n"
                            "layout(location = 0) out vec4 o;\n"
                            "void main() { o = vec4(float(gl_PrimitiveID)); }\n";
    EXPECT_NO_THROW(
        st::translateShader(src, st::ShaderStage::Fragment, st::ShaderTarget::Glsl450, "p"));
    try {
        st::translateShader(src, st::ShaderStage::Fragment, st::ShaderTarget::Es300, "p");
        FAIL() << "ES 3.00 has no gl_PrimitiveID";
    } catch (const st::TranslateError& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("p: frag stage: es300: glslang: "), std::string::npos) << what;
        EXPECT_NE(what.find("0:3"), std::string::npos) << what;
        EXPECT_NE(what.find("gl_PrimitiveID"), std::string::npos) << what;
        EXPECT_EQ(what.find('\n'), std::string::npos) << "one line: " << what;
    }
    // A syntax error stops every target before anything is made.
    const std::string broken = "#version 450 core\nvoid main() { float x = ; }\n";
    for (const st::ShaderTargetInfo& t : st::shaderTargets()) {
        EXPECT_THROW(st::translateShader(broken, st::ShaderStage::Fragment, t.target, "broken"),
                     st::TranslateError)
            << t.name;
    }
}

} // namespace

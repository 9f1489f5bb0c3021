// Every shader file under shaders/ compiles with the Khronos reference
// front end (glslangValidator), independently of the GL driver: each file is
// assembled standalone by the same include expander the programs use
// (sg::shaders::assemble, #version 450 first) and validated for its stage:
//   *.comp.glsl -> compute; *_vs.glsl / *.vert.glsl -> vertex;
//   *_tcs.glsl / *_tes.glsl -> tessellation control / evaluation;
//   everything else -> fragment (library files get an empty main()).
// A file that needs defines to compile standalone lists them in a comment
// line `// glslang-validate: NAME VALUE[, NAME VALUE...]`.
// Every file also compiles in the other dialects (docs/engines.md): GLSL
// 3.30 core and GLSL ES 3.00 (assembled for that target), and Vulkan (the
// GLSL 4.50 text through glslangValidator -V, the SPIR-V through spirv-val),
// except compute and tessellation files (stages only GLSL 4.50 has here)
// and files that name their dialects in a line `// glsl-targets: ...`
// (glsl450, glsl330, es300, vulkan).
// The last test proves the check can fail: a broken snippet is rejected.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>

#include "cli.h"
#include "surfgrad/shaders/shader_files.h"

namespace {

namespace fs = std::filesystem;

using RunResult = sg::test::CommandResult;

// Writes `source` to a scratch file named after `tag` with extension `ext`.
fs::path writeScratch(const std::string& source, const std::string& tag, const std::string& ext) {
    const fs::path& dir = sg::test::processScratchDir("surfgrad_glslang");
    std::string safe = tag;
    for (char& c : safe) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    const fs::path file = dir / (safe + "." + ext);
    std::ofstream out(file);
    out << source;
    return file;
}

// Writes `source` to a temporary file with the stage's extension and runs
// glslangValidator on it.
RunResult validate(const std::string& source, const std::string& stage, const std::string& tag) {
    const fs::path file = writeScratch(source, tag, stage);
    RunResult r = sg::test::runCommand("glslangValidator " + sg::test::shellQuote(file));
    fs::remove(file);
    return r;
}

std::string stageOf(const std::string& path) {
    auto ends = [&](const char* s) {
        const std::string suf(s);
        return path.size() >= suf.size() &&
               path.compare(path.size() - suf.size(), suf.size(), suf) == 0;
    };
    if (ends(".comp.glsl")) return "comp";
    if (ends("_vs.glsl") || ends(".vert.glsl")) return "vert";
    if (ends("_tcs.glsl")) return "tesc";
    if (ends("_tes.glsl")) return "tese";
    return "frag";
}

// Defines a file needs to compile on its own (values its host program
// normally sets), from its `// glslang-validate: NAME VALUE, ...` lines: the
// file states them beside the contract that documents them.
std::vector<std::string> definesOf(const std::string& text) {
    std::vector<std::string> defines;
    std::istringstream in(text);
    std::string line;
    const std::string key = "// glslang-validate:";
    while (std::getline(in, line)) {
        const size_t p = line.find(key);
        if (p == std::string::npos) continue;
        std::stringstream items(line.substr(p + key.size()));
        std::string item;
        while (std::getline(items, item, ',')) {
            const size_t a = item.find_first_not_of(' '), b = item.find_last_not_of(' ');
            if (a != std::string::npos) defines.push_back(item.substr(a, b - a + 1));
        }
    }
    return defines;
}

TEST(GlslValidate, ToolIsAvailable) {
    const RunResult r = validate("#version 450\nvoid main() {}\n", "frag", "trivial");
    ASSERT_EQ(r.exitCode, 0) << r.output();
}

TEST(GlslValidate, EmbeddedListIsEveryShaderFileInTheSourceTree) {
    std::set<std::string> onDisk;
    const fs::path root = fs::path(SURFGRAD_SOURCE_DIR) / "shaders";
    for (const auto& e : fs::recursive_directory_iterator(root)) {
        const auto ext = e.path().extension();
        if (e.is_regular_file() && (ext == ".glsl" || ext == ".hlsl")) {
            onDisk.insert(fs::relative(e.path(), root).generic_string());
        }
    }
    const auto embedded = sg::shaders::list();
    EXPECT_EQ(onDisk, std::set<std::string>(embedded.begin(), embedded.end()));
    EXPECT_GE(embedded.size(), 6u);
}

// The dialects a file must compile in, besides GLSL 4.50 (see the top).
std::set<std::string> extraTargetsOf(const std::string& path, const std::string& text) {
    const std::string stage = stageOf(path);
    if (stage == "comp" || stage == "tesc" || stage == "tese") return {};
    std::set<std::string> all = {"glsl330", "es300", "vulkan"};
    const std::string key = "// glsl-targets:";
    const size_t p = text.find(key);
    if (p == std::string::npos) return all;
    std::set<std::string> named;
    std::stringstream items(text.substr(p + key.size(), text.find('\n', p) - p - key.size()));
    std::string item;
    while (items >> item) {
        if (item.back() == ',') item.pop_back();
        if (all.count(item)) named.insert(item);
    }
    return named;
}

// glslangValidator -V (Vulkan 1.1 SPIR-V), then spirv-val on the module.
RunResult validateVulkan(const std::string& source, const std::string& stage,
                         const std::string& tag) {
    const fs::path file = writeScratch(source, tag + "_vk", stage);
    const fs::path spv = fs::path(file).replace_extension(".spv");
    RunResult r = sg::test::runCommand(
        "glslangValidator -V --target-env vulkan1.1 " + sg::test::shellQuote(file) + " -o " +
        sg::test::shellQuote(spv) + " && spirv-val " + sg::test::shellQuote(spv));
    fs::remove(file);
    fs::remove(spv);
    return r;
}

class GlslFile : public ::testing::TestWithParam<std::string> {};

// A program body that includes file `path` (text `text`), with an empty
// main() when the file has none.
std::string standaloneBody(const std::string& path, const std::string& text) {
    std::string body = "#include \"" + path + "\"\n";
    const bool hasMain = std::regex_search(text, std::regex(R"(\bvoid\s+main\s*\()"));
    if (!hasMain) body += "void main() {}\n";
    return body;
}

TEST_P(GlslFile, CompilesStandalone) {
    const std::string path = GetParam();
    const std::string text = sg::shaders::find(path);
    const std::string stage = stageOf(path);
    const std::string body = standaloneBody(path, text);
    std::vector<std::string> defines = definesOf(text);
    const auto src = sg::shaders::assemble(body, "validate[" + path + "]", defines);
    const RunResult r = validate(src.text, stage, path);
    EXPECT_EQ(r.exitCode, 0) << path << " (" << stage << "):\n"
                             << sg::shaders::annotateLog(r.output(), src.files);
}

TEST_P(GlslFile, CompilesInEveryDialectItTargets) {
    const std::string path = GetParam();
    const std::string text = sg::shaders::find(path);
    const std::string stage = stageOf(path);
    const std::string body = standaloneBody(path, text);
    const std::vector<std::string> defines = definesOf(text);
    for (const std::string& t : extraTargetsOf(path, text)) {
        sg::shaders::Target target = sg::shaders::Target::Glsl450;
        const bool vulkan = t == "vulkan";
        if (!vulkan) {
            ASSERT_TRUE(sg::shaders::parseTarget(t, target)) << t;
        }
        const auto src = sg::shaders::assemble(body, "validate[" + path + "]", defines, target);
        const RunResult r = vulkan ? validateVulkan(src.text, stage, path)
                                   : validate(src.text, stage, path + "_" + t);
        EXPECT_EQ(r.exitCode, 0) << path << " (" << stage << ", " << t << "):\n"
                                 << sg::shaders::annotateLog(r.output(), src.files);
    }
}

// The dialect checks can fail: frexp (GLSL 4.00) under GLSL 3.30 and ES
// 3.00, a default-block uniform in Vulkan GLSL.
TEST(GlslValidate, DialectChecksCanFail) {
    const std::string frexpUse = "float f(float x) { int e; return frexp(x, e); }\n"
                                 "void main() {}\n";
    for (auto t : {sg::shaders::Target::Glsl330, sg::shaders::Target::Es300}) {
        const auto src = sg::shaders::assemble(frexpUse, "frexp", {}, t);
        const RunResult r =
            validate(src.text, "frag", std::string("frexp_") + sg::shaders::targetName(t));
        EXPECT_NE(r.exitCode, 0) << sg::shaders::targetName(t);
    }
    const auto loose = sg::shaders::assemble("uniform float uLoose;\nout vec4 c;\n"
                                             "void main() { c = vec4(uLoose); }\n",
                                             "loose");
    EXPECT_NE(validateVulkan(loose.text, "frag", "loose").exitCode, 0);
}

// A shader path as a test name: every character but letters and digits '_'.
std::string paramName(const ::testing::TestParamInfo<std::string>& p) {
    std::string n = p.param;
    for (char& c : n) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    return n;
}

bool endsWith(const std::string& s, const std::string& suffix) {
    return s.size() >= suffix.size() &&
           s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// The GLSL files (the HLSL entries are checked by HlslFile below).
std::vector<std::string> shaderFiles() {
    std::vector<std::string> glsl;
    for (const std::string& f : sg::shaders::list())
        if (endsWith(f, ".glsl")) glsl.push_back(f);
    return glsl;
}

std::vector<std::string> hlslFiles() {
    std::vector<std::string> hlsl;
    for (const std::string& f : sg::shaders::list())
        if (endsWith(f, ".hlsl")) hlsl.push_back(f);
    return hlsl;
}

// glslang's HLSL front end (-D) to Vulkan SPIR-V, then spirv-val; with
// `metal`, also SPIRV-Cross's Metal translation of that SPIR-V (its text on
// stdout; there is no Metal compiler here to compile it).
RunResult validateHlsl(const std::string& source, const std::string& stage, const std::string& tag,
                       bool metal = false, const fs::path& includeDir = {}) {
    const fs::path file = writeScratch(source, tag + "_hlsl", "hlsl");
    const fs::path spv = fs::path(file).replace_extension(".spv");
    const std::string spvQ = sg::test::shellQuote(spv);
    const std::string include =
        includeDir.empty() ? std::string() : " -I" + sg::test::shellQuote(includeDir);
    RunResult r = sg::test::runCommand("glslangValidator -D -V --target-env vulkan1.1 -S " + stage +
                                       " -e main" + include + " " + sg::test::shellQuote(file) +
                                       " -o " + spvQ + " >&2 && spirv-val " + spvQ +
                                       (metal ? " && spirv-cross --msl " + spvQ : std::string()));
    fs::remove(file);
    fs::remove(spv);
    return r;
}

// Every HLSL entry compiles with glslang's HLSL front end: an entry with
// its own main() as a compute program (its `// glslang-validate:` defines
// set), a library header (sg/surfgrad.hlsl) inside a pixel shader that
// calls the per-pixel frame, a normal-map gradient and the resolve. The
// SPIR-V passes spirv-val, and SPIRV-Cross translates it to Metal.
class HlslFile : public ::testing::TestWithParam<std::string> {};

TEST_P(HlslFile, CompilesWithGlslangHlslFrontEnd) {
    const std::string path = GetParam();
    const std::string text = sg::shaders::find(path);
    const bool hasMain = std::regex_search(text, std::regex(R"(\bvoid\s+main\s*\()"));
    // A library file (no main) after the HLSL entry, whose SG_HLSL selects
    // the HLSL spelling (sg/compat.hlsl is only read that way).
    std::string body = hasMain ? "" : "#include \"sg/surfgrad.hlsl\"\n";
    body += "#include \"" + path + "\"\n";
    if (!hasMain) {
        body += "float4 main(float3 relPos : TEXCOORD0, float3 nrm : TEXCOORD1,\n"
                "            float2 uv : TEXCOORD2) : SV_Target {\n"
                "    SgFrame f = sgPrologue(nrm, ddx_fine(relPos), ddy_fine(relPos), true, 0);\n"
                "    float3 vT;\n    float3 vB;\n"
                "    sgGenBasisTB(f, uv, ddx_fine(uv), ddy_fine(uv), vT, vB);\n"
                "    float2 d = sgTspaceNormalToDeriv(uv, false);\n"
                "    return float4(sgResolve(f, sgSurfgradFromTBN(d, vT, vB)), 1.0f);\n}\n";
    }
    const auto src = sg::shaders::assemble(body, "validate[" + path + "]", definesOf(text),
                                           sg::shaders::Target::Hlsl);
    const RunResult r = validateHlsl(src.text, hasMain ? "comp" : "frag", path, true);
    EXPECT_EQ(r.exitCode, 0) << path << ":\n" << r.output();
    // SPIRV-Cross wrote a Metal entry point from it.
    const char* entry = hasMain ? "kernel void main0(" : "fragment main0_out main0(";
    EXPECT_NE(r.out.find(entry), std::string::npos) << path << ": no Metal entry\n" << r.out;
}

INSTANTIATE_TEST_SUITE_P(AllHlslEntries, HlslFile, ::testing::ValuesIn(hlslFiles()), paramName);

// Every file of shared functions (one that declares SG_FN functions: the
// core, the feature-curve evaluator, the layer kinds' functions, the patch
// basis) compiles as HLSL too, after the HLSL entry, with glslang's HLSL
// front end: sampler2D is sg/compat.hlsl's SgSampler2D (a Texture2D and its
// SamplerState), matrices are held transposed.
class SharedHlsl : public ::testing::TestWithParam<std::string> {};

TEST_P(SharedHlsl, CompilesAsHlsl) {
    const std::string path = GetParam();
    const std::string text = sg::shaders::find(path);
    const std::string body = "#include \"sg/surfgrad.hlsl\"\n#include \"" + path +
                             "\"\nfloat4 main(float2 uv : TEXCOORD0) : SV_Target {\n"
                             "    return float4(uv, 0.0f, 1.0f);\n}\n";
    const auto src = sg::shaders::assemble(body, "validate[" + path + "]", definesOf(text),
                                           sg::shaders::Target::Hlsl);
    const RunResult r = validateHlsl(src.text, "frag", path + "_shared");
    EXPECT_EQ(r.exitCode, 0) << path << ":\n" << r.output();
}

std::vector<std::string> sharedFiles() {
    std::vector<std::string> shared;
    for (const std::string& f : shaderFiles())
        if (std::string(sg::shaders::find(f)).find("SG_FN ") != std::string::npos)
            shared.push_back(f);
    return shared;
}

INSTANTIATE_TEST_SUITE_P(SharedFunctionFiles, SharedHlsl, ::testing::ValuesIn(sharedFiles()),
                         paramName);

// The single-file library (share/surfgrad/shaders/flat, written by the
// build's surfgrad_flatten): the files on disk are flatLibrary()'s text,
// i.e. what the source tree gives now, not a stale or hand-edited copy.
TEST(FlatLibrary, FilesAreTheSourceTreeFlattened) {
    const fs::path dir = fs::path(SURFGRAD_BINARY_DIR) / "shaders" / "flat";
    for (const auto& f : sg::shaders::flatLibrary()) {
        std::ifstream in(dir / f.name, std::ios::binary);
        ASSERT_TRUE(in) << (dir / f.name) << " is missing";
        const std::string onDisk((std::istreambuf_iterator<char>(in)),
                                 std::istreambuf_iterator<char>());
        EXPECT_EQ(onDisk, f.text) << f.name;
        const std::regex directive(R"((^|\n)\s*#\s*(include|line)\b)");
        EXPECT_FALSE(std::regex_search(f.text, directive)) << f.name;
    }
}

// ... and each compiles in its languages with nothing on the include path:
// the GLSL file after `#version` in GLSL 4.50, 3.30, ES 3.00 (with a sampler
// precision) and Vulkan, the HLSL file through glslang's HLSL front end.
TEST(FlatLibrary, CompilesWithoutAnIncludePath) {
    // Vulkan wants explicit locations, GLSL 3.30 has none for fragment inputs.
    const std::string vulkanInputs = "layout(location = 0) in vec3 vRelPos;\n"
                                     "layout(location = 1) in vec3 vNormal;\n"
                                     "layout(location = 2) in vec2 vUv;\n"
                                     "layout(location = 0) out vec4 outColor;\n";
    const std::string glInputs =
        "in vec3 vRelPos;\nin vec3 vNormal;\nin vec2 vUv;\nout vec4 outColor;\n";
    const std::string use =
        "void main() {\n"
        "    SgFrame f = sgPrologue(vNormal, dFdx(vRelPos), dFdy(vRelPos),\n"
        "                           gl_FrontFacing, SG_BFACE_NONE);\n"
        "    vec3 vT;\n    vec3 vB;\n"
        "    sgGenBasisTB(f, vUv, dFdx(vUv), dFdy(vUv), vT, vB);\n"
        "    vec2 d = sgTspaceNormalToDeriv(vUv, false);\n"
        "    outColor = vec4(sgResolve(f, sgSurfgradFromTBN(d, vT, vB)), 1.0);\n"
        "}\n";
    for (const auto& f : sg::shaders::flatLibrary()) {
        if (endsWith(f.name, ".glsl")) {
            const std::pair<const char*, const char*> versions[] = {
                {"450", "#version 450 core\n"},
                {"330", "#version 330 core\n"},
                {"es300", "#version 300 es\nprecision highp float;\n"}};
            for (const auto& [tag, header] : versions) {
                const RunResult r =
                    validate(header + f.text + glInputs + use, "frag", "flat_" + std::string(tag));
                EXPECT_EQ(r.exitCode, 0) << f.name << " " << tag << ":\n" << r.output();
            }
            const RunResult vk =
                validateVulkan("#version 450 core\n" + f.text + vulkanInputs + use, "frag", "flat");
            EXPECT_EQ(vk.exitCode, 0) << f.name << " vulkan:\n" << vk.output();
        } else {
            const std::string main =
                "float4 main(float3 relPos : TEXCOORD0, float3 nrm : TEXCOORD1,\n"
                "            float2 uv : TEXCOORD2) : SV_Target {\n"
                "    SgFrame f = sgPrologue(nrm, ddx_fine(relPos), ddy_fine(relPos), true, 0);\n"
                "    return float4(f.nrmBase, 1.0f);\n}\n";
            const RunResult r = validateHlsl(f.text + main, "frag", "flat_" + f.name);
            EXPECT_EQ(r.exitCode, 0) << f.name << ":\n" << r.output();
        }
    }
}

// The engine snippets of docs/engines.md (examples/engines/) compile
// against the installed single-file library as an engine would include
// them, each called from a pixel shader (glslang's HLSL front end, then
// spirv-val; Unity's and Unreal's own compilers are not on this machine).
TEST(EngineSnippets, CompileAgainstTheFlatLibrary) {
    const fs::path flat = fs::path(SURFGRAD_BINARY_DIR) / "shaders" / "flat";
    const fs::path dir = fs::path(SURFGRAD_SOURCE_DIR) / "examples" / "engines";
    const std::string in =
        "float4 main(float3 p : TEXCOORD0, float3 n : TEXCOORD1,\n"
        "            float2 uv : TEXCOORD2, bool ff : SV_IsFrontFace) : SV_Target {\n"
        "    const float3 nts = float3(0.1f, 0.2f, 0.97f);\n";
    const std::pair<const char*, std::string> snippets[] = {
        {"SurfgradUnity.hlsl",
         in + "    float3 o;\n    SurfgradNormalMap_float(p, n, uv, nts, ff, o);\n"
              "    return float4(o, 1.0f);\n}\n"},
        {"SurfgradUnreal.ush",
         in + "    return float4(SurfgradNormalMap(p, n, uv, nts, ff), 1.0f);\n}\n"},
    };
    for (const auto& [name, main] : snippets) {
        std::ifstream file(dir / name);
        ASSERT_TRUE(file) << (dir / name);
        const std::string text((std::istreambuf_iterator<char>(file)),
                               std::istreambuf_iterator<char>());
        const RunResult r = validateHlsl(text + main, "frag", name, false, flat);
        EXPECT_EQ(r.exitCode, 0) << name << ":\n" << r.output();
    }
}

// The Godot 4 and bgfx snippets (examples/engines/*.gdshader, *.sc): their
// engines' compilers are not on this machine, so each engine's built-ins are
// replaced by GLSL stand-ins of the same meaning and the file is compiled
// against the flat GLSL library (GLSL 4.50) with glslang. This checks the
// library calls (names, arguments, types), not the engines' acceptance.
//  - Godot: `shader_type` dropped, the res:// include replaced by the flat
//    library, `: hint_*` dropped, `void fragment()` made a function of
//    Godot's built-ins (NORMAL inout, VERTEX, UV, FRONT_FACING), called by a
//    main() on stage inputs;
//  - bgfx: `$input` as `in` declarations (types from the varying names:
//    v_texcoord* vec2, else vec3), bgfx_shader.sh as SAMPLER2D(n, r) ->
//    `uniform sampler2D n`, texture2D -> texture, gl_FragColor -> an output.
TEST(EngineSnippets, GodotAndBgfxCallTheLibraryAsGlsl) {
    const fs::path flat = fs::path(SURFGRAD_BINARY_DIR) / "shaders" / "flat" / "surfgrad.glsl";
    const fs::path dir = fs::path(SURFGRAD_SOURCE_DIR) / "examples" / "engines";
    const auto read = [](const fs::path& p) {
        std::ifstream in(p);
        return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    };
    const std::string library = read(flat);
    ASSERT_FALSE(library.empty()) << flat;

    std::string godot = read(dir / "surfgrad_godot.gdshader");
    ASSERT_NE(godot.find("shader_type spatial;"), std::string::npos);
    godot = std::regex_replace(godot, std::regex(R"(shader_type \w+;)"), "");
    const std::string godotInclude = "#include \"res://surfgrad/surfgrad.gdshaderinc\"";
    ASSERT_NE(godot.find(godotInclude), std::string::npos);
    godot.replace(godot.find(godotInclude), godotInclude.size(), library);
    godot = std::regex_replace(godot, std::regex(R"(\s*:\s*hint_\w+)"), "");
    godot = std::regex_replace(godot, std::regex(R"(void fragment\(\))"),
                               "void godotFragment(inout vec3 NORMAL, vec3 VERTEX, vec2 UV, "
                               "bool FRONT_FACING)");
    godot = "#version 450 core\nin vec3 sgVertex;\nin vec3 sgNormal;\nin vec2 sgUv;\n"
            "out vec4 sgOut;\n" +
            godot +
            "void main() {\n    vec3 n = sgNormal;\n"
            "    godotFragment(n, sgVertex, sgUv, gl_FrontFacing);\n"
            "    sgOut = vec4(n, 1.0);\n}\n";
    const RunResult g = validate(godot, "frag", "godot");
    EXPECT_EQ(g.exitCode, 0) << "surfgrad_godot.gdshader:\n" << g.output();

    std::string bgfx = read(dir / "surfgrad_bgfx.sc");
    std::smatch inputs;
    ASSERT_TRUE(std::regex_search(bgfx, inputs, std::regex(R"(\$input ([^\n]*))")));
    std::string decls;
    std::stringstream names(inputs[1].str());
    for (std::string n; std::getline(names, n, ',');) {
        n = std::regex_replace(n, std::regex(R"(\s)"), "");
        decls +=
            std::string("in ") + (n.rfind("v_texcoord", 0) == 0 ? "vec2 " : "vec3 ") + n + ";\n";
    }
    bgfx = std::regex_replace(bgfx, std::regex(R"(\$input [^\n]*)"), decls);
    bgfx = std::regex_replace(bgfx, std::regex(R"(#include <bgfx_shader.sh>)"),
                              "#define SAMPLER2D(name, reg) uniform sampler2D name\n"
                              "#define texture2D texture\n"
                              "out vec4 sgFragColor;\n#define gl_FragColor sgFragColor");
    const std::string bgfxInclude = "#include \"surfgrad.glsl\"";
    ASSERT_NE(bgfx.find(bgfxInclude), std::string::npos);
    bgfx.replace(bgfx.find(bgfxInclude), bgfxInclude.size(), library);
    const RunResult b = validate("#version 450 core\n" + bgfx, "frag", "bgfx");
    EXPECT_EQ(b.exitCode, 0) << "surfgrad_bgfx.sc:\n" << b.output();
}

// Splat constructors (vec3(x) from one scalar) in a file's code: GLSL and
// C++ take them, HLSL's float3(x) does not (DXC, FXC), so the shared source
// writes sgVec3(x) (sg/compat.glsl). Finds the literal and SG_* constant
// arguments, the splats this source writes; returns "line: text" per hit.
std::vector<std::string> splatConstructors(const std::string& text) {
    static const std::regex splat(
        R"(\b[iub]?vec[234]\(\s*(-?[0-9][0-9.]*(e[-+]?[0-9]+)?[fu]?|SG_[A-Z0-9_]+)\s*\))");
    std::vector<std::string> hits;
    std::istringstream in(text);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
        const std::string code = line.substr(0, line.find("//"));
        if (std::regex_search(code, splat)) hits.push_back(std::to_string(n) + ": " + line);
    }
    return hits;
}

// GLSL's mod(x, y) is x - y floor(x / y); HLSL's fmod truncates, so the
// shared functions use neither (write x - y * floor(x / y)).
TEST(GlslSubset, SharedFunctionsUseNoMod) {
    const std::regex mod(R"(\bmod\s*\()");
    for (const std::string& path : shaderFiles()) {
        const std::string text = sg::shaders::find(path);
        if (text.find("SG_FN ") == std::string::npos) continue;
        std::istringstream in(text);
        std::string line;
        for (int n = 1; std::getline(in, line); ++n) {
            if (std::regex_search(line.substr(0, line.find("//")), mod))
                ADD_FAILURE() << path << ":" << n << ": " << line;
        }
    }
}

// The shared functions (files declaring SG_FN functions, compiled as GLSL,
// C++ and HLSL) hold no splat constructor.
TEST(GlslSubset, SharedFunctionsWriteNoSplatConstructor) {
    for (const std::string& path : shaderFiles()) {
        const std::string text = sg::shaders::find(path);
        if (text.find("SG_FN ") == std::string::npos) continue;
        for (const std::string& hit : splatConstructors(text))
            ADD_FAILURE() << path << ":" << hit << " (write sgVecN(x), sg/compat.glsl)";
    }
    // The check can fail.
    EXPECT_EQ(splatConstructors("    vec3 a = vec3(0.0f);\n").size(), 1u);
    EXPECT_EQ(splatConstructors("    uvec4 u = uvec4(0u); // vec2(1.0f)\n").size(), 1u);
    EXPECT_EQ(splatConstructors("    vec3 e = vec3(SG_FLT_EPSILON);\n").size(), 1u);
    EXPECT_TRUE(splatConstructors("    vec3 b = vec3(0.0f, 1.0f, 0.0f) + sgVec3(2.0f);\n").empty());
}

INSTANTIATE_TEST_SUITE_P(AllShaders, GlslFile, ::testing::ValuesIn(shaderFiles()), paramName);

// The check can fail: a type error, an undeclared identifier and a C++-only
// construct (a float literal with an `f` suffix is legal GLSL, but `auto`
// is not) are each rejected with exit status 2.
TEST(GlslValidate, BrokenSnippetsAreRejected) {
    const char* broken[] = {
        "vec3 f(vec2 v) { return v; }\n",
        "float g() { return undeclaredThing * 2.0; }\n",
        "void h() { auto x = 1.0; }\n",
    };
    for (const char* snippet : broken) {
        const auto src = sg::shaders::assemble(std::string("#include \"sg/surfgrad.glsl\"\n") +
                                                   snippet + "void main() {}\n",
                                               "broken");
        const RunResult r = validate(src.text, "frag", "broken");
        EXPECT_NE(r.exitCode, 0) << snippet;
        EXPECT_NE(r.output().find("ERROR"), std::string::npos) << r.output();
    }
}

} // namespace

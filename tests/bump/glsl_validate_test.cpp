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
#include <regex>
#include <set>
#include <sstream>

#include "cli.h"
#include "surfgrad/shader_files.h"

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
        if (e.is_regular_file() && e.path().extension() == ".glsl") {
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

std::vector<std::string> shaderFiles() {
    return sg::shaders::list();
}

INSTANTIATE_TEST_SUITE_P(AllShaders, GlslFile, ::testing::ValuesIn(shaderFiles()),
                         [](const auto& p) {
                             std::string n = p.param;
                             for (char& c : n)
                                 c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                             return n;
                         });

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

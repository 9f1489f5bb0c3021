// Every scene example (examples/*/scene.json) through the CLI, as a user
// runs it:
//  - `surfgrad render` writes a linear EXR at a small size with no NaN/Inf
//    pixel, not a constant image, and a normal AOV whose covered pixels are
//    unit vectors (animated scenes: at several frames, so morphed meshes are
//    checked too);
//  - every assembled program variant (`surfgrad shader --vertex`: each
//    distinct fragment and vertex program of the scene) passes the Khronos
//    reference compiler, glslangValidator, independently of the GL driver,
//    and so does each program carried to every shader target
//    (`--target all`: GLSL 3.30 and ES 3.00, SPIR-V through spirv-val, HLSL
//    through glslang's HLSL front end; MSL is only written);
//  - README.md exists and names the rendered image, which exists under
//    docs/images/examples/;
//  - `surfgrad view` opens it under xvfb-run and screenshots the window.
// Examples are discovered from the source tree, so a new one is covered
// without editing this file; the expected ones must be there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "example_test_util.h"

namespace {

using namespace sg::examples_test;

const fs::path kSourceDir = SURFGRAD_SOURCE_DIR;
const std::string kCli = SG_SURFGRAD_BIN;

std::vector<std::string> sceneExamples() {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(kSourceDir / "examples")) {
        if (fs::exists(e.path() / "scene.json")) names.push_back(e.path().filename().string());
    }
    std::sort(names.begin(), names.end());
    return names;
}

std::string readText(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(Examples, TheDocumentedExamplesExist) {
    std::vector<std::string> names = sceneExamples();
    for (const char* required :
         {"tessellated-asset", "blendshape-asset", "terrain", "feature-curves"}) {
        EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
    }
}

class SceneExample : public ::testing::TestWithParam<std::string> {
protected:
    fs::path scene() const { return kSourceDir / "examples" / GetParam() / "scene.json"; }
    // Frames checked: 0, plus two inside the animation for animated scenes
    // (the scene's "frames.count"; found with a plain text search to keep
    // this test independent of the renderer's parser).
    std::vector<int> frames() const {
        std::string text = readText(scene());
        if (text.find("\"animation\"") == std::string::npos) return {0};
        return {0, 17, 41};
    }
};

TEST_P(SceneExample, RendersFiniteImagesFromTheCli) {
    fs::path dir = scratchDir("render_" + GetParam());
    for (int frame : frames()) {
        const std::string f = std::to_string(frame);
        fs::path color = dir / ("color_" + f + ".exr"), normal = dir / ("normal_" + f + ".exr");
        // 160x96: every layer and mesh of the scene still runs; seconds per example.
        CommandResult rc = runCommand(shellQuote(kCli) + " render " + shellQuote(scene()) + " -o " +
                                      shellQuote(color) + " --size 160x96 --frame " + f);
        ASSERT_EQ(rc.exitCode, 0) << rc.output();
        CommandResult rn =
            runCommand(shellQuote(kCli) + " render " + shellQuote(scene()) + " -o " +
                       shellQuote(normal) + " --size 160x96 --aov normal --frame " + f);
        ASSERT_EQ(rn.exitCode, 0) << rn.output();

        Image c = readImage(color), n = readImage(normal);
        ASSERT_EQ(c.width, 160) << "frame " << f;
        ASSERT_EQ(c.height, 96);
        ASSERT_EQ(n.width, 160);
        ASSERT_GE(c.channels, 3);
        ASSERT_GE(n.channels, 3);
        size_t nonFinite = 0;
        for (float v : c.pixels) nonFinite += !std::isfinite(v);
        for (float v : n.pixels) nonFinite += !std::isfinite(v);
        EXPECT_EQ(nonFinite, 0u) << "frame " << f;

        // Not constant: the scene covers part of the image with shaded surfaces.
        float lo = 1e30f, hi = -1e30f;
        for (int y = 0; y < c.height; ++y) {
            for (int x = 0; x < c.width; ++x) {
                float l = c.at(x, y, 0) + c.at(x, y, 1) + c.at(x, y, 2);
                lo = std::min(lo, l);
                hi = std::max(hi, l);
            }
        }
        EXPECT_GT(hi - lo, 0.05f) << "frame " << f << ": the colour image is (nearly) constant";

        // Covered pixels of the normal AOV hold unit perturbed normals (the
        // resolve normalizes; 1e-3 allows float rounding only). Background
        // pixels are exactly zero.
        size_t covered = 0, notUnit = 0;
        for (int y = 0; y < n.height; ++y) {
            for (int x = 0; x < n.width; ++x) {
                float a = n.at(x, y, 0), b = n.at(x, y, 1), d = n.at(x, y, 2);
                float len2 = a * a + b * b + d * d;
                if (len2 == 0.0f) continue;
                ++covered;
                notUnit += std::abs(std::sqrt(len2) - 1.0f) > 1e-3f;
            }
        }
        EXPECT_GT(covered, size_t(160 * 96 / 10))
            << "frame " << f << ": the scene should fill part of the view";
        EXPECT_EQ(notUnit, 0u) << "frame " << f;
    }
}

// Splits `surfgrad shader --vertex` output ("// ==== NAME: fragment|vertex|
// tesc|tese program, ..." headers) into programs.
struct Program {
    std::string header, stage, source;
};
std::vector<Program> splitPrograms(const std::string& text) {
    std::vector<Program> out;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind("// ==== ", 0) == 0) {
            Program p;
            p.header = line;
            p.stage = line.find(": vertex program") != std::string::npos ? "vert"
                      : line.find(": tesc program") != std::string::npos ? "tesc"
                      : line.find(": tese program") != std::string::npos ? "tese"
                                                                         : "frag";
            out.push_back(p);
        } else if (!out.empty()) {
            out.back().source += line + "\n";
        }
    }
    return out;
}

TEST_P(SceneExample, EveryAssembledShaderPassesGlslang) {
    fs::path dir = scratchDir("glslang_" + GetParam());
    CommandResult r = runCommand(shellQuote(kCli) + " shader " + shellQuote(scene()) + " --vertex");
    ASSERT_EQ(r.exitCode, 0) << r.output();
    std::vector<Program> progs = splitPrograms(r.output());
    ASSERT_GE(progs.size(), 2u) << "expected at least one fragment and one vertex program:\n"
                                << r.output().substr(0, 2000);
    std::set<std::string> stages;
    for (size_t i = 0; i < progs.size(); ++i) {
        const Program& p = progs[i];
        stages.insert(p.stage);
        ASSERT_NE(p.source.find("#version 450"), std::string::npos) << p.header;
        fs::path file = dir / ("program_" + std::to_string(i) + "." + p.stage);
        std::ofstream(file) << p.source;
        CommandResult v = runCommand("glslangValidator " + shellQuote(file));
        EXPECT_EQ(v.exitCode, 0) << p.header << "\n" << v.output();
    }
    EXPECT_TRUE(stages.count("vert") && stages.count("frag"));
}

// Every program of the scene for every shader target
// (`surfgrad shader --target all -o DIR`), each file checked again by the
// command-line tools, outside the process that made it: glslangValidator
// for GLSL 4.50, 3.30 and ES 3.00 (by the file's #version) and for HLSL
// (its HLSL front end, shader model 5.0 to Vulkan SPIR-V), spirv-val for
// SPIR-V (Vulkan 1.1). MSL has no validator here: the test checks that
// SPIRV-Cross wrote a Metal entry point of the right stage.
TEST_P(SceneExample, EveryShaderTargetIsWrittenAndValidated) {
    fs::path dir = scratchDir("targets_" + GetParam());
    CommandResult r = runCommand(shellQuote(kCli) + " shader " + shellQuote(scene()) +
                                 " --target all -o " + shellQuote(dir));
    ASSERT_EQ(r.exitCode, 0) << r.output();
    const std::vector<std::string> targets = {"glsl450", "glsl330", "es300",
                                              "spirv",   "hlsl",    "msl"};
    // Targets `all` skipped: programs with adaptive patches reach only the
    // targets with tessellation stages (GLSL 4.50, SPIR-V).
    std::set<std::string> skipped;
    std::istringstream lines(r.output());
    for (std::string line; std::getline(lines, line);) {
        if (line.rfind("skipped ", 0) == 0) skipped.insert(line.substr(8, line.find(':') - 8));
    }
    std::map<std::string, std::map<std::string, int>> files; // target -> stage -> count
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string name = e.path().filename().string();
        if (name == "hlsl.spv") continue; // written by the HLSL check below
        // program<N>[_p<points>].<target>.<stage><ext>
        std::vector<std::string> parts;
        std::stringstream ss(name);
        for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
        ASSERT_EQ(parts.size(), 4u) << name;
        const std::string& target = parts[1];
        const std::string& stage = parts[2];
        ASSERT_TRUE(stage == "vert" || stage == "frag" || stage == "tesc" || stage == "tese")
            << name;
        ++files[target][stage];
        const std::string file = shellQuote(e.path());
        if (target == "spirv") {
            CommandResult v = runCommand("spirv-val --target-env vulkan1.1 " + file);
            EXPECT_EQ(v.exitCode, 0) << name << "\n" << v.output();
        } else if (target == "hlsl") {
            CommandResult v =
                runCommand("glslangValidator -D -V --target-env vulkan1.1 -S " + stage +
                           " -e main " + file + " -o " + shellQuote(dir / "hlsl.spv"));
            EXPECT_EQ(v.exitCode, 0) << name << "\n" << v.output();
        } else if (target == "msl") {
            const std::string text = readText(e.path());
            EXPECT_NE(text.find("#include <metal_stdlib>"), std::string::npos) << name;
            EXPECT_NE(text.find(stage == "vert" ? "vertex main0_out main0("
                                                : "fragment main0_out main0("),
                      std::string::npos)
                << name;
        } else {
            const std::string text = readText(e.path());
            const std::string version = target == "glsl450"   ? "#version 450 core\n"
                                        : target == "glsl330" ? "#version 330 core\n"
                                                              : "#version 300 es\n";
            EXPECT_EQ(text.rfind(version, 0), 0u) << name;
            CommandResult v = runCommand("glslangValidator " + file);
            EXPECT_EQ(v.exitCode, 0) << name << "\n" << v.output();
        }
    }
    // Every target that was not skipped has the programs GLSL 4.50 has,
    // stage by stage; a skipped one has none.
    ASSERT_GE(files["glsl450"]["frag"], 1) << r.output();
    EXPECT_EQ(files["glsl450"]["vert"], files["glsl450"]["frag"]);
    EXPECT_FALSE(skipped.count("glsl450") || skipped.count("spirv")) << r.output();
    for (const std::string& t : targets) {
        if (skipped.count(t)) {
            EXPECT_TRUE(files[t].empty()) << t;
            EXPECT_NE(r.output().find("adaptive patches"), std::string::npos) << r.output();
        } else {
            EXPECT_EQ(files[t], files["glsl450"]) << t;
        }
    }
}

TEST_P(SceneExample, HasAReadmeAndARenderedImage) {
    fs::path readme = kSourceDir / "examples" / GetParam() / "README.md";
    ASSERT_TRUE(fs::exists(readme));
    std::string text = readText(readme);
    const std::string image = "docs/images/examples/" + GetParam() + ".png";
    EXPECT_NE(text.find(image), std::string::npos) << "README should show " << image;
    EXPECT_NE(text.find("surfgrad render examples/" + GetParam() + "/scene.json"),
              std::string::npos)
        << "README should give the render command";
    Image img = readImage(kSourceDir / image);
    EXPECT_GT(img.width, 0) << image << " missing or unreadable";
}

// The example opens in the interactive viewer (GLFW + Dear ImGui) under a
// virtual X server, draws a few frames and screenshots the window: a valid
// image of the requested size with the render and the panel in it.
TEST_P(SceneExample, OpensInTheViewerUnderXvfb) {
    fs::path dir = scratchDir("view_" + GetParam());
    fs::path shot = dir / "shot.png";
    CommandResult r = runCommand("xvfb-run -a -s '-screen 0 1280x1024x24' " + shellQuote(kCli) +
                                 " view " + shellQuote(scene()) +
                                 " --frames 3 --size 400x300 --screenshot " + shellQuote(shot));
    ASSERT_EQ(r.exitCode, 0) << r.output();
    Image img = readImage(shot);
    ASSERT_EQ(img.width, 400) << r.output();
    ASSERT_EQ(img.height, 300);
    // Many distinct colours: shaded surfaces and the panel, not a cleared window.
    std::set<int> colours;
    for (int y = 0; y < img.height; y += 2) {
        for (int x = 0; x < img.width; x += 2) {
            colours.insert(int(img.at(x, y, 0) * 255.0f) << 16 |
                           int(img.at(x, y, 1) * 255.0f) << 8 | int(img.at(x, y, 2) * 255.0f));
        }
    }
    EXPECT_GT(colours.size(), 100u);
}

INSTANTIATE_TEST_SUITE_P(All, SceneExample, ::testing::ValuesIn(sceneExamples()),
                         [](const ::testing::TestParamInfo<std::string>& p) {
                             std::string n = p.param;
                             std::replace(n.begin(), n.end(), '-', '_');
                             return n;
                         });

} // namespace

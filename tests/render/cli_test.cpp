// The renderer's subcommands from the outside: `surfgrad render` with no
// argument writes the default image, `render`/`shader` reject bad input with
// a message naming the field and a non-zero exit (no partial output), and
// `surfgrad view` opens a window under xvfb-run and screenshots it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "cli.h"
#include "render_test_util.h"

namespace sg::render::test {
namespace {

namespace fs = std::filesystem;

using CmdResult = sg::test::CommandResult;

// `surfgrad args` run in `cwd`.
CmdResult run(const std::string& args, const fs::path& cwd) {
    fs::create_directories(cwd);
    return sg::test::runSurfgrad(args, {.cwd = cwd});
}

fs::path scratch(const std::string& name) {
    fs::path p = fs::path(SURFGRAD_BINARY_DIR) / "tests/render/cli" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// Distinct 8-bit RGB values of an image: a constant or blank image has 1.
size_t distinctColours(const Image& img) {
    std::set<uint32_t> s;
    for (const auto& p : img.pixels) {
        s.insert(uint32_t(p.x * 255.0f + 0.5f) << 16 | uint32_t(p.y * 255.0f + 0.5f) << 8 |
                 uint32_t(p.z * 255.0f + 0.5f));
        if (s.size() > 1000) break;
    }
    return s.size();
}

TEST(Cli, RenderWithoutArgumentsWritesTheDefaultImage) {
    fs::path dir = scratch("default");
    CmdResult r = run("render --size 192x108", dir);
    ASSERT_EQ(r.exitCode, 0) << r.output();
    Image img = readImage(dir / "out/default.png");
    EXPECT_EQ(img.width, 192);
    EXPECT_EQ(img.height, 108);
    EXPECT_GT(distinctColours(img), 100u);
}

TEST(Cli, BadInputFailsWithTheFieldAndNoOutput) {
    fs::path dir = scratch("bad");
    std::ofstream(dir / "bad.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}],
        "materials": [{"layers": [{"type": "noise", "octaves": 40}]}]})";
    CmdResult r = run("render bad.json -o bad.png", dir);
    EXPECT_EQ(r.exitCode, 1);
    EXPECT_NE(
        r.output().find("bad.json: materials[0].layers[0].octaves: expected an integer in [1, 12]"),
        std::string::npos)
        << r.output();
    EXPECT_FALSE(fs::exists(dir / "bad.png"));
    // Same for `shader`, an unknown AOV, a bad size, an unsupported format,
    // and an output that would overwrite the input.
    EXPECT_EQ(run("shader bad.json", dir).exitCode, 1);
    CmdResult aov = run("render --aov normals -o x.png", dir);
    EXPECT_EQ(aov.exitCode, 1);
    EXPECT_NE(aov.output().find("--aov"), std::string::npos);
    EXPECT_NE(run("render --size 0x10 -o x.png", dir).exitCode, 0);
    CmdResult fmt = run("render --size 8x8 -o x.bmp", dir);
    EXPECT_EQ(fmt.exitCode, 1);
    EXPECT_NE(fmt.output().find("unsupported image format"), std::string::npos);
    std::ofstream(dir / "ok.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}]})";
    EXPECT_EQ(run("render ok.json -o ok.json", dir).exitCode, 1);
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}

TEST(Cli, ShaderPrintsOnlyWhatTheSceneUses) {
    fs::path dir = scratch("shader");
    std::ofstream(dir / "s.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}],
        "materials": [{"layers": [{"type": "noise"}]}]})";
    CmdResult r = run("shader s.json", dir);
    ASSERT_EQ(r.exitCode, 0) << r.output();
    EXPECT_NE(r.output().find("#version 450"), std::string::npos);
    EXPECT_NE(r.output().find("sgLayerNoise"), std::string::npos);
    EXPECT_EQ(r.output().find("sgLayerTriplanar"), std::string::npos);
    EXPECT_EQ(r.output().find("sgLayerUvNormal"), std::string::npos);
}

TEST(Cli, ExrOutputKeepsRawAovValues) {
    fs::path dir = scratch("exr");
    std::ofstream(dir / "p.json") << R"({"meshes": [{"procedural": {"type": "plane"}}],
        "camera": {"position": [0, 2, 0.01], "target": [0, 0, 0]}, "output": {"width": 32, "height": 24}})";
    ASSERT_EQ(run("render p.json --aov normal -o n.exr", dir).exitCode, 0);
    Image n = readImage(dir / "n.exr");
    // A flat plane without layers: the normal is +y everywhere it is seen.
    const glm::vec4& c = n.at(16, 12);
    EXPECT_NEAR(c.y, 1.0f, 1e-5f);
    EXPECT_NEAR(c.x, 0.0f, 1e-5f);
}

TEST(Viewer, OpensUnderXvfbAndScreenshotsTheWindow) {
    fs::path dir = scratch("viewer");
    const CmdResult r =
        sg::test::runCommand("xvfb-run -a -s '-screen 0 1280x1024x24' " +
                                 sg::test::shellQuote(sg::test::surfgradBinary()) +
                                 " view --frames 3 --size 400x300 --screenshot shot.png",
                             {.cwd = dir});
    ASSERT_EQ(r.exitCode, 0) << r.output();
    Image shot = readImage(dir / "shot.png");
    EXPECT_EQ(shot.width, 400);
    EXPECT_EQ(shot.height, 300);
    // The render, the display pass and the panel: many colours.
    EXPECT_GT(distinctColours(shot), 100u);
}

} // namespace
} // namespace sg::render::test

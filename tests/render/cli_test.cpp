// The renderer's subcommands from the outside: `surfgrad render` with no
// argument writes the default image, `render`/`shader` reject bad input with
// a message naming the field and a non-zero exit (no partial output), and
// `surfgrad view` opens a window under xvfb-run and screenshots it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#include <nlohmann/json.hpp>

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

std::string fileBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// Distinct 8-bit RGB values of an image: a constant or blank image has 1.
size_t distinctColours(const Image& img) {
    std::set<uint32_t> s;
    for (size_t i = 0; i < img.texelCount(); ++i) {
        const glm::vec4 p = img.rgba(i);
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
    EXPECT_EQ(aov.exitCode, 2); // a usage error
    EXPECT_NE(aov.output().find("--aov"), std::string::npos);
    EXPECT_NE(run("render --size 0x10 -o x.png", dir).exitCode, 0);
    CmdResult fmt = run("render --size 8x8 -o x.bmp", dir);
    EXPECT_EQ(fmt.exitCode, 2); // a usage error
    EXPECT_NE(fmt.output().find("unsupported image format"), std::string::npos);
    std::ofstream(dir / "ok.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}]})";
    EXPECT_EQ(run("render ok.json -o ok.json", dir).exitCode, 2); // not an image format
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

// One list of model formats everywhere: `render MODEL` and `shader MODEL`
// take every mesh format the loaders read (an STL model used to be refused
// by `render` while scenes and `mesh` took it), and every --help, the
// README and docs/scene.md give the same list.
TEST(Cli, EveryMeshFormatIsAModelAndListedTheSameWay) {
    fs::path dir = scratch("formats");
    // A closed tetrahedron, outward facets.
    std::ofstream(dir / "t.stl") << R"(solid t
facet normal 0 0 -1
outer loop
vertex 0 0 0
vertex 0 1 0
vertex 1 0 0
endloop
endfacet
facet normal 0 -1 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 0 1
endloop
endfacet
facet normal -1 0 0
outer loop
vertex 0 0 0
vertex 0 0 1
vertex 0 1 0
endloop
endfacet
facet normal 1 1 1
outer loop
vertex 1 0 0
vertex 0 1 0
vertex 0 0 1
endloop
endfacet
endsolid t
)";
    CmdResult r = run("render t.stl --size 64x48 -o t.png", dir);
    ASSERT_EQ(r.exitCode, 0) << r.output();
    EXPECT_GT(distinctColours(readImage(dir / "t.png")), 2u);
    CmdResult sh = run("shader t.stl", dir);
    EXPECT_EQ(sh.exitCode, 0) << sh.output();
    EXPECT_NE(sh.out.find("#version 450"), std::string::npos);

    const std::string list = ".obj, .off, .ply, .stl, .gltf or .glb";
    CmdResult unknown = run("render t.xyz", dir);
    EXPECT_NE(unknown.exitCode, 0);
    EXPECT_NE(unknown.err.find("a model (" + list + ")"), std::string::npos) << unknown.err;
    for (const char* cmd :
         {"render --help", "shader --help", "view --help", "mesh --help", "mesh info --help",
          "mesh subdivide --help", "mesh morph --help", "mesh tangents --help"}) {
        CmdResult help = run(cmd, dir);
        EXPECT_EQ(help.exitCode, 0) << cmd;
        EXPECT_NE(help.out.find(list), std::string::npos) << cmd << ":\n" << help.out;
    }
    for (const char* doc : {"README.md", "docs/scene.md"}) {
        std::ifstream in(fs::path(SURFGRAD_SOURCE_DIR) / doc);
        const std::string text((std::istreambuf_iterator<char>(in)),
                               std::istreambuf_iterator<char>());
        EXPECT_NE(text.find(list), std::string::npos) << doc;
    }
}

// `mesh --help` and the top-level --help name every mesh subcommand
// (tangents was missing from the group's description).
TEST(Cli, MeshHelpNamesEveryMeshSubcommand) {
    fs::path dir = scratch("meshhelp");
    for (const char* cmd : {"--help", "mesh --help"}) {
        CmdResult help = run(cmd, dir);
        EXPECT_EQ(help.exitCode, 0);
        EXPECT_NE(help.out.find("mesh pipeline: info, subdivide, morph, tangents"),
                  std::string::npos)
            << cmd << ":\n"
            << help.out;
    }
}

// `render --help` on --tbn names both kinds of limit-surface mesh that
// `--tbn limit` applies to (adaptive ones were missing) and that
// mikktspace is refused on adaptive meshes (overrideTangents in
// cmd_render.cpp). CLI11 wraps long descriptions, so the text is compared
// with its whitespace collapsed.
TEST(Cli, RenderHelpSaysTbnLimitAppliesToAdaptiveMeshes) {
    const CmdResult help = run("render --help", scratch("tbnhelp"));
    ASSERT_EQ(help.exitCode, 0) << help.err;
    const std::string text = std::regex_replace(help.out, std::regex("\\s+"), " ");
    EXPECT_NE(text.find("limit applies to meshes drawn as the limit surface, \"subdivision\": "
                        "{\"limit\": true} or {\"mode\": \"adaptive\"}"),
              std::string::npos)
        << help.out;
    EXPECT_NE(text.find("mikktspace is refused on adaptive meshes"), std::string::npos) << help.out;
}

// `normalmap from-height --help` documents one spelling of the output's
// green convention, --to-green as every other op; --green is gone.
TEST(Cli, FromHeightHelpHasOneGreenOption) {
    const fs::path dir = scratch("greenhelp");
    const CmdResult help = run("normalmap from-height --help", dir);
    ASSERT_EQ(help.exitCode, 0) << help.err;
    EXPECT_NE(help.out.find("--to-green"), std::string::npos) << help.out;
    EXPECT_NE(help.out.find("Output green convention: gl (+v up, default) or dx"),
              std::string::npos)
        << help.out;
    EXPECT_EQ(std::regex_search(help.out, std::regex("(^|[^-])--green\\b")), false) << help.out;
    // --to-green sets the output's convention (the summary line names it).
    const std::string lava = std::string(SURFGRAD_DATA_DIR) + "/textures/lava_height.png";
    const CmdResult dx = run(
        "normalmap from-height " + sg::test::shellQuote(lava) + " -o dx.png --to-green dx", dir);
    EXPECT_EQ(dx.exitCode, 0) << dx.err;
    EXPECT_NE(dx.out.find("dx green"), std::string::npos) << dx.out;
    const CmdResult old =
        run("normalmap from-height " + sg::test::shellQuote(lava) + " -o gl.png --green dx", dir);
    EXPECT_EQ(old.exitCode, 2) << old.err;
    EXPECT_FALSE(fs::exists(dir / "gl.png"));
}

// Lines of a text, without their "\n".
std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    size_t at = 0;
    while (at < text.size()) {
        size_t end = text.find('\n', at);
        if (end == std::string::npos) end = text.size();
        out.push_back(text.substr(at, end - at));
        at = end + 1;
    }
    return out;
}

// A wrong command line, in every subcommand: exit 2 and two lines on
// stderr, "surfgrad: error: <subcommand>: <what>" and a pointer to that
// subcommand's --help (CLI11's own messages used to exit 105/106 in
// another format); bad input stays exit 1 with one line; --help states
// the exit statuses.
TEST(Cli, UsageErrorsExit2InOneFormat) {
    fs::path dir = scratch("usage");
    std::ofstream(dir / "s.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}]})";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--bogus", ""},
        {"render --bogus", "render"},
        {"render --aov normals", "render"},
        {"render --size 8x8 --frame x", "render"},
        {"shader --mesh -1", "shader"},
        {"shader s.json --mesh 3", "shader"},
        // Shader targets: an unknown name, several targets without a
        // folder, a folder that is not there, --body of another target.
        {"shader s.json --target glsl", "shader"},
        {"shader s.json --target es300,", "shader"},
        {"shader s.json --target all", "shader"},
        {"shader s.json --target spirv -o missing", "shader"},
        {"shader s.json --body --target es300", "shader"},
        {"view --frames -2", "view"},
        {"mesh", "mesh"},
        {"mesh info", "mesh info"},
        {"mesh subdivide s.obj -o x.obj", "mesh subdivide"},
        {"mesh subdivide s.obj --level 99 -o x.obj", "mesh subdivide"},
        {"mesh morph s.glb -o x.glb", "mesh morph"},
        {"mesh tangents", "mesh tangents"},
        {"features bake --size 16 -o x.exr", "features bake"},
        {"features sample", "features sample"},
        {"features render --profile crease -o x.png", "features render"},
        {"eval", "eval"},
        {"selftest --only nope", "selftest"},
        {"normalmap --bogus", "normalmap"},
        // A word that names no command, at the top and in a group.
        {"frobnicate", ""},
        {"mesh frobnicate", "mesh"},
        // Numbers that are not finite, or that a float cannot hold.
        {"render --frame nan", "render"},
        {"render --frame inf", "render"},
        {"normalmap scale n.png -o o.png --alpha nan", "normalmap scale"},
        {"normalmap from-height n.png -o o.png --scale 1e39", "normalmap from-height"},
        {"normalmap scale n.png -o o.png --alpha 1 --threads -5", "normalmap scale"},
        {"normalmap scale n.png -o o.png --alpha 1 --threads 0", "normalmap scale"},
        {"normalmap scale n.png -o o.png --alpha 1 --threads 2000", "normalmap scale"},
        // Options out of range or of the wrong kind: a usage error, not bad input.
        {"features bake --curves c.json --size 0 -o x.exr", "features bake"},
        {"normalmap mips n.png --lean -o x.png", "normalmap mips"},
        // An output format that cannot hold the image, before any work.
        {"features render m.exr --profile crease -o x.jpg", "features render"},
    };
    std::ofstream(dir / "n.png") << "not read: the command line is refused first";
    for (const auto& [args, command] : cases) {
        SCOPED_TRACE(args);
        CmdResult r = run(args, dir);
        EXPECT_EQ(r.exitCode, 2) << r.output();
        const std::vector<std::string> err = lines(r.err);
        ASSERT_EQ(err.size(), 2u) << r.err;
        const std::string prefix =
            "surfgrad: error: " + (command.empty() ? std::string() : command);
        EXPECT_EQ(err[0].rfind(prefix, 0), 0u) << err[0];
        EXPECT_EQ(err[1],
                  "Run 'surfgrad " + command + (command.empty() ? "" : " ") + "--help' for usage.");
    }
    // The unknown word and the commands there are named.
    const CmdResult word = run("mesh frobnicate", dir);
    EXPECT_NE(word.err.find("mesh: 'frobnicate' is not a command (commands: info, subdivide, "),
              std::string::npos)
        << word.err;
    EXPECT_NE(run("render --frame nan", dir).err.find("--frame"), std::string::npos);
    CmdResult bad = run("render missing.json -o x.png", dir);
    EXPECT_EQ(bad.exitCode, 1) << bad.output();
    EXPECT_EQ(lines(bad.err).size(), 1u) << bad.err;
    EXPECT_EQ(bad.err.rfind("surfgrad: error: ", 0), 0u) << bad.err;
    for (const char* help : {"--help", "render --help", "mesh subdivide --help"}) {
        CmdResult h = run(help, dir);
        EXPECT_EQ(h.exitCode, 0);
        EXPECT_NE(h.out.find("Exit status: 0 success; 1 bad input"), std::string::npos) << help;
    }
}

// A PNG texture whose data is corrupt: our one error line only (libpng's
// own "libpng error: ..." line used to be printed before it).
TEST(Cli, CorruptPngTextureGivesOneErrorLine) {
    fs::path dir = scratch("corrupt_png");
    // A valid 4x4 RGB PNG, then its compressed data overwritten.
    const Image img(4, 4, glm::vec4(0.5f, 0.25f, 1.0f, 1.0f));
    writeImage(dir / "good.png", img, Aov::Color, 1.0f);
    std::ifstream in(dir / "good.png", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const size_t idat = bytes.find("IDAT");
    ASSERT_NE(idat, std::string::npos);
    for (size_t i = idat + 4; i < bytes.size() - 16; ++i) bytes[i] = char(0xA5 ^ i);
    std::ofstream(dir / "bad.png", std::ios::binary) << bytes;
    std::ofstream(dir / "s.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}],
        "materials": [{"layers": [{"type": "uv_normal", "map": "bad.png"}]}]})";
    CmdResult r = run("render s.json --size 16x16 -o x.png", dir);
    EXPECT_EQ(r.exitCode, 1) << r.output();
    EXPECT_EQ(r.err.find("libpng error"), std::string::npos) << r.err;
    const std::vector<std::string> err = lines(r.err);
    ASSERT_EQ(err.size(), 1u) << r.err;
    EXPECT_EQ(err[0].rfind("surfgrad: error: ", 0), 0u);
    EXPECT_NE(err[0].find("bad.png"), std::string::npos);
    EXPECT_FALSE(fs::exists(dir / "x.png"));
}

// A JPEG texture cut short: refused, naming the file and why (libjpeg
// decodes it with a warning only and fills the rest grey).
TEST(Cli, TruncatedJpegTextureIsRefused) {
    fs::path dir = scratch("truncated_jpeg");
    const std::string good =
        fileBytes(fs::path(SURFGRAD_SOURCE_DIR) / "tests/fuzz/corpus/texture/baseline.jpg");
    // Cut inside the scan data (after the start-of-scan marker FF DA), where
    // every header is whole and only the end-of-image marker can tell.
    const size_t sos = good.find("\xff\xda");
    ASSERT_NE(sos, std::string::npos);
    for (const size_t keep : {good.size() - 2, good.size() - 1, sos + (good.size() - sos) / 2}) {
        SCOPED_TRACE(keep);
        std::ofstream(dir / "cut.jpg", std::ios::binary) << good.substr(0, keep);
        std::ofstream(dir / "s.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}],
            "materials": [{"layers": [{"type": "uv_normal", "map": "cut.jpg"}]}]})";
        CmdResult r = run("render s.json --cpu --size 16x16 -o x.png", dir);
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_NE(r.err.find("cut.jpg: JPEG scan data: truncated: no end-of-image marker"),
                  std::string::npos)
            << r.err;
        EXPECT_FALSE(fs::exists(dir / "x.png"));
    }
    // The whole file renders (the check passes what is complete).
    std::ofstream(dir / "cut.jpg", std::ios::binary) << good;
    EXPECT_EQ(run("render s.json --cpu --size 16x16 -o x.png", dir).exitCode, 0);
}

// A texture that is a folder or a FIFO is "not a regular file"; a missing
// one "does not exist".
TEST(Cli, TextureThatIsNotAFileSaysSo) {
    fs::path dir = scratch("texture_kind");
    fs::create_directories(dir / "folder.png");
    ASSERT_EQ(::mkfifo((dir / "fifo.png").c_str(), 0600), 0);
    for (const auto& [map, reason] :
         {std::pair<std::string, std::string>{"folder.png", "not a regular file"},
          {"fifo.png", "not a regular file"},
          {"missing.png", "does not exist"}}) {
        SCOPED_TRACE(map);
        std::ofstream(dir / "s.json") << R"({"meshes": [{"procedural": {"type": "sphere"}}],
            "materials": [{"layers": [{"type": "uv_normal", "map": ")" +
                                             map + R"("}]}]})";
        CmdResult r = run("render s.json --cpu --size 16x16 -o x.png", dir);
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_NE(r.err.find(map + ": " + reason), std::string::npos) << r.err;
    }
}

// An output that cannot be written is refused before the work starts: a
// CPU render of 4096x4096 would take minutes before failing at the end.
TEST(Cli, UnwritableOutputIsRefusedBeforeRendering) {
    fs::path dir = scratch("unwritable");
    std::ofstream(dir / "file") << "x";
    for (const std::string& out : {std::string("no/such/dir/x.png"), std::string("file/x.png")}) {
        SCOPED_TRACE(out);
        const CmdResult r = run("render --cpu --size 4096x4096 -o " + out, dir);
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_NE(r.err.find(out + ": cannot be written: "), std::string::npos) << r.err;
        // Refused before loading: no progress line of the CPU reference.
        EXPECT_EQ(r.err.find("CPU reference"), std::string::npos) << r.err;
    }
}

// A glTF model whose image URI leaves its folder: refused unless the
// command line allows it (--allow-outside-uris, before or after the command).
TEST(Cli, GltfUrisOutsideTheModelsFolderNeedTheOption) {
    fs::path dir = scratch("outside_uri");
    fs::create_directories(dir / "model");
    const fs::path box =
        fs::path(SURFGRAD_SOURCE_DIR) / "data/gltf/MultiUVTest/glTF/MultiUVTest.gltf";
    nlohmann::json j = nlohmann::json::parse(fileBytes(box));
    for (auto& b : j["buffers"]) {
        fs::copy_file(box.parent_path() / b["uri"].get<std::string>(),
                      dir / b["uri"].get<std::string>(), fs::copy_options::overwrite_existing);
        b["uri"] = "../" + b["uri"].get<std::string>();
    }
    for (auto& img : j["images"]) {
        fs::copy_file(box.parent_path() / img["uri"].get<std::string>(),
                      dir / "model" / img["uri"].get<std::string>(),
                      fs::copy_options::overwrite_existing);
    }
    std::ofstream(dir / "model/m.gltf") << j.dump();
    CmdResult refused = run("render model/m.gltf --cpu --size 16x16 -o x.png", dir);
    EXPECT_EQ(refused.exitCode, 1) << refused.output();
    EXPECT_NE(refused.err.find("outside the model's folder (refused; --allow-outside-uris"),
              std::string::npos)
        << refused.err;
    EXPECT_EQ(
        run("render model/m.gltf --cpu --size 16x16 -o x.png --allow-outside-uris", dir).exitCode,
        0);
    EXPECT_EQ(
        run("--allow-outside-uris render model/m.gltf --cpu --size 16x16 -o y.png", dir).exitCode,
        0);
}

// `features bake`: the curve network comes with --curves, --json only asks
// for the statistics (it used to mean both), the output must be .exr (a
// .png got OpenImageIO's "PNG only supports 1-4 channels"), and progress
// reaches 100% in every phase it reports (it stopped at "distance 90%").
TEST(FeaturesCli, BakeTakesCurvesWritesExrAndEndsProgressAt100) {
    fs::path dir = scratch("features_bake");
    std::ofstream(dir / "net.json")
        << R"({"version": 1, "curves": [{"points": [[0, 0], [10, 0], [10, 5]]}]})";
    CmdResult png = run("features bake --curves net.json --size 64 -o m.png", dir);
    EXPECT_EQ(png.exitCode, 2) << png.output();
    EXPECT_NE(png.err.find("-o m.png: feature maps are .exr"), std::string::npos) << png.err;
    EXPECT_FALSE(fs::exists(dir / "m.png"));
    CmdResult r = run("features bake --curves net.json --size 64 -o m.exr --json --progress", dir);
    ASSERT_EQ(r.exitCode, 0) << r.output();
    EXPECT_NE(r.out.find("\"size\":64"), std::string::npos) << r.out;
    const std::vector<std::string> progress = lines(r.err);
    ASSERT_FALSE(progress.empty());
    std::set<std::string> phases, finished;
    for (const std::string& l : progress) {
        ASSERT_EQ(l.rfind("features bake: ", 0), 0u) << l;
        const std::string phase = l.substr(15, l.find(' ', 15) - 15);
        phases.insert(phase);
        if (l.size() >= 4 && l.substr(l.size() - 4) == "100%") finished.insert(phase);
    }
    EXPECT_EQ(phases, finished) << r.err;
    EXPECT_EQ(progress.back().substr(progress.back().size() - 4), "100%");
    EXPECT_EQ(r.err.back(), '\n');
}

// An OpenEXR file's bytes without the value of its capDate attribute (the
// time of writing, "YYYY:MM:DD HH:MM:SS"): two saves of the same maps differ
// only there.
std::string withoutCapDate(std::string bytes) {
    const std::string key("capDate\0string\0", 15);
    const size_t at = bytes.find(key);
    if (at == std::string::npos || at + key.size() + 4 > bytes.size()) return bytes;
    int32_t length = 0;
    std::memcpy(&length, bytes.data() + at + key.size(), 4);
    bytes.erase(at + key.size() + 4, size_t(length));
    return bytes;
}

// `features bake --threads N`: 1..1024 (0 and 2000 are usage errors naming
// the option); the maps file is the same bytes at 1 and 3 threads (but for
// the time of writing).
TEST(FeaturesCli, BakeThreadsAreCheckedAndGiveTheSameFile) {
    fs::path dir = scratch("features_bake_threads");
    const std::string svg = std::string(SURFGRAD_DATA_DIR) + "/svg/paw-print.svg";
    for (const char* bad : {"0", "2000"}) {
        CmdResult r =
            run("features bake --svg " + svg + " --size 160 -o x.exr --threads " + bad, dir);
        EXPECT_EQ(r.exitCode, 2) << r.output();
        EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "x.exr"));
    }
    for (const char* threads : {"1", "3"}) {
        CmdResult r =
            run("features bake --svg " + svg + " --size 256 --mode quadratic --near exact -o t" +
                    threads + ".exr --threads " + threads,
                dir);
        ASSERT_EQ(r.exitCode, 0) << r.output();
    }
    const std::string one = fileBytes(dir / "t1.exr");
    ASSERT_NE(withoutCapDate(one).size(), one.size()); // the attribute was found
    EXPECT_TRUE(withoutCapDate(one) == withoutCapDate(fileBytes(dir / "t3.exr")));
}

// `features sample`: a header line names the columns; a point outside the
// map is an error naming its line (it used to get plausible values).
TEST(FeaturesCli, SampleHasAHeaderAndRefusesPointsOutsideTheMap) {
    fs::path dir = scratch("features_sample");
    std::ofstream(dir / "net.json")
        << R"({"version": 1, "curves": [{"points": [[0, 0], [10, 0], [10, 5]]}]})";
    ASSERT_EQ(run("features bake --curves net.json --size 64 -o m.exr", dir).exitCode, 0);
    std::ofstream(dir / "in.txt") << "10 10\n32.5 20.25\n";
    CmdResult r = run("features sample m.exr --points in.txt", dir);
    ASSERT_EQ(r.exitCode, 0) << r.output();
    const std::vector<std::string> out = lines(r.out);
    ASSERT_EQ(out.size(), 3u) << r.out;
    EXPECT_EQ(out[0], "x y dist grad_x grad_y");
    EXPECT_EQ(out[1].rfind("10 10 ", 0), 0u) << out[1];
    std::ofstream(dir / "out.txt") << "10 10\n70 10\n";
    CmdResult bad = run("features sample m.exr --points out.txt", dir);
    EXPECT_EQ(bad.exitCode, 1) << bad.output();
    EXPECT_TRUE(bad.out.empty()) << bad.out;
    EXPECT_NE(bad.err.find("out.txt: line 2: point (70, 10) is outside the map"), std::string::npos)
        << bad.err;
}

TEST(Cli, ExrOutputKeepsRawAovValues) {
    fs::path dir = scratch("exr");
    std::ofstream(dir / "p.json") << R"({"meshes": [{"procedural": {"type": "plane"}}],
        "camera": {"position": [0, 2, 0.01], "target": [0, 0, 0]}, "output": {"width": 32, "height": 24}})";
    ASSERT_EQ(run("render p.json --aov normal -o n.exr", dir).exitCode, 0);
    Image n = readImage(dir / "n.exr");
    // A flat plane without layers: the normal is +y everywhere it is seen.
    const glm::vec4 c = n.rgba(16, 12);
    EXPECT_NEAR(c.y, 1.0f, 1e-5f);
    EXPECT_NEAR(c.x, 0.0f, 1e-5f);
}

// The "mesh NAME: N vertices, ..." lines of `render -v`.
std::vector<std::string> meshLines(const std::string& out) {
    std::vector<std::string> lines;
    std::istringstream in(out);
    for (std::string l; std::getline(in, l);)
        if (l.rfind("mesh ", 0) == 0) lines.push_back(l);
    return lines;
}

// `--tbn limit` is the same request as the scene field "tangents": "limit":
// it changes only the tangents of meshes with limit subdivision (same
// geometry, same image as the field), leaves the other meshes of the scene
// alone (named in a note), and a scene without such a mesh is an error
// naming its meshes.
TEST(Cli, TbnLimitChangesOnlyTheTangentsOfLimitMeshes) {
    fs::path dir = scratch("tbn_limit");
    const std::string spot =
        (fs::path(SURFGRAD_DATA_DIR) / "meshes/spot/spot_control_mesh.obj").string();
    auto scene = [&](const std::string& limitTangents) {
        return R"({"output": {"width": 96, "height": 64},
            "materials": [{"layers": [{"type": "uv_normal", "map": {"procedural": "bumps"}}]}],
            "meshes": [{"file": ")" +
               spot + R"(", "subdivision": {"level": 1, "limit": true})" + limitTangents + R"(},
                       {"file": ")" +
               spot + R"(", "transform": {"translate": [1.5, 0, 0]}},
                       {"procedural": {"type": "plane", "size": 4}, "transform": {"translate": [0, -1, 0]}}]})";
    };
    std::ofstream(dir / "s.json") << scene("");
    std::ofstream(dir / "field.json") << scene(R"(, "tangents": "limit")");
    CmdResult plain = run("render s.json -v --aov normal -o plain.exr", dir);
    ASSERT_EQ(plain.exitCode, 0) << plain.output();
    CmdResult cli = run("render s.json -v --tbn limit --aov normal -o cli.exr", dir);
    ASSERT_EQ(cli.exitCode, 0) << cli.output();
    CmdResult field = run("render field.json --aov normal -o field.exr", dir);
    ASSERT_EQ(field.exitCode, 0) << field.output();
    // Same vertex and triangle counts for every mesh (no mesh gets refined).
    EXPECT_EQ(meshLines(cli.out), meshLines(plain.out));
    EXPECT_EQ(meshLines(cli.out).size(), 3u) << cli.out;
    EXPECT_NE(cli.err.find("--tbn limit: meshes[1], meshes[2] keep their tangents"),
              std::string::npos)
        << cli.err;
    // The same request as the field: the same image, bit for bit (same
    // program, same inputs, same driver).
    Image a = readImage(dir / "cli.exr"), b = readImage(dir / "field.exr");
    ASSERT_EQ(a.texelCount(), b.texelCount());
    size_t differ = 0;
    for (size_t i = 0; i < a.texelCount(); ++i) differ += a.rgba(i) != b.rgba(i);
    EXPECT_EQ(differ, 0u);
    // Without a limit mesh: a usage error (exit 2: the option does not fit
    // the scene) naming the meshes, and no image.
    std::ofstream(dir / "none.json") << R"({"meshes": [{"file": ")" + spot +
                                            R"(", "subdivision": {"level": 1}},
        {"procedural": {"type": "sphere"}}]})";
    CmdResult none = run("render none.json --tbn limit -o none.png", dir);
    EXPECT_EQ(none.exitCode, 2);
    EXPECT_NE(none.err.find("surfgrad: error: render: --tbn limit: meshes[0], meshes[1]: limit "
                            "tangents "
                            "need \"subdivision\": {\"limit\": true}"),
              std::string::npos)
        << none.output();
    EXPECT_FALSE(fs::exists(dir / "none.png"));
}

// The summary line says what each time is: the wall time of the draws and
// the GPU draw time only when the timer query measured the frame (every
// frame of --all-frames has its own); no timing values are asserted.
TEST(Cli, RenderPrintsLabelledTimes) {
    fs::path dir = scratch("times");
    std::ofstream(dir / "a.json") << R"({"output": {"width": 48, "height": 32},
        "meshes": [{"procedural": {"type": "sphere"}}], "frames": {"count": 3, "fps": 24}})";
    CmdResult r = run("render a.json --all-frames -o a.png", dir);
    ASSERT_EQ(r.exitCode, 0) << r.output();
    const std::regex line(
        R"(wrote a_000[0-2]\.png \(48x32, color, OpenGL, [0-9]+ programs? compiled, draw [0-9.e+-]+ ms wall, GPU draw time \(timer query\) ([0-9.e+-]+ ms|not measured), [0-9.]+ s elapsed\))");
    std::istringstream in(r.out);
    int lines = 0;
    for (std::string l; std::getline(in, l); ++lines) {
        EXPECT_TRUE(std::regex_match(l, line)) << l;
        // A printed GPU time is one the query measured: never a zero.
        EXPECT_EQ(l.find("(timer query) 0 ms"), std::string::npos) << l;
    }
    EXPECT_EQ(lines, 3);
    CmdResult cpu = run("render a.json --cpu -o c.png", dir);
    ASSERT_EQ(cpu.exitCode, 0) << cpu.output();
    EXPECT_TRUE(std::regex_match(
        cpu.out,
        std::regex(R"(wrote c\.png \(48x32, color, CPU reference, [0-9.]+ s elapsed\)\n)")))
        << cpu.out;
}

// Long work shows progress on stderr, a line per step ending with a
// newline: subdivision to high levels, the bands of a large GPU render, the
// rows of a CPU reference render, the write of a large image.
TEST(Cli, LongRendersShowProgress) {
    fs::path dir = scratch("progress");
    const std::string spot =
        (fs::path(SURFGRAD_DATA_DIR) / "meshes/spot/spot_control_mesh.obj").string();
    std::ofstream(dir / "s.json") << R"({"meshes": [{"file": ")" + spot +
                                         R"(", "subdivision": {"level": 4}}]})";
    CmdResult gl = run("render s.json --size 2048x2048 -o big.png", dir);
    ASSERT_EQ(gl.exitCode, 0) << gl.output();
    EXPECT_NE(gl.err.find("surfgrad: meshes[0]: subdividing to level 4"), std::string::npos)
        << gl.err;
    for (int b = 1; b <= 4; ++b) {
        EXPECT_NE(gl.err.find("surfgrad: drawing 2048x2048: " + std::to_string(b) + "/4 bands\n"),
                  std::string::npos)
            << gl.err;
    }
    EXPECT_NE(gl.err.find("surfgrad: writing big.png\n"), std::string::npos) << gl.err;
    std::ofstream(dir / "c.json")
        << R"({"meshes": [{"procedural": {"type": "sphere", "segments": 8}}]})";
    CmdResult cpu = run("render c.json --cpu --size 512x512 -o c.png", dir);
    ASSERT_EQ(cpu.exitCode, 0) << cpu.output();
    EXPECT_NE(cpu.err.find("surfgrad: CPU reference 512x512: 512/512 rows\n"), std::string::npos)
        << cpu.err;
    EXPECT_EQ(cpu.err.back(), '\n');
}

// Errors in files a scene references keep the scene's context: the scene
// file, the JSON path of the field naming the file, the file (lexically
// normal), then the loader's reason; no image is written.
TEST(Cli, ReferencedFileErrorsNameTheSceneField) {
    fs::path dir = scratch("referenced");
    fs::create_directories(dir / "sub");
    auto expectError = [&](const std::string& json, const std::string& prefix) {
        std::ofstream(dir / "scene.json") << json;
        CmdResult r = run("render scene.json --size 16x16 -o x.png", dir);
        EXPECT_EQ(r.exitCode, 1);
        EXPECT_EQ(r.err.rfind("surfgrad: error: " + prefix, 0), 0u) << r.err;
        EXPECT_EQ(r.err.find("/../"), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find("sub/.."), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "x.png"));
    };
    // A missing mesh, named through a path that is not normal.
    expectError(
        R"({"meshes": [{"procedural": {"type": "sphere"}}, {"procedural": {"type": "plane"}},
                                {"file": "sub/../missing.obj"}]})",
        "scene.json: meshes[2].file: missing.obj: ");
    // A non-manifold mesh: three triangles share the edge 1-2.
    std::ofstream(dir / "sub/fan.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\n"
                                          "f 1 2 3\nf 2 1 4\nf 1 2 5\n";
    expectError(R"({"meshes": [{"file": "./sub/fan.obj", "subdivision": {"level": 1}}]})",
                "scene.json: meshes[0].file: sub/fan.obj: ");
    // A bad SVG curve file of a feature layer.
    std::ofstream(dir / "bad.svg") << "<svg><path d=\"M 0 0 L x y\"/></svg>";
    expectError(R"({"meshes": [{"procedural": {"type": "plane"}}],
        "materials": [{"layers": [{"type": "feature", "curves": {"svg": "sub/../bad.svg"}}]}]})",
                "scene.json: materials[0].layers[0].curves.svg: bad.svg: ");
    // A missing texture: the same shape.
    expectError(R"({"meshes": [{"procedural": {"type": "plane"}}],
        "materials": [{"layers": [{"type": "uv_normal", "map": "sub/../none.png"}]}]})",
                "scene.json: materials[0].layers[0].map: none.png: does not exist");
}

// The shell command running `surfgrad args` on a virtual X server.
std::string underXvfb(const std::string& args) {
    return "xvfb-run -a -s '-screen 0 1280x1024x24' " +
           sg::test::shellQuote(sg::test::surfgradBinary()) + " " + args;
}

TEST(Viewer, OpensUnderXvfbAndScreenshotsTheWindow) {
    fs::path dir = scratch("viewer");
    const CmdResult r = sg::test::runCommand(
        underXvfb("view --frames 3 --size 400x300 --screenshot shot.png"), {.cwd = dir});
    ASSERT_EQ(r.exitCode, 0) << r.output();
    Image shot = readImage(dir / "shot.png");
    EXPECT_EQ(shot.width, 400);
    EXPECT_EQ(shot.height, 300);
    // The render, the display pass and the panel: many colours.
    EXPECT_GT(distinctColours(shot), 100u);
}

// `view --screenshot` alone: the first complete frame (panel included),
// then the viewer quits by itself; `timeout` turns a viewer that waits for
// a window close (which never comes under Xvfb) into exit status 124.
TEST(Viewer, ScreenshotWithoutFramesQuitsAfterTheFirstCompleteFrame) {
    fs::path dir = scratch("viewer_once");
    const CmdResult r = sg::test::runCommand(
        "timeout 120 " + underXvfb("view --size 400x300 --screenshot shot.png"), {.cwd = dir});
    ASSERT_EQ(r.exitCode, 0) << r.output();
    Image shot = readImage(dir / "shot.png");
    EXPECT_EQ(shot.width, 400);
    // The panel is drawn (an incomplete first ImGui frame has none).
    EXPECT_GT(distinctColours(shot), 100u);
}

// A screenshot path that cannot be written is refused before the window opens.
TEST(Viewer, UnwritableScreenshotIsRefusedFirst) {
    fs::path dir = scratch("viewer_bad_out");
    const CmdResult r =
        sg::test::runCommand("timeout 120 " + sg::test::shellQuote(sg::test::surfgradBinary()) +
                                 " view --screenshot no/such/folder/shot.png",
                             {.cwd = dir});
    EXPECT_EQ(r.exitCode, 1) << r.output();
    EXPECT_NE(r.output().find("no/such/folder/shot.png: cannot be written: the folder "
                              "no/such/folder does not exist"),
              std::string::npos)
        << r.output();
}

// Fraction of the pixels in columns [x0, x1) whose 8-bit RGB values differ
// by more than `levels` in some channel.
double differingFraction(const Image& a, const Image& b, int x0, int x1, int levels) {
    size_t n = 0, bad = 0;
    for (int y = 0; y < a.height; ++y)
        for (int x = x0; x < x1; ++x, ++n) {
            const glm::vec4 d = glm::abs(a.rgba(x, y) - b.rgba(x, y)) * 255.0f;
            bad += std::max({d.x, d.y, d.z}) > float(levels) + 0.5f;
        }
    return n ? double(bad) / double(n) : 0.0;
}

// `view --no-ui --screenshot`: the window without the panel, i.e. the image
// `surfgrad render` writes for the same scene and size; with the panel, the
// panel's region (the right viewerPanelWidth(400) = 200 px) differs.
TEST(Viewer, CleanScreenshotHasNoPanel) {
    fs::path dir = scratch("viewer_clean");
    const std::string view = underXvfb("view --frames 3 --size 400x300 --screenshot ");
    CmdResult clean = sg::test::runCommand(view + "clean.png --no-ui", {.cwd = dir});
    ASSERT_EQ(clean.exitCode, 0) << clean.output();
    CmdResult ui = sg::test::runCommand(view + "ui.png", {.cwd = dir});
    ASSERT_EQ(ui.exitCode, 0) << ui.output();
    CmdResult cli = run("render --size 400x300 -o cli.png", dir);
    ASSERT_EQ(cli.exitCode, 0) << cli.output();
    Image c = readImage(dir / "clean.png"), u = readImage(dir / "ui.png"),
          r = readImage(dir / "cli.png");
    ASSERT_EQ(c.width, 400);
    ASSERT_EQ(c.height, 300);
    ASSERT_EQ(r.width, 400);
    // The same render through the same sgToneMap, once into the 8-bit
    // window and once into the PNG: within 2 levels (rounding of each
    // path), except where the viewer's orbit near/far planes (not the
    // scene camera's) flip a depth test at silhouettes: under 1% of pixels.
    EXPECT_LT(differingFraction(c, r, 0, 400, 2), 0.01);
    // The panel covers its region: most of it differs from the render.
    EXPECT_GT(differingFraction(u, r, 200, 400, 2), 0.5);
    EXPECT_LT(differingFraction(u, r, 0, 200, 2), 0.01);
}

} // namespace
} // namespace sg::render::test

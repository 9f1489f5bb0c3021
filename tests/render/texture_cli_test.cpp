// Image inputs that declare gigabytes, through `surfgrad render` under an
// address-space limit of 1.5 GB (issue 16): each is refused with the scene
// file, the field, the image and the reason, exit status 1, and no
// std::bad_alloc. The limit proves nothing large is allocated: `ulimit -v`
// in a plain build; in a sanitizer build (ASan reserves terabytes of
// address space) ASan's own allocation limit. No timing is asserted.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli.h"
#include "giga_images.h"
#include "render_test_util.h"

namespace sg::render::test {
namespace {

namespace fs = std::filesystem;

using sg::test::CommandResult;

// Runs `surfgrad ARGS` in `cwd` with at most 1.5 GB of memory.
CommandResult runLimited(const std::string& args, const fs::path& cwd) {
    return sg::test::runSurfgradMemoryLimited(args, cwd);
}

fs::path scratch(const std::string& name) {
    fs::path p = fs::path(SURFGRAD_BINARY_DIR) / "tests/render/texture_cli" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

// The issue's scene with `map` as the normal map of its one layer.
void writeScene(const fs::path& file, const std::string& map, const std::string& layerExtra = "") {
    std::ofstream(file)
        << R"({"output": {"width": 64, "height": 64}, "materials": [{"name": "m", )"
        << R"("layers": [{"type": "uv_normal", "map": ")" << map << "\"" << layerExtra
        << R"(}]}], "meshes": [{"procedural": {"type": "plane"}, "material": "m"}]})";
}

TEST(TextureLimits, HeadersPromisingGigabytesAreRefusedUnderAMemoryLimit) {
    const fs::path dir = scratch("giga");
    for (const sg::test::GigaImage& c : sg::test::gigaImages()) {
        SCOPED_TRACE(c.file);
        const std::string map = (sg::test::gigaImageDir() / c.file).string();
        writeScene(dir / "scene.json", map);
        const CommandResult r = runLimited("render scene.json -o out.png", dir);
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_NE(r.output().find("surfgrad: error: scene.json: materials[0].layers[0].map: " +
                                  map + ": " + c.reason),
                  std::string::npos)
            << r.output();
        EXPECT_EQ(r.output().find("bad_alloc"), std::string::npos) << r.output();
        EXPECT_FALSE(fs::exists(dir / "out.png"));
    }
}

// A glTF model's own images go through the same checks (sceneForModel):
// BoxTextured with its base colour image replaced by the issue's PNG.
TEST(TextureLimits, GltfMaterialImagesAreCheckedToo) {
    const fs::path dir = scratch("gltf");
    const fs::path box = fs::path(SURFGRAD_DATA_DIR) / "gltf/BoxTextured/glTF";
    fs::copy_file(box / "BoxTextured.gltf", dir / "BoxTextured.gltf");
    fs::copy_file(box / "BoxTextured0.bin", dir / "BoxTextured0.bin");
    fs::copy_file(fs::path(SURFGRAD_SOURCE_DIR) / "tests/fuzz/corpus/texture/issue16_huge_dims.png",
                  dir / "CesiumLogoFlat.png");
    const CommandResult r = runLimited("render BoxTextured.gltf -o out.png", dir);
    EXPECT_EQ(r.exitCode, 1) << r.output();
    EXPECT_NE(r.output().find("surfgrad: error: BoxTextured.gltf: BoxTextured.gltf "
                              "materials[0].baseColorTexture: "),
              std::string::npos)
        << r.output();
    EXPECT_NE(r.output().find("CesiumLogoFlat.png: PNG IDAT: 16384x16384 pixels"),
              std::string::npos)
        << r.output();
}

// CRC-32 of PNG chunks (ISO 15948 annex D).
uint32_t crc32(const std::string& bytes) {
    uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : bytes) {
        c ^= b;
        for (int k = 0; k < 8; ++k) c = c & 1u ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    }
    return c ^ 0xFFFFFFFFu;
}

std::string be32(uint32_t v) {
    return {char(v >> 24), char(v >> 16 & 255u), char(v >> 8 & 255u), char(v & 255u)};
}

std::string pngChunk(const std::string& type, const std::string& data) {
    return be32(uint32_t(data.size())) + type + data + be32(crc32(type + data));
}

// A 16384x16384 RGBA 16-bit PNG whose 2.1 MB of IDAT are enough, by the
// deflate bound, for its 2 GiB of rows (they are zeros, not valid deflate
// data). Within a budget raised past the memory limit, level 0 (2 GiB)
// cannot be allocated: the refusal names the image and the size of level 0.
TEST(TextureLimits, RunningOutOfMemoryNamesTheImageAndItsSize) {
    const fs::path dir = scratch("oom");
    std::string ihdr = be32(16384) + be32(16384);
    ihdr += std::string{char(16), char(6), 0, 0, 0}; // 16-bit RGBA, not interlaced
    const uint64_t rows = uint64_t(16384) * (1 + uint64_t(16384) * 8);
    const std::string idat(size_t(rows / 1032 + 1), '\0');
    std::ofstream(dir / "big.png", std::ios::binary)
        << std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) + pngChunk("IDAT", idat) +
               pngChunk("IEND", "");
    // "ag" reads g and a: all 4 channels are decoded.
    const std::string map = (dir / "big.png").string();
    writeScene(dir / "scene.json", map, R"(, "encoding": "ag")");
#ifdef SG_TEST_ASAN
    // ASan aborts on a failed operator new instead of throwing
    // std::bad_alloc, so a sanitizer build checks the budget's refusal of
    // the same file instead of the out-of-memory path.
    const CommandResult r = runLimited("render scene.json -o out.png --texture-budget 1G", dir);
    const std::string expected = map + ": 16384x16384 pixels, 4 channels as 16-bit unorm: needs "
                                       "3.33 GiB with its mip chain";
#else
    const CommandResult r = runLimited("render scene.json -o out.png --texture-budget 64G", dir);
    const std::string expected = map + ": out of memory decoding 16384x16384 pixels, 4 channels "
                                       "as 16-bit unorm (2.00 GiB)";
#endif
    EXPECT_EQ(r.exitCode, 1) << r.output();
    EXPECT_NE(
        r.output().find("surfgrad: error: scene.json: materials[0].layers[0].map: " + expected),
        std::string::npos)
        << r.output();
    EXPECT_EQ(r.output().find("std::bad_alloc"), std::string::npos) << r.output();
}

TEST(TextureLimits, TheBudgetOptionIsParsedAndNamedInMessages) {
    const fs::path dir = scratch("option");
    const std::string map =
        (fs::path(SURFGRAD_SOURCE_DIR) / "tests/fuzz/corpus/texture/rgb8.png").string();
    writeScene(dir / "scene.json", map);
    // 16x16 RGB 8-bit, 2 channels read: 512 bytes + the float mip chain.
    const CommandResult tiny = runLimited("render scene.json -o out.png --texture-budget 1K", dir);
    EXPECT_EQ(tiny.exitCode, 1) << tiny.output();
    EXPECT_NE(tiny.output().find(map + ": 16x16 pixels, 2 of 3 channels as 8-bit unorm: needs "),
              std::string::npos)
        << tiny.output();
    EXPECT_NE(tiny.output().find("the texture budget is 1.00 KiB (--texture-budget)"),
              std::string::npos)
        << tiny.output();
    EXPECT_EQ(runLimited("shader scene.json --texture-budget 2MiB", dir).exitCode, 0);
    const CommandResult bad = runLimited("render scene.json -o out.png --texture-budget 1X", dir);
    EXPECT_EQ(bad.exitCode, 2) << bad.output(); // a malformed option: a usage error
    EXPECT_NE(bad.output().find("--texture-budget: expected a size such as 512M"),
              std::string::npos)
        << bad.output();
    EXPECT_EQ(runLimited("shader scene.json --texture-budget 1K", dir).exitCode, 1);
}

} // namespace
} // namespace sg::render::test

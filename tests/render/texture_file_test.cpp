// Texture files (render/src/texture_file.cpp, surfgrad/image/image_header.h):
// every format a scene accepts decodes to exactly the values OpenImageIO
// gives as float (colour not premultiplied by alpha), in the file's own
// precision; the mip chain equals the all-float chain bit for bit; layers
// decode only the channels they read and refuse ones the file lacks;
// non-finite texels are refused; the texture budget covers all of a
// scene's textures.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>

#include "render_test_util.h"
#include "surfgrad/image/image_header.h"
#include "surfgrad/base/io.h"

namespace sg::render::test {
namespace {

namespace fs = std::filesystem;

fs::path corpus(const std::string& name) {
    return fs::path(SURFGRAD_SOURCE_DIR) / "tests/fuzz/corpus/texture" / name;
}

fs::path scratch(const std::string& name) {
    fs::path p = fs::path(SURFGRAD_BINARY_DIR) / "tests/render/texture_files" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

std::string readBytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The file as OpenImageIO reads it to float (what the loader stored before
// textures kept their own precision), top row first.
struct FloatImage {
    int width = 0, height = 0, channels = 0;
    std::vector<float> px;
    // RGBA of file pixel (x, yTop) with the loader's channel expansion.
    glm::vec4 rgba(int x, int yTop) const {
        const float* p = &px[(size_t(yTop) * size_t(width) + size_t(x)) * size_t(channels)];
        if (channels == 1) return glm::vec4(p[0], p[0], p[0], 1.0f);
        glm::vec4 t(0.0f, 0.0f, 0.0f, 1.0f);
        for (int c = 0; c < std::min(channels, 4); ++c) t[c] = p[c];
        return t;
    }
};

FloatImage readFloat(const fs::path& p) {
    FloatImage im;
    OIIO::ImageSpec config; // raw values, as textures read them
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(p.string(), &config);
    if (!in) {
        ADD_FAILURE() << p << ": " << OIIO::geterror();
        return im;
    }
    im.width = in->spec().width;
    im.height = in->spec().height;
    im.channels = in->spec().nchannels;
    im.px.resize(size_t(im.width) * size_t(im.height) * size_t(im.channels));
    EXPECT_TRUE(in->read_image(0, 0, 0, im.channels, OIIO::TypeDesc::FLOAT, im.px.data()));
    return im;
}

void writeImage(const fs::path& p, int w, int h, int nc, OIIO::TypeDesc type, const void* data) {
    auto out = OIIO::ImageOutput::create(p.string());
    ASSERT_TRUE(out);
    OIIO::ImageSpec spec(w, h, nc, type);
    ASSERT_TRUE(out->open(p.string(), spec));
    ASSERT_TRUE(out->write_image(type, data));
    ASSERT_TRUE(out->close());
}

bool sameBits(const glm::vec4& a, const glm::vec4& b) {
    return std::memcmp(&a, &b, 16) == 0;
}

// Every texel of every level of `img` equals the same level of `ref`.
void expectSameChain(const TextureImage& img, const TextureImage& ref, const std::string& what) {
    ASSERT_EQ(img.levels.size(), ref.levels.size()) << what;
    for (size_t l = 0; l < img.levels.size(); ++l) {
        const TextureLevel &a = img.levels[l], &b = ref.levels[l];
        ASSERT_EQ(a.width, b.width);
        ASSERT_EQ(a.height, b.height);
        size_t differ = 0;
        for (int y = 0; y < a.height; ++y)
            for (int x = 0; x < a.width; ++x) differ += !sameBits(a.texel(x, y), b.texel(x, y));
        EXPECT_EQ(differ, 0u) << what << ", level " << l;
    }
}

// The loader's previous texture: OpenImageIO's floats, expanded to RGBA
// (bottom row first), sRGB-decoded for colour maps, all-float mip chain.
TextureImage floatReference(const FloatImage& im, bool srgb) {
    std::vector<glm::vec4> texels(size_t(im.width) * size_t(im.height));
    for (int y = 0; y < im.height; ++y)
        for (int x = 0; x < im.width; ++x) {
            glm::vec4 t = im.rgba(x, im.height - 1 - y);
            for (int c = 0; c < 3 && srgb; ++c) t[c] = srgbToLinear(t[c]);
            texels[size_t(y) * size_t(im.width) + size_t(x)] = t;
        }
    return makeTexture(im.width, im.height, std::move(texels), Wrap::Repeat);
}

const char* const kValidFiles[] = {
    "rgb8.png",
    "grey16.png",
    "rgba8.png",
    "palette4_trns_interlaced.png",
    "baseline.jpg",
    "progressive.jpg",
    "grey.jpg",
    "half_zip.exr",
    "float_piz_tiled.exr",
    "half_dwaa.exr",
    "y_rle.exr",
    "half_none.exr",
    "half_mip_tiled.exr",
    "u8_lzw.tif",
    "float_deflate.tif",
    "u16_tiled.tif",
    "u8_packbits.tif",
    "u8_separate.tif",
    "u8_6ch.tif",
    "rle.hdr",
    "flat.hdr",
    "rgb.tga",
    "rgba_rle.tga",
    "grey.tga",
};

TEST(TextureFiles, EveryFormatDecodesToOpenImageIOsFloatValuesAndTheSameMipChain) {
    for (const char* file : kValidFiles) {
        SCOPED_TRACE(file);
        const FloatImage ref = readFloat(corpus(file));
        const std::string bytes = readBytes(corpus(file));
        for (bool srgb : {false, true}) {
            TextureImage img = decodeTextureImage(bytes, file, srgb, Wrap::Repeat);
            EXPECT_EQ(img.sourceChannels, ref.channels);
            EXPECT_EQ(img.bytes(), textureBytes(img.width(), img.height(), img.levels[0].channels,
                                                img.levels[0].type));
            expectSameChain(img, floatReference(ref, srgb), srgb ? "sRGB" : "raw");
        }
    }
}

// Colour channels come as stored, not multiplied by alpha (a normal map
// may carry a height in alpha): rgba8.png has alpha from 0 to 1.
TEST(TextureFiles, ColourChannelsAreNotPremultipliedByAlpha) {
    const FloatImage raw = readFloat(corpus("rgba8.png"));
    auto premultiplied = OIIO::ImageInput::open(corpus("rgba8.png").string());
    ASSERT_TRUE(premultiplied);
    std::vector<float> pre(raw.px.size());
    ASSERT_TRUE(premultiplied->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, pre.data()));
    ASSERT_NE(pre, raw.px) << "the file should have partial alpha";
    const TextureImage img =
        decodeTextureImage(readBytes(corpus("rgba8.png")), "rgba8.png", false, Wrap::Repeat);
    for (int y = 0; y < raw.height; ++y)
        for (int x = 0; x < raw.width; ++x)
            EXPECT_TRUE(sameBits(img.levels[0].texel(x, raw.height - 1 - y), raw.rgba(x, y)));
}

TEST(TextureFiles, LevelZeroKeepsTheFilesPrecision) {
    auto typeOf = [](const char* file) {
        return decodeTextureImage(readBytes(corpus(file)), file, false, Wrap::Repeat)
            .levels[0]
            .type;
    };
    EXPECT_EQ(typeOf("rgb8.png"), TexelType::Unorm8);
    EXPECT_EQ(typeOf("grey16.png"), TexelType::Unorm16);
    EXPECT_EQ(typeOf("baseline.jpg"), TexelType::Unorm8);
    EXPECT_EQ(typeOf("half_zip.exr"), TexelType::Half);
    EXPECT_EQ(typeOf("float_piz_tiled.exr"), TexelType::Float);
    EXPECT_EQ(typeOf("u16_tiled.tif"), TexelType::Unorm16);
    EXPECT_EQ(typeOf("float_deflate.tif"), TexelType::Float);
    EXPECT_EQ(typeOf("rle.hdr"), TexelType::Float);
    EXPECT_EQ(typeOf("rgb.tga"), TexelType::Unorm8);
    // An sRGB half map has no decoding table: it is stored decoded, as float.
    EXPECT_EQ(decodeTextureImage(readBytes(corpus("half_zip.exr")), "h.exr", true, Wrap::Repeat)
                  .levels[0]
                  .type,
              TexelType::Float);
}

// Every 8- and 16-bit code, raw and sRGB: the stored sample reads as
// OpenImageIO's float and, for colour maps, as srgbToLinear of it.
TEST(TextureFiles, EveryUnormCodeReadsAsOpenImageIOsFloat) {
    const fs::path dir = scratch("codes");
    std::vector<uint8_t> c8(256);
    for (size_t i = 0; i < c8.size(); ++i) c8[i] = uint8_t(i);
    std::vector<uint16_t> c16(65536);
    for (size_t i = 0; i < c16.size(); ++i) c16[i] = uint16_t(i);
    writeImage(dir / "c8.png", 16, 16, 1, OIIO::TypeDesc::UINT8, c8.data());
    writeImage(dir / "c16.png", 256, 256, 1, OIIO::TypeDesc::UINT16, c16.data());
    for (const char* f : {"c8.png", "c16.png"}) {
        const FloatImage ref = readFloat(dir / f);
        for (bool srgb : {false, true}) {
            TextureImage img = decodeTextureImage(readBytes(dir / f), f, srgb, Wrap::Repeat);
            expectSameChain(img, floatReference(ref, srgb), std::string(f) + (srgb ? " sRGB" : ""));
        }
    }
}

// What a scene's layers read decides what is decoded.
TEST(TextureFiles, LayersDecodeOnlyTheChannelsTheyRead) {
    const std::string six = corpus("u8_6ch.tif").string();
    // A normal map reads r and g: 2 of the 6 channels are kept.
    Scene s = sceneFromJson(
        oneMaterialScene(R"({"type": "uv_normal", "map": ")" + six + R"("})", kSphere));
    SceneAssets a = loadAssets(s);
    ASSERT_EQ(a.textures.size(), 1u);
    const TextureImage& t = *a.textures.begin()->second;
    EXPECT_EQ(t.sourceChannels, 6);
    EXPECT_EQ(t.levels[0].channels, 2);
    EXPECT_EQ(t.channelMask, 0x3u);
    // A height layer reading alpha from the same file, enabled later (the
    // viewer's toggle): the texture is decoded again with 4 channels.
    Scene s2 = sceneFromJson(oneMaterialScene(
        R"({"type": "uv_normal", "map": ")" + six +
            R"("}, {"type": "height", "enabled": false, "channel": "a", "map": ")" + six + R"("})",
        kSphere));
    SceneAssets a2 = loadAssets(s2);
    EXPECT_EQ(a2.textures.begin()->second->levels[0].channels, 2);
    s2.materials[0].layers[1].enabled = true;
    loadMissingAssets(s2, a2);
    ASSERT_EQ(a2.textures.size(), 1u);
    EXPECT_EQ(a2.textures.begin()->second->levels[0].channels, 4);
    EXPECT_EQ(a2.textures.begin()->second->channelMask, 0xFu);
}

TEST(TextureFiles, AChannelTheFileLacksIsRefusedWithTheField) {
    auto refusal = [](const std::string& layer) {
        Scene s = sceneFromJson(oneMaterialScene(layer, kSphere));
        try {
            loadAssets(s);
        } catch (const io::InputError& e) {
            return std::string(e.what());
        }
        return std::string("accepted");
    };
    const std::string rgb = corpus("rgb8.png").string(), grey = corpus("grey.jpg").string();
    EXPECT_NE(refusal(R"({"type": "height", "channel": "a", "map": ")" + rgb + R"("})")
                  .find("test.json: materials[0].layers[0].map: " + rgb +
                        ": the height channel reads channel a, but the image has 3 channels "
                        "(r, g, b)"),
              std::string::npos);
    // DXT5nm ("ag") reads alpha; a grey image has r, g and b only.
    EXPECT_NE(refusal(R"({"type": "uv_normal", "encoding": "ag", "map": ")" + grey + R"("})")
                  .find("the normal encoding reads channel a, but the image has 1 channel "
                        "(grey: r, g, b)"),
              std::string::npos);
    // A grey image is a fine height map (any of r, g, b).
    EXPECT_EQ(refusal(R"({"type": "height", "channel": "b", "map": ")" + grey + R"("})"),
              "accepted");
}

TEST(TextureFiles, NonFiniteOrHugeTexelsAreRefusedUnlessNoLayerReadsThem) {
    const fs::path dir = scratch("nan");
    std::vector<float> px(8 * 4 * 4, 0.5f);
    px[(1 * 8 + 3) * 4 + 1] = std::nanf(""); // pixel (3, 1), green
    px[(2 * 8 + 5) * 4 + 3] = INFINITY;      // pixel (5, 2), alpha
    writeImage(dir / "nan.exr", 8, 4, 4, OIIO::TypeDesc::FLOAT, px.data());
    const std::string bytes = readBytes(dir / "nan.exr");
    try {
        decodeTextureImage(bytes, "nan.exr", false, Wrap::Repeat);
        ADD_FAILURE() << "NaN texel accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), "pixel (3, 1) channel 1");
        EXPECT_EQ(e.reason(), "non-finite value");
    }
    // Only red is read: the NaN green and the infinite alpha are not decoded.
    TextureLoadOptions red;
    red.channels = 0x1u;
    TextureImage r = decodeTextureImage(bytes, "nan.exr", false, Wrap::Repeat, red);
    EXPECT_EQ(r.levels[0].channels, 1);
    // Finite texels so large that four of them overflow a float mip sum
    // (a Radiance RGBE exponent of 255 gives 1.7e38): refused.
    try {
        decodeTextureImage(readBytes(corpus("overflow_rgbe.hdr")), "o.hdr", false, Wrap::Repeat);
        ADD_FAILURE() << "texel of 1.7e38 accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element().rfind("pixel (0, 0) channel ", 0), 0u) << e.what();
        EXPECT_NE(e.reason().find("is out of range"), std::string::npos) << e.what();
    }
    // Half infinity (exponent all ones) is caught in half storage too.
    std::vector<uint16_t> half(4 * 4, 0x3800); // 0.5
    half[5] = 0x7C00;                          // pixel (1, 1): +inf
    writeImage(dir / "inf.exr", 4, 4, 1, OIIO::TypeDesc::HALF, half.data());
    try {
        decodeTextureImage(readBytes(dir / "inf.exr"), "inf.exr", false, Wrap::Repeat);
        ADD_FAILURE() << "infinite half texel accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), "pixel (1, 1) channel 0");
    }
}

TEST(TextureFiles, TheBudgetCoversAllTexturesOfAScene) {
    const std::string data = SURFGRAD_DATA_DIR;
    const std::string a = data + "/textures/ClearCoatCarPaint_Normal.png",
                      b = data + "/textures/wicker_normal.png",
                      c = data + "/meshes/spot/spot_texture.png";
    const std::string layers =
        R"({"type": "uv_normal", "map": ")" + a + R"("}, {"type": "uv_normal", "map": ")" + b +
        R"("}, {"type": "deriv_map", "encoding": "unorm", "map": ")" + c + R"("})";
    Scene s = sceneFromJson(oneMaterialScene(layers, kSphere));
    SceneAssets all = loadAssets(s);
    ASSERT_EQ(all.textures.size(), 3u);
    uint64_t total = 0;
    for (const auto& [key, t] : all.textures) total += t->bytes();
    const uint64_t third = all.textures.at("file:" + c + ":repeat")->bytes();
    // 1024^2 texels, r and g as 8 bits, float mip levels of 2 channels.
    EXPECT_EQ(third, textureBytes(1024, 1024, 2, TexelType::Unorm8));
    // Room for all three (plus the decoder's band buffers): loads. One byte
    // less than the three take: the last is refused, naming its field and
    // what the others take.
    AssetOptions roomy;
    roomy.textureBudgetBytes = total + (uint64_t(4) << 20);
    EXPECT_NO_THROW(loadAssets(s, roomy));
    AssetOptions tight;
    tight.textureBudgetBytes = total - 1;
    try {
        loadAssets(s, tight);
        ADD_FAILURE() << "over-budget scene accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.element(), "materials[0].layers[2].map");
        EXPECT_NE(e.reason().find("1024x1024 pixels, 2 of 3 channels as 8-bit unorm: needs " +
                                  io::formatBytes(third) + " with its mip chain"),
                  std::string::npos)
            << e.what();
        EXPECT_NE(e.reason().find("the texture budget is " + io::formatBytes(total - 1) +
                                  ", of which the scene's 2 other textures take " +
                                  io::formatBytes(total - third)),
                  std::string::npos)
            << e.what();
        EXPECT_NE(e.reason().find("--texture-budget"), std::string::npos);
    }
    // Procedural textures count too: 256^2 RGBA float with its mip chain.
    Scene p = sceneFromJson(
        oneMaterialScene(R"({"type": "uv_normal", "map": {"procedural": "tiles"}})", kSphere));
    AssetOptions small;
    small.textureBudgetBytes = textureBytes(256, 256, 4, TexelType::Float) - 1;
    EXPECT_THROW(loadAssets(p, small), io::InputError);
    small.textureBudgetBytes += 1;
    EXPECT_NO_THROW(loadAssets(p, small));
}

// Feature-map EXR files go through the same header scan; the refusal
// names the scene and the field.
TEST(TextureFiles, FeatureMapFilesAreScannedToo) {
    Scene s = sceneFromJson(oneMaterialScene(
        R"({"type": "feature", "maps": ")" + corpus("giga_none.exr").string() + R"("})", kSphere));
    try {
        loadAssets(s);
        ADD_FAILURE() << "accepted";
    } catch (const io::InputError& e) {
        EXPECT_EQ(e.file(), "test.json");
        EXPECT_EQ(e.element(), "materials[0].layers[0].maps");
        EXPECT_NE(e.reason().find("EXR pixel data: 16384x16384 pixels"), std::string::npos)
            << e.what();
    }
}

// The rule (docs/scene.md, image_decode.h): a quarter of physical memory,
// at most 8 GiB, at most half of the address-space and data limits. The
// machine is read here from /proc (MemTotal of /proc/meminfo; "Max address
// space" and "Max data size" of /proc/self/limits), not through the
// sysconf/getrlimit calls the code makes.
uint64_t procMemTotal() {
    std::ifstream in("/proc/meminfo");
    std::string key, unit;
    uint64_t kb = 0;
    while (in >> key >> kb >> unit)
        if (key == "MemTotal:") return kb * 1024;
    return 0;
}

uint64_t procLimit(const std::string& name) { // soft limit; ~0 for unlimited
    std::ifstream in("/proc/self/limits");
    std::string line;
    while (std::getline(in, line)) {
        if (line.rfind(name, 0) != 0) continue;
        std::istringstream f(line.substr(name.size()));
        std::string soft;
        f >> soft;
        return soft == "unlimited" ? ~uint64_t(0) : uint64_t(std::stoull(soft));
    }
    return ~uint64_t(0);
}

uint64_t expectedBudget() {
    uint64_t b = std::min(procMemTotal() / 4, uint64_t(8) << 30);
    for (const char* l : {"Max address space", "Max data size"}) b = std::min(b, procLimit(l) / 2);
    return b;
}

TEST(TextureFiles, DefaultBudgetFollowsTheMachine) {
    ASSERT_GT(procMemTotal(), 0u) << "/proc/meminfo";
    // Exact: MemTotal is the kernel's page count in kB, as sysconf's
    // _SC_PHYS_PAGES times the page size.
    EXPECT_EQ(defaultTextureBudget(), expectedBudget())
        << "MemTotal " << procMemTotal() << " bytes";
    // Under an address-space limit (a child process, so this one keeps
    // its limits): the current size plus 3 GiB, so the limit binds when
    // the machine has more than twice that (this one: 24 GiB) and the
    // child can still allocate.
    std::ifstream statm("/proc/self/statm");
    uint64_t pages = 0;
    statm >> pages;
    const uint64_t limit = pages * uint64_t(::sysconf(_SC_PAGE_SIZE)) + (uint64_t(3) << 30);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        rlimit rl{};
        ::getrlimit(RLIMIT_AS, &rl);
        rl.rlim_cur = rlim_t(limit);
        if (::setrlimit(RLIMIT_AS, &rl) != 0) ::_exit(2);
        const uint64_t want = expectedBudget();
        ::_exit(defaultTextureBudget() == want && procLimit("Max address space") == limit ? 0 : 1);
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0)
        << "under RLIMIT_AS " << limit << " bytes: the budget is not min(MemTotal / 4, 8 GiB, "
        << "limit / 2)";
    std::printf("budget %llu bytes (MemTotal %llu); under a %llu-byte address-space limit: %llu\n",
                static_cast<unsigned long long>(defaultTextureBudget()),
                static_cast<unsigned long long>(procMemTotal()),
                static_cast<unsigned long long>(limit),
                static_cast<unsigned long long>(std::min(procMemTotal() / 4, limit / 2)));
}

// The header scan (surfgrad/image/image_header.h) agrees with OpenImageIO on every
// valid file, from a file and from memory.
TEST(ImageHeader, AgreesWithTheDecoderOnValidFiles) {
    for (const char* file : kValidFiles) {
        SCOPED_TRACE(file);
        const std::string bytes = readBytes(corpus(file));
        const io::ImageHeader h = io::scanImageHeader(io::MemoryBytes(bytes), file);
        const io::ImageHeader hf = io::scanImageHeader(io::FileBytes(corpus(file).string()), file);
        auto in = OIIO::ImageInput::open(corpus(file).string());
        ASSERT_TRUE(in);
        EXPECT_EQ(h.width, in->spec().width);
        EXPECT_EQ(h.height, in->spec().height);
        EXPECT_EQ(h.channels, in->spec().nchannels);
        EXPECT_LE(h.minFileBytes, bytes.size());
        EXPECT_EQ(hf.width, h.width);
        EXPECT_EQ(hf.minFileBytes, h.minFileBytes);
        EXPECT_EQ(hf.decoderBytes, h.decoderBytes);
    }
}

// Files that declare more than they hold, and formats a scene does not read.
TEST(ImageHeader, RefusesWhatTheFileCannotHold) {
    struct Case {
        const char* file;
        const char* element;
        const char* reason;
    };
    const Case cases[] = {
        {"issue16_huge_dims.png", "PNG IDAT",
         "16384x16384 pixels, 4 channels of 8 bits (1.00 GiB): 1.00 GiB of filtered rows to "
         "inflate, but the file holds 12 bytes, which expand to at most 12.1 KiB (1032:1)"},
        {"issue16_huge_64ch.tif", "TIFF strips",
         "16384x16384 pixels, 64 channels of 8 bits (16.0 GiB): 16.0 GiB of uncompressed "
         "samples, but its 1 strip holds 1 byte"},
        {"giga_baseline.jpg", "JPEG scan data",
         "its first component has 4194304 blocks of 8x8, at least one bit each (512.0 KiB), but "
         "the file has 28 bytes after the scan header"},
        {"giga_progressive.jpg", "JPEG scan data", "4194304 blocks of 8x8"},
        {"giga_none.exr", "EXR pixel data",
         "16384x16384 pixels, 3 channels of 32 bits (3.00 GiB) in 16384 uncompressed chunks need "
         "at least 3.00 GiB"},
        {"giga_zip.exr", "EXR pixel data", "in 1024 zip chunks need at least 2.99 MiB"},
        {"giga.hdr", "HDR pixel data",
         "16384 scanlines of at least 1044 bytes each need 16.3 MiB, but the file has 69 bytes"},
        {"giga_rgba.tga", "TGA pixel data",
         "65535x65535 pixels, 4 channels of 8 bits (16.0 GiB): uncompressed pixels need at least "
         "16.0 GiB"},
        // Found by fuzz_texture: an offset table entry of 2^64 - 1 made
        // OpenImageIO's in-memory reader copy from before its buffer.
        {"oob_exr_offset_table.exr", "EXR chunk 0",
         "offset 18446744073709551615 is outside the pixel data (bytes 193..288)"},
        {"giga_deflate.tif", "TIFF strips",
         "768.0 MiB of deflate data to decode, but its 1 strip holds 64 bytes, which expand to "
         "at most 64.5 KiB (1032:1)"},
    };
    for (const Case& c : cases) {
        SCOPED_TRACE(c.file);
        const std::string bytes = readBytes(corpus(c.file));
        try {
            io::scanImageHeader(io::MemoryBytes(bytes), c.file);
            ADD_FAILURE() << "accepted";
        } catch (const io::InputError& e) {
            EXPECT_EQ(e.file(), c.file);
            EXPECT_EQ(e.element(), c.element) << e.what();
            EXPECT_NE(e.reason().find(c.reason), std::string::npos) << e.what();
        }
    }
    auto reason = [](std::string bytes, const std::string& name) {
        try {
            io::scanImageHeader(io::MemoryBytes(bytes), name);
        } catch (const io::InputError& e) {
            return e.reason();
        }
        return std::string("accepted");
    };
    EXPECT_EQ(reason("GIF89a\x10\0\x10\0", "a.gif"),
              "a GIF file; a scene reads PNG, JPEG, OpenEXR, TIFF, Radiance HDR and TGA");
    EXPECT_EQ(reason("BM\x36\0\0\0", "a.bmp").substr(0, 11), "a BMP file;");
    EXPECT_EQ(reason("plain text", "notes.txt").substr(0, 35),
              "not an image file this reader knows");
    // A colour-mapped TGA whose 8-bit indices can point past its 16-entry
    // map (OpenImageIO 2.4 would read past the map).
    std::string tga(18 + 16 * 3 + 4, '\0');
    tga[1] = 1;  // colour map
    tga[2] = 1;  // colour-mapped image
    tga[5] = 16; // 16 entries
    tga[7] = 24; // of 24 bits
    tga[12] = 2; // 2x2 pixels
    tga[14] = 2;
    tga[16] = 8; // 8-bit indices
    EXPECT_NE(reason(tga, "p.tga").find("does not cover every 8-bit index"), std::string::npos);
    tga[5] = 0;
    tga[6] = 1; // 256 entries: every index is inside
    tga.resize(18 + 256 * 3 + 4);
    EXPECT_EQ(reason(tga, "p.tga"), "accepted");
}

} // namespace
} // namespace sg::render::test

// The image writer (image/src/image_write.cpp, surfgrad/image/image_write.h):
// rows bottom first in memory and top first in the file, each format's
// sample types and metadata, what happens to NaN and out-of-range values,
// MIP chains, the refusals (format by extension, empty images) and atomic
// writes. Files are read back through OpenImageIO directly (independent of
// the decoder) and through the image decoder.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include "cli.h"
#include "surfgrad/image/image_decode.h"
#include "surfgrad/image/image_write.h"
#include "surfgrad/base/io.h"

namespace sg::image {
namespace {

namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
    fs::path d = sg::test::processScratchDir("surfgrad_image_write") / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

// The file's samples as float, top row first (file order), and its spec.
std::vector<float> readRaw(const fs::path& p, OIIO::ImageSpec* spec = nullptr, int level = 0) {
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(p.string(), &config);
    EXPECT_TRUE(in) << OIIO::geterror();
    if (!in) return {};
    EXPECT_TRUE(in->seek_subimage(0, level));
    const OIIO::ImageSpec& s = in->spec();
    std::vector<float> v(size_t(s.width) * size_t(s.height) * size_t(s.nchannels));
    EXPECT_TRUE(in->read_image(0, level, 0, s.nchannels, OIIO::TypeDesc::FLOAT, v.data()));
    if (spec) *spec = s;
    return v;
}

std::string writeError(const fs::path& p, const FloatPixels& px, const WriteOptions& o) {
    try {
        writeImageFile(p, px, o);
    } catch (const io::InputError& e) {
        return e.what();
    }
    return "";
}

TEST(ImageWrite, LowerExtension) {
    EXPECT_EQ(lowerExtension("a/b.PNG"), ".png");
    EXPECT_EQ(lowerExtension("x.tar.EXR"), ".exr");
    EXPECT_EQ(lowerExtension("dir.d/file"), "");
    EXPECT_EQ(lowerExtension("noext"), "");
    EXPECT_EQ(lowerExtension(".hidden"), "");
}

// Memory rows bottom first, file rows top first; float keeps every bit
// (NaN and infinities included unless asked otherwise); metadata of every
// kind arrives with its type.
TEST(ImageWrite, FloatExrRowsMetadataAndNonFinite) {
    const fs::path dir = scratch("float");
    const int w = 3, h = 2, c = 2;
    // Sample (x, y, ch) = 100 y + 10 x + ch, y = 0 the bottom row.
    std::vector<float> px(size_t(w * h * c));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int ch = 0; ch < c; ++ch)
                px[size_t((y * w + x) * c + ch)] = float(100 * y + 10 * x + ch);
    px[1] = std::numeric_limits<float>::quiet_NaN(); // (0, 0) channel 1
    px[2] = std::numeric_limits<float>::infinity();  // (1, 0) channel 0
    WriteOptions o;
    o.channelNames = {"u", "v"};
    o.attributes = {{"t:int", 7},
                    {"t:double", 0.1},
                    {"t:string", "text"},
                    {"t:floats", std::vector<float>{1.5f, -2.0f, 3.25f, 4.0f, 5.0f}}};
    const fs::path p = dir / "a.exr";
    writeImageFile(p, {px.data(), w, h, c}, o);
    OIIO::ImageSpec spec;
    const std::vector<float> raw = readRaw(p, &spec);
    ASSERT_EQ(spec.width, w);
    ASSERT_EQ(spec.height, h);
    ASSERT_EQ(spec.nchannels, c);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::FLOAT);
    EXPECT_EQ(spec.get_string_attribute("compression"), "zip");
    for (int row = 0; row < h; ++row)
        for (int x = 0; x < w; ++x)
            for (int ch = 0; ch < c; ++ch) {
                const float want = px[size_t(((h - 1 - row) * w + x) * c + ch)];
                const float got = raw[size_t((row * w + x) * c + ch)];
                if (std::isnan(want))
                    EXPECT_TRUE(std::isnan(got));
                else
                    EXPECT_EQ(got, want) << x << " " << row << " " << ch;
            }
    // OpenEXR stores channels sorted by name: u, v.
    EXPECT_EQ(spec.channel_name(0), "u");
    EXPECT_EQ(spec.get_int_attribute("t:int"), 7);
    double d = 0;
    ASSERT_TRUE(spec.getattribute("t:double", OIIO::TypeDesc::DOUBLE, &d));
    EXPECT_EQ(d, 0.1);
    EXPECT_EQ(spec.get_string_attribute("t:string"), "text");
    const OIIO::ParamValue* f = spec.find_attribute("t:floats");
    ASSERT_TRUE(f);
    ASSERT_EQ(f->type(), OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 5));
    EXPECT_EQ(static_cast<const float*>(f->data())[2], 3.25f);

    // nonFiniteToZero, half samples: the decoder reads it back bottom row
    // first, as written.
    o.type = SampleType::Half;
    o.nonFiniteToZero = true;
    writeImageFile(dir / "b.exr", {px.data(), w, h, c}, o);
    const DecodedImage back = decodeImageFile(dir / "b.exr");
    EXPECT_EQ(back.fileType, SampleType::Half);
    EXPECT_EQ(back.sample(0, 0, 1), 0.0f);
    EXPECT_EQ(back.sample(1, 0, 0), 0.0f);
    EXPECT_EQ(back.sample(2, 1, 1), 121.0f);
    // The decoder's view of the metadata: each value with its type.
    ASSERT_TRUE(back.stringAttribute("t:string"));
    EXPECT_EQ(*back.stringAttribute("t:string"), "text");
    EXPECT_EQ(std::get<int>(back.attributes.at("t:int")), 7);
    EXPECT_EQ(std::get<double>(back.attributes.at("t:double")), 0.1);
    EXPECT_EQ(std::get<std::vector<float>>(back.attributes.at("t:floats")),
              (std::vector<float>{1.5f, -2.0f, 3.25f, 4.0f, 5.0f}));
    EXPECT_EQ(back.channelNames, (std::vector<std::string>{"u", "v"}));
    EXPECT_EQ(back.channelFormats, (std::vector<std::string>{"half", "half"}));
    EXPECT_EQ(back.originX, 0);
    // NaN and infinity in a float file: refused by default, kept on request.
    EXPECT_THROW(decodeImageFile(p), io::InputError);
    DecodeOptions keep;
    keep.finiteOnly = false;
    const DecodedImage raw2 = decodeImageFile(p, keep);
    EXPECT_TRUE(std::isnan(raw2.sample(0, 0, 1)));
    EXPECT_EQ(raw2.sample(1, 0, 0), std::numeric_limits<float>::infinity());
}

// Unorm samples: NaN and infinities become 0, values are clamped to [0, 1]
// and rounded to the nearest code; alpha is stored as given (not
// premultiplied) and marked unassociated.
TEST(ImageWrite, UnormPngTgaTifClampAndKeepAlpha) {
    const fs::path dir = scratch("unorm");
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    // One row of two RGBA pixels.
    const std::vector<float> px = {0.5f, -1.0f, 2.0f, 0.25f, nan, inf, -inf, 1.0f};
    WriteOptions o;
    o.alphaChannel = 3;
    for (const char* name : {"a.png", "a.tga", "a.tif"}) {
        o.type = SampleType::Unorm8;
        writeImageFile(dir / name, {px.data(), 2, 1, 4}, o);
        OIIO::ImageSpec spec;
        const std::vector<float> raw = readRaw(dir / name, &spec);
        EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8) << name;
        ASSERT_EQ(raw.size(), 8u) << name;
        const float want[8] = {128.0f / 255.0f, 0, 1, 64.0f / 255.0f, 0, 0, 0, 1};
        for (int k = 0; k < 8; ++k) EXPECT_EQ(raw[size_t(k)], want[k]) << name << " " << k;
    }
    o.type = SampleType::Unorm16;
    writeImageFile(dir / "b.png", {px.data(), 2, 1, 4}, o);
    OIIO::ImageSpec spec;
    const std::vector<float> raw = readRaw(dir / "b.png", &spec);
    EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT16);
    ASSERT_EQ(raw.size(), 8u);
    EXPECT_EQ(raw[0], 32768.0f / 65535.0f);
    EXPECT_EQ(raw[3], 16384.0f / 65535.0f);
}

TEST(ImageWrite, RefusesFormatsByExtension) {
    const fs::path dir = scratch("refuse");
    auto refusal = [](const fs::path& p, SampleType t) {
        try {
            checkWritable(p, t);
        } catch (const io::InputError& e) {
            EXPECT_EQ(e.file(), p.string());
            return e.reason();
        }
        return std::string();
    };
    EXPECT_EQ(refusal("a.PNG", SampleType::Unorm16), "");
    EXPECT_EQ(refusal("a.tiff", SampleType::Half), "");
    EXPECT_EQ(refusal("a.exr", SampleType::Unorm8),
              "cannot write 8-bit samples as \".exr\" (png: 8/16-bit, tga: 8-bit, tif: any, exr: "
              "half/float)");
    EXPECT_NE(refusal("a.png", SampleType::Float).find("float samples as \".png\""),
              std::string::npos);
    EXPECT_NE(refusal("a.tga", SampleType::Unorm16).find("16-bit"), std::string::npos);
    const std::string jpg = refusal("a.jpg", SampleType::Unorm8);
    EXPECT_NE(jpg.find("cannot write 8-bit samples as \".jpg\": not an image format this writer"),
              std::string::npos)
        << jpg;
    EXPECT_NE(refusal("a", SampleType::Float).find("no extension"), std::string::npos);

    // The writer checks the same before writing anything; an empty image
    // is refused too. Nothing is left behind.
    const std::vector<float> px(4, 0.5f);
    EXPECT_NE(writeError(dir / "a.jpg", {px.data(), 2, 2, 1}, {}).find(".jpg"), std::string::npos);
    EXPECT_NE(writeError(dir / "e.exr", {px.data(), 0, 2, 1}, {}).find("0x2 pixels"),
              std::string::npos);
    EXPECT_NE(
        writeError(dir / "missing" / "a.exr", {px.data(), 2, 2, 1}, {}).find("does not exist"),
        std::string::npos);
    EXPECT_TRUE(fs::is_empty(dir));
}

// A failed write replaces nothing and leaves no temporary file; a good one
// replaces the old file whole.
TEST(ImageWrite, AtomicReplace) {
    const fs::path dir = scratch("atomic");
    const fs::path p = dir / "a.png";
    std::vector<float> px(16, 1.0f);
    WriteOptions o;
    o.type = SampleType::Unorm8;
    writeImageFile(p, {px.data(), 4, 4, 1}, o);
    const std::string before = io::readFile(p);
    o.type = SampleType::Float; // not a PNG type: refused before writing
    EXPECT_THROW(writeImageFile(p, {px.data(), 4, 4, 1}, o), io::InputError);
    EXPECT_EQ(io::readFile(p), before);
    px.assign(16, 0.0f);
    o.type = SampleType::Unorm8;
    writeImageFile(p, {px.data(), 4, 4, 1}, o);
    EXPECT_NE(io::readFile(p), before);
    for (const auto& e : fs::directory_iterator(dir)) EXPECT_EQ(e.path().filename(), "a.png");
}

// A MIP chain: one tiled OpenEXR file whose levels read back as written
// (levels larger than a tile, and a non-square chain down to 1x1).
TEST(ImageWrite, MipChainRoundTrip) {
    const fs::path dir = scratch("mips");
    std::vector<std::vector<float>> data;
    std::vector<FloatPixels> levels;
    for (int w = 150, h = 70, k = 0;; w = std::max(1, w / 2), h = std::max(1, h / 2), ++k) {
        std::vector<float> v(size_t(w * h * 3));
        for (size_t i = 0; i < v.size(); ++i) v[i] = float(k) + float(i) * 1e-3f;
        data.push_back(std::move(v));
        levels.push_back({nullptr, w, h, 3});
        if (w == 1 && h == 1) break;
    }
    for (size_t k = 0; k < levels.size(); ++k) levels[k].samples = data[k].data();
    WriteOptions o;
    // (OpenImageIO reads OpenEXR's "R", "G", "B", "A" first, in any case:
    // these names keep their order.)
    o.channelNames = {"p0", "p1", "p2"};
    o.attributes = {{"surfgrad:layout", "test"}};
    const fs::path p = dir / "chain.exr";
    writeMipChainFile(p, levels, o);
    DecodeOptions d;
    d.toFloat = true;
    for (size_t k = 0; k < levels.size(); ++k) {
        d.level = int(k);
        const DecodedImage L = decodeImageFile(p, d);
        EXPECT_EQ(L.levels, int(levels.size()));
        ASSERT_EQ(L.width, levels[k].width);
        ASSERT_EQ(L.height, levels[k].height);
        for (int y = 0; y < L.height; ++y)
            for (int x = 0; x < L.width; ++x)
                for (int c = 0; c < 3; ++c)
                    ASSERT_EQ(L.sample(x, y, c), data[k][size_t((y * L.width + x) * 3 + c)])
                        << "level " << k << " (" << x << ", " << y << ")";
        ASSERT_TRUE(L.stringAttribute("surfgrad:layout"));
        EXPECT_EQ(*L.stringAttribute("surfgrad:layout"), "test");
    }
    OIIO::ImageSpec spec;
    readRaw(p, &spec);
    EXPECT_EQ(spec.tile_width, 64);
    EXPECT_EQ(spec.get_int_attribute("openexr:levelmode"), 1);
    try {
        writeMipChainFile(dir / "chain.png", levels, o);
        ADD_FAILURE() << "a MIP chain as PNG";
    } catch (const io::InputError& e) {
        EXPECT_NE(std::string(e.reason()).find("OpenEXR"), std::string::npos);
    }
}

} // namespace
} // namespace sg::image

// `surfgrad normalmap` from the outside, on the repository's maps: every op
// (and its --naive variant) runs and writes a readable image of the right
// size; round trips through files hold; bad input (too few channels, NaN,
// unreadable, mismatched sizes, bad option values, output over an input)
// ends with `surfgrad: error: ...`, exit status 1 and no output file;
// image headers promising gigabytes (issue 16) are refused under a 1.5 GB
// memory limit by the same guarded decoder as the renderer's textures.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <vector>

#include "cli.h"
#include "giga_images.h"
#include "surfgrad/normalmap/operations.h"

namespace {

namespace fs = std::filesystem;
using namespace sg::normalmap;

const std::string kSrc = SURFGRAD_SOURCE_DIR;
const std::string kRock = kSrc + "/examples/data/rock_normal.png";
const std::string kBrand = kSrc + "/examples/data/brand_normal.png";
const std::string kPaint =
    std::string(SURFGRAD_DATA_DIR) + "/textures/ClearCoatCarPaint_Normal.png";
const std::string kLava = std::string(SURFGRAD_DATA_DIR) + "/textures/lava_height.png";

fs::path scratch(const std::string& name) {
    const fs::path p = fs::path(SURFGRAD_BINARY_DIR) / "tests/normalmap/cli" / name;
    fs::remove_all(p);
    fs::create_directories(p);
    return p;
}

struct CmdResult {
    int status = -1;
    std::string output; // stdout + stderr
};

CmdResult run(const std::string& args, const fs::path& cwd) {
    sg::test::CommandOptions opt;
    opt.cwd = cwd;
    const sg::test::CommandResult r = sg::test::runSurfgrad("normalmap " + args, opt);
    return {r.exitCode, r.output()};
}

// Files in a directory (an atomic write leaves no temporary behind).
size_t fileCount(const fs::path& dir) {
    size_t n = 0;
    for (const auto& e : fs::directory_iterator(dir)) n += e.is_regular_file();
    return n;
}

TEST(NormalmapCli, EveryOpAndItsNaiveVariantRunsOnTheRepositoryMaps) {
    const fs::path dir = scratch("ops");
    {
        // The mask and gain images: a luminance image of the brand map.
        std::ofstream(dir / "pts.txt") << "0,0 0.4,0.1 0.7,0.9 1,1\n";
    }
    const std::vector<std::string> ops = {
        "from-height " + kLava + " -o fh.png --scale 40 --wrap",
        "to-height " + kRock + " -o th.exr --wrap",
        "to-height " + kRock + " -o th16.png --wrap",
        "to-derivative " + kRock + " -o td.exr --wrap",
        "to-derivative " + kRock + " -o td16.png --range 4",
        "convert " + kRock + " -o rg.png --to rg",
        "convert " + kRock + " -o dx.tga --to-green dx",
        "convert " + kRock + " -o ag.tif --to ag --bits 16",
        "scale " + kRock + " -o s.png --alpha -1",
        "add " + kRock + " " + kBrand + " -o a.png --weights 0.5,1",
        "blend " + kRock + " " + kBrand + " --mask " + kBrand + " -o b.png --mask-channel 0",
        "modulate " + kRock + " --by " + kBrand + " -o m.png --by-channel 2 --wrap",
        "curves " + kRock + " -o c.png --boost 100,0.5 --wrap",
        "curves " + kRock + " -o c2.png --points-file pts.txt --wrap",
        "deform " + kRock + " -o d.png --warp sine:0.02,25.1327 --wrap",
        "deform " + kRock + " -o r.png --warp rotate:30",
        "shade " + kRock + " -o sh.png",
    };
    for (const std::string& op : ops) {
        for (bool naive : {false, true}) {
            if (naive && op.rfind("shade", 0) == 0) continue;
            const CmdResult r = run(op + (naive ? " --naive" : ""), dir);
            ASSERT_EQ(r.status, 0) << op << (naive ? " --naive" : "") << "\n" << r.output;
            ASSERT_NE(r.output.find("wrote "), std::string::npos) << r.output;
        }
    }
    // Outputs are readable maps of the input's size.
    for (const char* f : {"fh.png", "th.exr", "td.exr", "rg.png", "dx.tga", "ag.tif", "s.png",
                          "a.png", "b.png", "m.png", "c.png", "d.png", "r.png", "sh.png"}) {
        const Image img = readImage(dir / f);
        EXPECT_EQ(img.width, std::string(f) == "fh.png" ? 1024 : 256) << f;
    }
    EXPECT_EQ(readImage(dir / "rg.png").channels, 2);
    EXPECT_EQ(readImage(dir / "ag.tif").channels, 4);
    EXPECT_EQ(readImage(dir / "th.exr").channels, 1);
    // MIP chains.
    for (const char* mode : {"--lean", "--toksvig", "--naive"}) {
        const CmdResult r = run("mips " + kPaint + " -o mips.exr --wrap " + mode, dir);
        ASSERT_EQ(r.status, 0) << r.output;
        std::string layout;
        const auto levels = readMipChain(dir / "mips.exr", nullptr, &layout);
        EXPECT_EQ(levels.size(), 8u); // 128 ... 1
        EXPECT_EQ(layout, std::string(mode) == "--lean"      ? kLeanLayout
                          : std::string(mode) == "--toksvig" ? kToksvigLayout
                                                             : kNaiveMipLayout);
    }
}

TEST(NormalmapCli, RoundTripsThroughFiles) {
    const fs::path dir = scratch("roundtrip");
    // scale -1 twice gives the map back (x, y codes identical: negation is
    // exact and listing 4 reads x, y only).
    ASSERT_EQ(run("scale " + kRock + " -o inv.png --alpha -1", dir).status, 0);
    ASSERT_EQ(run("scale inv.png -o back.png --alpha -1", dir).status, 0);
    const Image a = readImage(kRock), b = readImage(dir / "back.png");
    for (int j = 0; j < a.height; ++j)
        for (int i = 0; i < a.width; ++i)
            for (int c = 0; c < 2; ++c)
                ASSERT_EQ(std::lround(a.at(i, j, c) * 255), std::lround(b.at(i, j, c) * 255));
    // to-height (float) then from-height gives the integrable part of the
    // slopes; applying both again changes them by rounding only.
    ASSERT_EQ(run("to-height " + kRock + " -o h.exr --wrap", dir).status, 0);
    ASSERT_EQ(run("from-height h.exr -o p.exr --to deriv --wrap", dir).status, 0);
    ASSERT_EQ(run("to-height p.exr --encoding deriv -o h2.exr --wrap", dir).status, 0);
    const Image h1 = readImage(dir / "h.exr"), h2 = readImage(dir / "h2.exr");
    double maxDiff = 0;
    for (size_t k = 0; k < h1.samples.size(); ++k)
        maxDiff = std::max(maxDiff, double(std::abs(h1.samples[k] - h2.samples[k])));
    // Heights of a few texels stored in binary32: 1e-4 texels.
    EXPECT_LT(maxDiff, 1e-4);
}

TEST(NormalmapCli, BadInputIsAnErrorWithoutOutput) {
    const fs::path dir = scratch("errors");
    {
        auto out = OIIO::ImageOutput::create((dir / "nan.exr").string());
        OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeDesc::FLOAT);
        std::vector<float> px(48, 0.5f);
        px[7] = std::numeric_limits<float>::infinity();
        ASSERT_TRUE(out->open((dir / "nan.exr").string(), spec) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close());
        std::ofstream(dir / "junk.png") << "not an image";
        // A 4x4 PNG whose compressed data is garbage: libpng printed its own
        // "libpng error: ..." line before ours.
        auto png = OIIO::ImageOutput::create((dir / "bad.png").string());
        OIIO::ImageSpec pngSpec(4, 4, 3, OIIO::TypeDesc::UINT8);
        std::vector<uint8_t> texels(48, 128);
        ASSERT_TRUE(png->open((dir / "bad.png").string(), pngSpec) &&
                    png->write_image(OIIO::TypeDesc::UINT8, texels.data()) && png->close());
        std::ifstream in(dir / "bad.png", std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        in.close();
        const size_t idat = bytes.find("IDAT");
        ASSERT_NE(idat, std::string::npos);
        for (size_t i = idat + 4; i + 16 < bytes.size(); ++i) bytes[i] = char(0xA5 ^ i);
        std::ofstream(dir / "bad.png", std::ios::binary) << bytes;
    }
    // Exit status 2: the command line itself is wrong (options missing or
    // exclusive); 1: the input or a value does not work.
    struct Case {
        std::string args, needle;
        int status = 1;
    };
    const std::vector<Case> cases = {
        {"scale " + kLava + " -o out.png --alpha 2",
         "lava_height.png: channels: the image has 1 channel(s); the rgb encoding needs 3"},
        {"scale nan.exr -o out.png --alpha 2", "nan.exr: pixel (2, 0) channel 1: non-finite value"},
        {"scale junk.png -o out.png --alpha 2", "junk.png: cannot read image"},
        {"scale bad.png -o out.png --alpha 2", "bad.png: row 0: cannot decode"},
        {"scale nothere.png -o out.png --alpha 2", "nothere.png: no such file"},
        {"add " + kRock + " " + kPaint + " -o out.png",
         "ClearCoatCarPaint_Normal.png: size: 128x128 does not match"},
        {"scale " + kRock + " -o " + kRock + " --alpha 2", "rock_normal.png"},
        {"curves " + kRock + " -o out.png --points \"0,0 0.5\"",
         "--points: point 2: \"0.5\" is not x,y"},
        {"curves " + kRock + " -o out.png", "give exactly one of --boost, --points, --points-file",
         2},
        {"deform " + kRock + " -o out.png --warp twist:3", "--warp: twist:3"},
        {"mips " + kRock + " -o out.png --lean", "a MIP chain is written as OpenEXR", 2},
        {"mips " + kRock + " -o out.exr", "give exactly one of --lean, --toksvig, --naive", 2},
        {"convert " + kRock + " -o out.png --to signed", "signed normals need a float output"},
        {"convert " + kRock + " -o out.png --to object",
         "object-space maps need `convert --mesh M`", 2},
        {"convert " + kRock + " -o out.png --to yuv",
         "encoding: yuv: expected rgb, rg, ag, signed or deriv"},
        {"scale " + kRock + " -o out.jpg --alpha 2", "cannot write 8-bit samples as \".jpg\""},
    };
    const size_t before = fileCount(dir);
    for (const Case& c : cases) {
        const CmdResult r = run(c.args, dir);
        EXPECT_EQ(r.status, c.status) << c.args << "\n" << r.output;
        EXPECT_EQ(r.output.rfind("surfgrad: error: ", 0), 0u) << c.args << "\n" << r.output;
        EXPECT_NE(r.output.find(c.needle), std::string::npos) << c.args << "\n" << r.output;
        EXPECT_EQ(fileCount(dir), before) << c.args;
    }
}

// Every image header of tests/common/giga_images.h as a `surfgrad
// normalmap` input with at most 1.5 GB of memory: refused by the header scan
// with the file and the reason, exit 1, no output, no std::bad_alloc.
TEST(NormalmapCli, HeadersPromisingGigabytesAreRefusedUnderAMemoryLimit) {
    const fs::path dir = scratch("giga");
    const size_t before = fileCount(dir);
    for (const sg::test::GigaImage& c : sg::test::gigaImages()) {
        SCOPED_TRACE(c.file);
        const std::string file = (sg::test::gigaImageDir() / c.file).string();
        const sg::test::CommandResult r = sg::test::runSurfgradMemoryLimited(
            "normalmap scale " + sg::test::shellQuote(file) + " -o out.png --alpha 2", dir);
        EXPECT_EQ(r.exitCode, 1) << r.output();
        EXPECT_EQ(r.output().rfind("surfgrad: error: " + file + ": " + c.reason, 0), 0u)
            << r.output();
        EXPECT_EQ(r.output().find("bad_alloc"), std::string::npos) << r.output();
        EXPECT_EQ(fileCount(dir), before);
    }
}

} // namespace

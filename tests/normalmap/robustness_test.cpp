// Hard inputs stay numerically stable and bad images are refused clearly:
// flat, extreme (xy on the unit circle, z = 0), beyond-the-horizon and
// all-zero texels through every op (correct and naive), to-height, the
// MIP chains and object space give finite slopes and unit normals; NaN
// texels, missing or undecodable files and too few channels are
// InputErrors naming the file and the element.
#include <gtest/gtest.h>
#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "analytic_fields.h"
#include "hardcase.h"
#include "surfgrad/base/io.h"

namespace {

using namespace sg::normalmap;
using namespace sg::normalmap::test;
namespace fs = std::filesystem;

fs::path scratch(const std::string& name) {
    const fs::path p = fs::path(SURFGRAD_BINARY_DIR) / "tests/normalmap/robust" / name;
    fs::create_directories(p.parent_path());
    return p;
}

// An 8-bit-style RGB image (values in [0, 1]) whose texels cycle through
// the hard cases.
Image hardMap(int W, int H) {
    const float cases[][3] = {
        {0.5f, 0.5f, 1.0f},           // flat
        {1.0f, 0.5f, 0.5f},           // horizon: x = 1, z = 0
        {0.5f, 0.0f, 0.5f},           // horizon: y = -1
        {0.853553f, 0.853553f, 0.5f}, // on the unit circle at 45 degrees
        {1.0f, 1.0f, 1.0f},           // beyond: |xy| = sqrt(2)
        {0.0f, 0.0f, 0.0f},           // (-1, -1, -1): inward and beyond
        {0.5f, 0.5f, 0.0f},           // straight down
        {0.5f, 0.5f, 0.5f},           // zero vector
    };
    Image img;
    img.width = W;
    img.height = H;
    img.channels = 3;
    img.samples.resize(size_t(W) * size_t(H) * 3);
    for (int j = 0; j < H; ++j)
        for (int i = 0; i < W; ++i) {
            const auto& c = cases[size_t(i + 3 * j) % 8];
            for (int k = 0; k < 3; ++k) img.at(i, j, k) = c[k];
        }
    return img;
}

// The worst values the checks below saw in the running test (reported as
// rows of docs/hard-cases.md at its end; NaN sticks).
sg::test::Worst worstSlope, worstUnit;

// Listing 4 bounds every slope by 128; the ops combine a few such slopes
// with O(1) factors, so 1e5 is far above any ordinary result.
void expectFinite(const DerivField& d, const char* what, float bound = 1e5f) {
    for (const auto& v : d.v) {
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y)) << what;
        ASSERT_LT(std::max(std::abs(v.x), std::abs(v.y)), bound) << what;
        worstSlope.add(std::max(std::abs(v.x), std::abs(v.y)));
    }
}
void expectUnit(const NormalField& n, const char* what) {
    for (const auto& v : n.v) {
        ASSERT_TRUE(std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z)) << what;
        ASSERT_NEAR(glm::length(v), 1.0f, 1e-5f) << what;
        worstUnit.add(std::abs(double(glm::length(v)) - 1.0));
    }
}

TEST(Robustness, HardTexelsThroughEveryOpStayFinite) {
    const int W = 40, H = 24;
    const Image img = hardMap(W, H);
    for (Encoding e : {Encoding::Rgb, Encoding::Rg}) {
        MapFormat f;
        f.encoding = e;
        const DerivField d = decodeSlopes(img, f, "hard");
        const NormalField n = decodeNormals(img, f, "hard");
        expectFinite(d, "decode");
        expectUnit(n, "decode normals");
        for (Wrap wrap : {Wrap::Repeat, Wrap::Clamp}) {
            const ScalarField h = toHeight(d, wrap);
            for (float x : h.v) ASSERT_TRUE(std::isfinite(x) && x >= 0.0f);
            const ScalarField mask = heights(sines(W, H, 0.5), W, H);
            expectFinite(scale(d, -1.0f), "scale");
            expectFinite(scale(d, 2.0f), "scale");
            expectFinite(add(d, 1.0f, d, 1.0f), "add");
            expectFinite(blend(d, h, scale(d, -1.0f), h, mask, wrap), "blend");
            expectFinite(modulate(d, h, mask, wrap), "modulate");
            expectFinite(applyCurve(d, h, boostCurve(1000.0f, 0.5f)), "curves");
            expectFinite(applyCurve(d, h, parseCurvePoints("0,0 0.5,0.9 1,1", "t")), "curves");
            expectFinite(deform(d, Warp{Warp::Kind::Sine, 0.3f, 100.0f}, wrap), "deform");
            expectFinite(deform(d, Warp{Warp::Kind::Rotate, 33.0f, 0.0f}, wrap), "deform");
            expectFinite(fromHeight(h, 1.0f, wrap), "from-height");
            expectUnit(naive::scale(n, 2.0f), "naive scale");
            expectUnit(naive::scale(n, -1.0f), "naive scale");
            expectUnit(naive::add(n, 1.0f, n, -1.0f), "naive add (cancels to zero)");
            expectUnit(naive::blend(n, naive::scale(n, -1.0f), mask), "naive blend");
            expectUnit(naive::deform(n, Warp{Warp::Kind::Sine, 0.3f, 100.0f}, wrap),
                       "naive deform");
        }
        // Every result encodes without NaN.
        const Image out = encodeSlopes(scale(d, 2.0f), MapFormat{}, false);
        for (float v : out.samples) ASSERT_TRUE(std::isfinite(v));
        auto lean = mipChain(leanLevel0(d));
        auto toks = mipChain(toksvigLevel0(n));
        finishToksvig(toks);
        for (const auto& L : lean)
            for (float v : L.samples) ASSERT_TRUE(std::isfinite(v));
        for (const auto& L : toks)
            for (float v : L.samples) ASSERT_TRUE(std::isfinite(v) && v >= -1.0f);
    }
    const std::string c = "flat, horizon, beyond-the-rim, inward and zero texels, every op";
    sg::test::reportHardCase({"normal-map-images", c, "largest |slope| of the correct ops",
                              "finite, < 1e+05", sg::test::hardCaseNumber(worstSlope.value)});
    sg::test::reportHardCase({"normal-map-images", c, "| |n| - 1 | of the naive ops", "<= 1e-05",
                              sg::test::hardCaseNumber(worstUnit.value)});
    sg::test::reportHardCaseHolds("normal-map-images", c,
                                  "to-height, encoded results, LEAN/Toksvig MIP levels",
                                  "finite (Toksvig >= -1)", "holds");
}

TEST(Robustness, ExtremeValuesAndSizes) {
    // A 1 x 1 map, a 1-texel-high strip, a huge height scale.
    for (auto [w, h] : {std::pair{1, 1}, std::pair{17, 1}}) {
        const Image img = hardMap(w, h);
        const DerivField d = decodeSlopes(img, MapFormat{}, "tiny");
        // A warp slope A B = 1e12 multiplies slopes of up to 128: finite
        // (sgSineWarpJacobian clamps the slope to 1e18).
        expectFinite(deform(d, Warp{Warp::Kind::Sine, 1e6f, 1e6f}, Wrap::Clamp), "huge warp",
                     1e21f);
        const auto levels = mipChain(leanLevel0(d));
        EXPECT_EQ(levels.back().width, 1);
        EXPECT_EQ(levels.back().height, 1);
    }
    ScalarField big(16, 16, 0.0f);
    big.at(8, 8) = 1e30f;
    expectFinite(scale(fromHeight(big, 1.0f, Wrap::Clamp), 1e-30f), "huge height");
    sg::test::reportHardCaseHolds(
        "normal-map-images", "1x1 and 17x1 maps under a sine warp of slope 1e12",
        "warped slopes; MIP chain down to 1x1", "finite, < 1e+21", "holds");
    sg::test::reportHardCaseHolds("normal-map-images", "a height spike of 1e30, scaled by 1e-30",
                                  "slopes", "finite, < 1e+05", "holds");
}

TEST(Robustness, BadFilesAreInputErrors) {
    auto expectError = [](const fs::path& p, const std::string& needle) {
        try {
            (void)readImage(p);
            FAIL() << "no error for " << p;
        } catch (const sg::io::InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
            EXPECT_EQ(e.file(), p.string());
        }
    };
    expectError(scratch("missing.png"), "no such file");
    {
        const fs::path p = scratch("garbage.png");
        std::ofstream(p) << "this is not a PNG file at all";
        expectError(p, "cannot read image");
    }
    {
        // A float EXR with a NaN texel: refused, naming the pixel.
        const fs::path p = scratch("nan.exr");
        auto out = OIIO::ImageOutput::create(p.string());
        OIIO::ImageSpec spec(4, 3, 3, OIIO::TypeDesc::FLOAT);
        std::vector<float> px(4 * 3 * 3, 0.5f);
        px[(1 * 4 + 2) * 3 + 1] = std::numeric_limits<float>::quiet_NaN();
        ASSERT_TRUE(out->open(p.string(), spec) &&
                    out->write_image(OIIO::TypeDesc::FLOAT, px.data()) && out->close());
        try {
            (void)readImage(p);
            FAIL();
        } catch (const sg::io::InputError& e) {
            EXPECT_EQ(e.element(), "pixel (2, 1) channel 1");
            EXPECT_EQ(e.reason(), "non-finite value");
        }
    }
    {
        // One channel decoded as rgb: too few channels.
        Image gray;
        gray.width = gray.height = 4;
        gray.channels = 1;
        gray.samples.assign(16, 0.5f);
        try {
            (void)decodeSlopes(gray, MapFormat{}, "gray.png");
            FAIL();
        } catch (const sg::io::InputError& e) {
            EXPECT_EQ(e.element(), "channels");
            EXPECT_NE(std::string(e.reason()).find("needs 3"), std::string::npos);
        }
        // Signed values cannot be integer samples.
        MapFormat s;
        s.encoding = Encoding::Signed;
        Image rgb = hardMap(4, 4);
        EXPECT_THROW((void)decodeSlopes(rgb, s, "int.png"), sg::io::InputError);
    }
}

TEST(Robustness, CurveAndWarpTextIsValidated) {
    for (const char* bad : {"", "0,0", "0,0 1", "0,0 0,1", "0,0 0.00001,1", "0,0 2,1", "x,0 1,1",
                            "0,nan 1,1", "0,0 1,inf", "0,0 1,1e9", "0,0;;1,1;0.5,0.5"}) {
        EXPECT_THROW((void)parseCurvePoints(bad, "t"), sg::io::InputError) << bad;
    }
    const Curve c = parseCurvePoints(" 0,0 ;0.25,0.5\n 1,1 ", "t");
    EXPECT_EQ(c.points.size(), 3u);
    // Monotone data gives a monotone curve (Fritsch-Carlson): f' >= 0.
    const Curve m = parseCurvePoints("0,0 0.1,0.9 0.2,0.91 1,1", "t");
    for (int k = 0; k <= 1000; ++k) EXPECT_GE(m.slopeAt(k / 1000.0f), -1e-6f) << k;
    for (const char* bad :
         {"", "sine", "sine:1", "sine:1,2,3", "rotate:", "rotate:x", "twist:1,2", "sine:1e9,1"}) {
        EXPECT_THROW((void)parseWarp(bad), sg::io::InputError) << bad;
    }
    EXPECT_EQ(parseWarp("rotate:45").kind, Warp::Kind::Rotate);
}

} // namespace

// The engine-integration sample (examples/engine-integration) runs
// headlessly, writes a valid non-constant PNG, and its perturbed normals
// match the ones derived analytically from its scene
// (examples/engine-integration/example_setup.h): for every checked pixel the
// test casts the pixel's ray at the exact sphere, takes the sphere's
// orthonormal frame (N, dP/ds, dP/dt) there, and composes the two layers as
// Mikkelsen 2019 prescribes:
//   uv layer:    surfGrad = d.x T + d.y B             (listings 5, 6)
//   decal layer: surfGrad = g - (N.g) N, g = d.x X + d.y Y, times the fade
//                                                     (listings 12, 15)
//   normal = normalize(N - sum of surface gradients)  (listing 1)
// with the derivatives d evaluated from the same analytic patterns the
// sample bakes into its textures. Checked for each layer alone, both, none,
// and with dFdxFine replaced by the analytic sgScreenDerivOfPos (listing 17).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <ostream>

#include "../../examples/engine-integration/example_setup.h"
#include "example_test_util.h"

namespace {

using namespace sg::examples_test;
using namespace example;

const std::string kProgram = SG_EXAMPLE_ENGINE_BIN;

// Test image size: big enough that the normal map (768 texels around the
// sphere, ~1 texel per pixel across the front at this size) is sampled near
// mip level 0, small enough to run in well under a second on llvmpipe.
constexpr int kSize = 320;

struct Expected {
    bool valid = false;     // the pixel is in the checked region
    glm::vec3 normal{0.0f}; // expected perturbed normal
    glm::vec3 base{0.0f};   // the sphere's normal
    float decalGrad = 0.0f; // |decal surface gradient| (to count decal pixels)
};

// Expected normal at pixel (x, y) (top row first) for the given layers.
Expected expectedAt(int x, int y, bool useUv, bool useDecal) {
    Expected e;
    float tanHalf = std::tan(glm::radians(kFovYDeg) * 0.5f);
    float ndcX = 2.0f * (float(x) + 0.5f) / kSize - 1.0f,
          ndcY = 1.0f - 2.0f * (float(y) + 0.5f) / kSize;
    glm::vec3 origin(0.0f, 0.0f, kCameraDistance);
    glm::vec3 dir = glm::normalize(glm::vec3(ndcX * tanHalf, ndcY * tanHalf, -1.0f));
    // |origin + t dir| = 1, nearest root.
    float b = glm::dot(origin, dir), c = glm::dot(origin, origin) - 1.0f, disc = b * b - c;
    if (disc <= 0.0f) return e;
    glm::vec3 p = origin + (-b - std::sqrt(disc)) * dir;
    glm::vec3 n = glm::normalize(p);
    // Checked region: away from the silhouette (2x2-quad derivatives and the
    // polygonal outline differ most at grazing angles) and from the poles
    // (where UV cells collapse and the normal map is strongly minified).
    if (glm::dot(n, -dir) < 0.45f || std::abs(n.y) > 0.85f) return e;
    glm::vec3 sumGrad(0.0f);
    if (useUv) {
        glm::vec3 t, bt;
        sphereTangents(n, t, bt);
        glm::vec2 d = kNormalMapStrength * dimpleDeriv(sphereUv(n));
        sumGrad += d.x * t + d.y * bt;
    }
    if (useDecal) {
        glm::vec3 ax, ay, az;
        decalAxes(ax, ay, az);
        glm::vec3 r = p - decalCenter();
        glm::vec3 l(glm::dot(r, ax) / kDecalHalfSize, glm::dot(r, ay) / kDecalHalfSize,
                    glm::dot(r, az) / kDecalHalfDepth);
        if (std::abs(l.x) <= 1.0f && std::abs(l.y) <= 1.0f && std::abs(l.z) <= 1.0f) {
            float fade = std::clamp(
                (glm::dot(n, az) - kDecalCosEnd) / (kDecalCosStart - kDecalCosEnd), 0.0f, 1.0f);
            glm::vec2 d = decalDeriv(0.5f * glm::vec2(l.x, l.y) + 0.5f);
            glm::vec3 g = d.x * ax + d.y * ay;
            glm::vec3 sg = fade * kDecalStrength * (g - glm::dot(n, g) * n);
            e.decalGrad = glm::length(sg);
            sumGrad += sg;
        }
    }
    e.valid = true;
    e.base = n;
    e.normal = glm::normalize(n - sumGrad);
    return e;
}

struct Stats {
    int checked = 0, decalPixels = 0, bumpedPixels = 0;
    double meanDeg = 0.0, maxDeg = 0.0, p99Deg = 0.0;
};

Stats compareNormals(const Image& img, bool useUv, bool useDecal) {
    Stats s;
    std::vector<double> angles;
    for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
            Expected e = expectedAt(x, y, useUv, useDecal);
            if (!e.valid) continue;
            glm::vec3 got(2.0f * img.at(x, y, 0) - 1.0f, 2.0f * img.at(x, y, 1) - 1.0f,
                          2.0f * img.at(x, y, 2) - 1.0f);
            double cosA = std::clamp(double(glm::dot(glm::normalize(got), e.normal)), -1.0, 1.0);
            double deg = std::acos(cosA) * 180.0 / 3.141592653589793;
            angles.push_back(deg);
            s.decalPixels += e.decalGrad > 0.1f;
            // How far the layers move the normal (they are not no-ops).
            s.bumpedPixels += glm::dot(e.normal, e.base) < std::cos(glm::radians(5.0f));
        }
    }
    s.checked = int(angles.size());
    if (angles.empty()) return s;
    for (double a : angles) s.meanDeg += a / double(angles.size());
    std::sort(angles.begin(), angles.end());
    s.maxDeg = angles.back();
    s.p99Deg = angles[size_t(0.99 * double(angles.size() - 1))];
    return s;
}

// Renders with the sample; returns the image (empty on failure, with the
// program's output in `log`).
Image render(const fs::path& dir, const std::string& name, const std::string& args,
             std::string& log) {
    fs::path out = dir / (name + ".png");
    CommandResult r = runCommand(shellQuote(kProgram) + " -o " + shellQuote(out) + " --size " +
                                 std::to_string(kSize) + "x" + std::to_string(kSize) + " " + args);
    log = r.output();
    if (r.exitCode != 0) return {};
    return readImage(out);
}

TEST(EngineIntegration, ColorImageIsValidAndNotConstant) {
    fs::path dir = scratchDir("ei_color");
    std::string log;
    Image img = render(dir, "color", "", log);
    ASSERT_EQ(img.width, kSize) << log;
    ASSERT_EQ(img.height, kSize);
    ASSERT_EQ(img.channels, 3);
    // The corner is background (the sample clears to linear 0.02, 0.022,
    // 0.026 = sRGB 39, 41, 45 of 255), the centre is lit sphere.
    EXPECT_NEAR(img.at(0, 0, 0) * 255.0f, 39.0f, 1.0f);
    EXPECT_NEAR(img.at(0, 0, 2) * 255.0f, 45.0f, 1.0f);
    EXPECT_GT(img.at(kSize / 2, kSize / 2, 0), 0.3f);
    // Not constant over the sphere: the bumps make the luminance vary
    // strongly (a flat-shaded or failed render would not).
    double sum = 0.0, sumSq = 0.0;
    int n = 0;
    for (int y = kSize / 4; y < 3 * kSize / 4; ++y) {
        for (int x = kSize / 4; x < 3 * kSize / 4; ++x) {
            double l =
                0.2126 * img.at(x, y, 0) + 0.7152 * img.at(x, y, 1) + 0.0722 * img.at(x, y, 2);
            sum += l;
            sumSq += l * l;
            ++n;
        }
    }
    double sd = std::sqrt(std::max(0.0, sumSq / n - (sum / n) * (sum / n)));
    EXPECT_GT(sd, 0.05) << "luminance standard deviation over the sphere's centre";
}

struct LayerCase {
    const char* layers;
    bool useUv, useDecal;
    const char* derivs;
};

// For ctest's test names.
void PrintTo(const LayerCase& c, std::ostream* os) {
    *os << c.layers << " / " << c.derivs;
}

class EngineIntegrationNormals : public ::testing::TestWithParam<LayerCase> {};

TEST_P(EngineIntegrationNormals, MatchAnalyticComposition) {
    const LayerCase& c = GetParam();
    fs::path dir = scratchDir(std::string("ei_normals_") + (c.useUv ? "u" : "") +
                              (c.useDecal ? "d" : "") + c.derivs);
    std::string log;
    Image img =
        render(dir, "normal",
               std::string("--aov normal --layers ") + c.layers + " --derivs " + c.derivs, log);
    ASSERT_EQ(img.width, kSize) << log;
    Stats s = compareNormals(img, c.useUv, c.useDecal);
    std::printf("layers %s, derivs %s: %d pixels (%d in the decal), angle to the analytic normal: "
                "mean %.3f "
                "p99 %.3f max %.3f deg\n",
                c.layers, c.derivs, s.checked, s.decalPixels, s.meanDeg, s.p99Deg, s.maxDeg);
    // The checked region covers most of the sphere's front.
    EXPECT_GT(s.checked, kSize * kSize / 8);
    if (c.useUv) {
        EXPECT_GT(s.bumpedPixels, s.checked / 4) << "the dimples tilt many normals by > 5 degrees";
    }
    if (c.useDecal) {
        EXPECT_GT(s.decalPixels, 500) << "the decal's ring and boss must be in the checked region";
    }
    // Error budget. With no layers (measured mean 0.17, max 0.40 deg) the
    // difference is the 8-bit PNG encoding of the output (up to 0.45 deg)
    // plus the faceted sphere's interpolated normal. The maps add their own
    // 8-bit quantization, bilinear/trilinear filtering of the baked pattern
    // (worst on the foreshortened sides, where the isotropic mip choice
    // blurs along the other axis) and the faceted mesh's per-pixel frame vs
    // the exact sphere's: measured mean 0.47, p99 1.47, max 2.8 deg at 320^2.
    // A wrong convention is far outside these bounds: a flipped green
    // channel or a swapped basis tilts the dimples' normals by up to 75 deg.
    EXPECT_LT(s.meanDeg, 0.6);
    EXPECT_LT(s.p99Deg, 1.8);
    EXPECT_LT(s.maxDeg, 3.5);
}

INSTANTIATE_TEST_SUITE_P(Layers, EngineIntegrationNormals,
                         ::testing::Values(LayerCase{"none", false, false, "fine"},
                                           LayerCase{"uv", true, false, "fine"},
                                           LayerCase{"decal", false, true, "fine"},
                                           LayerCase{"uv,decal", true, true, "fine"},
                                           LayerCase{"uv,decal", true, true, "analytic"}),
                         [](const ::testing::TestParamInfo<LayerCase>& p) {
                             std::string n = p.param.layers;
                             std::replace(n.begin(), n.end(), ',', '_');
                             return n + "_" + p.param.derivs;
                         });

// The sample's assembled fragment shader (both derivative variants) passes
// the Khronos reference compiler, independently of the GL driver.
TEST(EngineIntegration, AssembledShaderValidates) {
    fs::path dir = scratchDir("ei_glslang");
    for (const char* derivs : {"fine", "analytic"}) {
        CommandResult src = runCommand(shellQuote(kProgram) + " --print-shader --derivs " + derivs);
        ASSERT_EQ(src.exitCode, 0) << src.output();
        ASSERT_NE(src.output().find("#version 450"), std::string::npos);
        ASSERT_NE(src.output().find("sgResolve"), std::string::npos)
            << "the library was not included";
        fs::path f = dir / (std::string("bumped_") + derivs + ".frag");
        std::ofstream(f) << src.output();
        CommandResult v = runCommand("glslangValidator " + shellQuote(f));
        EXPECT_EQ(v.exitCode, 0) << derivs << ":\n" << v.output();
    }
}

TEST(EngineIntegration, BadArgumentsFailWithAMessage) {
    fs::path dir = scratchDir("ei_bad");
    for (const char* args : {"--size 0x5", "--layers bumps", "--aov depth", "--frobnicate",
                             "--shader-dir /nonexistent"}) {
        CommandResult r =
            runCommand(shellQuote(kProgram) + " -o " + shellQuote(dir / "x.png") + " " + args);
        EXPECT_NE(r.exitCode, 0) << args;
        EXPECT_NE(r.output().find("error"), std::string::npos) << args << ": " << r.output();
        EXPECT_FALSE(fs::exists(dir / "x.png")) << args;
    }
}

} // namespace

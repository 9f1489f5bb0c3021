// The renderer's shared shader functions on the CPU (the same source the GPU
// compiles), against independent answers: noise gradients against finite
// differences of the noise itself, the texture emulation against the GL
// rules it follows, and layers on a flat frame against the height field
// they stand for.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "surfgrad/render/render_shaders.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;

// Central differences of a scalar field in double steps of h.
template <class F>
glm::dvec3 finiteGradient(F&& f, glm::vec3 p, float h) {
    glm::dvec3 g;
    for (int i = 0; i < 3; ++i) {
        glm::vec3 a = p, b = p;
        a[i] += h;
        b[i] -= h;
        g[i] = (double(f(a)) - double(f(b))) / (double(a[i]) - double(b[i]));
    }
    return g;
}

TEST(Noise, PerlinGradientIsTheDerivativeOfTheValue) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> u(-50.0f, 50.0f);
    double worst = 0.0;
    for (int i = 0; i < 2000; ++i) {
        glm::vec3 p(u(rng), u(rng), u(rng));
        glm::vec4 n = G::sgPerlinNoise(p);
        glm::dvec3 fd = finiteGradient([](glm::vec3 q) { return G::sgPerlinNoise(q).x; }, p, 1e-3f);
        worst = std::max(worst, glm::length(fd - glm::dvec3(n.y, n.z, n.w)));
    }
    // Central differences with h = 1e-3 on a C2 quintic-faded field whose
    // second derivatives are O(10): truncation O(h^2 * 10) ~ 1e-5, float
    // rounding of values ~1e-7 / 2e-3 ~ 1e-4; 2e-3 leaves room for both.
    EXPECT_LT(worst, 2e-3);
}

TEST(Noise, PerlinIsZeroOnTheLatticeAndBounded) {
    for (int x = -3; x <= 3; ++x)
        for (int y = -3; y <= 3; ++y)
            for (int z = -3; z <= 3; ++z) EXPECT_EQ(G::sgPerlinNoise(glm::vec3(x, y, z)).x, 0.0f);
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> u(-1000.0f, 1000.0f);
    float m = 0.0f;
    for (int i = 0; i < 20000; ++i)
        m = std::max(m, std::abs(G::sgPerlinNoise(glm::vec3(u(rng), u(rng), u(rng))).x));
    // Improved noise with edge gradients stays within about [-1, 1].
    EXPECT_LT(m, 1.1f);
    EXPECT_GT(m, 0.5f); // and is not degenerate
}

TEST(Noise, FbmAndCompositeGradientsAreDerivatives) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> u(-5.0f, 5.0f);
    for (int i = 0; i < 500; ++i) {
        glm::vec3 p(u(rng), u(rng), u(rng));
        auto fbm = [](glm::vec3 q) {
            return G::sgNoiseOctaves(SG_NOISE_FBM, q, 4, 2.0f, 0.5f, 0.0f);
        };
        glm::vec4 n = fbm(p);
        glm::dvec3 fd = finiteGradient([&](glm::vec3 q) { return fbm(q).x; }, p, 2e-4f);
        // Four octaves: the finest (frequency 8) has third derivatives 8^3
        // times those of one octave (O(100)), so the central-difference
        // truncation h^2/6 * f''' reaches 4e-8 / 6 * 5e4 ~ 4e-4 per octave
        // sum... times the gradient's O(10) magnitude: 2e-2 bounds it.
        EXPECT_LT(glm::length(fd - glm::dvec3(n.y, n.z, n.w)), 2e-2) << i;
        // Gritz composite g = sign(f)|f|^3: chain rule.
        glm::vec4 g = G::sgNoisePowerComposite(n, 3.0f);
        glm::dvec3 fdg = finiteGradient(
            [&](glm::vec3 q) { return G::sgNoisePowerComposite(fbm(q), 3.0f).x; }, p, 2e-4f);
        EXPECT_LT(glm::length(fdg - glm::dvec3(g.y, g.z, g.w)), 2e-2) << i;
    }
}

TEST(Noise, TurbulenceIsTheSumOfAbsoluteOctaves) {
    glm::vec3 p(0.37f, -1.21f, 2.5f);
    glm::vec4 t = G::sgNoiseOctaves(SG_NOISE_TURBULENCE, p, 3, 2.0f, 0.5f, 0.0f);
    glm::vec4 expect(0.0f);
    float f = 1.0f, a = 1.0f;
    for (int o = 0; o < 3; ++o) {
        glm::vec4 n = G::sgPerlinNoise(p * f);
        float s = n.x < 0 ? -1.0f : 1.0f;
        expect += glm::vec4(a * std::abs(n.x), a * f * s * glm::vec3(n.y, n.z, n.w));
        f *= 2.0f;
        a *= 0.5f;
    }
    EXPECT_NEAR(glm::length(t - expect), 0.0f, 1e-5f);
}

TEST(Noise, FrequencyClampFadesOctavesFinerThanTwoPixels) {
    glm::vec3 p(1.3f, 0.2f, -0.7f);
    // A footprint of one noise unit per pixel: octave 0 has 1 cycle/pixel,
    // beyond Nyquist: everything fades.
    glm::vec4 none = G::sgNoiseOctaves(SG_NOISE_FBM, p, 6, 2.0f, 0.5f, 1.0f);
    EXPECT_EQ(none.x, 0.0f);
    // A tiny footprint keeps every octave (weight 1).
    glm::vec4 all = G::sgNoiseOctaves(SG_NOISE_FBM, p, 6, 2.0f, 0.5f, 1e-6f);
    glm::vec4 ref = G::sgNoiseOctaves(SG_NOISE_FBM, p, 6, 2.0f, 0.5f, 0.0f);
    EXPECT_EQ(all, ref);
}

// A texture from a function of the texel index (level 0), with mips.
TextureImage ramp(int w, int h, Wrap wrap) {
    std::vector<glm::vec4> t(size_t(w) * size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            t[size_t(y) * size_t(w) + size_t(x)] = glm::vec4(float(x), float(y), 1.0f, 0.5f);
    return makeTexture(w, h, std::move(t), wrap);
}

TEST(TextureEmulation, FollowsTheGlFilteringRules) {
    TextureImage img = ramp(8, 4, Wrap::Clamp);
    ASSERT_EQ(img.levels.size(), 4u); // 8x4, 4x2, 2x1, 1x1
    EXPECT_EQ(img.levels[1].width, 4);
    EXPECT_EQ(img.levels[3].height, 1);
    G::sampler2D s{&img};
    // Magnification: bilinear between texel centres (i + 0.5) / size.
    glm::vec2 tiny(1e-4f, 0.0f), tinyY(0.0f, 1e-4f);
    EXPECT_NEAR(G::textureGrad(s, glm::vec2(2.5f / 8, 1.5f / 4), tiny, tinyY).x, 2.0f, 1e-5f);
    EXPECT_NEAR(G::textureGrad(s, glm::vec2(2.75f / 8, 1.5f / 4), tiny, tinyY).x, 2.25f, 1e-5f);
    // Clamp to edge.
    EXPECT_NEAR(G::textureGrad(s, glm::vec2(-1.0f, 0.5f), tiny, tinyY).x, 0.0f, 1e-6f);
    // One texel per pixel along x: lambda = 0, level 0 exactly.
    glm::vec2 dx(1.0f / 8, 0.0f), dy(0.0f, 1.0f / 4);
    glm::vec4 l0 = G::textureLod(s, glm::vec2(0.4f, 0.6f), 0.0f);
    EXPECT_NEAR(glm::length(G::textureGrad(s, glm::vec2(0.4f, 0.6f), dx, dy) - l0), 0.0f, 1e-6f);
    // Two texels per pixel: lambda = 1, level 1 exactly; 2^1.5: the mean of levels 1 and 2.
    glm::vec4 l1 = G::textureLod(s, glm::vec2(0.4f, 0.6f), 1.0f);
    glm::vec4 l2 = G::textureLod(s, glm::vec2(0.4f, 0.6f), 2.0f);
    EXPECT_NEAR(glm::length(G::textureGrad(s, glm::vec2(0.4f, 0.6f), 2.0f * dx, 2.0f * dy) - l1),
                0.0f, 1e-5f);
    float r = std::pow(2.0f, 1.5f);
    EXPECT_NEAR(
        glm::length(G::textureGrad(s, glm::vec2(0.4f, 0.6f), r * dx, r * dy) - 0.5f * (l1 + l2)),
        0.0f, 1e-4f);
    // The longer of the two derivative vectors decides (isotropic filtering).
    EXPECT_NEAR(glm::length(G::textureGrad(s, glm::vec2(0.4f, 0.6f), 2.0f * dx, 0.1f * dy) - l1),
                0.0f, 1e-5f);
    // Repeat wrap: one period apart is the same texel.
    TextureImage rep = ramp(8, 4, Wrap::Repeat);
    G::sampler2D sr{&rep};
    EXPECT_NEAR(glm::length(G::textureGrad(sr, glm::vec2(0.3f, 0.2f), tiny, tinyY) -
                            G::textureGrad(sr, glm::vec2(2.3f, -0.8f), tiny, tinyY)),
                0.0f, 1e-4f);
    // No image: (0, 0, 0, 1), as an incomplete GL texture.
    EXPECT_EQ(G::textureGrad(G::sampler2D{}, glm::vec2(0.5f), dx, dy), glm::vec4(0, 0, 0, 1));
    // Non-finite coordinates and derivatives stay finite.
    glm::vec4 nanSample = G::textureGrad(s, glm::vec2(NAN, 0.5f), glm::vec2(INFINITY), dy);
    for (int c = 0; c < 4; ++c) EXPECT_TRUE(std::isfinite(nanSample[c]));
}

TEST(TextureEmulation, FastLog2LodMatchesLlvmpipesApproximation) {
    TextureImage img = ramp(64, 64, Wrap::Repeat);
    G::sampler2D exact{&img}, fast{&img, G::LodRule::FastLog2};
    glm::vec2 st(0.31f, 0.57f), dy(0.0f, 1.0f / 64);
    // At powers of two both rules agree...
    for (float k : {1.0f, 2.0f, 4.0f, 8.0f}) {
        glm::vec2 dx(k / 64, 0.0f);
        EXPECT_NEAR(
            glm::length(G::textureGrad(exact, st, dx, dy) - G::textureGrad(fast, st, dx, dy)), 0.0f,
            1e-4f);
    }
    // ...in between, fastlog2(rho^2)/2 = e + m - 1 for rho^2 = 2^e m: at
    // rho = sqrt(3), rho^2 = 3 = 2^1 * 1.5 -> lambda = 0.75, not 0.792.
    glm::vec2 dx(std::sqrt(3.0f) / 64, 0.0f);
    glm::vec4 expect = G::textureLod(exact, st, 0.75f);
    EXPECT_NEAR(glm::length(G::textureGrad(fast, st, dx, dy) - expect), 0.0f, 1e-4f);
}

// A flat frame: the plane y = 0 seen from above, screen x along +x, screen y
// along -z, `pix` world units per pixel.
G::SgFrame flatFrame(float pix) {
    return G::sgPrologue(glm::vec3(0, 1, 0), glm::vec3(pix, 0, 0), glm::vec3(0, 0, -pix), true,
                         SG_BFACE_NONE);
}

TEST(Layers, HeightMapSurfaceGradientIsTheSlopeOfTheDisplacement) {
    // Height texture h = texel x index (a ramp), on a plane where st = P.x /
    // size, P.z / -size. The displacement scale * h has slope scale * 64 / size
    // (world per world) along +x: listing 8 must return exactly that.
    const float size = 2.0f, scale = 0.001f, pix = 0.004f;
    TextureImage img = ramp(64, 64, Wrap::Repeat);
    G::sampler2D s{&img};
    G::SgFrame f = flatFrame(pix);
    glm::vec2 st(0.3f, 0.4f), dSTdx(pix / size, 0.0f), dSTdy(0.0f, pix / size);
    G::SgUvFrame uv = G::sgUvFramePixel(f, st, dSTdx, dSTdy);
    G::SgHeightParams p{scale, 0};
    glm::vec3 g = G::sgLayerHeight(f, uv, p, s);
    // Texels are linear in x between centres: forward differences are exact.
    EXPECT_NEAR(g.x, scale * 64.0f / size, 1e-3f * scale * 64.0f / size);
    EXPECT_NEAR(g.y, 0.0f, 1e-6f);
    EXPECT_NEAR(g.z, 0.0f, 1e-6f);
}

TEST(Layers, FlatNormalMapsAddNothing) {
    std::vector<glm::vec4> flat(16 * 16, glm::vec4(0.5f, 0.5f, 1.0f, 1.0f));
    TextureImage img = makeTexture(16, 16, flat, Wrap::Repeat);
    G::sampler2D s{&img};
    G::SgFrame f = flatFrame(0.01f);
    G::SgUvFrame uv =
        G::sgUvFramePixel(f, glm::vec2(0.2f), glm::vec2(0.01f, 0), glm::vec2(0, 0.01f));
    EXPECT_EQ(G::sgLayerUvNormal(uv, G::sgUnpackUvNormal(glm::vec4(1, 0, 0, -1), glm::vec4(0)), s),
              glm::vec3(0.0f));
    G::SgVolumeSpace vs =
        G::sgVolumeSpace(f, glm::vec3(0.3f, 0.0f, 0.2f), glm::mat3(1.0f), glm::mat3(1.0f));
    glm::vec3 tri = G::sgLayerTriplanar(
        f, vs, G::sgUnpackTriplanar(glm::vec4(1, 1, 4, 1), glm::vec4(0), glm::vec4(0)), s, s, s);
    EXPECT_LT(glm::length(tri), 1e-6f);
}

TEST(Layers, UvNormalTiltResolvesToTheMapsNormal) {
    // A constant tangent-space normal m on a plane with an orthonormal
    // per-pixel frame (T = +x, B = -z along +t): the resolved normal is m
    // expressed in (T, B, N) (listings 4, 5, 6 and 1 together).
    glm::vec3 m = glm::normalize(glm::vec3(0.3f, -0.2f, 0.9f));
    std::vector<glm::vec4> tex(4 * 4, glm::vec4(0.5f * m + 0.5f, 1.0f));
    TextureImage img = makeTexture(4, 4, tex, Wrap::Repeat);
    G::sampler2D s{&img};
    G::SgFrame f = flatFrame(0.01f);
    G::SgUvFrame uv =
        G::sgUvFramePixel(f, glm::vec2(0.5f), glm::vec2(0.01f, 0), glm::vec2(0, 0.01f));
    EXPECT_NEAR(glm::length(uv.vT - glm::vec3(1, 0, 0)), 0.0f, 1e-6f);
    EXPECT_NEAR(glm::length(uv.vB - glm::vec3(0, 0, -1)), 0.0f, 1e-6f);
    glm::vec3 g =
        G::sgLayerUvNormal(uv, G::sgUnpackUvNormal(glm::vec4(1, 0, 0, -1), glm::vec4(0)), s);
    glm::vec3 n = G::sgResolve(f, g);
    glm::vec3 expect = glm::normalize(m.x * glm::vec3(1, 0, 0) + m.y * glm::vec3(0, 0, -1) +
                                      m.z * glm::vec3(0, 1, 0));
    EXPECT_NEAR(glm::length(n - expect), 0.0f, 1e-5f);
    // DirectX green: the t component flips.
    glm::vec3 gdx =
        G::sgLayerUvNormal(uv, G::sgUnpackUvNormal(glm::vec4(1, 0, 1, -1), glm::vec4(0)), s);
    glm::vec3 ndx = G::sgResolve(f, gdx);
    EXPECT_NEAR(ndx.z, -expect.z, 1e-5f);
    EXPECT_NEAR(ndx.x, expect.x, 1e-5f);
}

TEST(Layers, NoiseSurfaceGradientIsTheTangentialVolumeGradient) {
    G::SgFrame f = flatFrame(1e-4f);
    glm::vec3 p(0.3f, 0.0f, -0.7f);
    G::SgVolumeSpace vs = G::sgVolumeSpace(f, p, glm::mat3(1.0f), glm::mat3(1.0f));
    G::SgNoiseParams np =
        G::sgUnpackNoise(glm::vec4(0.05f, 3.0f, SG_NOISE_PERLIN, 1), glm::vec4(2, 0.5f, 1, 0),
                         glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f));
    glm::vec3 g = G::sgLayerNoise(f, vs, np);
    auto H = [&](glm::vec3 q) { return 0.05f * G::sgPerlinNoise(3.0f * q).x; };
    glm::dvec3 fd = finiteGradient(H, p, 1e-3f);
    EXPECT_NEAR(g.x, fd.x, 2e-3);
    EXPECT_EQ(g.y, 0.0f); // no component along the normal (listing 12)
    EXPECT_NEAR(g.z, fd.z, 2e-3);
}

TEST(Layers, DecalFadesOutsideItsBox) {
    G::SgDecalParams p =
        G::sgUnpackDecal(glm::vec4(0, 0, 0, 1), glm::vec4(1, 0, 0, 0.5f), glm::vec4(0, 0, -1, 0.5f),
                         glm::vec4(0, 1, 0, 0.5f), glm::vec4(0.25f, 0.5f, 0.17f, 0), glm::vec4(0));
    glm::vec3 up(0, 1, 0);
    EXPECT_EQ(G::sgDecalFade(p, glm::vec3(0.2f, 0.3f, 0.0f), up), 1.0f);
    EXPECT_EQ(G::sgDecalFade(p, glm::vec3(1.2f, 0.3f, 0.0f), up), 0.0f);
    EXPECT_EQ(G::sgDecalFade(p, glm::vec3(0.2f, 0.3f, 1.01f), up), 0.0f);
    EXPECT_GT(G::sgDecalFade(p, glm::vec3(0.2f, 0.3f, 0.9f), up), 0.0f);
    EXPECT_LT(G::sgDecalFade(p, glm::vec3(0.2f, 0.3f, 0.9f), up), 1.0f);
    // A surface facing away from the projector gets nothing.
    EXPECT_EQ(G::sgDecalFade(p, glm::vec3(0.0f), glm::vec3(1, 0, 0)), 0.0f);
}

} // namespace
} // namespace sg::render::test

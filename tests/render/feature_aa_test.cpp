// Antialiased feature-curve layers (sg/render/layer_feature_aa.glsl, the
// prefiltered chain of layer_feature.cpp): every chain level holds the
// average of the level-0 moments; a single straight crease gives the known
// mean and variance of a two-valued slope distribution; curve joints and
// stars stay finite at every level; the switch from the exact evaluator to
// the chain has no step; the GPU matches the CPU reference on the path; and
// nothing of it is compiled unless a layer asks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "hardcase.h"
#include "layers/feature_assets.h"
#include "render_internal.h"
#include "render_test_util.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;
namespace F = sg::features;

F::Segment line(glm::dvec2 a, glm::dvec2 b, int curve) {
    F::Segment s;
    s.p0 = a;
    s.p2 = b;
    s.p1 = 0.5 * (a + b);
    s.curve = curve;
    return s;
}

// Bakes a texel-space network (identity transform) into the assets' form.
FeatureMapsAsset bakeAsset(const F::CurveNetwork& net, int size) {
    F::BakeOptions o;
    o.size = size;
    o.fit = false;
    const F::FeatureMaps maps = F::bake(net, o);
    FeatureMapsAsset a;
    a.gpu = maps.packGpu();
    a.bandTexels = maps.bandTexels;
    return a;
}

FeatureChainSource chainSource(const std::string& profile, float depth, float w0, float w,
                               int part) {
    FeatureChainSource c;
    c.profile = profile;
    c.depth = depth;
    c.w0 = w0;
    c.width = w;
    c.part = part;
    return c;
}

// The vertical line x = x0 across (and far beyond) an n-texel map.
F::CurveNetwork verticalLine(double x0, int n) {
    F::CurveNetwork net;
    net.curves.resize(1);
    net.segments.push_back(line({x0, -3.0 * n}, {x0, 4.0 * n}, 0));
    return net;
}

TEST(FeatureAa, ChainLevelsAverageLevelZero) {
    // The flame outline fitted into 64 texels (curves, joints, a closed
    // path): level k texel (i, j) against the mean of the 2^k x 2^k
    // level-0 texels it covers.
    F::CurveNetwork net = F::loadSvg(std::string(SURFGRAD_DATA_DIR) + "/svg/flame.svg");
    F::BakeOptions o;
    o.size = 64;
    const F::FeatureMaps maps = F::bake(net, o);
    FeatureMapsAsset asset;
    asset.gpu = maps.packGpu();
    asset.bandTexels = maps.bandTexels;
    const detail::FeatureChainTextures chain =
        detail::featureChainTextures(asset, chainSource("crease", 1.5f, 0.0f, 3.0f, 0));
    for (int part = 0; part < 2; ++part) {
        const TextureImage& t = chain.part[part];
        ASSERT_EQ(t.levels.size(), 7u);
        double maxAbs = 0.0;
        for (int j = 0; j < 64; ++j)
            for (int i = 0; i < 64; ++i)
                for (int c = 0; c < 4; ++c)
                    maxAbs = std::max(maxAbs, std::abs(double(t.levels[0].texel(i, j)[c])));
        ASSERT_GT(maxAbs, 0.1); // the creases are in the map
        double worst = 0.0;
        for (size_t k = 1; k < t.levels.size(); ++k) {
            const int n = t.levels[k].width, block = 1 << k;
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    glm::dvec4 sum(0.0);
                    for (int y = 0; y < block; ++y)
                        for (int x = 0; x < block; ++x)
                            sum += glm::dvec4(t.levels[0].texel(i * block + x, j * block + y));
                    const glm::dvec4 mean = sum / double(block * block);
                    const glm::dvec4 got(t.levels[k].texel(i, j));
                    for (int c = 0; c < 4; ++c) worst = std::max(worst, std::abs(got[c] - mean[c]));
                }
        }
        // Each level is a float 2x2 average of the one above: at most one
        // rounding (2^-24 relative) of the largest value per level, six
        // levels.
        EXPECT_LT(worst, 6.0 * maxAbs * 1.2e-7) << "part " << part;
    }
}

// The chain is the same bits at 1, 2, 3 and 7 threads (rows of level 0 in
// parallel), with and without the exact near field.
TEST(FeatureAa, ChainIsTheSameAtEveryThreadCount) {
    F::CurveNetwork net = F::loadSvg(std::string(SURFGRAD_DATA_DIR) + "/svg/paw-print.svg");
    F::BakeOptions o;
    o.size = 96;
    o.mode = F::BakeMode::Quadratic;
    o.nearField = true;
    const F::FeatureMaps maps = F::bake(net, o);
    FeatureMapsAsset asset;
    asset.gpu = maps.packGpu();
    asset.bandTexels = maps.bandTexels;
    asset.nearBandTexels = maps.nearBandTexels;
    for (bool near : {false, true}) {
        FeatureChainSource c = chainSource("vgroove", 1.0f, 0.5f, 2.5f, 0);
        c.nearExact = near;
        const detail::FeatureChainTextures one =
            detail::featureChainTextures(asset, c, detail::kFeatureChainSamples, 1);
        for (int threads : {2, 3, 7}) {
            SCOPED_TRACE("near " + std::to_string(near) + ", threads " + std::to_string(threads));
            const detail::FeatureChainTextures m =
                detail::featureChainTextures(asset, c, detail::kFeatureChainSamples, threads);
            for (int part = 0; part < 2; ++part) {
                ASSERT_EQ(one.part[part].levels.size(), m.part[part].levels.size());
                for (size_t l = 0; l < m.part[part].levels.size(); ++l)
                    EXPECT_TRUE(one.part[part].levels[l].data == m.part[part].levels[l].data)
                        << "part " << part << " level " << l;
            }
        }
    }
}

TEST(FeatureAa, StraightCreaseGivesTheTwoValuedVariance) {
    // A V-groove of depth D = 2 and half-width w = 4 (w0 = w: no blend
    // band) along x = x0 = 32.5: the slope is (-D/w, 0) on [x0 - w, x0),
    // (+D/w, 0) on (x0, x0 + w], 0 beyond. Over [a, b] with fractions pL,
    // pR of the two flanks: E[d.x] = s (pR - pL), E[d.x^2] = s^2 (pL + pR),
    // var = E[d.x^2] - E[d.x]^2 (with pL + pR = 1 the two-valued 4 s^2 pL pR).
    const int n = 64;
    const double x0 = 32.5, w = 4.0, s = 2.0 / w;
    const FeatureMapsAsset asset = bakeAsset(verticalLine(x0, n), n);
    const detail::FeatureChainTextures chain =
        detail::featureChainTextures(asset, chainSource("vgroove", 2.0f, 4.0f, 4.0f, 0));
    const TextureImage& a = chain.part[0];
    const TextureImage& b = chain.part[1];
    auto overlap = [](double lo, double hi, double a0, double a1) {
        return std::max(0.0, std::min(hi, a1) - std::max(lo, a0));
    };
    for (size_t k = 0; k < a.levels.size(); ++k) {
        const int size = 1 << k;
        const int i = 32 / size, j = a.levels[k].height / 2;
        const double lo = double(i * size), hi = double((i + 1) * size);
        const double pL = overlap(lo, hi, x0 - w, x0) / size,
                     pR = overlap(lo, hi, x0, x0 + w) / size;
        const double mean = s * (pR - pL), second = s * s * (pL + pR);
        const glm::vec4 ta = a.levels[k].texel(i, j), tb = b.levels[k].texel(i, j);
        const glm::vec3 cov =
            G::sgLeanCovariance(glm::vec2(ta.x, ta.y), glm::vec3(ta.z, ta.w, tb.x));
        // The 8 x 8 sample midpoints are 1/16 texel from the line and the
        // flanks' ends, farther than the evaluator's half-float distance
        // error (5e-4 texels): every sample is classified exactly, and only
        // float rounding of the 64-sample averages remains.
        EXPECT_NEAR(ta.x, mean, 1e-5) << "level " << k;
        EXPECT_NEAR(ta.z, second, 1e-5) << "level " << k;
        EXPECT_NEAR(cov.x, second - mean * mean, 2e-5) << "level " << k;
        EXPECT_NEAR(ta.y, 0.0, 1e-5) << "level " << k;
        EXPECT_NEAR(cov.y, 0.0, 1e-5) << "level " << k;
        if (k == 0) {
            EXPECT_NEAR(cov.x, s * s, 2e-5); // pL = pR = 1/2: the full s^2
        }
    }
}

// A six-armed star (arms meeting at one point off the texel grid) and a
// sharp corner joint: the evaluator's hardest configurations.
F::CurveNetwork starAndJoint() {
    F::CurveNetwork net;
    net.curves.resize(7);
    const glm::dvec2 c(16.3, 15.7);
    for (int k = 0; k < 6; ++k) {
        const double a = 0.3 + k * 6.283185307179586 / 6.0;
        net.segments.push_back(line(c, c + 9.0 * glm::dvec2(std::cos(a), std::sin(a)), k));
    }
    net.segments.push_back(line({24.2, 4.1}, {29.6, 6.3}, 6));
    net.segments.push_back(line({29.6, 6.3}, {24.9, 7.2}, 6));
    return net;
}

TEST(FeatureAa, FiniteAtJointsAndStarsAtEveryLevel) {
    const FeatureMapsAsset asset = bakeAsset(starAndJoint(), 32);
    sg::test::Worst second;
    double bad = 0.0;
    for (const char* profile : {"vgroove", "crease", "step", "seam"}) {
        const detail::FeatureChainTextures chain =
            detail::featureChainTextures(asset, chainSource(profile, 3.0f, 0.5f, 2.5f, 0));
        const TextureImage& a = chain.part[0];
        const TextureImage& b = chain.part[1];
        for (size_t k = 0; k < a.levels.size(); ++k)
            for (int j = 0; j < a.levels[k].height; ++j)
                for (int i = 0; i < a.levels[k].width; ++i) {
                    const glm::vec4 ta = a.levels[k].texel(i, j), tb = b.levels[k].texel(i, j);
                    const glm::vec3 cov =
                        G::sgLeanCovariance(glm::vec2(ta.x, ta.y), glm::vec3(ta.z, ta.w, tb.x));
                    bool ok = std::isfinite(tb.x);
                    for (int c = 0; c < 4; ++c) ok = ok && std::isfinite(ta[c]);
                    // A covariance: non-negative variances, |cov| bounded.
                    ok = ok && cov.x >= 0.0f && cov.y >= 0.0f &&
                         std::abs(cov.z) <= std::sqrt(cov.x) * std::sqrt(cov.y) * 1.0001f;
                    bad += ok ? 0.0 : 1.0;
                    second.add(double(ta.z + ta.w));
                }
    }
    sg::test::hardCaseAtMost("feature-stars",
                             "prefiltered chain of a six-armed star and a sharp joint "
                             "(vgroove, crease, step, seam), every level",
                             "texels with a non-finite moment or an indefinite covariance", bad,
                             0.0);
    // |slope| <= max |h'| = 2 D / w = 2.4 (crease, step) and the seam's
    // pi/2 D / w = 1.9: E[|d|^2] is an average of squares of at most 5.76.
    sg::test::hardCaseAtMost("feature-stars",
                             "prefiltered chain of a six-armed star and a sharp joint",
                             "E[|d|^2] of any texel of any level", second.value, 5.76);
}

// The layer at texel position `pos` of an n-texel map with an isotropic
// footprint of rho texels per pixel: surface gradient (frame = identity
// TBN) and the added covariance.
struct AaSample {
    glm::vec3 surfGrad;
    glm::mat3 cov;
};
AaSample sampleLayer(const FeatureMapsAsset& asset, const TextureImage& a, const TextureImage& b,
                     const G::SgFeatProfile& pr, int n, glm::vec2 pos, float rho) {
    G::SgUvFrame uv;
    uv.st = pos / float(n);
    uv.dSTdx = glm::vec2(rho / float(n), 0.0f);
    uv.dSTdy = glm::vec2(0.0f, rho / float(n));
    uv.vT = glm::vec3(1.0f, 0.0f, 0.0f);
    uv.vB = glm::vec3(0.0f, 1.0f, 0.0f);
    G::SgFeatureLayerParams p{};
    p.strength = 1.0f;
    p.mapSize = float(n);
    p.tiling = 1.0f;
    G::SgFeatureAaParams aa{true};
    G::sampler2D sa{&a}, sb{&b};
    AaSample r;
    r.cov = glm::mat3(0.0f);
    r.surfGrad = G::sgLayerFeatureAa(uv, p, aa, pr, asset.gpu.cornerSampler(),
                                     asset.gpu.edgeSampler(), sa, sa, sb, r.cov);
    return r;
}

TEST(FeatureAa, SwitchHasNoStep) {
    // Footprints 0.5 .. 4 texels in steps of 2^(1/64) at points on and near
    // the flanks of a crease: the exact evaluator below one texel, the
    // chain from two, the mixture between. Its mean and covariance are
    // continuous in the weight w (C1 in log2 rho), so consecutive steps
    // differ by at most |dw| (|exact - chain| + |cov|) plus the chain's own
    // change between levels (trilinear: linear in log2 rho).
    const int n = 64;
    const FeatureMapsAsset asset = bakeAsset(verticalLine(32.5, n), n);
    const detail::FeatureChainTextures chain =
        detail::featureChainTextures(asset, chainSource("crease", 2.0f, 0.0f, 4.0f, 0));
    const TextureImage& a = chain.part[0];
    const TextureImage& b = chain.part[1];
    const G::SgFeatProfile pr = F::makeProfile("crease", 2.0f, 0.0f, 4.0f);
    const float step = std::exp2(1.0f / 64.0f);
    for (float x : {32.2f, 32.45f, 32.9f, 34.1f, 36.3f}) {
        const glm::vec2 pos(x, 20.37f);
        double worstJump = 0.0, worstAtSwitch = 0.0;
        AaSample prev = sampleLayer(asset, a, b, pr, n, pos, 0.5f);
        for (float rho = 0.5f * step; rho <= 4.0f; rho *= step) {
            AaSample cur = sampleLayer(asset, a, b, pr, n, pos, rho);
            ASSERT_TRUE(std::isfinite(cur.surfGrad.x) && std::isfinite(cur.cov[0][0]));
            const double jump = glm::length(cur.surfGrad - prev.surfGrad) +
                                std::abs(double(cur.cov[0][0] - prev.cov[0][0]));
            worstJump = std::max(worstJump, jump);
            if (rho > 0.95f && rho < 1.06f) worstAtSwitch = std::max(worstAtSwitch, jump);
            prev = cur;
        }
        // The slope magnitude is at most 2 D / w = 1, its square 1: a
        // 1/64-octave step of smoothstep's weight (slope <= 1.5 per octave)
        // moves the mixture by at most 1.5/64 (2 + 1) ~ 0.07, the
        // trilinear chain by about the same; a step at the switch would
        // show as a jump of the full exact-chain difference (up to 1).
        EXPECT_LT(worstJump, 0.1) << "x " << x;
        EXPECT_LT(worstAtSwitch, 0.1) << "x " << x;
    }
    // Below one texel the mean is today's exact evaluator; the covariance
    // is level 0's scaled by the footprint's area, none below 1/8 texel.
    const glm::vec2 at(32.9f, 20.37f);
    G::SgFeatResult r = F::sample(asset.gpu, at);
    const glm::vec2 d = G::sgFeatDeriv(r, pr, glm::vec2(0.0f));
    const glm::vec3 g = G::sgSurfgradFromTBN(d, glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
    const AaSample tiny = sampleLayer(asset, a, b, pr, n, at, 0.1f);
    EXPECT_EQ(tiny.surfGrad, g);
    EXPECT_EQ(tiny.cov[0][0], 0.0f);
    const AaSample fine = sampleLayer(asset, a, b, pr, n, at, 0.9f);
    const AaSample one = sampleLayer(asset, a, b, pr, n, at, 1.0f);
    EXPECT_EQ(fine.surfGrad, g);
    ASSERT_GT(one.cov[0][0], 0.0f) << "the point lies on a flank: its texel's slopes vary";
    // (0.81 - 1/64) / (1 - 1/64) of the one-texel variance; both read level 0
    // bilinearly at the same point, so only float rounding separates them.
    EXPECT_NEAR(fine.cov[0][0], one.cov[0][0] * (0.81f - 1.0f / 64.0f) / (1.0f - 1.0f / 64.0f),
                1e-5f * one.cov[0][0]);
}

// The renderer's path: a sphere with a feature layer tiled 6 x 6 over the
// view, minified from about one to several texels per pixel.
std::string featureScene(const std::string& aa) {
    return oneMaterialScene(
        R"({"type": "feature", "curves": {"svg": ")" + std::string(SURFGRAD_DATA_DIR) +
            R"(/svg/flame.svg", "size": 64}, "profile": "crease", "depth": 1.5, "width": 3,
             "tiling": 1, "antialias": ")" +
            aa + R"("})",
        kSphere, R"("roughness": 0.25,)");
}

// The same with the exact near field and per-curve profiles
// (sgLayerFeatureNearAa), next to a layer without antialiasing in the same
// loop.
std::string nearScene() {
    return oneMaterialScene(
        R"({"type": "feature", "near": "exact", "antialias": "lean", "curves": {"json": ")" +
            std::string(SURFGRAD_SOURCE_DIR) +
            R"(/examples/feature-profiles/curves.json", "size": 96, "mode": "quadratic", "margin": 6},
             "profile": "crease", "depth": 1.5, "width": 3},
            {"type": "feature", "curves": {"svg": ")" +
            std::string(SURFGRAD_DATA_DIR) +
            R"(/svg/flame.svg", "size": 64}, "profile": "vgroove", "depth": 1, "width": 2, "tiling": 2})",
        kSphere, R"("roughness": 0.25,)");
}

TEST(FeatureAa, GpuMatchesCpuWithTheNearFieldAndAMixedLoop) {
    Scene s = sceneFromJson(nearScene());
    SceneAssets a = loadAssets(s);
    CpuOptions parity;
    parity.derivatives = CpuDerivatives::Quad;
    parity.textureLod = sg::glsl::LodRule::FastLog2;
    NormalRenders p = renderNormalsBoth(s, a, parity);
    ASSERT_GT(countCovered(p.gpuPrim), 1000u);
    EXPECT_EQ(p.diff.nonFinite, 0u);
    // The evaluator's branches on rounded distances and llvmpipe's LOD
    // arithmetic near the switch, as in the test below.
    EXPECT_LE(p.diff.p99Deg, 0.5);
    std::printf("feature lean + near parity: normals max %.4f deg, p99 %.4f deg\n", p.diff.maxDeg,
                p.diff.p99Deg);
}

TEST(FeatureAa, GpuMatchesCpuOnTheAntialiasedPath) {
    Scene s = sceneFromJson(featureScene("lean"));
    SceneAssets a = loadAssets(s);
    CpuOptions parity;
    parity.derivatives = CpuDerivatives::Quad;
    parity.textureLod = sg::glsl::LodRule::FastLog2;
    NormalRenders p = renderNormalsBoth(s, a, parity);
    ASSERT_GT(countCovered(p.gpuPrim), 1000u);
    EXPECT_EQ(p.diff.nonFinite, 0u);
    // The bound of the other feature-layer parity checks (image_test.cpp):
    // the evaluator's branches on rounded distances, plus llvmpipe's LOD
    // arithmetic near the switch (FastLog2 on the CPU side).
    EXPECT_LE(p.diff.p99Deg, 0.5);
    View v = makeView(s, a, 0, 0, Aov::Color);
    Image g = gpu().render(s, a, v), c = renderCpu(s, a, v, parity);
    EXPECT_EQ(countNonFinite(g), 0u);
    EXPECT_EQ(countNonFinite(c), 0u);
    std::printf("feature lean parity: normals max %.4f deg, p99 %.4f deg\n", p.diff.maxDeg,
                p.diff.p99Deg);
}

TEST(FeatureAa, NothingIsCompiledUnlessAsked) {
    auto fragment = [](const std::string& json) {
        Scene s = sceneFromJson(json);
        SceneAssets a = loadAssets(s);
        return assembleProgram(planMaterial(s, a, 0, 0)).fragment;
    };
    const std::string off = fragment(featureScene("none"));
    for (const char* marker :
         {"slopeCov", "sgLayerFeatureAa", "uFeatChainA", "layer_feature_aa", "sgAaRoughness"})
        EXPECT_EQ(off.find(marker), std::string::npos) << marker;
    const std::string lean = fragment(featureScene("lean"));
    for (const char* marker : {"sgLayerFeatureAa(", "uFeatChainA", "sgAaRoughness("})
        EXPECT_NE(lean.find(marker), std::string::npos) << marker;
}

TEST(FeatureAa, SceneFieldIsValidated) {
    EXPECT_THROW(sceneFromJson(featureScene("toksvig")), sg::io::InputError);
    const std::string withBase = oneMaterialScene(
        R"({"type": "feature", "curves": {"svg": ")" + std::string(SURFGRAD_DATA_DIR) +
            R"(/svg/flame.svg", "size": 32}, "antialias": "lean",
            "base_map": {"procedural": "bumps", "size": 16}})",
        kSphere);
    EXPECT_THROW(sceneFromJson(withBase), sg::io::InputError);
}

// The chain counts in the scene's texture budget (2 float RGBA textures of
// 64^2 with mips: 2 x 87,376 bytes), is refused with the layer's field when
// it does not fit, and is built once for both of its textures.
TEST(FeatureAa, ChainCountsInTheTextureBudget) {
    const Scene s = sceneFromJson(featureScene("lean"));
    const uint64_t chainBytes = 2 * textureBytes(64, 64, 4, TexelType::Float);
    AssetOptions tight;
    tight.textureBudgetBytes = chainBytes - 1;
    try {
        (void)loadAssets(s, tight);
        ADD_FAILURE() << "a budget one byte short of the chain was accepted";
    } catch (const sg::io::InputError& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("materials[0].layers[0]"), std::string::npos) << m;
        EXPECT_NE(m.find("prefiltered chain"), std::string::npos) << m;
        EXPECT_NE(m.find("texture budget"), std::string::npos) << m;
    }
    AssetOptions enough;
    enough.textureBudgetBytes = chainBytes;
    const SceneAssets a = loadAssets(s, enough);
    uint64_t chains = 0;
    int count = 0;
    for (const auto& [key, tex] : a.textures)
        if (key.rfind("featchain:", 0) == 0) {
            chains += tex->bytes();
            ++count;
        }
    EXPECT_EQ(count, 2);
    EXPECT_EQ(chains, chainBytes);
}

} // namespace
} // namespace sg::render::test

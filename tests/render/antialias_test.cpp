// Bump antialiasing (sg/render/antialias.glsl, layer_uv_normal_aa.glsl):
// LEAN and Toksvig give the known slope variance of a known field; the
// covariances of independent layers add after each is mapped by its own
// Jacobian; the GPU matches the CPU reference on the antialiased path
// (normals and radiance); flat, extreme and horizon maps stay finite; and
// nothing of it is compiled into a program that does not ask for it.
#include <gtest/gtest.h>

#include <unistd.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "render_internal.h"
#include "surfgrad/base/io.h"
#include "antialias_test_util.h"
#include "render_test_util.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;

constexpr double kTwoPi = 6.283185307179586;

// A footprint of `texels` texels per pixel along s and t on an n-texel map.
glm::vec2 footprint(int n, double texels) {
    return glm::vec2(float(texels / n));
}

TEST(Antialias, LeanGivesTheSineFieldsSlopeVariance) {
    // 256 texels, 8 periods along s and 4 along t: a level-5 texel covers
    // 32 x 32 texels, one whole period along s and half of one along t, so
    // the footprint's slope variance is ax^2 / 2 along s; along t it is
    // ay^2 / 2 at the top level (the whole map). The slopes are separable
    // cosines: cov xy = 0.
    const int n = 256;
    const double ax = 0.8, ay = 0.3;
    TextureImage map = sineSlopeMap(n, ax, 8, ay, 4);
    Moments m = momentsOf(map);
    G::sampler2D sa{&m.a}, sb{&m.b};
    // Every level-5 texel centre: var x = ax^2 / 2 (the sampled cosine's
    // mean square is exactly 1/2 over whole periods).
    double worst = 0.0;
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
            glm::vec2 st((i + 0.5f) / 8.0f, (j + 0.5f) / 8.0f);
            glm::vec2 d = footprint(n, 32.0);
            G::SgSlopeDist s = G::sgSampleLeanSlopes(sa, sb, st, glm::vec2(d.x, 0.0f),
                                                     glm::vec2(0.0f, d.y), false);
            worst = std::max(worst, std::abs(double(s.cov.x) - ax * ax / 2.0));
            EXPECT_NEAR(s.mean.x, 0.0f, 1e-5f);
        }
    // Float sums of 1024 texels per level-5 texel, 5 averaging steps: a few
    // ulps of the second moment (0.32) each.
    EXPECT_LT(worst, 1e-5) << "LEAN var x at level 5";
    // The top level: the whole map, both variances and zero covariance.
    G::SgSlopeDist top = G::sgSampleLeanSlopes(sa, sb, glm::vec2(0.5f), glm::vec2(1.0f, 0.0f),
                                               glm::vec2(0.0f, 1.0f), false);
    std::printf("LEAN top level: cov error x %.3g y %.3g xy %.3g\n",
                double(top.cov.x) - ax * ax / 2.0, double(top.cov.y) - ay * ay / 2.0,
                double(top.cov.z));
    // The whole map averaged in float, 8 box-filter steps of the moments:
    // a few ulps of values up to 0.32 per step (ulp 3e-8) and the
    // difference E[x^2] - E[x]^2 of two rounded values; 1e-5 is over 100x
    // that (measured -7.2e-9, 1.8e-9 and 0).
    EXPECT_NEAR(top.cov.x, ax * ax / 2.0, 1e-5);
    EXPECT_NEAR(top.cov.y, ay * ay / 2.0, 1e-5);
    EXPECT_NEAR(top.cov.z, 0.0, 1e-5);
    EXPECT_NEAR(top.mean.x, 0.0f, 1e-5f);
    EXPECT_NEAR(top.mean.y, 0.0f, 1e-5f);
    // Level 0 (one texel per pixel, at a texel centre): no variance.
    G::SgSlopeDist fine = G::sgSampleLeanSlopes(sa, sb, glm::vec2(0.5f / n), footprint(n, 0.5),
                                                footprint(n, 0.5), false);
    EXPECT_NEAR(fine.cov.x, 0.0, 1e-6);
    EXPECT_NEAR(fine.mean.x, ax * std::cos(kTwoPi * 8 * 0.5 / n), 1e-5);
    // DirectX green: t flips, so mean y and cov xy change sign.
    G::SgSlopeDist dx = G::sgSampleLeanSlopes(sa, sb, glm::vec2(0.5f / n), footprint(n, 0.5),
                                              footprint(n, 0.5), true);
    EXPECT_EQ(dx.mean.y, -fine.mean.y);
}

TEST(Antialias, LeanCovarianceOfCorrelatedSlopes) {
    // d = (a cos(w s), b cos(w s)): fully correlated, cov xy = a b / 2.
    const int n = 64;
    std::vector<glm::vec4> texels(size_t(n) * size_t(n));
    const double a = 0.5, b = -0.25;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double c = std::cos(kTwoPi * 2 * (i + 0.5) / n);
            glm::dvec3 m = glm::normalize(glm::dvec3(-a * c, -b * c, 1.0));
            texels[size_t(j) * size_t(n) + size_t(i)] = glm::vec4(glm::vec3(m), 1.0f);
        }
    TextureImage map = makeTexture(n, n, std::move(texels), Wrap::Repeat);
    Moments m = momentsOf(map);
    G::sampler2D sa{&m.a}, sb{&m.b};
    G::SgSlopeDist top = G::sgSampleLeanSlopes(sa, sb, glm::vec2(0.5f), glm::vec2(1.0f, 0.0f),
                                               glm::vec2(0.0f, 1.0f), false);
    // Float moments of a 64 x 64 map: 1e-6 relative to values of 0.1.
    EXPECT_NEAR(top.cov.x, a * a / 2, 1e-6);
    EXPECT_NEAR(top.cov.y, b * b / 2, 1e-6);
    EXPECT_NEAR(top.cov.z, a * b / 2, 1e-6);
    G::SgSlopeDist flipped = G::sgSampleLeanSlopes(sa, sb, glm::vec2(0.5f), glm::vec2(1.0f, 0.0f),
                                                   glm::vec2(0.0f, 1.0f), true);
    EXPECT_EQ(flipped.cov.z, -top.cov.z);
}

TEST(Antialias, ToksvigApproximatesTheSlopeVariance) {
    // Toksvig's s2 = (1 - |E[n]|) / |E[n]| estimates the per-axis slope
    // variance (var x + var y) / 2; its error grows with the fourth moment
    // of the slopes (docs/normalmap.md: 0.1% at slopes 0.06, 1% at 0.18).
    const int n = 256;
    const double ax = 0.15, ay = 0.1;
    TextureImage map = sineSlopeMap(n, ax, 8, ay, 4);
    Moments m = momentsOf(map);
    G::sampler2D st{&m.toksvig};
    G::SgSlopeDist top = G::sgSampleToksvigSlopes(st, glm::vec2(0.5f), glm::vec2(1.0f, 0.0f),
                                                  glm::vec2(0, 1), false);
    const double expect = (ax * ax / 2 + ay * ay / 2) / 2;
    // 3%: the fourth-moment term at slopes up to 0.15 (measured -0.74%).
    EXPECT_NEAR(top.cov.x, expect, 0.03 * expect);
    EXPECT_EQ(top.cov.x, top.cov.y);
    EXPECT_EQ(top.cov.z, 0.0f);
    std::printf("toksvig s2 %.6g vs slope variance %.6g (%.2f%%)\n", double(top.cov.x), expect,
                100.0 * (double(top.cov.x) - expect) / expect);
}

TEST(Antialias, CovariancesOfIndependentLayersAddThroughTheirJacobians) {
    // Two LEAN layers on different UV frames (non-orthogonal vT, vB, as a
    // vertex basis gives), strengths 0.7 and -1.3: the frame-space
    // covariance is the sum of s^2 J C J^T, J = [vT vB], computed here in
    // double from the known field variances.
    const int n = 128;
    TextureImage mapA = sineSlopeMap(n, 0.6, 4, 0.0, 1); // var (0.18, 0)
    TextureImage mapB = sineSlopeMap(n, 0.2, 2, 0.4, 8); // var (0.02, 0.08)
    Moments a = momentsOf(mapA), b = momentsOf(mapB);
    G::SgUvFrame uvA{}, uvB{};
    uvA.st = uvB.st = glm::vec2(0.5f);
    uvA.dSTdx = uvB.dSTdx = glm::vec2(1.0f, 0.0f); // the whole map: the top level
    uvA.dSTdy = uvB.dSTdy = glm::vec2(0.0f, 1.0f);
    uvA.vT = glm::vec3(1.0f, 0.0f, 0.0f);
    uvA.vB = glm::vec3(0.3f, 0.0f, -0.9f);
    uvB.vT = glm::vec3(0.6f, 0.0f, 0.8f);
    uvB.vB = glm::vec3(-0.8f, 0.0f, 0.7f);
    G::SgUvNormalParams pA = G::sgUnpackUvNormal(glm::vec4(0.7f, 3, 0, -1), glm::vec4(0));
    G::SgUvNormalParams pB = G::sgUnpackUvNormal(glm::vec4(-1.3f, 3, 0, -1), glm::vec4(0));
    glm::mat3 cov(0.0f);
    G::sgLayerUvNormalLean(uvA, pA, G::sampler2D{&a.a}, G::sampler2D{&a.b}, cov);
    G::sgLayerUvNormalLean(uvB, pB, G::sampler2D{&b.a}, G::sampler2D{&b.b}, cov);
    auto term = [](double s, glm::dvec3 t, glm::dvec3 bb, double vx, double vy) {
        return s * s * (vx * glm::outerProduct(t, t) + vy * glm::outerProduct(bb, bb));
    };
    glm::dmat3 expect = term(0.7, glm::dvec3(uvA.vT), glm::dvec3(uvA.vB), 0.18, 0.0) +
                        term(-1.3, glm::dvec3(uvB.vT), glm::dvec3(uvB.vB), 0.02, 0.08);
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(cov[c][r], expect[c][r], 2e-6) // float moments, as above
                << "entry " << c << "," << r;
    // The lobe: alpha'^2 = alpha^2 + trace.
    const float rough = G::sgAaRoughness(0.5f, cov);
    const double tr = expect[0][0] + expect[1][1] + expect[2][2];
    EXPECT_NEAR(std::pow(double(rough), 4.0), 0.0625 + tr, 1e-5);
}

TEST(Antialias, FlatExtremeAndHorizonMapsStayFinite) {
    // rgb codes: flat, the zero vector (mid grey), slopes at listing 4's
    // clamp (x, y on the unit circle), horizon normals, beyond the circle,
    // and the corners of the code cube.
    const std::vector<glm::vec4> hard = {{0.5f, 0.5f, 1.0f, 1}, {0.5f, 0.5f, 0.5f, 1},
                                         {1.0f, 0.5f, 0.5f, 1}, {0.5f, 0.0f, 0.5f, 1},
                                         {1.0f, 1.0f, 0.0f, 1}, {0.0f, 0.0f, 0.0f, 1},
                                         {1.0f, 1.0f, 1.0f, 1}, {0.853553f, 0.853553f, 0.5f, 1}};
    for (const glm::vec4& code : hard) {
        for (int mixed = 0; mixed < 2; ++mixed) {
            // 8 x 8 of the code alone, or a checker of it and flat.
            std::vector<glm::vec4> t(64);
            for (int i = 0; i < 64; ++i)
                t[size_t(i)] = mixed && ((i + i / 8) & 1) ? glm::vec4(0.5f, 0.5f, 1, 1) : code;
            TextureImage map = makeTexture(8, 8, t, Wrap::Repeat);
            Moments m = momentsOf(map, NormalEncoding::Rgb);
            for (float texels : {0.5f, 1.5f, 3.0f, 8.0f, 1e6f}) {
                glm::vec2 d(texels / 8.0f, 0.0f), e(0.0f, texels / 8.0f);
                for (int flip = 0; flip < 2; ++flip) {
                    G::SgSlopeDist l = G::sgSampleLeanSlopes(G::sampler2D{&m.a}, G::sampler2D{&m.b},
                                                             glm::vec2(0.3f), d, e, flip != 0);
                    G::SgSlopeDist k = G::sgSampleToksvigSlopes(G::sampler2D{&m.toksvig},
                                                                glm::vec2(0.3f), d, e, flip != 0);
                    for (const G::SgSlopeDist& s : {l, k}) {
                        EXPECT_TRUE(std::isfinite(s.mean.x) && std::isfinite(s.mean.y));
                        EXPECT_TRUE(std::isfinite(s.cov.x) && std::isfinite(s.cov.y) &&
                                    std::isfinite(s.cov.z));
                        EXPECT_GE(s.cov.x, 0.0f);
                        EXPECT_GE(s.cov.y, 0.0f);
                        // Positive semi-definite (sgLeanCovariance's clamp).
                        EXPECT_LE(double(s.cov.z) * s.cov.z,
                                  double(s.cov.x) * s.cov.y * (1 + 1e-5) + 1e-30);
                        glm::mat3 cov =
                            G::sgSlopeCovToFrame(s.cov, glm::vec3(3, 0, 0), glm::vec3(0, 0, 3));
                        float r = G::sgAaRoughness(0.3f, cov);
                        EXPECT_TRUE(std::isfinite(r) && r > 0.0f) << r;
                    }
                }
            }
        }
    }
    // Infinite covariance (a caller's worst case): a flat lobe, not Inf.
    glm::mat3 inf(0.0f);
    inf[0][0] = std::numeric_limits<float>::infinity();
    EXPECT_TRUE(std::isfinite(G::sgAaRoughness(0.5f, inf)));
}

// ---------------------------------------------------------------------------
// The renderer's antialiased path.

std::string aaScene(const std::string& aa, const std::string& extraLayer = "") {
    const std::string map = R"({"procedural": "bumps", "size": 64, "bump_height": 0.3})";
    // UV set 1 tiles the map 8 x 4 times: 512 texels around the sphere,
    // minified 1x..8x across the 200 x 150 view.
    return oneMaterialScene(
        R"({"type": "uv_normal", "strength": 1.2, "uv_set": 1, "antialias": ")" + aa +
            R"(", "map": )" + map + "}" + extraLayer,
        R"({"procedural": {"type": "sphere", "size": 1, "segments": 48, "uv_sets": 1},
                                 "uv_sets": [{"from": 0, "scale": [8, 4]}]})",
        R"("roughness": 0.25,)");
}

TEST(Antialias, GpuMatchesCpuOnTheAntialiasedPath) {
    for (const char* aa : {"lean", "toksvig"}) {
        Scene s = sceneFromJson(aaScene(aa));
        SceneAssets a = loadAssets(s);
        CpuOptions parity;
        parity.derivatives = CpuDerivatives::Quad;
        parity.textureLod = sg::glsl::LodRule::FastLog2;
        NormalRenders p = renderNormalsBoth(s, a, parity);
        const size_t covered = countCovered(p.gpuPrim);
        ASSERT_GT(covered, 1000u);
        EXPECT_EQ(p.diff.nonFinite, 0u);
        // Same bound as the other layers' parity (image_test.cpp).
        EXPECT_LE(p.diff.maxDeg, 0.05) << aa;
        // Radiance: the widened lobe on both sides.
        View v = makeView(s, a, 0, 0, Aov::Color);
        Image g = gpu().render(s, a, v), c = renderCpu(s, a, v, parity);
        EXPECT_EQ(countNonFinite(g), 0u);
        EXPECT_EQ(countNonFinite(c), 0u);
        double maxRel = 0.0;
        size_t compared = 0;
        for (size_t i = 0; i < g.texelCount(); ++i) {
            if (p.gpuPrim.rgba(i).x <= 0.0f || p.gpuPrim.rgba(i).x != p.cpuPrim.rgba(i).x) continue;
            glm::vec3 x(g.rgba(i)), y(c.rgba(i));
            const double scale = std::max(double(glm::length(y)), 0.05);
            maxRel = std::max(maxRel, double(glm::length(x - y)) / scale);
            ++compared;
        }
        EXPECT_GT(compared, 1000u);
        // llvmpipe and the C++ build round differently (normals within
        // 0.05 degrees); a GGX highlight turns that into a few 1e-3 of
        // the radiance (measured 1.1e-3 LEAN, 6.6e-4 Toksvig).
        EXPECT_LT(maxRel, 0.01) << aa;
        std::printf("[%s] parity: normals max %.5f deg, radiance max rel %.2e over %zu px\n", aa,
                    p.diff.maxDeg, maxRel, compared);
    }
}

TEST(Antialias, WidensTheHighlightOnlyWhereTheFootprintHidesBumps) {
    // The same view with and without antialiasing: the radiance differs
    // (the lobe is wider where the map is minified) and is finite.
    Scene sOn = sceneFromJson(aaScene("lean"));
    Scene sOff = sceneFromJson(aaScene("none"));
    SceneAssets aOn = loadAssets(sOn), aOff = loadAssets(sOff);
    Image on = gpu().render(sOn, aOn, makeView(sOn, aOn, 0, 0, Aov::Color));
    Image off = gpu().render(sOff, aOff, makeView(sOff, aOff, 0, 0, Aov::Color));
    double maxDiff = 0.0;
    for (size_t i = 0; i < on.texelCount(); ++i)
        maxDiff = std::max(maxDiff, double(glm::length(glm::vec3(on.rgba(i) - off.rgba(i)))));
    EXPECT_GT(maxDiff, 1e-3);
    EXPECT_EQ(countNonFinite(on), 0u);
}

// ... and only there: a normal map flat in a band of s (texel centres in
// [0.55, 0.85), the middle of the sphere's visible side) with bumps
// elsewhere (float texels, so flat is exactly (0, 0, 1) and its slope
// variance exactly 0 at every level). A pixel whose footprint lies in the
// flat band has no slope variance, and its
// radiance must not change. The footprint is measured independently of
// the renderer's LOD: from the uv AOV's differences to the neighbouring
// pixels (texels per pixel, f), a pixel is in the flat half when the
// texels its level can reach (the bilinear support at the level of f,
// 2 f, plus one texel) stay in s in (0.56, 0.84) (the band less the
// bilinear half texel at its edges). The other pixels of the surface must
// change somewhere (the lobe widens).
TEST(Antialias, LeavesPixelsWithoutSlopeVarianceUnchanged) {
    const int n = 128;
    std::vector<float> texels(size_t(n) * size_t(n) * 3);
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const double s = (i + 0.5) / n, t = (j + 0.5) / n;
            glm::dvec3 nm(0.0, 0.0, 1.0);
            if (s < 0.55 || s >= 0.85) {
                const double dx = 0.6 * std::cos(kTwoPi * 16.0 * s) * std::sin(kTwoPi * 8.0 * t);
                const double dy = 0.6 * std::sin(kTwoPi * 16.0 * s) * std::cos(kTwoPi * 8.0 * t);
                nm = glm::normalize(glm::dvec3(-dx, -dy, 1.0));
            }
            for (int c = 0; c < 3; ++c)
                texels[(size_t(j) * size_t(n) + size_t(i)) * 3 + size_t(c)] = float(nm[c]);
        }
    const std::string file = (std::filesystem::temp_directory_path() /
                              ("surfgrad_aa_half_flat_" + std::to_string(::getpid()) + ".exr"))
                                 .string();
    {
        auto out = OIIO::ImageOutput::create(file);
        ASSERT_TRUE(out);
        OIIO::ImageSpec spec(n, n, 3, OIIO::TypeDesc::FLOAT);
        ASSERT_TRUE(out->open(file, spec));
        ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, texels.data()));
        ASSERT_TRUE(out->close());
    }
    auto scene = [&](const char* aa) {
        return sceneFromJson(oneMaterialScene(
            std::string(R"({"type": "uv_normal", "encoding": "float", "antialias": ")") + aa +
                R"(", "map": ")" + file + R"("})",
            kSphere, R"("roughness": 0.25,)"));
    };
    Scene sOn = scene("lean"), sOff = scene("none");
    SceneAssets aOn = loadAssets(sOn), aOff = loadAssets(sOff);
    std::filesystem::remove(file);
    const Image on = gpu().render(sOn, aOn, makeView(sOn, aOn, 0, 0, Aov::Color));
    const Image off = gpu().render(sOff, aOff, makeView(sOff, aOff, 0, 0, Aov::Color));
    const Image uv = gpu().render(sOff, aOff, makeView(sOff, aOff, 0, 0, Aov::Uv));
    const Image prim = gpu().render(sOff, aOff, makeView(sOff, aOff, 0, 0, Aov::PrimId));
    const int w = on.width, h = on.height;
    size_t flat = 0, changedElsewhere = 0;
    double worstFlat = 0.0;
    for (int y = 1; y < h - 1; ++y)
        for (int x = 1; x < w - 1; ++x) {
            bool covered = true;
            double f = 0.0; // texels per pixel, the largest neighbour difference
            for (int j = -1; j <= 1; ++j)
                for (int i = -1; i <= 1; ++i) {
                    covered = covered && prim.rgba(x + i, y + j).x > 0.0f;
                    const glm::dvec2 d = glm::dvec2(glm::vec2(uv.rgba(x + i, y + j))) -
                                         glm::dvec2(glm::vec2(uv.rgba(x, y)));
                    f = std::max(f, glm::length(d) * n);
                }
            if (!covered) continue;
            const glm::vec3 a(on.rgba(x, y)), b(off.rgba(x, y));
            const double rel = double(glm::length(a - b)) / std::max(double(glm::length(b)), 1e-6);
            const double s = double(uv.rgba(x, y).x);
            const double reach = (2.0 * std::max(f, 1.0) + 1.0) / n;
            if (s - reach > 0.56 && s + reach < 0.84) {
                ++flat;
                worstFlat = std::max(worstFlat, rel);
            } else {
                changedElsewhere += rel > 1e-3;
            }
        }
    std::printf("flat pixels %zu (worst relative change %.3g), changed pixels elsewhere %zu\n",
                flat, worstFlat, changedElsewhere);
    EXPECT_GT(flat, 1000u) << "the view must show the flat band";
    EXPECT_GT(changedElsewhere, 300u) << "antialiasing must change the bumped part";
    // The lobe's roughness passes through sqrt(sqrt(r^4)) with a zero
    // variance: r within an ulp or two, a relative change of the GGX term
    // of a few 1e-7 (measured 0: r comes back exactly here).
    EXPECT_LE(worstFlat, 1e-5);
}

TEST(Antialias, NothingIsCompiledUnlessAsked) {
    auto fragment = [](const std::string& json) {
        Scene s = sceneFromJson(json);
        SceneAssets a = loadAssets(s);
        return assembleProgram(planMaterial(s, a, 0, 0)).fragment;
    };
    const std::string off = fragment(aaScene("none"));
    for (const char* marker : {"slopeCov", "sgAaRoughness", "SG_RENDER_ANTIALIAS_GLSL",
                               "SG_LEAN_GLSL", "sgLayerUvNormalLean", "sgLayerUvNormalToksvig"})
        EXPECT_EQ(off.find(marker), std::string::npos) << marker;
    const std::string lean = fragment(aaScene("lean"));
    EXPECT_NE(lean.find("sgLayerUvNormalLean("), std::string::npos);
    EXPECT_NE(lean.find("sgAaRoughness("), std::string::npos);
    EXPECT_EQ(lean.find("sgLayerUvNormalToksvig"), std::string::npos);
    const std::string tok = fragment(aaScene("toksvig"));
    EXPECT_NE(tok.find("sgLayerUvNormalToksvig("), std::string::npos);
    EXPECT_EQ(tok.find("sgLayerUvNormalLean"), std::string::npos);
}

TEST(Antialias, SceneFieldIsValidated) {
    EXPECT_THROW(sceneFromJson(aaScene("bilinear")), sg::io::InputError);
    const std::string withMods = oneMaterialScene(
        R"({"type": "uv_normal", "antialias": "lean", "map": {"procedural": "bumps", "size": 16},
            "modifiers": [{"type": "scale", "alpha": 2}]})",
        kSphere);
    EXPECT_THROW(sceneFromJson(withMods), sg::io::InputError);
}

} // namespace
} // namespace sg::render::test

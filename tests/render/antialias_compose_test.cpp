// Bump antialiasing through composition for projected layers
// (layer_triplanar_aa.glsl, layer_decal_aa.glsl): a plane's or a
// projector's slope covariance is mapped by the Jacobian that maps its
// derivative; triplanar weights enter squared; independent layers add;
// the GPU matches the CPU reference; equal weights, horizon footprints and
// projectors parallel to the surface stay finite.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "hardcase.h"
#include "render_internal.h"
#include "antialias_test_util.h"
#include "render_test_util.h"
#include "surfgrad/base/io.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;
using sg::test::hardCaseAtMost;
using sg::test::Worst;

constexpr double kTwoPi = 6.283185307179586;

G::SgFrame frameWithNormal(glm::vec3 n, glm::vec3 dPdx, glm::vec3 dPdy) {
    G::SgFrame f{};
    f.nrmBase = glm::normalize(n);
    f.dPdx = dPdx;
    f.dPdy = dPdy;
    f.sigmaX = dPdx - glm::dot(dPdx, f.nrmBase) * f.nrmBase;
    f.sigmaY = dPdy - glm::dot(dPdy, f.nrmBase) * f.nrmBase;
    f.flipSign = 1.0f;
    f.resolveSign = 1.0f;
    return f;
}

// r0 = (strength, scale, sharpness, rightHanded), r1 = (encoding, flipV),
// r2 = (texShift, 0).
G::SgTriplanarParams triplanarParams(float strength, float scale, bool rightHanded) {
    return G::sgUnpackTriplanar(glm::vec4(strength, scale, 4.0f, rightHanded ? 1.0f : 0.0f),
                                glm::vec4(float(NormalEncoding::Float), 0, 0, 0), glm::vec4(0.0f));
}

// s^2 P G (sum over the axes' outer products weighted by C) G^T P, in
// double: the analytically transformed covariance of one plane whose
// derivative lands on the domain axes a (d.x) and b (d.y).
glm::dmat3 transformedCov(double s, glm::dvec3 n, glm::dmat3 gradToFrame, glm::dvec3 a,
                          glm::dvec3 b, double vx, double vy) {
    glm::dmat3 proj = glm::dmat3(1.0) - glm::outerProduct(n, n);
    glm::dvec3 ja = s * (proj * (gradToFrame * a));
    glm::dvec3 jb = s * (proj * (gradToFrame * b));
    return vx * glm::outerProduct(ja, ja) + vy * glm::outerProduct(jb, jb);
}

void expectMatNear(const glm::mat3& got, const glm::dmat3& want, double tol, const char* what) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            EXPECT_NEAR(got[c][r], want[c][r], tol) << what << " entry " << c << "," << r;
}

// A footprint of at least the whole map on every plane (top level):
// derivatives of length >= 1 domain unit on each plane's two axes.
const glm::vec3 kWholeMapDx(1.5f, 1.5f, 1.5f);
const glm::vec3 kWholeMapDy(1.5f, -1.5f, 1.5f);

TEST(AntialiasCompose, TriplanarPlaneCovarianceIsMappedByItsJacobian) {
    // One plane (z: |n.x|, |n.y| < 0.2 give the x and y planes weight 0),
    // an object domain with a non-orthogonal gradient map G: the plane's
    // covariance diag(ax^2/2, ay^2/2) must come out as s^2 P G [e_x e_y]
    // C [e_x e_y]^T G^T P, computed here in double.
    const int n = 64;
    const double ax = 0.5, ay = 0.3;
    TextureImage map = sineSlopeMap(n, ax, 4, ay, 2);
    Moments m = momentsOf(map);
    const glm::vec3 nrm = glm::normalize(glm::vec3(0.15f, -0.1f, 1.0f));
    G::SgFrame f = frameWithNormal(nrm, glm::vec3(1, 0, 0), glm::vec3(0, 1, 0));
    G::SgVolumeSpace vs{};
    vs.pos = glm::vec3(0.3f, 0.2f, 0.1f);
    vs.dPdx = kWholeMapDx;
    vs.dPdy = kWholeMapDy;
    vs.gradToFrame = glm::mat3(glm::vec3(1.2f, 0.1f, 0.0f), glm::vec3(-0.3f, 0.8f, 0.2f),
                               glm::vec3(0.0f, 0.4f, 1.1f));
    vs.normalToDomain = glm::mat3(1.0f);
    for (bool rh : {false, true}) {
        const float strength = -1.7f;
        G::SgTriplanarParams p = triplanarParams(strength, 1.0f, rh);
        glm::vec3 w = G::sgTriplanarWeights(nrm, p.sharpness);
        ASSERT_EQ(w.x, 0.0f);
        ASSERT_EQ(w.y, 0.0f);
        glm::mat3 cov(0.0f);
        G::sampler2D sa{&m.a}, sb{&m.b};
        G::sgLayerTriplanarAa(f, vs, p, SG_AA_LEAN, sa, sb, sa, sb, sa, sb, cov);
        glm::dmat3 want = transformedCov(strength, glm::dvec3(nrm), glm::dmat3(vs.gradToFrame),
                                         {1, 0, 0}, {0, 1, 0}, ax * ax / 2, ay * ay / 2);
        // Float moments of a 64 x 64 map (1e-6 relative on values ~0.1)
        // times |J|^2 ~ 4.
        expectMatNear(cov, want, 1e-5, rh ? "right-handed" : "left-handed");
    }
}

TEST(AntialiasCompose, TriplanarWeightsEnterSquaredAndPlanesAdd) {
    // Base normal (1,1,1)/sqrt 3: equal weights 1/3. Each plane adds
    // (1/3)^2 J_i C J_i^T with its own axes (listing 13, right-handed: the
    // x plane's d.x and the y plane's d.y land on -e_z).
    const int n = 64;
    const double ax = 0.4, ay = 0.2;
    TextureImage map = sineSlopeMap(n, ax, 2, ay, 4);
    Moments m = momentsOf(map);
    const glm::vec3 nrm = glm::normalize(glm::vec3(1.0f));
    G::SgFrame f = frameWithNormal(nrm, glm::vec3(1, -1, 0), glm::vec3(0, 1, -1));
    G::SgVolumeSpace vs{};
    vs.pos = glm::vec3(0.1f);
    vs.dPdx = kWholeMapDx;
    vs.dPdy = kWholeMapDy;
    vs.gradToFrame = glm::mat3(1.0f);
    vs.normalToDomain = glm::mat3(1.0f);
    G::SgTriplanarParams p = triplanarParams(2.0f, 1.0f, true);
    glm::vec3 w = G::sgTriplanarWeights(nrm, p.sharpness);
    EXPECT_NEAR(w.x, 1.0 / 3.0, 1e-6);
    glm::mat3 cov(0.0f);
    G::sampler2D sa{&m.a}, sb{&m.b};
    glm::vec3 g = G::sgLayerTriplanarAa(f, vs, p, SG_AA_LEAN, sa, sb, sa, sb, sa, sb, cov);
    const glm::dvec3 ex(1, 0, 0), ey(0, 1, 0), ez(0, 0, 1);
    const double s = 2.0 / 3.0, vx = ax * ax / 2, vy = ay * ay / 2;
    const glm::dmat3 id(1.0);
    const glm::dvec3 nd(nrm);
    glm::dmat3 want = transformedCov(s, nd, id, -ez, ey, vx, vy) +
                      transformedCov(s, nd, id, ex, -ez, vx, vy) +
                      transformedCov(s, nd, id, ex, ey, vx, vy);
    expectMatNear(cov, want, 1e-6, "equal weights"); // float moments, |J| < 1
    // The mixture reading (w, not w^2) would give three times as much.
    const double tr = want[0][0] + want[1][1] + want[2][2];
    EXPECT_NEAR(double(G::sgSlopeCovTrace(cov)), tr, 1e-6);
    // The mean slope over the whole map is 0: no gradient.
    EXPECT_LT(glm::length(g), 1e-5f);
    // In the tangent plane: P S P = S.
    glm::vec3 sn = cov * nrm;
    EXPECT_LT(glm::length(sn), 1e-6f);
}

TEST(AntialiasCompose, SineFieldThroughTriplanarGivesItsVariance) {
    // A flat surface z = const in a world domain, base normal +z (only the
    // z plane), scale 1: 256 texels, 8 periods along s; a footprint of 32
    // texels (level 5) covers one period along s, so the frame-space
    // variance along x is strength^2 ax^2 / 2 at every level-5 texel
    // centre, and nothing leaves the tangent plane.
    const int n = 256;
    const double ax = 0.8, ay = 0.3;
    TextureImage map = sineSlopeMap(n, ax, 8, ay, 4);
    Moments m = momentsOf(map);
    const float fp = 32.0f / n;
    G::SgFrame f = frameWithNormal(glm::vec3(0, 0, 1), glm::vec3(fp, 0, 0), glm::vec3(0, fp, 0));
    G::SgTriplanarParams p = triplanarParams(0.5f, 1.0f, true);
    G::sampler2D sa{&m.a}, sb{&m.b};
    double worst = 0.0;
    for (int j = 0; j < 8; ++j)
        for (int i = 0; i < 8; ++i) {
            G::SgVolumeSpace vs{};
            vs.pos = glm::vec3((i + 0.5f) / 8.0f, (j + 0.5f) / 8.0f, 0.25f);
            vs.dPdx = f.dPdx;
            vs.dPdy = f.dPdy;
            vs.gradToFrame = glm::mat3(1.0f);
            vs.normalToDomain = glm::mat3(1.0f);
            glm::mat3 cov(0.0f);
            G::sgLayerTriplanarAa(f, vs, p, SG_AA_LEAN, sa, sb, sa, sb, sa, sb, cov);
            worst = std::max(worst, std::abs(double(cov[0][0]) - 0.25 * ax * ax / 2));
            EXPECT_EQ(cov[2][2], 0.0f);
            EXPECT_EQ(cov[0][2], 0.0f);
        }
    // Level-5 float moments (antialias_test.cpp: 1e-5) times strength^2.
    EXPECT_LT(worst, 0.25 * 1e-5);
}

TEST(AntialiasCompose, DecalCovarianceIsMappedByTheProjectorAndLayersAdd) {
    // A projector tilted against the surface: J = fade strength P [X Y];
    // a LEAN uv_normal layer's covariance adds to it.
    const int n = 64;
    const double ax = 0.6, ay = 0.25;
    TextureImage map = sineSlopeMap(n, ax, 2, ay, 2);
    Moments m = momentsOf(map);
    const glm::vec3 nrm(0, 0, 1);
    G::SgFrame f = frameWithNormal(nrm, glm::vec3(2, 0, 0), glm::vec3(0, 2, 0));
    // Projector axes: z tilted 20 degrees about x (inside the angle fade's
    // full range), x = e_x.
    const float a = glm::radians(20.0f);
    const glm::vec3 X(1, 0, 0), Z(0, -std::sin(a), std::cos(a)), Y = glm::cross(Z, X);
    // r0 = (origin, strength), r1..r3 = (axis, half size), r4 = (fade width,
    // cos start, cos end, encoding), r5 = (flipV).
    const float strength = 1.4f;
    G::SgDecalParams p = G::sgUnpackDecal(
        glm::vec4(0, 0, 0, strength), glm::vec4(X, 0.5f), glm::vec4(Y, 0.5f), glm::vec4(Z, 1.0f),
        glm::vec4(0.25f, 0.5f, 0.17f, float(NormalEncoding::Float)), glm::vec4(0));
    glm::mat3 cov(0.0f);
    G::sampler2D sa{&m.a}, sb{&m.b};
    // Near the centre: depth fade 1, angle fade 1 (cos 20 > 0.5).
    G::sgLayerDecalAa(f, glm::vec3(0.01f, 0.02f, 0.0f), p, SG_AA_LEAN, sa, sb, cov);
    glm::dmat3 want = transformedCov(strength, glm::dvec3(nrm), glm::dmat3(1.0), glm::dvec3(X),
                                     glm::dvec3(Y), ax * ax / 2, ay * ay / 2);
    expectMatNear(cov, want, 1e-5, "decal"); // float moments times strength^2 ~ 2
    // Plus an independent uv_normal layer on the same frame: the sum.
    G::SgUvFrame uv{};
    uv.st = glm::vec2(0.5f);
    uv.dSTdx = glm::vec2(1.0f, 0.0f);
    uv.dSTdy = glm::vec2(0.0f, 1.0f);
    uv.vT = glm::vec3(0.8f, 0.6f, 0.0f);
    uv.vB = glm::vec3(-0.6f, 0.8f, 0.0f);
    G::SgUvNormalParams pu = G::sgUnpackUvNormal(glm::vec4(0.9f, 3, 0, -1), glm::vec4(0));
    G::sgLayerUvNormalLean(uv, pu, sa, sb, cov);
    glm::dmat3 uvTerm =
        0.81 * (ax * ax / 2 * glm::outerProduct(glm::dvec3(uv.vT), glm::dvec3(uv.vT)) +
                ay * ay / 2 * glm::outerProduct(glm::dvec3(uv.vB), glm::dvec3(uv.vB)));
    expectMatNear(cov, want + uvTerm, 2e-5, "decal + uv_normal");
}

bool finiteMat(const glm::mat3& m) {
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r)
            if (!std::isfinite(m[c][r])) return false;
    return true;
}

// Non-finite values among a surface gradient, a covariance and the
// roughness it widens (0 when all are finite).
int nonFinite(glm::vec3 sg, const glm::mat3& cov) {
    int bad = std::isfinite(sg.x) && std::isfinite(sg.y) && std::isfinite(sg.z) ? 0 : 1;
    bad += finiteMat(cov) ? 0 : 1;
    const float r = G::sgAaRoughness(0.3f, cov);
    bad += std::isfinite(r) && r > 0.0f ? 0 : 1;
    bad += G::sgSlopeCovTrace(cov) >= 0.0f ? 0 : 1;
    return bad;
}

// A map with slopes at listing 4's clamp and flat texels (rgb codes).
Moments hardMoments() {
    std::vector<glm::vec4> t(64);
    for (int i = 0; i < 64; ++i)
        t[size_t(i)] = (i + i / 8) & 1 ? glm::vec4(0.5f, 0.5f, 1, 1) : glm::vec4(1, 0.5f, 0.5f, 1);
    return momentsOf(makeTexture(8, 8, t, Wrap::Repeat), NormalEncoding::Rgb);
}

const float kReach[] = {0.0f, 1e-3f, 1e6f, 1e30f};

TEST(AntialiasCompose, HardTriplanarAtEqualWeightsAndTheHorizon) {
    Moments m = hardMoments();
    G::sampler2D sa{&m.a}, sb{&m.b}, st{&m.toksvig};
    G::SgTriplanarParams p = G::sgUnpackTriplanar(glm::vec4(3.0f, 2.0f, 64.0f, 1.0f),
                                                  glm::vec4(0, 0, 0, 0), glm::vec4(0.0f));
    // Equal weights (diagonal normals), a normal at the edge of two planes,
    // footprints from 0 to the horizon (1e30 units per pixel) and a zero
    // gradient map (whose domain normal is 0: the frame's is used).
    const glm::vec3 normals[] = {glm::vec3(1.0f), glm::vec3(-1.0f, 1.0f, -1.0f),
                                 glm::vec3(1.0f, 1e-7f, 0.0f)};
    int bad = 0;
    Worst leak;
    for (const glm::vec3& nrm : normals)
        for (float r : kReach)
            for (int mode : {SG_AA_LEAN, SG_AA_TOKSVIG})
                for (float g : {1.0f, 0.0f}) {
                    G::SgFrame f = frameWithNormal(nrm, glm::vec3(r, 0, 0), glm::vec3(0, 0, r));
                    G::SgVolumeSpace vs{};
                    vs.pos = glm::vec3(0.3f, -0.7f, 0.2f);
                    vs.dPdx = f.dPdx;
                    vs.dPdy = f.dPdy;
                    vs.gradToFrame = glm::mat3(g);
                    vs.normalToDomain = glm::mat3(g);
                    glm::mat3 cov(0.0f);
                    G::sampler2D a = mode == SG_AA_LEAN ? sa : st, b = mode == SG_AA_LEAN ? sb : st;
                    glm::vec3 sg = G::sgLayerTriplanarAa(f, vs, p, mode, a, b, a, b, a, b, cov);
                    bad += nonFinite(sg, cov);
                    leak.add(double(glm::length(cov * f.nrmBase)) /
                             (1.0 + G::sgSlopeCovTrace(cov)));
                }
    hardCaseAtMost("triplanar-equal",
                   "antialiased triplanar (LEAN, Toksvig) at equal weights and at the edge of two "
                   "planes, footprints 0 to 1e30, zero gradient map",
                   "non-finite gradient, covariance or widened roughness values", bad, 0);
    // The covariance lies in the tangent plane: P S P = S up to rounding of
    // the projection of a unit normal (a few ulps of the trace).
    hardCaseAtMost("triplanar-equal", "the same", "|S n| / (1 + trace S)", leak.value, 1e-6);
}

TEST(AntialiasCompose, HardDecalParallelToTheSurface) {
    // The projection direction in the tangent plane, with the angle fade on
    // (fades out) and off (angle_fade_deg [180, 180]: full strength, the
    // footprint degenerate along the axis that lies along the normal);
    // footprints 0 to 1e30.
    Moments m = hardMoments();
    G::sampler2D sa{&m.a}, sb{&m.b}, st{&m.toksvig};
    const glm::vec3 nrm(0, 0, 1);
    const glm::vec3 X(1, 0, 0), Y(0, 0, 1), Z(0, -1, 0); // Z in the tangent plane
    int bad = 0;
    Worst leak, faded;
    for (float cosLimit : {0.17f, -1.0f})
        for (float r : kReach)
            for (int mode : {SG_AA_LEAN, SG_AA_TOKSVIG}) {
                G::SgDecalParams p = G::sgUnpackDecal(
                    glm::vec4(0, 0, 0, 2.0f), glm::vec4(X, 0.5f), glm::vec4(Y, 0.5f),
                    glm::vec4(Z, 0.5f),
                    glm::vec4(0.25f, cosLimit < 0 ? -1.0f : 0.5f, cosLimit, 0.0f), glm::vec4(0));
                G::SgFrame f = frameWithNormal(nrm, glm::vec3(r, 0, 0), glm::vec3(0, r, 0));
                glm::mat3 cov(0.0f);
                G::sampler2D a = mode == SG_AA_LEAN ? sa : st, b = mode == SG_AA_LEAN ? sb : st;
                glm::vec3 sg =
                    G::sgLayerDecalAa(f, glm::vec3(0.1f, 0.05f, 0.0f), p, mode, a, b, cov);
                bad += nonFinite(sg, cov);
                if (cosLimit > 0) faded.add(double(glm::length(sg)) + G::sgSlopeCovTrace(cov));
                leak.add(double(glm::length(cov * nrm)) / (1.0 + G::sgSlopeCovTrace(cov)));
            }
    hardCaseAtMost("decals-parallel",
                   "antialiased decal (LEAN, Toksvig), projection direction in the surface, angle "
                   "fade on and off, footprints 0 to 1e30",
                   "non-finite gradient, covariance or widened roughness values", bad, 0);
    hardCaseAtMost("decals-parallel", "the same", "|S n| / (1 + trace S)", leak.value, 1e-6);
    hardCaseAtMost("decals-parallel", "the same with the default angle fade",
                   "|sg| + trace S (faded out)", faded.value, 0.0);
}

// ---------------------------------------------------------------------------
// Noise: the clamped octaves' slope energy moves into the covariance.

// Per-axis mean and variance of the domain gradient of sgNoiseOctaves at
// `count` points spread over 1000^3 lattice cells (a fixed LCG: the same
// points every run).
struct GradStats {
    glm::dvec3 var{0.0};
};

GradStats gradientStats(int type, int octaves, float lacunarity, float gain, float footprint,
                        int count) {
    uint64_t state = 0x9e3779b97f4a7c15ull;
    auto next = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return double(state >> 11) / double(1ull << 53);
    };
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int i = 0; i < count; ++i) {
        glm::vec3 q(float(1000.0 * next()), float(1000.0 * next()), float(1000.0 * next()));
        glm::vec4 n = G::sgNoiseOctaves(type, q, octaves, lacunarity, gain, footprint);
        glm::dvec3 g(n.y, n.z, n.w);
        sum += g;
        sum2 += g * g;
    }
    GradStats s;
    s.var = sum2 / double(count) - (sum / double(count)) * (sum / double(count));
    return s;
}

TEST(AntialiasCompose, NoiseRemovedVarianceMatchesTheMeasuredFullDetailVariance) {
    // Measured: the full-detail gradient's variance over the domain, and the
    // variance kept by the fade at a footprint of 1/8 (octaves 2.. of 5 are
    // faded or gone). Predicted: kept + moved = full, and the moved part at
    // an infinite footprint (every octave removed) = the full variance.
    const glm::dvec3 d(G::sgPerlinGradientVariance());
    const int count = 40000;
    for (int type : {SG_NOISE_PERLIN, SG_NOISE_FBM, SG_NOISE_TURBULENCE}) {
        const int octaves = 5;
        const float lac = 2.0f, gain = 0.55f, fp = 0.125f;
        GradStats full = gradientStats(type, octaves, lac, gain, 0.0f, count);
        GradStats kept = gradientStats(type, octaves, lac, gain, fp, count);
        const double all = G::sgNoiseRemovedEnergy(type, octaves, lac, gain, 1e30f);
        const double moved = G::sgNoiseRemovedEnergy(type, octaves, lac, gain, fp);
        EXPECT_EQ(G::sgNoiseRemovedEnergy(type, octaves, lac, gain, 0.0f), 0.0f);
        for (int k = 0; k < 3; ++k) {
            // 4%: the sampling error of a variance from 40000 points
            // (relative sd ~ sqrt((kurtosis - 1) / N) < 1%) plus the
            // octaves' and neighbouring samples' residual correlation.
            EXPECT_NEAR(all * d[k], full.var[k], 0.04 * full.var[k]) << type << " axis " << k;
            EXPECT_NEAR(kept.var[k] + moved * d[k], full.var[k], 0.04 * full.var[k])
                << type << " axis " << k;
            std::printf("noise %d axis %d: full %.5f, predicted %.5f; kept %.5f + moved %.5f\n",
                        type, k, full.var[k], all * d[k], kept.var[k], moved * d[k]);
        }
        if (type == SG_NOISE_PERLIN) {
            EXPECT_EQ(moved, 0.0); // one octave at 1/8 cycle per pixel: kept whole
        } else {
            EXPECT_GT(moved, 0.5 * all); // the footprint removes most of the energy
        }
    }
}

G::SgNoiseParams noiseParams(int type, float amplitude, float frequency, int octaves,
                             float exponent) {
    // r0 = (amplitude, frequency, type, octaves), r1 = (lacunarity, gain,
    // exponent, antialias), r2 = (originFrac, 0) (the offset: cell 0, as
    // in object space), r3, r4 = (originCell's halves, 0).
    return G::sgUnpackNoise(glm::vec4(amplitude, frequency, float(type), float(octaves)),
                            glm::vec4(2.0f, 0.5f, exponent, 1.0f), glm::vec4(0.3f, 0.1f, 0.7f, 0),
                            glm::vec4(0.0f), glm::vec4(0.0f));
}

TEST(AntialiasCompose, NoiseLeanKeepsTheFadedGradientAndMapsTheCovariance) {
    // An object domain (non-orthogonal G), a tilted surface: the surface
    // gradient is sgLayerNoise's with the fade, the covariance
    // s P G D G^T P with s = (A F)^2 E(footprint).
    const glm::vec3 nrm = glm::normalize(glm::vec3(0.2f, -0.4f, 1.0f));
    G::SgFrame f = frameWithNormal(nrm, glm::vec3(0.02f, 0, 0), glm::vec3(0, 0.03f, 0.01f));
    G::SgVolumeSpace vs{};
    vs.pos = glm::vec3(0.3f, -0.2f, 0.5f);
    vs.dPdx = f.dPdx;
    vs.dPdy = f.dPdy;
    vs.gradToFrame = glm::mat3(glm::vec3(1.1f, 0.2f, 0.0f), glm::vec3(0.0f, 0.9f, -0.3f),
                               glm::vec3(0.1f, 0.0f, 1.2f));
    vs.normalToDomain = glm::mat3(1.0f);
    for (int type : {SG_NOISE_PERLIN, SG_NOISE_FBM, SG_NOISE_TURBULENCE}) {
        G::SgNoiseParams p = noiseParams(type, 0.02f, 40.0f, 6, 1.0f);
        glm::mat3 cov(0.0f);
        glm::vec3 lean = G::sgLayerNoiseLean(f, vs, p, cov);
        glm::vec3 fade = G::sgLayerNoise(f, vs, p);
        std::printf("noise type %d: |lean - fade| %.3g, |fade| %.3g\n", type,
                    double(glm::length(lean - fade)), double(glm::length(fade)));
        // The same octave sum and fade computed on two paths (the LEAN one
        // also accumulates the covariance): they may round differently in
        // the last bits of the gradient's components; 1e-6 relative is
        // about 8 binary32 ulps. Measured 0 for all three types, and
        // |fade| is 0 too: at this footprint (0.02 to 0.03 units per pixel
        // at frequency 40, about a period per pixel) every octave is faded
        // out, so this bound only says the LEAN path fades as much; the
        // covariance below is what carries the removed energy.
        EXPECT_LE(glm::length(lean - fade), 1e-6f * (1.0f + glm::length(fade)));
        const double fp = double(G::sgVolumeFootprint(vs)) * 40.0;
        const double s =
            (0.02 * 40.0) * (0.02 * 40.0) * G::sgNoiseRemovedEnergy(type, 6, 2.0f, 0.5f, float(fp));
        EXPECT_GT(s, 0.0);
        glm::dmat3 want(0.0);
        const glm::dvec3 d(G::sgPerlinGradientVariance());
        for (int k = 0; k < 3; ++k) {
            glm::dvec3 e(0.0);
            e[k] = 1.0;
            want += transformedCov(1.0, glm::dvec3(nrm), glm::dmat3(vs.gradToFrame), e, e, d[k] / 2,
                                   d[k] / 2);
        }
        // transformedCov with a = b = e_k and halves adds d_k (P G e_k)^2.
        expectMatNear(cov, s * want, 1e-6 * s * 10.0, "noise lean"); // float sums, |G| ~ 1
    }
}

TEST(AntialiasCompose, HardNoiseLeanAtTheHorizonAndAtExtremes) {
    const glm::vec3 nrm(0, 0, 1);
    int bad = 0;
    for (float reach : {0.0f, 1e-3f, 1e6f, 1e30f, std::numeric_limits<float>::infinity()})
        for (int type : {SG_NOISE_PERLIN, SG_NOISE_FBM, SG_NOISE_TURBULENCE})
            for (float amp : {0.0f, 0.02f, 1e6f})
                for (float exponent : {1.0f, 3.0f, 16.0f}) {
                    G::SgFrame f =
                        frameWithNormal(nrm, glm::vec3(reach, 0, 0), glm::vec3(0, reach, 0));
                    G::SgVolumeSpace vs{};
                    vs.pos = glm::vec3(0.3f, -0.2f, 0.5f);
                    vs.dPdx = f.dPdx;
                    vs.dPdy = f.dPdy;
                    vs.gradToFrame = glm::mat3(1.0f);
                    vs.normalToDomain = glm::mat3(1.0f);
                    // With a footprint: the scene's largest frequency (1e6),
                    // 12 octaves of lacunarity 8 and gain 1, all removed (the
                    // moved energy overflows float). At footprint 0 every
                    // octave is evaluated: frequencies that keep the lattice
                    // coordinates in int range.
                    const bool zero = reach == 0.0f;
                    G::SgNoiseParams p =
                        G::sgUnpackNoise(glm::vec4(amp, zero ? 10.0f : 1e6f, float(type), 12.0f),
                                         glm::vec4(zero ? 2.0f : 8.0f, 1.0f, exponent, 1.0f),
                                         glm::vec4(0.0f), glm::vec4(0.0f), glm::vec4(0.0f));
                    glm::mat3 cov(0.0f);
                    glm::vec3 g = G::sgLayerNoiseLean(f, vs, p, cov);
                    bad += nonFinite(g, cov);
                }
    hardCaseAtMost("horizon",
                   "noise \"lean\" (Perlin, fBm, turbulence; x^1, x^3, x^16), footprints 0 to "
                   "Inf, amplitude up to 1e6, frequencies up to 1e6 x 8^11",
                   "non-finite gradient, covariance or widened roughness values", bad, 0);
}

// ---------------------------------------------------------------------------
// The renderer's antialiased path.

const std::string kTiles = R"({"procedural": "tiles", "size": 64})";

std::string triplanarLayer(const std::string& aa) {
    return R"({"type": "triplanar", "space": "object", "scale": 6, "strength": 1.5, "antialias": ")" +
           aa + R"(", "map": )" + kTiles + "}";
}

std::string decalLayer(const std::string& aa) {
    return R"({"type": "decal", "position": [0, 0, 0.9], "direction": [0, 0, -1], "size": [1.2, 1.2, 1], "strength": 2, "antialias": ")" +
           aa + R"(", "map": {"procedural": "bricks", "size": 128}})";
}

std::string composedScene(const std::string& layers) {
    return oneMaterialScene(layers, kSphere, R"("roughness": 0.25,)");
}

TEST(AntialiasCompose, GpuMatchesCpuOnTriplanarAndDecals) {
    for (const char* aa : {"lean", "toksvig"}) {
        Scene s = sceneFromJson(composedScene(triplanarLayer(aa) + ", " + decalLayer(aa)));
        SceneAssets a = loadAssets(s);
        CpuOptions parity;
        parity.derivatives = CpuDerivatives::Quad;
        parity.textureLod = sg::glsl::LodRule::FastLog2;
        NormalRenders r = renderNormalsBoth(s, a, parity);
        ASSERT_GT(countCovered(r.gpuPrim), 1000u);
        EXPECT_EQ(r.diff.nonFinite, 0u);
        // The other layers' parity bound (image_test.cpp).
        EXPECT_LE(r.diff.maxDeg, 0.05) << aa;
        View v = makeView(s, a, 0, 0, Aov::Color);
        Image g = gpu().render(s, a, v), c = renderCpu(s, a, v, parity);
        EXPECT_EQ(countNonFinite(g), 0u);
        EXPECT_EQ(countNonFinite(c), 0u);
        double maxRel = 0.0;
        size_t compared = 0;
        for (size_t i = 0; i < g.texelCount(); ++i) {
            if (r.gpuPrim.rgba(i).x <= 0.0f || r.gpuPrim.rgba(i).x != r.cpuPrim.rgba(i).x) continue;
            glm::vec3 x(g.rgba(i)), y(c.rgba(i));
            const double scale = std::max(double(glm::length(y)), 0.05);
            maxRel = std::max(maxRel, double(glm::length(x - y)) / scale);
            ++compared;
        }
        EXPECT_GT(compared, 1000u);
        // As the uv_normal parity (antialias_test.cpp): normals within 0.05
        // degrees become a few 1e-3 of a GGX highlight's radiance.
        EXPECT_LT(maxRel, 0.01) << aa;
        std::printf("[%s] triplanar + decal parity: normals max %.5f deg, radiance max rel %.2e "
                    "over %zu px\n",
                    aa, r.diff.maxDeg, maxRel, compared);
    }
}

TEST(AntialiasCompose, NoneCompilesAsBeforeAndAaWidensTheLobe) {
    auto fragment = [](const std::string& json) {
        Scene s = sceneFromJson(json);
        SceneAssets a = loadAssets(s);
        return assembleProgram(planMaterial(s, a, 0, 0)).fragment;
    };
    const std::string none =
        fragment(composedScene(triplanarLayer("none") + ", " + decalLayer("none")));
    const std::string plain = fragment(composedScene(
        R"({"type": "triplanar", "space": "object", "scale": 6, "strength": 1.5, "map": )" +
        kTiles +
        R"(}, {"type": "decal", "position": [0, 0, 0.9], "direction": [0, 0, -1], "size": [1.2, 1.2, 1], "strength": 2, "map": {"procedural": "bricks", "size": 128}})"));
    EXPECT_EQ(none, plain);
    for (const char* marker : {"slopeCov", "sgAaRoughness", "SG_RENDER_SLOPE_DIST_GLSL",
                               "sgLayerTriplanarAa", "sgLayerDecalAa"})
        EXPECT_EQ(none.find(marker), std::string::npos) << marker;
    const std::string lean =
        fragment(composedScene(triplanarLayer("lean") + ", " + decalLayer("lean")));
    EXPECT_NE(lean.find("sgLayerTriplanarAa(frame"), std::string::npos);
    EXPECT_NE(lean.find("sgLayerDecalAa(frame"), std::string::npos);
    EXPECT_NE(lean.find("sgAaRoughness("), std::string::npos);
    EXPECT_THROW(sceneFromJson(composedScene(triplanarLayer("bilinear"))), sg::io::InputError);
    EXPECT_THROW(sceneFromJson(composedScene(decalLayer("yes"))), sg::io::InputError);
    // The widened lobe changes the image where the maps are minified.
    Scene sOn = sceneFromJson(composedScene(triplanarLayer("lean")));
    Scene sOff = sceneFromJson(composedScene(triplanarLayer("none")));
    SceneAssets aOn = loadAssets(sOn), aOff = loadAssets(sOff);
    Image on = gpu().render(sOn, aOn, makeView(sOn, aOn, 0, 0, Aov::Color));
    Image off = gpu().render(sOff, aOff, makeView(sOff, aOff, 0, 0, Aov::Color));
    double maxDiff = 0.0;
    for (size_t i = 0; i < on.texelCount(); ++i)
        maxDiff = std::max(maxDiff, double(glm::length(glm::vec3(on.rgba(i) - off.rgba(i)))));
    EXPECT_GT(maxDiff, 1e-3);
    EXPECT_EQ(countNonFinite(on), 0u);
}

// The study variant SG_AA_COV_UNMAPPED (docs/accuracy-cost.md, table 8's
// "LEAN per layer", set through GlRenderer::setFragmentDefines) drops the
// Jacobian and nothing else: a uv_normal layer at strength 1 has an
// orthonormal one (listing 6's vT, vB), so its image is the composition's;
// at strength 2 the composition's covariance is 4x the layer's own and the
// highlight differs. Programs are keyed by their defines: switching back
// gives the composition's image bit for bit.
TEST(AntialiasCompose, UnmappedStudyVariantDropsOnlyTheJacobian) {
    // 16 repeats of the 64-texel map around the sphere: minified in the
    // 200 x 150 view, so the footprints' covariance is not small.
    const std::string mesh = std::string(R"({"procedural": {"type": "sphere", "size": 1, )") +
                             R"("segments": 48}, "uv_sets": [{"from": 0, "scale": 16}]})";
    GlRenderer& gl = gpu();
    auto render = [&](float strength, bool unmapped) {
        Scene s = sceneFromJson(oneMaterialScene(
            R"({"type": "uv_normal", "uv_set": 1, "antialias": "lean", "strength": )" +
                std::to_string(strength) + R"(, "map": )" + kTiles + "}",
            mesh, R"("roughness": 0.25,)"));
        SceneAssets a = loadAssets(s);
        gl.setFragmentDefines(unmapped ? std::vector<std::string>{"SG_AA_COV_UNMAPPED"}
                                       : std::vector<std::string>{});
        Image img = gl.render(s, a, makeView(s, a, 0, 0, Aov::Color));
        gl.setFragmentDefines({});
        return img;
    };
    auto maxDiff = [](const Image& x, const Image& y) {
        double d = 0.0;
        for (size_t i = 0; i < x.texelCount(); ++i)
            d = std::max(d, double(glm::length(glm::vec3(x.rgba(i) - y.rgba(i)))));
        return d;
    };
    const size_t programsBefore = gl.cachedPrograms();
    const Image m1 = render(1.0f, false), u1 = render(1.0f, true);
    const Image m2 = render(2.0f, false), u2 = render(2.0f, true);
    const Image m1Again = render(1.0f, false);
    for (const Image* img : {&u1, &u2}) EXPECT_EQ(countNonFinite(*img), 0u);
    // Rounding only: the outer products of unit vectors sum to the trace
    // within a few ulps; radiances are below 10, so 1e-4 absolute is wide.
    EXPECT_LT(maxDiff(m1, u1), 1e-4);
    // Strength 2: the composed variance is 4x the layer's own trace, a
    // visibly wider lobe (differences of 0.1 and more where the
    // highlight is).
    EXPECT_GT(maxDiff(m2, u2), 1e-2);
    EXPECT_EQ(maxDiff(m1, m1Again), 0.0);
    // Strength is a scene parameter, not a program's: one program with
    // the define and one without.
    EXPECT_EQ(gl.cachedPrograms(), programsBefore + 2);
}

TEST(AntialiasCompose, NoiseAntialiasValuesAndCompilation) {
    auto fragment = [](const std::string& json) {
        Scene s = sceneFromJson(json);
        SceneAssets a = loadAssets(s);
        return assembleProgram(planMaterial(s, a, 0, 0)).fragment;
    };
    auto noise = [](const std::string& aa) {
        return composedScene(
            R"({"type": "noise", "noise": "fbm", "amplitude": 0.01, "frequency": 20)" +
            (aa.empty() ? std::string() : ", \"antialias\": " + aa) + "}");
    };
    const std::string today = fragment(noise(""));
    EXPECT_EQ(fragment(noise("true")), today);
    EXPECT_EQ(fragment(noise("\"fade\"")), today);
    EXPECT_EQ(today.find("slopeCov"), std::string::npos);
    EXPECT_EQ(today.find("sgLayerNoiseLean"), std::string::npos);
    EXPECT_EQ(fragment(noise("false")).find("slopeCov"), std::string::npos);
    EXPECT_EQ(fragment(noise("\"none\"")).find("slopeCov"), std::string::npos);
    const std::string lean = fragment(noise("\"lean\""));
    EXPECT_NE(lean.find("sgLayerNoiseLean(frame"), std::string::npos);
    EXPECT_NE(lean.find("sgAaRoughness("), std::string::npos);
    // The fade flag in the record: true for fade and lean, false for none.
    for (const char* bad : {"\"toksvig\"", "1", "\"yes\""}) {
        try {
            sceneFromJson(noise(bad));
            ADD_FAILURE() << bad;
        } catch (const sg::io::InputError& e) {
            EXPECT_NE(std::string(e.what()).find("antialias"), std::string::npos) << e.what();
        }
    }
    // GPU/CPU parity of the noise LEAN path with a triplanar and a decal.
    Scene s = sceneFromJson(composedScene(
        triplanarLayer("lean") + ", " + decalLayer("lean") +
        R"(, {"type": "noise", "noise": "turbulence", "amplitude": 0.004, "frequency": 30, "antialias": "lean"})"));
    SceneAssets a = loadAssets(s);
    CpuOptions parity;
    parity.derivatives = CpuDerivatives::Quad;
    parity.textureLod = sg::glsl::LodRule::FastLog2;
    NormalRenders r = renderNormalsBoth(s, a, parity);
    EXPECT_EQ(r.diff.nonFinite, 0u);
    // The other layers' parity bound (image_test.cpp).
    EXPECT_LE(r.diff.maxDeg, 0.05);
    View v = makeView(s, a, 0, 0, Aov::Color);
    Image g = gpu().render(s, a, v), c = renderCpu(s, a, v, parity);
    EXPECT_EQ(countNonFinite(g), 0u);
    double maxRel = 0.0;
    for (size_t i = 0; i < g.texelCount(); ++i) {
        if (r.gpuPrim.rgba(i).x <= 0.0f || r.gpuPrim.rgba(i).x != r.cpuPrim.rgba(i).x) continue;
        glm::vec3 x(g.rgba(i)), y(c.rgba(i));
        maxRel =
            std::max(maxRel, double(glm::length(x - y)) / std::max(double(glm::length(y)), 0.05));
    }
    // As GpuMatchesCpuOnTriplanarAndDecals.
    EXPECT_LT(maxRel, 0.01);
    std::printf("all composed parity: normals max %.5f deg, radiance max rel %.2e\n", r.diff.maxDeg,
                maxRel);
}

TEST(AntialiasCompose, MaterialDefaultAppliesUnlessALayerSaysOtherwise) {
    const std::string bumps = R"({"procedural": "bumps", "size": 16})";
    const std::string layers = R"({"type": "uv_normal", "map": )" + bumps + R"(},
           {"type": "uv_normal", "antialias": "none", "map": )" +
                               bumps + R"(},
           {"type": "uv_normal", "map": )" +
                               bumps + R"(, "modifiers": [{"type": "scale", "alpha": 2}]},
           {"type": "triplanar", "map": )" +
                               bumps + R"(},
           {"type": "decal", "antialias": "toksvig", "map": )" +
                               bumps + R"(},
           {"type": "noise"},
           {"type": "height", "map": {"procedural": "bumps", "output": "height", "size": 16}},
           {"type": "post_resolve", "layers": [{"type": "noise", "antialias": false},
                                               {"type": "triplanar", "map": )" +
                               bumps + "}]}";
    auto read = [&](const std::string& aa) {
        return sceneFromJson(
            oneMaterialScene(layers, kSphere, aa.empty() ? "" : R"("antialias": ")" + aa + "\","));
    };
    auto uvAa = [](const Layer& L) { return L.params<UvNormalParams>().antialias; };
    auto triAa = [](const Layer& L) { return L.params<TriplanarParams>().antialias; };
    {
        Scene s = read("lean");
        const std::vector<Layer>& L = s.materials[0].layers;
        EXPECT_EQ(uvAa(L[0]), SG_AA_LEAN);
        EXPECT_EQ(uvAa(L[1]), 0); // the layer says "none"
        EXPECT_EQ(uvAa(L[2]), 0); // modifiers do not antialias
        EXPECT_EQ(triAa(L[3]), SG_AA_LEAN);
        EXPECT_EQ(L[3].maps.size(), 6u);                                // three planes' A and B
        EXPECT_EQ(L[4].params<DecalParams>().antialias, SG_AA_TOKSVIG); // its own
        EXPECT_EQ(L[5].params<NoiseParams>().antialias, NoiseAntialias::Lean);
        EXPECT_EQ(L[7].children[0].params<NoiseParams>().antialias, NoiseAntialias::None);
        EXPECT_EQ(triAa(L[7].children[1]), SG_AA_LEAN); // groups' layers too
    }
    {
        Scene s = read("toksvig");
        const std::vector<Layer>& L = s.materials[0].layers;
        EXPECT_EQ(uvAa(L[0]), SG_AA_TOKSVIG);
        EXPECT_EQ(triAa(L[3]), SG_AA_TOKSVIG);
        EXPECT_EQ(L[3].maps.size(), 3u);
        // Noise has no Toksvig measure: its analytic covariance ("lean").
        EXPECT_EQ(L[5].params<NoiseParams>().antialias, NoiseAntialias::Lean);
    }
    for (const char* aa : {"none", ""}) {
        Scene s = read(aa);
        const std::vector<Layer>& L = s.materials[0].layers;
        EXPECT_EQ(uvAa(L[0]), 0);
        EXPECT_EQ(triAa(L[3]), 0);
        // "none" on the material leaves noise's default fade (no widening).
        EXPECT_EQ(L[5].params<NoiseParams>().antialias, NoiseAntialias::Fade);
    }
    // An invalid value: the error names the material's field.
    try {
        read("bilinear");
        ADD_FAILURE() << "accepted";
    } catch (const sg::io::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("materials[0].antialias"), std::string::npos)
            << e.what();
    }
}

} // namespace
} // namespace sg::render::test

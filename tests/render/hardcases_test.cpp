// Hard cases of the renderer's layer functions (shaders/sg/render/*.glsl,
// the same source the GPU compiles, on the CPU through
// surfgrad/render/render_shaders.h), reported as rows of docs/hard-cases.md
// (tests/common/hardcase.h):
//  - a decal projector (Mikkelsen 2019, section 2.9, listing 15) whose
//    plane is parallel to the surface, and one turned until its projection
//    direction lies in the surface (the angle fade of docs/scene.md);
//  - a triplanar layer (section 2.8, listings 13, 14) at the diagonal
//    normal, where the three planes weigh the same;
//  - a bumped sphere and its camera 1e5, 1e6 and 1e7 units from the world
//    origin (listing 16's camera-relative positions, composed in binary64
//    by sg::render::modelToCameraRelative): the same normals as at the
//    origin, on the CPU reference renderer and on the GPU.
#include <gtest/gtest.h>

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

#include "hardcase.h"
#include "render_test_util.h"
#include "surfgrad/render/render_shaders.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;
using sg::test::hardCaseAtMost;
using sg::test::hardCaseNumber;
using sg::test::reportHardCase;
using sg::test::Worst;

// A constant tangent-space normal map m (RGB encoding, 8x8).
TextureImage constantNormalMap(glm::vec3 m) {
    std::vector<glm::vec4> t(64, glm::vec4(0.5f * m + 0.5f, 1.0f));
    return makeTexture(8, 8, std::move(t), Wrap::Clamp);
}

// The plane y = 0 (normal +y) seen from above, `pix` units per pixel.
G::SgFrame flatFrame(float pix) {
    return G::sgPrologue(glm::vec3(0, 1, 0), glm::vec3(pix, 0, 0), glm::vec3(0, 0, -pix), true,
                         SG_BFACE_NONE);
}

// Decal records (layer_decal.glsl): origin at 0, strength 1, half size
// (0.5, 0.5, 0.5), depth fade 0.25, angle fade [start, end] degrees.
G::SgDecalParams decal(glm::vec3 x, glm::vec3 y, glm::vec3 z, float startDeg, float endDeg) {
    return G::sgUnpackDecal(
        glm::vec4(0, 0, 0, 1), glm::vec4(x, 0.5f), glm::vec4(y, 0.5f), glm::vec4(z, 0.5f),
        glm::vec4(0.25f, std::cos(glm::radians(startDeg)), std::cos(glm::radians(endDeg)), 0),
        glm::vec4(0));
}

TEST(RenderHardCases, DecalsParallelToTheSurface) {
    const glm::vec3 m = glm::normalize(glm::vec3(0.35f, -0.2f, 0.9f));
    TextureImage img = constantNormalMap(m);
    G::sampler2D tex{&img};
    const G::SgFrame f = flatFrame(0.002f);
    const glm::vec3 n(0, 1, 0);
    // The map's derivative, decoded as the layer decodes it (8-bit texels).
    const glm::vec4 texel = G::textureGrad(tex, glm::vec2(0.5f), glm::vec2(0), glm::vec2(0));
    const glm::vec2 d = G::sgTspaceNormalToDeriv(G::sgDecodeNormalXY(texel, 0), false);

    // (a) Projector plane parallel to the surface, any rotation in it: the
    // layer is the TBN-style bump with T = axis x, B = axis y (fade 1 in
    // the box's core).
    Worst tbn;
    for (int k = 0; k < 72; ++k) {
        const float a = glm::radians(5.0f * float(k));
        const glm::vec3 x(std::cos(a), 0, std::sin(a)), z = n, y = glm::cross(z, x);
        const glm::vec3 g =
            G::sgLayerDecal(f, glm::vec3(0.05f, 0.0f, -0.03f), decal(x, y, z, 60, 80), tex);
        const glm::vec3 ref = G::sgSurfgradFromTBN(d, x, y);
        tbn.add(glm::length(g - ref) / std::max(1.0f, glm::length(ref)));
    }
    // Same products as listing 5 after a projection that removes a rounding-
    // size normal component: a few ulps.
    hardCaseAtMost("decals-parallel",
                   "decal layer, projector plane parallel to the surface, "
                   "rotated 0 to 355 deg in it",
                   "|sg - TBN sg (T = axis x, B = axis y)| / max(1, |sg|)", tbn.value, 1e-6);

    // (b) The projector turned from facing the surface (0 deg) until its
    // projection direction lies in the surface (90 deg): the fade never
    // grows as it turns, the gradient is never longer than the map's
    // derivative, and with the default angle fade [60, 80] nothing is left
    // at 90 deg; without an angle fade ([90, 90]) the edge-on decal keeps
    // only the tangential part of its volume gradient.
    Worst longer, rise, normalPart;
    double atNinety = 0;
    for (float endDeg : {80.0f, 90.0f}) {
        float prevFade = 2.0f;
        for (int k = 0; k <= 180; ++k) {
            const float a = glm::radians(0.5f * float(k));
            const glm::vec3 z(std::sin(a), std::cos(a), 0.0f), x(0, 0, 1), y = glm::cross(z, x);
            const G::SgDecalParams p = decal(x, y, z, endDeg == 80.0f ? 60.0f : 90.0f, endDeg);
            const glm::vec3 pos(0.02f, 0.01f, -0.04f);
            const glm::vec3 g = G::sgLayerDecal(f, pos, p, tex);
            ASSERT_TRUE(std::isfinite(g.x + g.y + g.z)) << k;
            const glm::vec3 r = pos - p.origin;
            const glm::vec3 l =
                glm::vec3(glm::dot(r, p.axisX), glm::dot(r, p.axisY), glm::dot(r, p.axisZ)) /
                p.halfSize;
            const float fade = G::sgDecalFade(p, l, f.nrmBase);
            rise.add(double(fade) - double(prevFade));
            prevFade = fade;
            longer.add(double(glm::length(g)) / double(glm::length(d)) - 1.0);
            normalPart.add(std::fabs(double(glm::dot(g, n))) / double(glm::length(d)));
            if (k == 180 && endDeg == 80.0f) atNinety = glm::length(g);
        }
    }
    hardCaseAtMost("decals-parallel",
                   "decal layer turned 0 to 90 deg until its projection direction lies in the "
                   "surface, angle fade [60, 80] and none",
                   "largest increase of the fade as it turns", rise.value, 0.0);
    hardCaseAtMost("decals-parallel", "the same", "|sg| / |d| - 1", longer.value, 1e-6);
    hardCaseAtMost("decals-parallel", "the same", "|sg . n| / |d|", normalPart.value, 1e-6);
    EXPECT_EQ(atNinety, 0.0);
    reportHardCase({"decals-parallel", "the same at 90 deg with the default angle fade [60, 80]",
                    "|sg|", "= 0", hardCaseNumber(atNinety)});
}

// A decal thinner than the rounding of the positions it is measured between
// (sgDecalHalfDepth): 1e-6 deep, its middle plane the surface, 3 units from
// the camera, where a position carries 2.4e-7 of rounding. Surface points
// moved by -2..2 ulps of their distance (what the interpolation of a
// rounded vertex gives) keep the decal at full strength and the same
// gradient; without the floor of 16 ulps on the half depth they would sit
// at |l.z| up to 0.95 of the box and fade by up to 85%.
TEST(RenderHardCases, DecalThinnerThanTheRoundingKeepsItsSurface) {
    const glm::vec3 m = glm::normalize(glm::vec3(0.35f, -0.2f, 0.9f));
    TextureImage img = constantNormalMap(m);
    G::sampler2D tex{&img};
    const G::SgFrame f = flatFrame(0.002f);
    const G::SgDecalParams p = G::sgUnpackDecal(
        glm::vec4(0, -3, 0, 1), glm::vec4(1, 0, 0, 0.5f), glm::vec4(0, 0, -1, 0.5f),
        glm::vec4(0, 1, 0, 5e-7f), glm::vec4(0.25f, 0.5f, 0.17f, 0), glm::vec4(0));
    const glm::vec3 ref = G::sgLayerDecal(f, glm::vec3(0.1f, -3.0f, 0.05f), p, tex);
    ASSERT_GT(glm::length(ref), 0.1f);
    Worst moved;
    for (int ulps = -2; ulps <= 2; ++ulps) {
        const float y = -3.0f + float(ulps) * 2.384185791e-7f; // ulp(3) = 2^-22
        const glm::vec3 g = G::sgLayerDecal(f, glm::vec3(0.1f, y, 0.05f), p, tex);
        moved.add(glm::length(g - ref) / glm::length(ref));
    }
    // The local depth is at most 2 ulps / 16 ulps of the widened half depth:
    // inside the core (the fade starts at 0.75), the gradient the same up to
    // the rounding of the dot products.
    sg::test::hardCasePerturbedAtMost(
        "decals-parallel", "decal 1e-6 deep lying on the surface, 3 units from the camera",
        "the surface point moved by -2..2 ulps of its distance along the decal's axis",
        "|sg - sg unmoved| / |sg|", moved.value, 1e-6);
}

TEST(RenderHardCases, TriplanarLayerAtEqualWeights) {
    // Three different constant maps on the three planes; the layer's
    // gradient at the diagonal normal is the projection of the average of
    // the three planar gradients (eq. 7, w = 1/3), computed here from the
    // decoded derivatives.
    const glm::vec3 mx = glm::normalize(glm::vec3(0.3f, 0.1f, 0.9f)),
                    my = glm::normalize(glm::vec3(-0.2f, 0.25f, 0.9f)),
                    mz = glm::normalize(glm::vec3(0.05f, -0.3f, 0.9f));
    TextureImage ix = constantNormalMap(mx), iy = constantNormalMap(my), iz = constantNormalMap(mz);
    G::sampler2D tx{&ix}, ty{&iy}, tz{&iz};
    auto deriv = [](G::sampler2D& t) {
        return G::sgTspaceNormalToDeriv(
            G::sgDecodeNormalXY(G::textureGrad(t, glm::vec2(0.5f), glm::vec2(0), glm::vec2(0)), 0),
            false);
    };
    const glm::vec2 dX = deriv(tx), dY = deriv(ty), dZ = deriv(tz);
    Worst err, unequal;
    for (int octant = 0; octant < 8; ++octant) {
        const glm::vec3 n = glm::normalize(
            glm::vec3(octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1));
        const glm::vec3 e1 = glm::normalize(glm::cross(n, glm::vec3(0.3f, 0.5f, 0.8f)));
        const glm::vec3 e2 = glm::cross(n, e1);
        const G::SgFrame f = G::sgPrologue(n, 0.001f * e1, 0.001f * e2, true, SG_BFACE_NONE);
        const G::SgVolumeSpace vs =
            G::sgVolumeSpace(f, glm::vec3(0.3f, 0.2f, 0.1f), glm::mat3(1.0f), glm::mat3(1.0f));
        for (float k : {1.0f, 4.0f, 64.0f}) {
            for (int rh = 0; rh < 2; ++rh) {
                const G::SgTriplanarParams p =
                    G::sgUnpackTriplanar(glm::vec4(1, 1, k, float(rh)), glm::vec4(0), glm::vec4(0));
                const glm::vec3 g = G::sgLayerTriplanar(f, vs, p, tx, ty, tz);
                ASSERT_TRUE(std::isfinite(g.x + g.y + g.z));
                const glm::vec3 w = G::sgTriplanarWeights(n, k);
                for (int c = 0; c < 3; ++c) unequal.add(std::fabs(double(w[c]) - 1.0 / 3.0));
                // Eq. 7 in double with w = 1/3 (rh negates z), projected.
                glm::dvec3 grad = (1.0 / 3.0) * glm::dvec3(double(dZ.x) + dY.x, double(dZ.y) + dX.y,
                                                           double(dX.x) + dY.y);
                if (rh) grad.z = -grad.z;
                const glm::dvec3 nd(n);
                const glm::dvec3 oracle = grad - glm::dot(grad, nd) * nd;
                err.add(glm::length(glm::dvec3(g) - oracle) / std::max(1.0, glm::length(oracle)));
            }
        }
    }
    // The weights are 1/3 up to the rounding of the binary32 diagonal
    // raised to k (k ulps); the gradient then differs from the average by
    // as much: measured below 1e-5 for k <= 64.
    hardCaseAtMost("triplanar-equal",
                   "triplanar layer at the 8 diagonal normals, sharpness 1, 4, 64, both handedness",
                   "|w_i - 1/3|", unequal.value, 4e-5);
    hardCaseAtMost("triplanar-equal", "the same",
                   "|sg - projected average of the planar gradients| / max(1, |sg|)", err.value,
                   4e-5);
}

// The scene of the far-from-origin case: a sphere with a tangent-space
// normal map (the per-pixel frame from dPdx and dUVdx) at (c, c, c), its
// camera 3 units away along +z. c is an integer below 2^23, so the object
// and camera positions are exact in binary32 and the view is the same at
// every distance. (Scene files bound translations to 1e6 per component;
// the scene is moved after parsing.)
Scene farScene(float c) {
    Scene scene = sceneFromJson(oneMaterialScene(
        R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 128}})",
        R"({"procedural": {"type": "sphere", "size": 1, "segments": 48}})", "", 96, 72,
        R"(, "camera": {"position": [0, 0, 3], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 38, "near": 0.5, "far": 10})"));
    const glm::dvec3 offset(c);
    scene.meshes[0].transform = glm::translate(glm::dmat4(1.0), offset);
    scene.camera.position += offset;
    scene.camera.target += offset;
    return scene;
}

// Largest angle (degrees) between the normal AOVs of two renders over the
// pixels both cover; coverage must match.
double maxNormalAngleDeg(const Image& a, const Image& b) {
    EXPECT_EQ(a.texelCount(), b.texelCount());
    double worst = 0.0;
    size_t covered = 0;
    for (size_t i = 0; i < a.texelCount() && i < b.texelCount(); ++i) {
        const glm::dvec3 u(a.rgba(i)), v(b.rgba(i));
        const bool ca = glm::length(u) > 0.5, cb = glm::length(v) > 0.5;
        EXPECT_EQ(ca, cb) << "pixel " << i;
        if (!ca || !cb) continue;
        ++covered;
        const double ang =
            std::atan2(glm::length(glm::cross(u, v)), glm::dot(u, v)) * (180.0 / 3.141592653589793);
        if (!(ang <= worst)) worst = ang;
    }
    EXPECT_GT(covered, 1000u);
    return worst;
}

TEST(RenderHardCases, FarFromOriginCameraRelative) {
    const Scene origin = farScene(0.0f);
    const SceneAssets originAssets = loadAssets(origin);
    const View originView = makeView(origin, originAssets, 0, 0, Aov::Normal);
    const Image cpu0 = renderCpu(origin, originAssets, originView);
    const Image gpu0 = gpu().render(origin, originAssets, originView);
    Worst cpuWorst, gpuWorst;
    // 1e5, 1e6, 1e7 units from the origin (|(c, c, c)| = c sqrt 3).
    for (float c : {57735.0f, 577350.0f, 5773503.0f}) {
        const Scene far = farScene(c);
        const SceneAssets assets = loadAssets(far);
        const View view = makeView(far, assets, 0, 0, Aov::Normal);
        cpuWorst.add(maxNormalAngleDeg(renderCpu(far, assets, view), cpu0));
        gpuWorst.add(maxNormalAngleDeg(gpu().render(far, assets, view), gpu0));
    }
    // The camera-relative transform of every distance is the origin's
    // (translation (0, 0, -3) exactly), so the relative positions and every
    // shading input are bit for bit those at the origin; the bound leaves
    // room for a view matrix rounded differently at large magnitudes (a
    // hundredth of a degree; world positions minus the camera in binary32
    // were off by degrees at 1e6).
    hardCaseAtMost("far-from-origin-render",
                   "bumped sphere (uv_normal) and camera 1e5, 1e6, 1e7 units from the origin, CPU "
                   "reference renderer",
                   "normal AOV angle vs the same view at the origin, deg", cpuWorst.value, 0.01);
    hardCaseAtMost("far-from-origin-render", "the same, GPU (llvmpipe)",
                   "normal AOV angle vs the same view at the origin, deg", gpuWorst.value, 0.01,
                   false);
}

} // namespace
} // namespace sg::render::test

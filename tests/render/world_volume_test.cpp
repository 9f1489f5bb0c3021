// World-space volume layers far from the world origin: Mikkelsen 2019,
// section 2.7 (volume bump maps) and 2.8 (triplanar, listing 13) evaluated
// on a domain placed by the camera-relative position (listing 16) plus a
// per-layer shift packed in binary64 (shaders/sg/render/layer_triplanar.glsl,
// layer_noise.glsl, noise.glsl):
//  - known answers through the shared C++ functions: a world point near the
//    origin and the same point moved by a large offset, the camera moved
//    with it, give the same surface gradient (triplanar: whole texture
//    repeats; noise: the lattice moved by the offset), and against the
//    layer on the absolute position near the origin (triplanar) or the
//    noise placed in extended precision at the absolute lattice point;
//  - renders (hard case far-from-origin-render): a sphere with world-space
//    triplanar or noise layers 1e5 units from the origin, its camera
//    nearby, on the GPU and on the CPU reference renderer, against each
//    other and against the same view at the origin.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "hardcase.h"
#include "layer_kind.h"
#include "render_test_util.h"
#include "surfgrad/render/render_shaders.h"

namespace sg::render::test {
namespace {

namespace G = sg::glsl;
using sg::test::hardCaseAtMost;
using sg::test::Worst;

// ---------------------------------------------------------------------------
// Known answers through the shared functions (the CPU build of the layers'
// GLSL, with the records packed as both renderers pack them)

// A surface point whose normal leans towards all three axes (every
// triplanar plane weighs), 1e-3 units per pixel.
G::SgFrame tiltedFrame() {
    const glm::vec3 n = glm::normalize(glm::vec3(0.5f, 0.8f, 0.35f));
    const glm::vec3 e1 = glm::normalize(glm::cross(n, glm::vec3(0.3f, -0.5f, 0.8f)));
    const glm::vec3 e2 = glm::cross(n, e1);
    return G::sgPrologue(n, 1e-3f * e1, 1e-3f * e2, true, SG_BFACE_NONE);
}

// The layer's records for a camera at cameraPos (packLayer: the packer of
// both renderers).
std::vector<glm::vec4> packFor(const Layer& L, glm::dvec3 cameraPos) {
    View view;
    view.width = view.height = 1;
    view.cameraPos = cameraPos;
    std::vector<glm::vec4> r(size_t(L.kind->recordCount()), glm::vec4(0.0f));
    packLayer(L, view, nullptr, r.data());
    return r;
}

// The world domain at the world point x seen from cameraPos, as the
// renderers build it: x - camera in binary64, rounded once (vRelPos).
G::SgVolumeSpace worldDomain(const G::SgFrame& f, glm::dvec3 x, glm::dvec3 cameraPos) {
    return G::sgVolumeSpace(f, glm::vec3(x - cameraPos), glm::mat3(1.0f), glm::mat3(1.0f));
}

// Points of a 0.1-unit box around (0.3, 0.2, 0.1), the camera 2.5 units
// from them (the render test's view), and the offsets that move both:
// c (1, 1, 1) with |c (1, 1, 1)| = 1e5, 1e6, 1e7 and -1e6 (integers: scale
// 2 and frequency 4 make them whole texture repeats and lattice cells;
// negative cells take the two's complement path).
const glm::dvec3 kEye(0.6, 0.5, 2.4);
std::vector<glm::dvec3> nearPoints() {
    std::vector<glm::dvec3> v;
    for (int i = 0; i < 64; ++i) {
        const double a = 0.05 * std::sin(1.7 * i + 0.3), b = 0.05 * std::cos(2.3 * i + 0.1),
                     c = 0.05 * std::sin(0.9 * i + 1.2);
        v.push_back(glm::dvec3(0.3 + a, 0.2 + b, 0.1 + c));
    }
    return v;
}
constexpr double kOffsets[] = {57735.0, 577350.0, 5773503.0, -577350.0};

// A repeating (or clamped) 16 x 16 map of pseudo-random unit normals in
// float texels (RGB encoding, no 8-bit rounding).
TextureImage randomNormalMap(Wrap wrap) {
    std::vector<glm::vec4> t;
    for (int i = 0; i < 256; ++i) {
        const glm::vec3 n = glm::normalize(
            glm::vec3(0.5f * std::sin(3.1f * float(i)), 0.5f * std::cos(1.3f * float(i)), 1.0f));
        t.push_back(glm::vec4(0.5f * n + 0.5f, 1.0f));
    }
    return makeTexture(16, 16, std::move(t), wrap);
}

TEST(WorldVolume, TriplanarFarFromOriginSamplesTheOriginsTexels) {
    const G::SgFrame f = tiltedFrame();
    for (Wrap wrap : {Wrap::Repeat, Wrap::Clamp}) {
        const TextureImage img = randomNormalMap(wrap);
        const G::sampler2D tex{&img};
        Layer L = makeLayer("triplanar");
        L.params<TriplanarParams>().scale = 2.0f;
        L.params<TriplanarParams>().space = Space::World;
        L.maps.assign(3, TextureSource{});
        for (TextureSource& m : L.maps) m.wrap = wrap;
        // Expected: the layer on the absolute position near the origin,
        // where binary32 holds it to 2^-24 of 0.4 (texShift 0).
        const std::vector<glm::vec4> r0 = packFor(L, glm::dvec3(0.0));
        const G::SgTriplanarParams pAbs = G::sgUnpackTriplanar(r0[0], r0[1], glm::vec4(0.0f));
        std::vector<glm::dvec3> want;
        double sumSq = 0.0;
        for (const glm::dvec3& x : nearPoints()) {
            const G::SgVolumeSpace vsAbs =
                G::sgVolumeSpace(f, glm::vec3(x), glm::mat3(1.0f), glm::mat3(1.0f));
            want.push_back(glm::dvec3(G::sgLayerTriplanar(f, vsAbs, pAbs, tex, tex, tex)));
            sumSq += glm::dot(want.back(), want.back());
        }
        const double rms = std::sqrt(sumSq / double(want.size()));
        ASSERT_GT(rms, 0.05);
        Worst nearErr, farErr, moved;
        for (size_t i = 0; i < want.size(); ++i) {
            const glm::dvec3 x = nearPoints()[i];
            glm::vec3 gNear(0.0f);
            for (double c : {0.0, 57735.0, 577350.0, 5773503.0, -577350.0}) {
                const glm::dvec3 d(c), eye = x + kEye + d;
                const std::vector<glm::vec4> r = packFor(L, eye);
                const G::SgTriplanarParams p = G::sgUnpackTriplanar(r[0], r[1], r[2]);
                if (wrap == Wrap::Repeat) {
                    EXPECT_TRUE(p.texShift.x >= 0.0f && p.texShift.x <= 1.0f);
                } else {
                    // A clamped map: the absolute position (scale * camera).
                    EXPECT_EQ(p.texShift, glm::vec3(2.0 * eye));
                }
                if (wrap == Wrap::Clamp && c != 0.0) continue; // the edge texels far out
                const glm::vec3 g =
                    G::sgLayerTriplanar(f, worldDomain(f, x + d, eye), p, tex, tex, tex);
                (c == 0.0 ? nearErr : farErr).add(glm::length(glm::dvec3(g) - want[i]) / rms);
                // Translation: the same point and camera near the origin.
                if (c == 0.0) gNear = g;
                moved.add(glm::length(glm::dvec3(g) - glm::dvec3(gNear)) / rms);
            }
        }
        const char* what = wrap == Wrap::Repeat ? "repeating maps" : "clamped maps";
        std::printf("[triplanar, %s] near %.3g far %.3g moved %.3g (far: repeating maps only)\n",
                    what, nearErr.value, farErr.value, moved.value);
        // The texture coordinate scale (x - camera) + fract(scale camera)
        // equals scale x up to a few ulps of values below 8 (about 1e-6),
        // 2e-5 texels on this 16-texel map, whose neighbouring texels'
        // derivatives differ by about the RMS gradient: errors of order
        // 1e-5 of it.
        EXPECT_LE(nearErr.value, 1e-4) << what;
        if (wrap == Wrap::Repeat) {
            EXPECT_LE(farErr.value, 1e-4) << what;
            // fract(scale camera) far out is the origin's up to one ulp of
            // a value below 1 (binary64 sums at 1e7 round at 2e-9).
            EXPECT_LE(moved.value, 1e-5) << what;
        }
    }
}

// Independent evaluation of the noise layer's surface gradient at the
// world point x: octave k's argument F_k (frequency x + offset) (F_k the
// binary32 product of k lacunarities, the layer's octave frequency) in
// long double at the absolute point, split into its lattice cell (modulo
// 2^32, as the hash reads it) and fraction, one sgPerlinNoiseCell per
// octave (fBm, no fade: the kernel the layer shares, not its placement).
glm::dvec3 noiseReference(const G::SgFrame& f, const NoiseParams& np, glm::dvec3 x) {
    glm::dvec3 grad(0.0);
    float freq = 1.0f, amp = 1.0f;
    for (int k = 0; k < np.octaves; ++k) {
        glm::uvec3 cell;
        glm::vec3 frac;
        for (int i = 0; i < 3; ++i) {
            const long double a =
                (long double)freq *
                ((long double)np.frequency * (long double)x[i] + (long double)np.offset[i]);
            const long double whole = std::floor(a);
            frac[i] = float(a - whole);
            long double wrapped = std::fmod(whole, 4294967296.0L);
            if (wrapped < 0) wrapped += 4294967296.0L;
            cell[i] = uint32_t(wrapped);
        }
        const glm::vec4 n = G::sgPerlinNoiseCell(cell, frac);
        grad += double(amp) * double(freq) * glm::dvec3(n.y, n.z, n.w);
        freq *= np.lacunarity;
        amp *= np.gain;
    }
    grad *= double(np.amplitude) * double(np.frequency);
    const glm::dvec3 nrm(f.nrmBase);
    return grad - glm::dot(nrm, grad) * nrm; // listing 12
}

// One world-space fBm layer (frequency 4, 5 octaves of gain 0.5, an offset
// with a fraction) of the given lacunarity, no fade.
Layer worldNoise(float lacunarity) {
    Layer L = makeLayer("noise");
    NoiseParams& np = L.params<NoiseParams>();
    np.type = NoiseType::Fbm;
    np.amplitude = 0.02f;
    np.frequency = 4.0f;
    np.octaves = 5;
    np.lacunarity = lacunarity;
    np.gain = 0.5f;
    np.offset = glm::vec3(0.25f, -1.5f, 3.0f);
    np.space = Space::World;
    np.antialias = NoiseAntialias::None;
    return L;
}

// The layer's surface gradient at world point x, the camera at eye.
glm::vec3 noiseAt(const G::SgFrame& f, const Layer& L, glm::dvec3 x, glm::dvec3 eye) {
    const std::vector<glm::vec4> r = packFor(L, eye);
    return G::sgLayerNoise(f, worldDomain(f, x, eye),
                           G::sgUnpackNoise(r[0], r[1], r[2], r[3], r[4]));
}

TEST(WorldVolume, NoiseFarFromOriginIsTheNoiseAtTheAbsoluteLatticePoint) {
    const G::SgFrame f = tiltedFrame();
    // Errors in units of the RMS of the expected gradient (a few near-zero
    // gradients would make relative errors meaningless).
    Worst nearErr, farErr, unchanged, moved, wrappedErr;
    for (float lacunarity : {2.0f, 3.0f, 2.37f, 1.9f}) {
        const Layer L = worldNoise(lacunarity);
        const NoiseParams& np = L.params<NoiseParams>();
        double sumSq = 0.0;
        for (const glm::dvec3& x : nearPoints())
            sumSq += glm::dot(noiseReference(f, np, x), noiseReference(f, np, x));
        const double rms = std::sqrt(sumSq / double(nearPoints().size()));
        ASSERT_GT(rms, 0.05);
        auto err = [rms](glm::vec3 a, glm::dvec3 b) {
            return glm::length(glm::dvec3(a) - b) / rms;
        };
        for (const glm::dvec3& x : nearPoints()) {
            // Near the origin: the reference, and the pattern the absolute
            // binary32 position gave (sgNoiseOctaves at frequency x + offset).
            const glm::vec3 g = noiseAt(f, L, x, x + kEye);
            nearErr.add(err(g, noiseReference(f, np, x)));
            const glm::vec4 h = G::sgNoiseOctaves(SG_NOISE_FBM, 4.0f * glm::vec3(x) + np.offset, 5,
                                                  lacunarity, 0.5f, 0.0f);
            unchanged.add(err(g, glm::dvec3(G::sgSurfgradFromVolumeGradient(
                                     f, (0.02f * 4.0f) * glm::vec3(h.y, h.z, h.w)))));
            for (double c : kOffsets) {
                const glm::dvec3 d(c);
                const glm::vec3 gFar = noiseAt(f, L, x + d, x + kEye + d);
                farErr.add(err(gFar, noiseReference(f, np, x + d)));
                // Translation: the point near the origin, its lattice moved
                // by frequency * d (whole cells) through the offset (exact
                // in binary32 up to 1e6: 4 c + 0.25 < 2^22).
                if (std::fabs(c) > 1e6) continue;
                Layer shifted = L;
                shifted.params<NoiseParams>().offset += glm::vec3(4.0 * d);
                moved.add(err(gFar, glm::dvec3(noiseAt(f, shifted, x, x + kEye))));
            }
            // An argument beyond 2^31 cells (frequency 1000, 1e7 out, the
            // camera 0.0025 away): the cell wraps modulo 2^32, exact for
            // integer lacunarities only.
            if (lacunarity == 2.0f || lacunarity == 3.0f) {
                Layer fine = L;
                fine.params<NoiseParams>().frequency = 1000.0f;
                fine.params<NoiseParams>().amplitude = 0.02f * 4.0f / 1000.0f; // same slopes
                const glm::dvec3 xf =
                    glm::dvec3(5773503.0) + 0.01 * (x - glm::dvec3(0.3, 0.2, 0.1));
                wrappedErr.add(err(noiseAt(f, fine, xf, xf + 0.001 * kEye),
                                   noiseReference(f, fine.params<NoiseParams>(), xf)));
            }
        }
    }
    std::printf("[noise] near %.3g far %.3g unchanged %.3g moved %.3g wrapped %.3g\n",
                nearErr.value, farErr.value, unchanged.value, moved.value, wrappedErr.value);
    // What is left is the binary32 rounding of the small argument: octave
    // k reads F_k q, q = originFrac + frequency (x - camera), |q| <= 12
    // cells here, F_4 = 81 for lacunarity 3: about 7e-5 cells (half an ulp
    // of 920 plus 81 half ulps of 12), which the finest octave's Hessian
    // (amplitude frequency gain^4 F_4^2 |H|, |H| ~ 10) turns into 2.3e-4 of
    // gradient, about 1e-3 of the RMS gradient at worst; the old absolute
    // position rounds a value of the same size near the origin. Far out,
    // the records' split is exact, so the far error is the near one's.
    EXPECT_LE(nearErr.value, 1e-3);
    EXPECT_LE(farErr.value, 1e-3);
    EXPECT_LE(unchanged.value, 1e-3);
    EXPECT_LE(wrappedErr.value, 1e-3);
    // The same relative position and fraction give the same binary32
    // inputs (measured bit for bit; a fraction may round one ulp apart).
    EXPECT_LE(moved.value, 1e-5);
}

// ---------------------------------------------------------------------------
// Renders

// A world-space volume layer (or layers) on a sphere at (c, c, c), the
// camera at (c, c, c) + (0.6, 0.5, 2.4) (2.5 units away, the stability
// table's far-from-origin view). c is an integer below 2^23: the object
// and the camera are exact in binary32 and binary64, and the camera-relative
// transform is the same at every c. Scene files bound translations to 1e6:
// the scene is moved after parsing.
Scene worldVolumeScene(const std::string& layers, double c) {
    Scene scene = sceneFromJson(oneMaterialScene(
        layers, R"({"procedural": {"type": "sphere", "size": 1, "segments": 48}})", "", 128, 96,
        R"(, "camera": {"position": [0.6, 0.5, 2.4], "target": [0, 0, 0], "up": [0, 1, 0], "fov_deg": 38, "near": 0.5, "far": 10})"));
    const glm::dvec3 offset(c);
    scene.meshes[0].transform = glm::translate(glm::dmat4(1.0), offset);
    scene.camera.position += offset;
    scene.camera.target += offset;
    return scene;
}

struct Renders {
    Image gpuNormal, gpuPrim, cpuNormal, cpuPrim;
};

Renders renderBoth(const Scene& s) {
    const SceneAssets a = loadAssets(s);
    CpuOptions parity;
    parity.derivatives = CpuDerivatives::Quad;
    parity.textureLod = sg::glsl::LodRule::FastLog2;
    NormalRenders r = renderNormalsBoth(s, a, parity);
    return {r.gpuNormal, r.gpuPrim, r.cpuNormal, r.cpuPrim};
}

struct WorldCase {
    const char* name;
    std::string farLayers;    // the layers of the sphere at (c, c, c)
    std::string originLayers; // the same pattern on the sphere at the origin
};

// c = 57735: |(c, c, c)| = 1e5. The triplanar scales are integers, so
// scale * c is a whole number of repeats and the origin sees the same
// texture; noise frequency 4 puts the far sphere's lattice 4c = 230940
// cells out, which the origin scene's "offset" adds back (an integer,
// exact in binary32).
constexpr double kFar = 57735.0;

std::vector<WorldCase> worldCases() {
    const std::string tiles = R"({"procedural": "bumps", "size": 64})";
    const std::string noise =
        R"({"type": "noise", "noise": "fbm", "amplitude": 0.01, "frequency": 4, "octaves": 5, "space": "world")";
    const std::string shifted = R"(, "offset": [230940, 230940, 230940])";
    return {
        {"triplanar", R"({"type": "triplanar", "scale": 2, "map": )" + tiles + "}",
         R"({"type": "triplanar", "scale": 2, "map": )" + tiles + "}"},
        {"triplanar-lean",
         R"({"type": "triplanar", "scale": 2, "antialias": "lean", "map": )" + tiles + "}",
         R"({"type": "triplanar", "scale": 2, "antialias": "lean", "map": )" + tiles + "}"},
        {"noise", noise + "}", noise + shifted + "}"},
        {"noise-lacunarity-2.37-lean", noise + R"(, "lacunarity": 2.37, "antialias": "lean"})",
         noise + R"(, "lacunarity": 2.37, "antialias": "lean")" + shifted + "}"},
        // The post-resolve group after parallax re-prologues on the virtual
        // surface (layer_parallax.cpp) and moves the world domain there.
        {"parallax-then-triplanar",
         R"({"type": "parallax", "scale": 0.03, "map": {"procedural": "bricks", "output": "height", "size": 64}},
            {"type": "post_resolve", "layers": [{"type": "triplanar", "scale": 2, "map": )" +
             tiles + "}]}",
         R"({"type": "parallax", "scale": 0.03, "map": {"procedural": "bricks", "output": "height", "size": 64}},
            {"type": "post_resolve", "layers": [{"type": "triplanar", "scale": 2, "map": )" +
             tiles + "}]}"},
    };
}

TEST(RenderHardCases, WorldVolumeLayersFarFromOrigin) {
    Worst parityFar, parityOrigin, gpuMoved, cpuMoved;
    for (const WorldCase& wc : worldCases()) {
        const Renders far = renderBoth(worldVolumeScene(wc.farLayers, kFar));
        const Renders origin = renderBoth(worldVolumeScene(wc.originLayers, 0.0));
        const VectorImageDiff pf =
            compareVectorImages(far.gpuNormal, far.cpuNormal, far.gpuPrim, far.cpuPrim);
        const VectorImageDiff po =
            compareVectorImages(origin.gpuNormal, origin.cpuNormal, origin.gpuPrim, origin.cpuPrim);
        const VectorImageDiff gm =
            compareVectorImages(far.gpuNormal, origin.gpuNormal, far.gpuPrim, origin.gpuPrim);
        const VectorImageDiff cm =
            compareVectorImages(far.cpuNormal, origin.cpuNormal, far.cpuPrim, origin.cpuPrim);
        for (const VectorImageDiff* d : {&pf, &po, &gm, &cm}) {
            EXPECT_GT(d->compared, 4000u) << wc.name;
            EXPECT_EQ(d->nonFinite, 0u) << wc.name;
        }
        std::printf("[%s] p99 (max) deg: GPU vs CPU far %.3g (%.3g), at the origin %.3g (%.3g); "
                    "far vs origin GPU %.3g (%.3g), CPU %.3g (%.3g)\n",
                    wc.name, pf.p99Deg, pf.maxDeg, po.p99Deg, po.maxDeg, gm.p99Deg, gm.maxDeg,
                    cm.p99Deg, cm.maxDeg);
        parityFar.add(pf.p99Deg);
        parityOrigin.add(po.p99Deg);
        gpuMoved.add(gm.p99Deg);
        cpuMoved.add(cm.p99Deg);
    }
    const std::string what =
        "sphere with world-space triplanar (plain, LEAN, after parallax) or noise (fBm, "
        "lacunarity 2 and 2.37 LEAN) layers, camera 2.5 units away, 1e5 units from the origin";
    // Bounds: the parity bound of every layer kind at the origin
    // (image_test.cpp: 0.05 deg, max) taken at p99, and the same for the
    // far view against the origin's. The layers' inputs far out are the
    // origin's camera-relative position plus a shift below one texture
    // repeat or lattice cell, so what is left is the rounding of those
    // small numbers (and of the view at 1e5): measured GPU vs CPU 1.4e-3
    // deg p99 (the origin's), far vs origin 0 (the same binary32 inputs).
    // The absolute binary32 world position gave, on this view, GPU vs CPU
    // 38-42 deg p99 for triplanar, 3.2-4.6 for noise, and far vs origin
    // 35-40 (GPU) and 19-21 (CPU) for triplanar, 1.8-4.5 for noise.
    hardCaseAtMost("far-from-origin-render", what + ": GPU vs CPU reference (quad derivatives)",
                   "normal AOV p99 angle, deg", parityFar.value, 0.05, false);
    hardCaseAtMost("far-from-origin-render", "the same view at the origin, GPU vs CPU",
                   "normal AOV p99 angle, deg", parityOrigin.value, 0.05, false);
    hardCaseAtMost("far-from-origin-render", what + ": GPU, vs the same view at the origin",
                   "normal AOV p99 angle, deg", gpuMoved.value, 0.05, false);
    hardCaseAtMost("far-from-origin-render", what + ": CPU reference, vs the view at the origin",
                   "normal AOV p99 angle, deg", cpuMoved.value, 0.05);
}

} // namespace
} // namespace sg::render::test

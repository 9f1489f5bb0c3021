// Encodings of tangent-space maps (Loviscach 2008, "Care: Two, three, or
// four channels"; Mikkelsen 2019, section 2.1): round trips are lossless up
// to quantisation, green conventions mirror the green channel, and the
// object-space conversion through a mesh's mikktspace frames matches the
// classic TBN transform and inverts.
#include <gtest/gtest.h>

#include <cstdio>

#include "analytic_fields.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/render_mesh.h"
#include "surfgrad/mesh/tangents.h"

namespace {

using namespace sg::normalmap;
using namespace sg::normalmap::test;

// What writing with `bits` integer samples and reading back does.
Image quantise(Image img, int bits) {
    const float q = float((1 << bits) - 1);
    for (float& v : img.samples) v = std::round(std::clamp(v, 0.0f, 1.0f) * q) / q;
    return img;
}

int maxLsbDiff(const Image& a, const Image& b, int channel, int bits) {
    const float q = float((1 << bits) - 1);
    int m = 0;
    for (int j = 0; j < a.height; ++j)
        for (int i = 0; i < a.width; ++i) {
            m = std::max(m,
                         int(std::lround(std::abs(a.at(i, j, channel) - b.at(i, j, channel)) * q)));
        }
    return m;
}

DerivField testSlopes() {
    return slopes(sines(128, 96, 6.0), 128, 96);
}

TEST(Encoding, RgbRoundTripIsLosslessUpToQuantisation) {
    for (int bits : {8, 16}) {
        const Image stored = quantise(encodeSlopes(testSlopes(), MapFormat{}, false), bits);
        const Image again = quantise(
            encodeSlopes(decodeSlopes(stored, MapFormat{}, "t"), MapFormat{}, false), bits);
        // x and y are what listing 4 reads: identical codes.
        EXPECT_EQ(maxLsbDiff(stored, again, 0, bits), 0) << bits;
        EXPECT_EQ(maxLsbDiff(stored, again, 1, bits), 0) << bits;
        // z is recomputed from the quantised x, y: within one code.
        EXPECT_LE(maxLsbDiff(stored, again, 2, bits), 1) << bits;
    }
}

TEST(Encoding, EveryEncodingCarriesTheSameSlopes) {
    const DerivField d = testSlopes();
    const double steepest = 1.2; // |slope| of testSlopes() stays below this
    struct Case {
        Encoding e;
        bool isFloat;
        int bits; // 0: float
    };
    for (const Case& c : {Case{Encoding::Rgb, false, 16}, Case{Encoding::Rg, false, 16},
                          Case{Encoding::Ag, false, 16}, Case{Encoding::Deriv, false, 16},
                          Case{Encoding::Deriv, true, 0}, Case{Encoding::Signed, true, 0}}) {
        MapFormat f;
        f.encoding = c.e;
        f.derivRange = 4.0f;
        Image img = encodeSlopes(d, f, c.isFloat);
        if (c.bits) img = quantise(img, c.bits);
        const DerivField back = decodeSlopes(img, f, "t");
        double err = 0;
        for (size_t k = 0; k < d.size(); ++k)
            err = std::max(err, double(glm::length(back.v[k] - d.v[k])));
        // 16-bit codes: a normal component to 1/65535, i.e. a slope to
        // (1 + s^2)^1.5 / 32768 ~ 1e-4 at s = 1.2; a 16-bit derivative map
        // to 2 range / 65535 = 1.2e-4; float: rounding (1e-6).
        const double tol = c.bits ? 2.5e-4 * std::pow(1 + steepest * steepest, 1.5) : 1e-5;
        EXPECT_LT(err, tol) << encodingName(c.e) << (c.isFloat ? " float" : " 16-bit");
    }
}

TEST(Encoding, DirectXGreenMirrorsTheGreenChannel) {
    const Image gl = quantise(encodeSlopes(testSlopes(), MapFormat{}, false), 8);
    MapFormat dxf;
    dxf.green = Green::Dx;
    const Image dx = quantise(encodeSlopes(decodeSlopes(gl, MapFormat{}, "t"), dxf, false), 8);
    for (int j = 0; j < gl.height; ++j)
        for (int i = 0; i < gl.width; ++i) {
            ASSERT_EQ(std::lround(dx.at(i, j, 1) * 255), 255 - std::lround(gl.at(i, j, 1) * 255));
            ASSERT_EQ(std::lround(dx.at(i, j, 0) * 255), std::lround(gl.at(i, j, 0) * 255));
        }
    // Decoding the DirectX file as DirectX gives the OpenGL slopes back
    // (2 (1 - c) - 1 and -(2 c - 1) round differently: a few ulps).
    const DerivField a = decodeSlopes(gl, MapFormat{}, "gl"), b = decodeSlopes(dx, dxf, "dx");
    for (size_t k = 0; k < a.size(); ++k) ASSERT_LT(glm::length(a.v[k] - b.v[k]), 1e-5f) << k;
}

TEST(Encoding, ObjectSpaceThroughSpotsFramesMatchesTbnAndInverts) {
    const auto mesh = sg::mesh::loadRenderMesh(std::string(SURFGRAD_DATA_DIR) +
                                               "/meshes/spot/spot_control_mesh.obj");
    const Image map =
        readImage(std::string(SURFGRAD_SOURCE_DIR) + "/examples/data/spot_normal.png");
    const DerivField d = decodeSlopes(map, MapFormat{}, "spot_normal");
    const TexelFrames frames = rasterizeFrames(mesh, 0, map.width, map.height, 2);
    const NormalField obj = objectFromTangent(d, frames);
    size_t covered = 0;
    double worstTbn = 0;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            if (!frames.covered.at(i, j)) continue;
            ++covered;
            // Classic mikktspace TBN: normalize(mx t + my (w n x t) + mz n)
            // with the interpolated, unnormalised n and t.
            const glm::vec3 n = frames.normal.at(i, j);
            const glm::vec4 t = frames.tangent.at(i, j);
            const glm::vec3 b = t.w * glm::cross(n, glm::vec3(t));
            const glm::vec3 m = normalsFromSlopes(DerivField(1, 1, d.at(i, j))).v[0];
            const glm::dvec3 tbn =
                glm::normalize(glm::dvec3(m.x * glm::vec3(t) + m.y * b + m.z * n));
            const glm::vec3 o = obj.at(i, j);
            worstTbn = std::max(worstTbn, angleDeg(tbn, glm::dvec3(o.x, o.y, o.z)));
        }
    const DerivField back = tangentFromObject(obj, frames);
    double worstBack = 0;
    for (int j = 0; j < map.height; ++j)
        for (int i = 0; i < map.width; ++i) {
            if (!frames.covered.at(i, j)) continue;
            const glm::vec2 a = back.at(i, j), e = d.at(i, j);
            worstBack = std::max(worstBack, angleDeg(glm::dvec2(a.x, a.y), glm::dvec2(e.x, e.y)));
        }
    std::printf("[ measure  ] spot 512^2: %zu texels covered; object vs classic TBN max %.2e deg; "
                "tangent -> object -> tangent max %.2e deg\n",
                covered, worstTbn, worstBack);
    EXPECT_GT(covered, size_t(map.width) * size_t(map.height) / 3);
    // binary32 frames of O(1) vectors: 1e-3 degrees is ~2e-5 rad.
    EXPECT_LT(worstTbn, 1e-3);
    EXPECT_LT(worstBack, 1e-3);
}

} // namespace

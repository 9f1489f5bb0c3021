// Table 11's error measure (bench/accuracy/adaptive_error.h; docs/
// accuracy-cost.md, section 11) checked on spot's cage against OpenSubdiv's
// limit: the reference puts limit points at distance ~0, the chord error of
// uniform limit meshes converges quadratically, and the picks the page
// quotes for the medium view (uniform level 3; level 2 is not under the
// 0.5 px bound) hold; and table 11e's frame error compares only pixels
// where both images see the same sheet of the surface.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "adaptive_error.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/render.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using namespace sg::render;

const std::string kSpot = std::string(SURFGRAD_DATA_DIR) + "/meshes/spot/spot_control_mesh.obj";

sg::mesh::RenderMesh limitMesh(int level) {
    const sg::mesh::PolygonMesh cage = sg::mesh::loadPolygonMesh(kSpot);
    sg::mesh::SubdivisionSettings st;
    st.level = level;
    st.options = cage.options;
    st.limit = true;
    return sg::mesh::Subdivider(cage, st, kSpot).renderMesh();
}

// Spot on the tessellated-asset camera at distance scale 1.2 (table 11a's
// medium view), 960x540.
View mediumView(float& focalPx) {
    Scene s = parseScene(R"({"output": {"width": 960, "height": 540},
        "camera": {"azimuth_deg": 105, "elevation_deg": 14, "distance_scale": 1.2, "fov_deg": 32},
        "materials": [{"name": "m"}], "meshes": [{"file": ")" +
                             kSpot + R"(", "subdivision": {"level": 1, "limit": true}}]})",
                         "adaptive_error_test.json", ".");
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a);
    focalPx = sg::glsl::sgPatchFocalPx(v.proj[1][1], float(v.height));
    return v;
}

TEST(StudyAdaptiveError, LimitPointsLieOnTheReference) {
    const study::SurfaceReference ref(limitMesh(5));
    // Level 3's vertices are limit points of the surface level 5 samples
    // (the same points, evaluated from another level's stencils): their
    // distance is float rounding of positions of magnitude ~1 (ulp 1.2e-7),
    // a few ulps of each evaluation; 2e-6 is 16 ulps.
    const sg::mesh::RenderMesh l3 = limitMesh(3);
    float worst = 0.0f;
    for (const glm::vec3& p : l3.positions) {
        const float d = ref.distance(p);
        ASSERT_GE(d, 0.0f);
        worst = std::max(worst, d);
    }
    EXPECT_LT(worst, 2e-6f);
    // Far from every reference vertex: no distance.
    EXPECT_EQ(ref.distance(glm::vec3(100.0f)), -1.0f);
}

TEST(StudyAdaptiveError, ChordErrorConvergesQuadratically) {
    float focalPx = 0.0f;
    const View v = mediumView(focalPx);
    const study::SurfaceReference ref(limitMesh(6));
    double prev = 0.0;
    // From level 2: level 1's chords lie farther from the surface than the
    // reference grid reaches in places (SurfaceReference::distance's -1;
    // 266 of 5856 samples measured), and no table picks spot at level 1.
    for (int level = 2; level <= 4; ++level) {
        const study::ScreenError e = study::screenError(ref, limitMesh(level), v, focalPx);
        EXPECT_GT(e.samples, size_t(1000));
        EXPECT_EQ(e.missed, 0u);
        std::printf("level %d: p99 %.3f px, max %.3f px, %zu samples\n", level, e.p99, e.max,
                    e.samples);
        // Chords of a smooth surface sag by h^2 k / 8: halving h divides the
        // error by 4; below 2.5 per level would be linear convergence (or a
        // reference that does not follow the surface).
        if (level > 2) {
            EXPECT_GT(prev / e.p99, 2.5);
        }
        prev = e.p99;
    }
}

TEST(StudyAdaptiveError, MediumViewNeedsUniformLevel3) {
    float focalPx = 0.0f;
    const View v = mediumView(focalPx);
    const study::SurfaceReference ref(limitMesh(6));
    const study::ScreenError l2 = study::screenError(ref, limitMesh(2), v, focalPx);
    const study::ScreenError l3 = study::screenError(ref, limitMesh(3), v, focalPx);
    // The page's pick (table 11a, spot medium): the bound is p99 and max
    // under 0.5 px; level 2 misses it, level 3 meets it.
    EXPECT_GE(std::max(l2.p99, l2.max), 0.5);
    EXPECT_LT(l3.p99, 0.5);
    EXPECT_LT(l3.max, 0.5);
}

// Table 11e's frame error on synthetic 4x1 images: a pixel both images
// cover with base normals 0.5 degrees apart is compared (its vectors 30
// degrees apart), background in both is skipped, a pixel only one image
// covers and one whose base normals are 20 degrees apart (another sheet)
// are counted, a NaN vector is counted as non-finite.
TEST(StudyAdaptiveError, FrameErrorComparesOnlyTheSameSheet) {
    auto img = [](std::vector<glm::vec4> px) {
        Image i(int(px.size()), 1, 4);
        for (size_t k = 0; k < px.size(); ++k) i.setRgba(k, px[k]);
        return i;
    };
    auto dir = [](double deg) {
        const double r = deg * M_PI / 180.0;
        return glm::vec4(float(std::cos(r)), float(std::sin(r)), 0.0f, 0.0f);
    };
    const glm::vec4 none(0.0f);
    const float nan = std::nanf("");
    const Image a = img({dir(0), none, dir(0), dir(0), glm::vec4(nan, 0, 0, 0)});
    const Image b = img({dir(30), none, dir(0), dir(0), dir(0)});
    const Image baseA = img({dir(90), none, dir(90), dir(90), dir(90)});
    const Image baseB = img({dir(90.5), none, none, dir(110), dir(90)});
    const study::DirectionDiff d = study::compareDirections(a, b, baseA, baseB);
    ASSERT_EQ(d.deg.size(), 1u);
    EXPECT_NEAR(d.deg[0], 30.0, 1e-4); // float inputs: 1e-4 degrees covers their rounding
    EXPECT_EQ(d.otherSheet, 2u);
    EXPECT_EQ(d.nonFinite, 1u);
    // The sheet threshold sits between the two cases above.
    EXPECT_GT(study::kSameSheetDeg, 0.5);
    EXPECT_LT(study::kSameSheetDeg, 20.0);
}

} // namespace

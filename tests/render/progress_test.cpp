// Progress of long renders: the GPU renderer draws large images in
// scissored bands and reports each, the CPU reference reports rows; both
// give the image of a render without progress, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "render_test_util.h"

namespace sg::render::test {
namespace {

size_t differingPixels(const Image& a, const Image& b) {
    size_t n = 0;
    for (size_t i = 0; i < a.texelCount(); ++i) n += a.rgba(i) != b.rgba(i);
    return n;
}

TEST(Progress, BandedGpuRenderIsTheSameImage) {
    // 2048x2048 is the smallest banded size: 4 bands of 512 rows. A noise
    // layer (derivatives, so quads matter at band edges) and two meshes.
    Scene s = sceneFromJson(R"({"materials": [{"layers": [{"type": "noise"}]}],
        "meshes": [{"procedural": {"type": "sphere", "segments": 32}},
                   {"procedural": {"type": "plane", "size": 4}, "transform": {"translate": [0, -1, 0]}}]})");
    SceneAssets a = loadAssets(s);
    GlRenderer& gl = gpu();
    View v = makeView(s, a, 2048, 2048, Aov::Normal);
    gl.setProgress(nullptr);
    Image once = gl.render(s, a, v);
    std::vector<std::pair<int, int>> reports;
    gl.setProgress([&](int done, int total) { reports.emplace_back(done, total); });
    Image banded = gl.render(s, a, v);
    gl.setProgress(nullptr);
    const std::vector<std::pair<int, int>> expected{{1, 4}, {2, 4}, {3, 4}, {4, 4}};
    EXPECT_EQ(reports, expected);
    ASSERT_EQ(banded.texelCount(), once.texelCount());
    // Scissoring discards fragments after shading: the same values.
    EXPECT_EQ(differingPixels(banded, once), 0u);
    // Small images: one pass, no report.
    reports.clear();
    gl.setProgress([&](int done, int total) { reports.emplace_back(done, total); });
    gl.render(s, a, makeView(s, a, 256, 256));
    gl.setProgress(nullptr);
    EXPECT_TRUE(reports.empty());
}

TEST(Progress, CpuReferenceReportsRows) {
    Scene s = sceneFromJson(R"({"meshes": [{"procedural": {"type": "sphere", "segments": 16}}]})");
    SceneAssets a = loadAssets(s);
    View v = makeView(s, a, 64, 48, Aov::Normal);
    Image plain = renderCpu(s, a, v);
    CpuOptions opt;
    std::vector<int> done;
    opt.progress = [&](int d, int total) {
        EXPECT_EQ(total, 48);
        done.push_back(d);
    };
    Image reported = renderCpu(s, a, v, opt);
    // Every 1/16 of the rows (3 of 48): 3, 6, ..., 48, in the order the
    // worker threads got there.
    std::sort(done.begin(), done.end());
    std::vector<int> expected;
    for (int r = 3; r <= 48; r += 3) expected.push_back(r);
    EXPECT_EQ(done, expected);
    EXPECT_EQ(differingPixels(plain, reported), 0u);
}

} // namespace
} // namespace sg::render::test

// The viewer panel's layout and labels without a window: the panel docked
// narrow (at most 300 px and 30% of the window), morph sliders named by the
// glTF target names (mesh.extras.targetNames) or "target N", and the timing
// line that prints a GPU time only when the timer query measured the frame.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/viewer.h"

namespace sg::render::test {
namespace {

namespace fs = std::filesystem;

TEST(ViewerPanel, DockedNarrow) {
    // 960x540 (the window of the report): 288 px, 30%.
    EXPECT_FLOAT_EQ(viewerPanelWidth(960), 288.0f);
    EXPECT_FLOAT_EQ(viewerPanelWidth(1280), 300.0f);
    EXPECT_FLOAT_EQ(viewerPanelWidth(3840), 300.0f);
    EXPECT_FLOAT_EQ(viewerPanelWidth(400), 200.0f); // still usable in a small window
    EXPECT_FLOAT_EQ(viewerPanelWidth(120), 120.0f); // never wider than the window
    for (int w : {640, 800, 960, 1280, 1920})
        EXPECT_LE(viewerPanelWidth(w), std::max(200.0f, 0.3f * float(w)));
}

TEST(ViewerPanel, MorphSlidersNamedByTheTargetNames) {
    const fs::path src = fs::path(SURFGRAD_DATA_DIR) / "gltf/AnimatedMorphSphere/glTF";
    const fs::path dir = fs::path(SURFGRAD_BINARY_DIR) / "tests/render/viewer_panel";
    fs::create_directories(dir);
    nlohmann::json doc;
    std::ifstream(src / "AnimatedMorphSphere.gltf") >> doc;
    for (const auto& b : doc["buffers"]) {
        const std::string uri = b["uri"].get<std::string>();
        fs::copy_file(src / uri, dir / uri, fs::copy_options::overwrite_existing);
    }
    std::ofstream(dir / "plain.gltf") << doc.dump();
    doc["meshes"][0]["extras"]["targetNames"] = {"Ship", "Thin"};
    std::ofstream(dir / "named.gltf") << doc.dump();

    sg::mesh::RenderMesh named = sg::mesh::loadRenderMesh(dir / "named.gltf");
    ASSERT_EQ(named.morphTargets.size(), 2u);
    EXPECT_EQ(morphTargetLabel(named, 0), "Ship");
    EXPECT_EQ(morphTargetLabel(named, 1), "Thin");
    // Without names: "target N", never the mesh name.
    sg::mesh::RenderMesh plain = sg::mesh::loadRenderMesh(dir / "plain.gltf");
    ASSERT_EQ(plain.morphTargets.size(), 2u);
    EXPECT_EQ(morphTargetLabel(plain, 0), "target 0");
    EXPECT_EQ(morphTargetLabel(plain, 1), "target 1");
}

// An adaptive mesh keeps its morph targets on the cage (MeshAsset::
// morphCage), not in the render mesh: the panel still gets one slider per
// cage target, named by the file's targetNames, and setting the weights by
// hand (what the slider does) moves the cage.
TEST(ViewerPanel, AdaptiveCageBlendshapesGetSliders) {
    Scene s = parseScene(R"({"materials": [{"name": "m"}], "meshes": [{"file":
        "examples/data/morph_blob.gltf", "subdivision": {"mode": "adaptive", "isolation": 2}}]})",
                         "test.json", SURFGRAD_SOURCE_DIR);
    SceneAssets a = loadAssets(s);
    ASSERT_TRUE(a.meshes[0].patches);
    EXPECT_TRUE(a.meshes[0].mesh.morphTargets.empty()); // why the cage is asked
    ASSERT_EQ(morphTargetCount(a.meshes[0]), 2u);
    EXPECT_EQ(morphTargetLabel(a.meshes[0], 0), "squash");
    EXPECT_EQ(morphTargetLabel(a.meshes[0], 1), "lobes");
    EXPECT_EQ(morphTargetLabel(a.meshes[0], 5), "target 5");

    applyFrame(s, a, 0.0f);
    const std::vector<glm::vec3> rest = a.meshes[0].cagePositions;
    s.meshes[0].morphKeys.clear();
    s.meshes[0].morphWeights = {1.0f, 0.0f}; // the "squash" slider at 1
    applyFrame(s, a, 0.0f);
    ASSERT_EQ(a.meshes[0].cagePositions.size(), rest.size());
    size_t moved = 0;
    for (size_t v = 0; v < rest.size(); ++v) moved += a.meshes[0].cagePositions[v] != rest[v];
    EXPECT_GT(moved, 0u);
    EXPECT_EQ(a.meshes[0].appliedWeights, s.meshes[0].morphWeights);
}

TEST(ViewerPanel, TimingLinePrintsOnlyAMeasuredGpuTime) {
    RenderStats st;
    st.drawWallMs = 3.25;
    st.drawCalls = 2;
    st.gpuMs = 0.0445;
    st.gpuMeasured = false;
    const std::string off = viewerTimingText(16.7, st);
    EXPECT_EQ(off, "frame 16.7 ms | draw 3.2 ms wall | GPU (timer query) not measured | 2 draws");
    st.gpuMeasured = true;
    st.gpuMs = 2.5;
    EXPECT_EQ(viewerTimingText(16.7, st),
              "frame 16.7 ms | draw 3.2 ms wall | GPU (timer query) 2.50 ms | 2 draws");
}

} // namespace
} // namespace sg::render::test

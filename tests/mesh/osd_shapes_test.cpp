// Every OpenSubdiv regression shape (data/osd-shapes) is either
// processed (refined, and evaluated on the limit surface, finite) or
// rejected with a clear reason; the rejected ones and their reasons are
// listed here and asserted.
#include <gtest/gtest.h>

#include <map>

#include <glm/geometric.hpp>

#include "hardcase.h"
#include "mesh_test_util.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/subdivision.h"

namespace {

using namespace sg::mesh;

// Scheme from the file-name prefix, as OpenSubdiv's regression suite does
// (osd-shapes/README.md); the OBJ text has no scheme tag.
Scheme schemeOf(const std::string& name) {
    if (name.rfind("loop_", 0) == 0) return Scheme::Loop;
    if (name.rfind("bilinear_", 0) == 0) return Scheme::Bilinear;
    return Scheme::Catmark;
}

bool finite(const RenderMesh& m) {
    for (const auto& p : m.positions) {
        if (!std::isfinite(p.x + p.y + p.z)) return false;
    }
    for (const auto& n : m.normals) {
        if (!std::isfinite(n.x + n.y + n.z) || std::abs(glm::length(n) - 1.0f) > 1e-4f)
            return false;
    }
    return true;
}

TEST(OsdShapes, EveryShapeIsProcessedOrRejectedWithAReason) {
    // Rejected shapes: (element fragment, reason fragment).
    const std::map<std::string, std::pair<std::string, std::string>> kRejected = {
#include "osd_shapes_expected.inc"
    };
    size_t processed = 0, rejected = 0;
    for (const auto& entry :
         std::filesystem::directory_iterator(sg::test::dataPath("osd-shapes"))) {
        if (entry.path().extension() != ".obj") continue;
        const std::string name = entry.path().stem().string();
        SCOPED_TRACE(name);
        auto it = kRejected.find(name);
        try {
            PolygonMesh cage = loadPolygonMesh(entry.path());
            SubdivisionSettings s;
            s.options = cage.options;
            if (!(cage.explicitTags & kTagScheme)) s.options.scheme = schemeOf(name);
            for (bool limit : {false, true}) {
                s.level = 2;
                s.limit = limit;
                Subdivider sub(cage, s, entry.path().string());
                EXPECT_TRUE(finite(sub.renderMesh())) << (limit ? "limit" : "refined");
                EXPECT_GT(sub.renderMesh().triangleCount(), 0u);
                if (limit) {
                    for (const auto& d : sub.limitFrame().dPdu)
                        EXPECT_TRUE(std::isfinite(d.x + d.y + d.z));
                }
            }
            EXPECT_TRUE(it == kRejected.end()) << "expected a rejection: " << it->second.second;
            ++processed;
        } catch (const sg::io::InputError& e) {
            ++rejected;
            if (it == kRejected.end()) {
                ADD_FAILURE() << "unexpected rejection: " << e.what();
                continue;
            }
            EXPECT_EQ(e.file(), entry.path().string());
            EXPECT_NE(e.element().find(it->second.first), std::string::npos) << e.what();
            EXPECT_NE(e.reason().find(it->second.second), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(processed + rejected, 61u); // every file of the folder was seen
    EXPECT_EQ(rejected, kRejected.size());
}

TEST(OsdShapes, RepairDropsDegenerateFacesButNotNonManifoldTopology) {
    // After --repair drops the faces that use a vertex twice, the
    // non-manifold edges these shapes exist for are what is left: no honest
    // fix, still an error, named.
    for (const char* name : {"catmark_nonman_edges", "loop_nonman_edges"}) {
        SCOPED_TRACE(name);
        LoadOptions o;
        o.repair = true;
        LoadReport report;
        sg::test::expectInputError(
            [&] {
                loadPolygonMesh(sg::test::dataPath(std::string("osd-shapes/") + name + ".obj"), o,
                                &report);
            },
            "edge (", "non-manifold edge");
        EXPECT_GT(report.degenerateFacesDropped, 0u);
    }
    sg::test::reportHardCaseHolds(
        "non-manifold", "OpenSubdiv's catmark_nonman_edges and loop_nonman_edges, repair on",
        "loading", "InputError naming a non-manifold edge",
        "InputError naming a non-manifold edge");
}

} // namespace

// Fuzz entry point: glTF/GLB input (sg::mesh::parseGltf: tinygltf plus our
// accessor, index, node-graph and GLB-container checks), then the welding
// into a cage and validation. In-memory input: external files are refused.
// Documented errors (InputError) are expected; anything else is a bug.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace sg::mesh;
    InputLimits limits;
    limits.maxVertices = 1 << 16;
    limits.maxCorners = 1 << 18;
    limits.maxFileBytes = 1 << 20;
    try {
        Scene scene = parseGltf(std::string_view(reinterpret_cast<const char*>(data), size),
                                "fuzz.gltf", {}, limits);
        for (const SceneInstance& inst : scene.instances) {
            const RenderMesh& m = inst.mesh;
            for (uint32_t i : m.indices) {
                if (i >= m.vertexCount()) std::abort(); // the reader checks every index
            }
            for (const auto& p : m.positions) {
                if (!std::isfinite(p.x + p.y + p.z)) std::abort();
            }
            for (const auto& set : m.uvSets) {
                if (set.size() != m.vertexCount()) std::abort();
            }
            for (const auto& t : m.morphTargets) {
                if (!t.positionDeltas.empty() && t.positionDeltas.size() != m.vertexCount())
                    std::abort();
            }
            PolygonMesh cage = toPolygonMesh(m);
            validate(cage, "fuzz.gltf", true, nullptr, limits);
        }
        for (const MorphWeightAnimation& a : scene.animations) {
            std::vector<float> w = sampleWeights(a, 0.5f * (a.times.front() + a.times.back()));
            if (w.size() != a.targetCount) std::abort();
        }
    } catch (const sg::io::InputError&) {
    }
    return 0;
}

// Helpers shared by the adaptive-patch tests of the bump module
// (patch_basis_test.cpp, patch_uv_test.cpp, patch_tangent_test.cpp): the
// data directory, and a patch's position, UV set and their derivatives at
// a point of its square, evaluated from sg::mesh::AdaptivePatches with the
// shared basis (shaders/sg/patch/basis.glsl compiled as C++) exactly as the
// tessellation evaluation stage sums them.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "surfgrad/adaptive_patches.h"
#include "surfgrad/patch_basis.h"

namespace sg::test {

// `rel` under the test data directory (SURFGRAD_DATA_DIR from the
// environment, else the build's).
inline std::filesystem::path patchDataPath(const std::string& rel) {
    const char* env = std::getenv("SURFGRAD_DATA_DIR");
    return (env && *env ? std::filesystem::path(env) : std::filesystem::path(SURFGRAD_DATA_DIR)) /
           rel;
}

// Patch index -> index of its array in ap.arrays.
inline std::vector<uint32_t> patchArrayOf(const sg::mesh::AdaptivePatches& ap) {
    std::vector<uint32_t> out(ap.patchCount(), 0);
    for (size_t a = 0; a < ap.arrays.size(); ++a)
        for (uint32_t k = 0; k < ap.arrays[a].patchCount; ++k)
            out[ap.arrays[a].firstPatch + k] = uint32_t(a);
    return out;
}

// Position and its derivatives with respect to the ptex face's (u,v).
struct PatchSample {
    glm::vec3 pos{0.0f}, du{0.0f}, dv{0.0f};
};

// Patch `p` (global index, in array `arr`) at `patchUv` in its square.
inline PatchSample evalPatchSample(const sg::mesh::AdaptivePatches& ap,
                                   const sg::mesh::AdaptivePatchArray& arr, uint32_t p,
                                   glm::vec2 patchUv) {
    const uint32_t f1 = ap.params[p].y;
    const sg::glsl::SgPatchBasis b =
        sg::glsl::sgPatchBasis(arr.type, f1, sg::glsl::sgPatchUnnormalizeUv(f1, patchUv));
    const uint32_t* idx =
        &ap.indices[arr.firstIndex + (p - arr.firstPatch) * uint32_t(arr.pointsPerPatch)];
    PatchSample s;
    for (int i = 0; i < b.count; ++i) {
        s.pos += b.point.v[i] * ap.points[idx[i]];
        s.du += b.du.v[i] * ap.points[idx[i]];
        s.dv += b.dv.v[i] * ap.points[idx[i]];
    }
    return s;
}

// UV set `set` and its derivatives with respect to the ptex face's (u,v).
struct PatchUvSample {
    glm::vec2 st{0.0f}, du{0.0f}, dv{0.0f};
};

// UV set `set` of patch `p` at `patchUv` of the POSITION patch's square
// (the evaluation stage's patchUv, through the ptex face's (u,v)).
inline PatchUvSample evalPatchUvSample(const sg::mesh::AdaptivePatches& ap, size_t set, uint32_t p,
                                       glm::vec2 patchUv) {
    const sg::mesh::AdaptiveUvSet& uvs = ap.uvSets[set];
    const glm::vec2 faceUv = sg::glsl::sgPatchUnnormalizeUv(ap.params[p].y, patchUv);
    const sg::glsl::SgPatchBasis b =
        sg::glsl::sgPatchBasis(int(uvs.types[p]), uvs.field1[p], faceUv);
    const uint32_t* idx = &uvs.indices[size_t(p) * sg::mesh::AdaptiveUvSet::kUvValuesPerPatch];
    PatchUvSample s;
    for (int i = 0; i < b.count; ++i) {
        s.st += b.point.v[i] * uvs.values[idx[i]];
        s.du += b.du.v[i] * uvs.values[idx[i]];
        s.dv += b.dv.v[i] * uvs.values[idx[i]];
    }
    return s;
}

} // namespace sg::test

// Helpers shared by the adaptive-patch tests of the bump module
// (patch_basis_test.cpp, patch_uv_test.cpp, patch_tangent_test.cpp): the
// data directory, and a patch's position, UV set and their derivatives at
// a point of its square, evaluated from sg::mesh::AdaptivePatches with the
// shared basis (shaders/sg/patch/basis.glsl compiled as C++) exactly as the
// tessellation evaluation stage sums them; and the search for the uniform
// refinement's vertices at patch points (points sorted by x, the patch
// grid of a level, a cage's extent for tolerances).
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/bump/patch_basis.h"

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

// A value and its derivatives with respect to the ptex face's (u,v).
template <class T>
struct PatchValue {
    T value{0.0f}, du{0.0f}, dv{0.0f};
};

// The basis `b` applied to values[idx[i]], summed in i order as the
// evaluation stage sums them.
template <class T>
PatchValue<T> applyBasis(const sg::glsl::SgPatchBasis& b, const uint32_t* idx,
                         const std::vector<T>& values) {
    PatchValue<T> s;
    for (int i = 0; i < b.count; ++i) {
        s.value += b.pos.v[i] * values[idx[i]];
        s.du += b.du.v[i] * values[idx[i]];
        s.dv += b.dv.v[i] * values[idx[i]];
    }
    return s;
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
    const PatchValue<glm::vec3> v = applyBasis(b, idx, ap.points);
    return {v.value, v.du, v.dv};
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
    const PatchValue<glm::vec2> v = applyBasis(b, idx, uvs.values);
    return {v.value, v.du, v.dv};
}

// Largest coordinate magnitude of `positions` (a cage's extent, for
// tolerances relative to its size).
inline float maxAbsCoordinate(const std::vector<glm::vec3>& positions) {
    float extent = 0.0f;
    for (const glm::vec3& p : positions) extent = std::max(extent, sg::glsl::sgMaxAbs3(p));
    return extent;
}

// Points sorted by x, to visit the candidates near a query point.
class PointsByX {
public:
    explicit PointsByX(const std::vector<glm::vec3>& positions)
        : pos_(positions), order_(positions.size()) {
        for (uint32_t i = 0; i < order_.size(); ++i) order_[i] = i;
        std::sort(order_.begin(), order_.end(),
                  [&](uint32_t a, uint32_t b) { return pos_[a].x < pos_[b].x; });
    }
    // fn(index) for every point whose x is within `tol` of q.x (a superset
    // of the points within tol of q: the caller measures the distance).
    template <class F>
    void forEachNear(glm::vec3 q, float tol, F fn) const {
        auto it = std::lower_bound(order_.begin(), order_.end(), q.x - tol,
                                   [&](uint32_t v, float x) { return pos_[v].x < x; });
        for (; it != order_.end() && pos_[*it].x <= q.x + tol; ++it) fn(*it);
    }

private:
    const std::vector<glm::vec3>& pos_;
    std::vector<uint32_t> order_;
};

// fn(patch, patchUv) at the (2^(level - depth) + 1)^2 grid points of every
// patch of depth <= level: the patch points that are vertices of the
// uniform level-`level` refinement (one corner grid for deeper patches).
template <class F>
void forEachLevelGridPoint(const sg::mesh::AdaptivePatches& ap, int level, F fn) {
    for (uint32_t p = 0; p < ap.patchCount(); ++p) {
        const int steps = 1 << std::max(level - sg::glsl::sgPatchDepth(ap.params[p].y), 0);
        for (int j = 0; j <= steps; ++j)
            for (int i = 0; i <= steps; ++i)
                fn(p, glm::vec2(float(i) / float(steps), float(j) / float(steps)));
    }
}

} // namespace sg::test

// The bake's view of the limit surface: OpenSubdiv's feature-adaptive patch
// table evaluated with the shared bases (shaders/sg/patch/basis.glsl;
// Niessner, Loop, Meyer & DeRose 2012; Loop et al. 2009), and Newton's
// method on one patch's face-varying UV map. See limit_patches.h.
#include "limit_patches.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "surfgrad/bump/patch_basis.h"

namespace sg::bake::detail {

namespace G = sg::glsl;

LimitPatches::LimitPatches(const mesh::PolygonMesh& cage, int isolation, int uvSet,
                           const std::string& file, int threads)
    : ap_(mesh::buildAdaptivePatches(cage, cage.options, isolation, file, threads)), uvSet_(uvSet) {
    arrayOf_.resize(ap_.patchCount());
    for (uint32_t a = 0; a < ap_.arrays.size(); ++a) {
        const mesh::AdaptivePatchArray& arr = ap_.arrays[a];
        std::fill_n(arrayOf_.begin() + arr.firstPatch, arr.patchCount, a);
    }
}

glm::vec2 LimitPatches::st(uint32_t p, glm::vec2 patchUv) const {
    const mesh::AdaptiveUvSet& set = ap_.uvSets[size_t(uvSet_)];
    const glm::vec2 faceUv = G::sgPatchUnnormalizeUv(ap_.params[p].y, patchUv);
    const G::SgPatchBasis b = G::sgPatchBasis(int(set.types[p]), set.field1[p], faceUv);
    const uint32_t* idx = &set.indices[size_t(p) * mesh::AdaptiveUvSet::kUvValuesPerPatch];
    glm::vec2 s(0.0f);
    for (int i = 0; i < b.count; ++i) s += b.pos.v[i] * set.values[idx[i]];
    return s;
}

SurfaceSample LimitPatches::sample(uint32_t p, glm::vec2 patchUv) const {
    SurfaceSample out;
    const mesh::AdaptivePatchArray& arr = ap_.arrays[arrayOf_[p]];
    const uint32_t f1 = ap_.params[p].y;
    const glm::vec2 faceUv = G::sgPatchUnnormalizeUv(f1, patchUv);
    const G::SgPatchBasis b = G::sgPatchBasis(arr.type, f1, faceUv);
    const uint32_t* idx =
        &ap_.indices[arr.firstIndex + (p - arr.firstPatch) * uint32_t(arr.pointsPerPatch)];
    for (int i = 0; i < b.count; ++i) {
        const glm::vec3 c = ap_.points[idx[i]];
        out.pos += b.pos.v[i] * c;
        out.dPdu += b.du.v[i] * c;
        out.dPdv += b.dv.v[i] * c;
    }
    const mesh::AdaptiveUvSet& set = ap_.uvSets[size_t(uvSet_)];
    const G::SgPatchBasis ub = G::sgPatchBasis(int(set.types[p]), set.field1[p], faceUv);
    const uint32_t* uidx = &set.indices[size_t(p) * mesh::AdaptiveUvSet::kUvValuesPerPatch];
    for (int i = 0; i < ub.count; ++i) {
        const glm::vec2 x = set.values[uidx[i]];
        out.st += ub.pos.v[i] * x;
        out.dSTdu += ub.du.v[i] * x;
        out.dSTdv += ub.dv.v[i] * x;
    }
    return out;
}

SurfaceSample LimitPatches::invertUv(uint32_t p, glm::vec2 target, glm::vec2 start,
                                     float& residual) const {
    // sgPatchBasis returns the derivatives with respect to the patch's own
    // square times 2^depth (its ptex-face scale): a step solved in those
    // units is 2^depth times longer in the patch's square.
    const float toPatch = float(1 << G::sgPatchDepth(ap_.params[p].y));
    glm::vec2 uv = glm::clamp(start, glm::vec2(0.0f), glm::vec2(1.0f));
    SurfaceSample s = sample(p, uv);
    glm::vec2 err = target - s.st;
    // Converged: the UV is within rounding of the chart's own scale.
    const float stScale = std::max({std::abs(target.x), std::abs(target.y), 1.0f});
    const float tol = 1e-7f * stScale;
    for (int k = 0; k < kNewtonSteps && std::max(std::abs(err.x), std::abs(err.y)) > tol; ++k) {
        const glm::vec2 du = s.dSTdu, dv = s.dSTdv;
        const float det = du.x * dv.y - dv.x * du.y;
        const float size = std::max(glm::dot(du, du), glm::dot(dv, dv));
        if (!(std::abs(det) > 1e-6f * size)) break; // singular chart: keep the iterate
        const glm::vec2 stepFace((dv.y * err.x - dv.x * err.y) / det,
                                 (du.x * err.y - du.y * err.x) / det);
        uv = glm::clamp(uv + stepFace * toPatch, glm::vec2(0.0f), glm::vec2(1.0f));
        s = sample(p, uv);
        err = target - s.st;
    }
    residual = glm::length(err);
    return s;
}

} // namespace sg::bake::detail

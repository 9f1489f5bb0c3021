// Blendshapes (surfgrad/mesh/morph.h): glTF 2.0 sec. 3.7.2.2, P = P0 + sum w_i dP_i,
// applied to a cage or to a refined/limit mesh; normals recomputed (from
// the geometry or from the blended limit derivatives) or blended.
#include "surfgrad/mesh/morph.h"

#include <cmath>

#include "mesh_internal.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/mesh/subdivision.h"

namespace sg::mesh {

void morphCagePositions(const PolygonMesh& cage, std::span<const float> weights,
                        std::vector<glm::vec3>& out) {
    SG_EXPECTS(weights.size() == cage.morphTargets.size(), "one weight per morph target");
    out.assign(cage.positions.begin(), cage.positions.end());
    for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
        const float w = weights[t];
        SG_EXPECTS(std::isfinite(w), "morph weights are finite");
        if (w == 0.0f) continue;
        const glm::vec3* d = cage.morphTargets[t].positionDeltas.data();
        for (size_t v = 0; v < out.size(); ++v) out[v] += w * d[v];
    }
}

Morpher::Morpher(const RenderMesh& base, const LimitFrame* baseFrame)
    : base_(&base), baseFrame_(baseFrame) {
    // Smooth groups: render vertices that coincide in the base mesh and in
    // every target (exact comparison), i.e. copies split at UV seams.
    smoothGroup_ = detail::coincidentVertexGroups(base);
}

namespace {

// out = base + sum_t w_t * deltas[t] (targets with an empty array skipped).
void blend(const std::vector<glm::vec3>& base, std::span<const float> weights,
           const std::vector<const std::vector<glm::vec3>*>& deltas, std::vector<glm::vec3>& out) {
    out.resize(base.size());
    std::copy(base.begin(), base.end(), out.begin());
    for (size_t t = 0; t < deltas.size(); ++t) {
        const float w = weights[t];
        if (w == 0.0f || !deltas[t] || deltas[t]->empty()) continue;
        const glm::vec3* d = deltas[t]->data();
        glm::vec3* o = out.data();
        for (size_t v = 0; v < out.size(); ++v) o[v] += w * d[v];
    }
}

glm::vec3 unitOr(const glm::vec3& v, const glm::vec3& fallback) {
    float len = glm::length(v);
    return len > 0.0f && std::isfinite(len) ? v / len : fallback;
}

} // namespace

void Morpher::apply(std::span<const float> weights, MorphNormals normals, RenderMesh& out,
                    LimitFrame* outFrame) const {
    const RenderMesh& base = *base_;
    SG_EXPECTS(weights.size() == base.morphTargets.size(), "one weight per morph target");
    for (float w : weights) SG_EXPECTS(std::isfinite(w), "morph weights are finite");
    if (out.positions.size() != base.positions.size() || out.indices.size() != base.indices.size())
        out = base;
    const size_t T = base.morphTargets.size();
    std::vector<const std::vector<glm::vec3>*> dP(T), dN(T), dT(T);
    for (size_t t = 0; t < T; ++t) {
        dP[t] = &base.morphTargets[t].positionDeltas;
        dN[t] = &base.morphTargets[t].normalDeltas;
        dT[t] = &base.morphTargets[t].tangentDeltas;
    }
    blend(base.positions, weights, dP, out.positions);

    const bool limit = baseFrame_ && !baseFrame_->empty();
    std::vector<glm::vec3>* du = nullptr;
    std::vector<glm::vec3>* dv = nullptr;
    if (limit) {
        if (outFrame) {
            if (outFrame->dPdu.size() != baseFrame_->dPdu.size()) *outFrame = *baseFrame_;
            du = &outFrame->dPdu;
            dv = &outFrame->dPdv;
        } else {
            du = &scratchU_;
            dv = &scratchV_;
        }
        std::vector<const std::vector<glm::vec3>*> tu(T, nullptr), tv(T, nullptr);
        for (size_t t = 0; t < T && t < baseFrame_->morphDPdu.size(); ++t) {
            tu[t] = &baseFrame_->morphDPdu[t];
            tv[t] = &baseFrame_->morphDPdv[t];
        }
        blend(baseFrame_->dPdu, weights, tu, *du);
        blend(baseFrame_->dPdv, weights, tv, *dv);
    }
    const size_t n = out.positions.size();
    if (normals == MorphNormals::Blend && !base.normals.empty()) {
        blend(base.normals, weights, dN, out.normals);
        bool vanished = false;
        for (size_t v = 0; v < n; ++v) {
            float len = glm::length(out.normals[v]);
            if (len > 0.0f && std::isfinite(len))
                out.normals[v] /= len;
            else {
                out.normals[v] = glm::vec3(0.0f);
                vanished = true;
            }
        }
        if (vanished) {
            RenderMesh tmp;
            tmp.positions = out.positions;
            tmp.indices = out.indices;
            computeVertexNormals(tmp, smoothGroup_);
            for (size_t v = 0; v < n; ++v) {
                if (out.normals[v] == glm::vec3(0.0f)) out.normals[v] = tmp.normals[v];
            }
        }
        if (!base.tangents.empty()) {
            out.tangents.resize(n);
            std::vector<glm::vec3> xyz(n);
            for (size_t v = 0; v < n; ++v) xyz[v] = glm::vec3(base.tangents[v]);
            std::vector<glm::vec3> blended;
            blend(xyz, weights, dT, blended);
            for (size_t v = 0; v < n; ++v)
                out.tangents[v] = glm::vec4(unitOr(blended[v], xyz[v]), base.tangents[v].w);
        }
        return;
    }
    // Recompute.
    if (limit) {
        out.normals.resize(n);
        for (size_t v = 0; v < n; ++v) {
            glm::vec3 nrm = glm::cross((*du)[v], (*dv)[v]);
            out.normals[v] =
                unitOr(nrm, base.normals.empty() ? glm::vec3(0.0f, 0.0f, 1.0f) : base.normals[v]);
        }
    } else {
        computeVertexNormals(out, smoothGroup_);
    }
    // Tangents of the base geometry do not fit the new one.
    out.tangents.clear();
}

} // namespace sg::mesh

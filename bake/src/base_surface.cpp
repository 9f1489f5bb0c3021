// The two surfaces a bake measures from (base_surface.h): the limit surface
// (adaptive patches and the limit frame, sg/patch/limit_tangent.glsl) and a
// uniformly refined triangle mesh with MikkTSpace frames (Mikkelsen 2008,
// as mesh/src/mikktspace.cpp implements it).
#include "base_surface.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "surfgrad/base/io.h"
#include "surfgrad/bump/patch_basis.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::bake::detail {

namespace {

namespace G = sg::glsl;

float texelLengthOf(float areaP, float areaSt, glm::vec2 texelsPerUv) {
    const float texel = std::max(texelsPerUv.x, texelsPerUv.y);
    return areaSt > 0.0f ? std::sqrt(areaP / areaSt) / texel : 0.0f;
}

class LimitBase final : public BaseSurface {
public:
    LimitBase(const mesh::PolygonMesh& cage, int isolation, int uvSet, const std::string& file,
              int threads, glm::vec2 texelsPerUv)
        : patches_(cage, isolation, uvSet, file, threads), texelsPerUv_(texelsPerUv) {}

    UvCover cover(int width, int height) const override {
        return coverTexels(patches_, width, height);
    }
    size_t primitiveCount() const override { return patches_.patchCount(); }

    BaseSample at(uint32_t prim, glm::vec2 estimate, glm::vec2 target) const override {
        BaseSample b;
        float residual = 0.0f;
        const SurfaceSample s = patches_.invertUv(prim, target, estimate, residual);
        b.pos = s.pos;
        b.normal = G::sgSafeNormalize(glm::cross(s.dPdu, s.dPdv), glm::vec3(0.0f, 0.0f, 1.0f));
        int resolved = 0;
        b.tangent = G::sgPatchLimitTangent(s.dPdu, s.dPdv, s.dSTdu, s.dSTdv, b.normal, resolved);
        b.texelLength =
            texelLengthOf(glm::length(glm::cross(s.dPdu, s.dPdv)),
                          std::abs(s.dSTdu.x * s.dSTdv.y - s.dSTdv.x * s.dSTdu.y), texelsPerUv_);
        b.residualTexels = residual * std::max(texelsPerUv_.x, texelsPerUv_.y);
        return b;
    }

private:
    LimitPatches patches_;
    glm::vec2 texelsPerUv_;
};

class TriangleBase final : public BaseSurface {
public:
    TriangleBase(const mesh::PolygonMesh& cage, int level, int uvSet, const std::string& file,
                 int threads, glm::vec2 texelsPerUv)
        : uvSet_(uvSet), texelsPerUv_(texelsPerUv) {
        mesh::SubdivisionSettings s;
        s.level = level;
        s.options = cage.options;
        s.threads = threads;
        mesh_ = mesh::Subdivider(cage, s, file).renderMesh();
        const std::string why =
            mesh::tangentInputProblem(mesh_, mesh::TangentMethod::MikkTSpace, uvSet);
        if (!why.empty()) throw io::InputError(file, "level " + std::to_string(level), why);
        mesh::generateMikkTSpaceTangents(mesh_, uvSet, threads);
    }

    UvCover cover(int width, int height) const override {
        return coverTriangles(mesh_, uvSet_, width, height);
    }
    size_t primitiveCount() const override { return mesh_.triangleCount(); }

    // Linear interpolation over the triangle (barycentrics exact from the
    // rasteriser): the normal normalised for the ray, the tangent
    // interpolated and not normalised (Mikkelsen 2019, section 2.2: the
    // mikktspace basis uses the interpolated vectors; sgMikktsBasis).
    BaseSample at(uint32_t prim, glm::vec2 estimate, glm::vec2) const override {
        const uint32_t* v = &mesh_.indices[size_t(prim) * 3];
        const float w[3] = {1.0f - estimate.x - estimate.y, estimate.x, estimate.y};
        BaseSample b;
        glm::vec3 n(0.0f), t(0.0f);
        b.pos = glm::vec3(0.0f);
        for (int k = 0; k < 3; ++k) {
            b.pos += w[k] * mesh_.positions[v[k]];
            n += w[k] * mesh_.normals[v[k]];
            t += w[k] * glm::vec3(mesh_.tangents[v[k]]);
        }
        b.normal = G::sgSafeNormalize(n, glm::vec3(0.0f, 0.0f, 1.0f));
        b.tangent = glm::vec4(t, mesh_.tangents[v[0]].w);
        const std::vector<glm::vec2>& uv = mesh_.uvSets[size_t(uvSet_)];
        const glm::vec2 e1 = uv[v[1]] - uv[v[0]], e2 = uv[v[2]] - uv[v[0]];
        const glm::vec3 p0 = mesh_.positions[v[0]];
        b.texelLength = texelLengthOf(
            glm::length(glm::cross(mesh_.positions[v[1]] - p0, mesh_.positions[v[2]] - p0)),
            std::abs(e1.x * e2.y - e1.y * e2.x), texelsPerUv_);
        return b;
    }

private:
    mesh::RenderMesh mesh_;
    int uvSet_;
    glm::vec2 texelsPerUv_;
};

} // namespace

std::unique_ptr<BaseSurface> limitBase(const mesh::PolygonMesh& cage, int isolation, int uvSet,
                                       const std::string& file, int threads,
                                       glm::vec2 texelsPerUv) {
    return std::make_unique<LimitBase>(cage, isolation, uvSet, file, threads, texelsPerUv);
}

std::unique_ptr<BaseSurface> triangleBase(const mesh::PolygonMesh& cage, int level, int uvSet,
                                          const std::string& file, int threads,
                                          glm::vec2 texelsPerUv) {
    return std::make_unique<TriangleBase>(cage, level, uvSet, file, threads, texelsPerUv);
}

} // namespace sg::bake::detail

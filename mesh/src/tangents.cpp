// Tangent frames on RenderMesh: method names, MikkTSpace applied to a
// RenderMesh (vertex splitting where corners disagree), and the exact
// tangent frame of a parametric (limit) surface carrying UVs, by the chain
// rule through the UV Jacobian (see surfgrad/mesh/tangents.h for the contracts;
// docs/tangents.md for the derivation).
#include "surfgrad/mesh/tangents.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include <glm/geometric.hpp>

#include "surfgrad/base/contract.h"
#include "surfgrad/base/threads.h"

namespace sg::mesh {

std::string_view tangentMethodName(TangentMethod method) {
    switch (method) {
    case TangentMethod::MikkTSpace:
        return "mikktspace";
    case TangentMethod::Limit:
        return "limit";
    case TangentMethod::Pixel:
        return "pixel";
    }
    return "unknown";
}

std::optional<TangentMethod> parseTangentMethod(std::string_view name) {
    for (TangentMethod m : {TangentMethod::MikkTSpace, TangentMethod::Limit, TangentMethod::Pixel})
        if (tangentMethodName(m) == name) return m;
    return std::nullopt;
}

namespace {

constexpr uint32_t kNoVariant = std::numeric_limits<uint32_t>::max();

bool sameBits(const glm::vec4& a, const glm::vec4& b) {
    return std::memcmp(&a, &b, sizeof a) == 0;
}

template <typename T>
void duplicateEntry(std::vector<T>& values, uint32_t from) {
    if (!values.empty()) values.push_back(values[from]);
}

} // namespace

size_t applyCornerTangents(RenderMesh& mesh, int uvSet, std::span<const glm::vec4> cornerTangents) {
    SG_EXPECTS(cornerTangents.size() == mesh.indices.size(), "one tangent per mesh corner");
    const size_t vertexCount = mesh.vertexCount();
    for (const uint32_t v : mesh.indices) SG_EXPECTS(v < vertexCount, "mesh indices in range");
    // Each vertex keeps a chain of the distinct tangents its corners got;
    // the first stays in the vertex, each further one becomes a copy.
    struct Variant {
        glm::vec4 tangent;
        uint32_t vertex;
        uint32_t next;
    };
    std::vector<uint32_t> head(vertexCount, kNoVariant);
    std::vector<Variant> variants;
    variants.reserve(vertexCount);
    const glm::vec4 unused(kMikkTSpaceDefaultFrame.tangent, kMikkTSpaceDefaultFrame.sign);
    mesh.tangents.assign(vertexCount, unused);
    size_t added = 0;
    for (size_t c = 0; c < mesh.indices.size(); ++c) {
        const uint32_t v = mesh.indices[c];
        const glm::vec4& t = cornerTangents[c];
        uint32_t* link = &head[v];
        while (*link != kNoVariant && !sameBits(variants[*link].tangent, t))
            link = &variants[*link].next;
        if (*link != kNoVariant) {
            mesh.indices[c] = variants[*link].vertex;
            continue;
        }
        uint32_t target = v;
        if (head[v] != kNoVariant) { // v already holds another tangent: copy it
            target = uint32_t(mesh.positions.size());
            mesh.positions.push_back(mesh.positions[v]);
            duplicateEntry(mesh.normals, v);
            for (auto& set : mesh.uvSets) duplicateEntry(set, v);
            for (auto& morph : mesh.morphTargets) {
                duplicateEntry(morph.positionDeltas, v);
                duplicateEntry(morph.normalDeltas, v);
                duplicateEntry(morph.tangentDeltas, v);
            }
            mesh.tangents.push_back(t);
            ++added;
        } else {
            mesh.tangents[v] = t;
        }
        *link = uint32_t(variants.size());
        variants.push_back({t, target, kNoVariant});
        mesh.indices[c] = target;
    }
    mesh.tangentUvSet = uvSet;
    return added;
}

namespace {

MikkTSpaceInput mikktspaceInputOf(const RenderMesh& mesh, int uvSet) {
    MikkTSpaceInput input;
    input.positions = mesh.positions;
    input.normals = mesh.normals;
    input.uvs = mesh.uvSets[size_t(uvSet)];
    input.cornerVertices = mesh.indices;
    return input;
}

std::string uvSetProblem(const RenderMesh& mesh, int uvSet) {
    if (uvSet >= 0 && size_t(uvSet) < mesh.uvSets.size()) return {};
    return "UV set " + std::to_string(uvSet) + " does not exist (mesh '" + mesh.name + "' has " +
           std::to_string(mesh.uvSets.size()) + ")";
}

std::string limitFrameProblem(const RenderMesh& mesh, const LimitFrame& frame, int uvSet) {
    const size_t n = mesh.vertexCount();
    if (frame.dPdu.size() != n || frame.dPdv.size() != n || frame.dUVdu.size() <= size_t(uvSet) ||
        frame.dUVdv.size() <= size_t(uvSet) || frame.dUVdu[size_t(uvSet)].size() != n ||
        frame.dUVdv[size_t(uvSet)].size() != n)
        return "limit frame does not match mesh '" + mesh.name + "' (" + std::to_string(n) +
               " vertices, " + std::to_string(frame.dPdu.size()) + " limit derivatives)";
    return {};
}

} // namespace

std::string tangentInputProblem(const RenderMesh& mesh, TangentMethod method, int uvSet,
                                const LimitFrame* frame) {
    switch (method) {
    case TangentMethod::MikkTSpace:
        if (mesh.normals.size() != mesh.positions.size())
            return "MikkTSpace needs vertex normals (mesh '" + mesh.name + "' has " +
                   std::to_string(mesh.normals.size()) + " for " +
                   std::to_string(mesh.positions.size()) + " vertices)";
        if (std::string why = uvSetProblem(mesh, uvSet); !why.empty()) return why;
        return mikktspaceInputProblem(mikktspaceInputOf(mesh, uvSet));
    case TangentMethod::Limit:
        if (!frame || frame->empty())
            return "limit tangents need the subdivider's limit frame (subdivide with limit "
                   "evaluation first)";
        if (std::string why = uvSetProblem(mesh, uvSet); !why.empty()) return why;
        return limitFrameProblem(mesh, *frame, uvSet);
    case TangentMethod::Pixel:
        return {};
    }
    return {};
}

size_t uvAreaWithinRounding(const RenderMesh& mesh, int uvSet) {
    SG_EXPECTS(uvSet >= 0 && size_t(uvSet) < mesh.uvSets.size(), "uvSet indexes mesh.uvSets");
    const std::vector<glm::vec2>& uv = mesh.uvSets[size_t(uvSet)];
    size_t count = 0;
    for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const uint32_t a = mesh.indices[i], b = mesh.indices[i + 1], c = mesh.indices[i + 2];
        if (a >= uv.size() || b >= uv.size() || c >= uv.size()) continue;
        const glm::dvec2 t0(uv[a]), t1(uv[b]), t2(uv[c]);
        const glm::dvec2 e1 = t1 - t0, e2 = t2 - t0, e3 = t2 - t1;
        const double area2 = std::fabs(e1.x * e2.y - e1.y * e2.x);
        const double m = std::max({std::fabs(t0.x), std::fabs(t0.y), std::fabs(t1.x),
                                   std::fabs(t1.y), std::fabs(t2.x), std::fabs(t2.y)});
        const double l =
            std::sqrt(std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)}));
        // 16 ulps (2^-23 relative) of the coordinates, over the longest edge.
        count += area2 <= 16.0 * std::ldexp(1.0, -23) * m * l;
    }
    return count;
}

void generateMikkTSpaceTangents(RenderMesh& mesh, int uvSet, int threads) {
    SG_EXPECTS(mesh.normals.size() == mesh.positions.size(), "the mesh has vertex normals");
    SG_EXPECTS(uvSetProblem(mesh, uvSet).empty(), "uvSet indexes mesh.uvSets");
    const MikkTSpaceInput input = mikktspaceInputOf(mesh, uvSet);
    std::vector<glm::vec4> cornerTangents;
    MikkTSpaceGenerator generator;
    generator.setThreads(threads);
    generator.generate(input, cornerTangents);
    applyCornerTangents(mesh, uvSet, cornerTangents);
}

// ---------------------------------------------------------------------------
// Limit-surface tangents
// ---------------------------------------------------------------------------

namespace {

// A frame point is regular when its charts are well conditioned relative
// to their size: |det J| > kMinRelDet max(|dST/du|, |dST/dv|)^2 in UV
// space, |dP/du x dP/dv| > kMinRelDet max(|dP/du|, |dP/dv|)^2 on the surface
// (for derivatives of equal length: the sine of their angle). The chain
// rule divides by those determinants: with float inputs (relative error
// ~1e-7 of the longer derivative) the result is then good to ~1e-4 rad.
// Below, the ratio is dominated by rounding: at smooth boundary corners of
// a Catmull-Clark surface, where the limit parameterization collapses, and
// on charts where one derivative is rounding noise (the side walls of a
// planar UV projection, dST/dv ~ 1e-7 |st|). Relative to the longer
// derivative, not to the product of both lengths (the sine of their angle),
// because a noise derivative has a random direction: its sine is anything,
// its length says it is noise (shaders/sg/patch/limit_tangent.glsl uses the
// same rule).
constexpr double kMinRelDet = 1e-3;

glm::dvec3 unitOrZero(const glm::dvec3& v) {
    const double len = glm::length(v);
    return len > 0.0 && std::isfinite(len) ? v / len : glm::dvec3(0.0);
}

// v minus its component along unit n, normalized; zero if nothing is left
// beyond the rounding of v itself.
glm::dvec3 tangentPart(const glm::dvec3& v, const glm::dvec3& n) {
    const glm::dvec3 t = v - glm::dot(v, n) * n;
    if (!(glm::length(t) > 1e-6 * glm::length(v))) return glm::dvec3(0.0);
    return unitOrZero(t);
}

} // namespace

glm::vec4 limitTangent(const glm::vec3& dPduF, const glm::vec3& dPdvF, const glm::vec2& dSTdu,
                       const glm::vec2& dSTdv, LimitTangentCase* resolved) {
    const glm::dvec3 dPdu(dPduF), dPdv(dPdvF);
    // J = [[ds/du ds/dv], [dt/du dt/dv]].
    const double a = dSTdu.x, b = dSTdv.x, c = dSTdu.y, d = dSTdv.y;
    const double det = a * d - b * c;
    const double kJ2 = std::max(a * a + c * c, b * b + d * d);
    const bool uvRegular =
        std::isfinite(det) && kJ2 > 0.0 && std::isfinite(kJ2) && std::fabs(det) > kMinRelDet * kJ2;
    const glm::dvec3 cross = glm::cross(dPdu, dPdv);
    const double crossLen = glm::length(cross);
    const double kP2 = std::max(glm::dot(dPdu, dPdu), glm::dot(dPdv, dPdv));
    const bool surfaceRegular =
        std::isfinite(crossLen) && kP2 > 0.0 && std::isfinite(kP2) && crossLen > kMinRelDet * kP2;
    const double w = uvRegular ? (det > 0.0 ? 1.0 : -1.0) : 1.0;
    const glm::dvec3 dPds = uvRegular ? (d * dPdu - c * dPdv) / det : glm::dvec3(0.0);

    glm::dvec3 t(0.0);
    LimitTangentCase kase;
    if (surfaceRegular) {
        const glm::dvec3 n = cross / crossLen;
        if (uvRegular) t = tangentPart(dPds, n);
        kase = t != glm::dvec3(0.0) ? LimitTangentCase::Regular : LimitTangentCase::DegenerateUv;
        if (t == glm::dvec3(0.0)) t = tangentPart(dPdu, n);
        if (t == glm::dvec3(0.0)) t = tangentPart(dPdv, n);
    } else {
        kase = LimitTangentCase::DegenerateSurface;
        t = unitOrZero(dPds);
        if (t == glm::dvec3(0.0)) t = unitOrZero(dPdu);
        if (t == glm::dvec3(0.0)) t = unitOrZero(dPdv);
    }
    if (t == glm::dvec3(0.0)) t = glm::dvec3(1.0, 0.0, 0.0);
    if (resolved) *resolved = kase;
    const glm::vec3 tf = glm::normalize(glm::vec3(t)); // renormalize after rounding to float
    return glm::vec4(tf, float(w));
}

size_t limitTangents(std::span<const glm::vec3> dPdu, std::span<const glm::vec3> dPdv,
                     std::span<const glm::vec2> dSTdu, std::span<const glm::vec2> dSTdv,
                     std::span<glm::vec4> out) {
    const size_t n = dPdu.size();
    SG_EXPECTS(dPdv.size() == n && dSTdu.size() == n && dSTdv.size() == n && out.size() == n,
               "arrays of equal length");
    size_t irregular = 0;
    for (size_t i = 0; i < n; ++i) {
        LimitTangentCase k;
        out[i] = limitTangent(dPdu[i], dPdv[i], dSTdu[i], dSTdv[i], &k);
        irregular += k != LimitTangentCase::Regular;
    }
    return irregular;
}

size_t generateLimitTangents(RenderMesh& mesh, const LimitFrame& frame, int uvSet) {
    const size_t n = mesh.vertexCount();
    SG_EXPECTS(uvSetProblem(mesh, uvSet).empty(), "uvSet indexes mesh.uvSets");
    SG_EXPECTS(limitFrameProblem(mesh, frame, uvSet).empty(),
               "the frame is the limit frame of this mesh, with uvSet's UV derivatives");
    const bool haveNormals = mesh.normals.size() == n;
    mesh.tangents.resize(n);
    std::vector<uint8_t> regular(n, 0);
    size_t irregular = 0;
    for (size_t v = 0; v < n; ++v) {
        LimitTangentCase kase;
        mesh.tangents[v] = limitTangent(frame.dPdu[v], frame.dPdv[v], frame.dUVdu[size_t(uvSet)][v],
                                        frame.dUVdv[size_t(uvSet)][v], &kase);
        regular[v] = kase == LimitTangentCase::Regular;
        irregular += !regular[v];
    }
    // Irregular points (collapsed parameterizations, zero-area UVs) take
    // the handedness of the majority of their regular neighbours and the
    // normalized sum of those neighbours' tangents with that handedness:
    // the tangent field is continuous there even though the chain rule is
    // not usable at the point itself.
    std::vector<glm::dvec3> sumPos, sumNeg;
    std::vector<int> votes;
    if (irregular > 0) {
        sumPos.assign(n, glm::dvec3(0.0));
        sumNeg.assign(n, glm::dvec3(0.0));
        votes.assign(n, 0);
        for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
            const uint32_t tri[3] = {mesh.indices[i], mesh.indices[i + 1], mesh.indices[i + 2]};
            for (int a = 0; a < 3; ++a) {
                const uint32_t v = tri[a];
                if (v >= n || regular[v]) continue;
                for (int b = 0; b < 3; ++b) {
                    const uint32_t u = tri[b];
                    if (u >= n || !regular[u]) continue;
                    const glm::dvec3 tu(glm::vec3(mesh.tangents[u]));
                    if (mesh.tangents[u].w > 0.0f) {
                        sumPos[v] += tu;
                        ++votes[v];
                    } else {
                        sumNeg[v] += tu;
                        --votes[v];
                    }
                }
            }
        }
        for (size_t v = 0; v < n; ++v) {
            if (regular[v] || (sumPos[v] == glm::dvec3(0.0) && sumNeg[v] == glm::dvec3(0.0)))
                continue;
            const bool positive = votes[v] != 0 ? votes[v] > 0 : mesh.tangents[v].w > 0.0f;
            const glm::dvec3 sum = positive ? sumPos[v] : sumNeg[v];
            if (glm::length(sum) > 1e-6)
                mesh.tangents[v] =
                    glm::vec4(glm::vec3(sum / glm::length(sum)), positive ? 1.0f : -1.0f);
        }
    }
    for (size_t v = 0; v < n; ++v) {
        glm::dvec3 t(glm::vec3(mesh.tangents[v]));
        if (haveNormals) {
            // Orthogonal to the normal the renderer will use; at regular
            // points this only removes float rounding (that normal is the
            // normalized dP/du x dP/dv).
            const glm::dvec3 nrm(mesh.normals[v]);
            const double nLen = glm::length(nrm);
            if (nLen > 0.0 && std::isfinite(nLen)) {
                const glm::dvec3 un = nrm / nLen;
                glm::dvec3 tt = t - glm::dot(t, un) * un;
                if (glm::length(tt) < 1e-6) { // tangent along the normal: any orthogonal direction
                    const glm::dvec3 axis =
                        std::fabs(un.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
                    tt = axis - glm::dot(axis, un) * un;
                }
                t = tt / glm::length(tt);
            }
        }
        mesh.tangents[v] = glm::vec4(glm::normalize(glm::vec3(t)), mesh.tangents[v].w);
    }
    mesh.tangentUvSet = uvSet;
    return irregular;
}

size_t generateTangents(RenderMesh& mesh, TangentMethod method, int uvSet, const LimitFrame* frame,
                        int threads) {
    SG_EXPECTS(threads >= 0 && threads <= kMaxThreads,
               "0 (all cores) or 1..1024 threads (surfgrad/base/threads.h)");
    switch (method) {
    case TangentMethod::MikkTSpace: {
        const size_t before = mesh.vertexCount();
        generateMikkTSpaceTangents(mesh, uvSet, threads);
        return mesh.vertexCount() - before;
    }
    case TangentMethod::Limit:
        SG_EXPECTS(frame && !frame->empty(), "Limit needs the subdivider's limit frame");
        return generateLimitTangents(mesh, *frame, uvSet);
    case TangentMethod::Pixel:
        mesh.tangents.clear();
        mesh.tangentUvSet = -1;
        for (auto& morph : mesh.morphTargets) morph.tangentDeltas.clear();
        return 0;
    }
    return 0;
}

} // namespace sg::mesh

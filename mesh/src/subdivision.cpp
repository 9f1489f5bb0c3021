// Subdivision with OpenSubdiv 3.5 (surfgrad/mesh/subdivision.h).
//
// build():
//  1. PolygonMesh -> Far::TopologyDescriptor (arrays are used in place;
//     creases, corners, holes and one face-varying channel per UV set);
//  2. uniform refinement to level N; positions (and morph deltas)
//     through PrimvarRefiner::Interpolate, UVs through
//     InterpolateFaceVarying, ping-pong buffers kept between builds. A
//     manifold Catmull-Clark cage (without a limit evaluation) takes the
//     specialised refiner of uniform_refiner.h instead: the same numbers
//     bit for bit from OpenSubdiv's level 0, 3-4x faster;
//  3. level-N faces (holes dropped) -> refined() polygons;
//  4. limit (optional): a second, adaptively refined TopologyRefiner
//     (isolation >= N, so every level-N vertex is a patch corner and patch
//     corners are exact limit points, Gregory-basis end caps included), a
//     PatchTable with face-varying patches, and for every render vertex its
//     home location (ptex face, u, v) found by following the uniform
//     refinement's parent/child relations (see locateCorners). Each location
//     is evaluated once into per-sample basis weights (PatchTable::
//     EvaluateBasis / EvaluateBasisFaceVarying), so positions, normals and
//     derivatives come from one weight table that update() reuses;
//  5. render mesh: vertices split at UV seams and at infinitely sharp
//     edges (convert.cpp), quads split along 0-2.
//
// update(): the refined points are linear in the cage, so both the uniform
// refinement and the adaptive points are applied as "factored stencils":
// one sparse matrix per refinement level recorded from PrimvarRefiner (a few
// weights per point: ~3x fewer than Far's flattened StencilTable at level 4
// on spot, and no 50 ms StencilTableFactory build), applied level by level
// with plain loops (Osd's CpuEvaluator takes a slow path for stride-3 data,
// docs/platform.md).
//
// Files: this one runs the steps (refinement, render mesh, rebuilds,
// update()); limit_samples.cpp the limit evaluation of step 4;
// factored_stencils.h the stencils; osd_plumbing.{h,cpp} Far's callbacks,
// options, descriptor and face-varying interpolation; subdivision_impl.h
// the job's state; adaptive_patches.cpp the GPU patch tables
// (surfgrad/mesh/adaptive_patches.h).
#include "subdivision_impl.h"

#include <opensubdiv/far/error.h>

namespace sg::mesh {

using io::InputError;
using namespace detail;
namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

// Refined face count of level N, for the size check before refining.
long double refinedFaceEstimate(const PolygonMesh& cage, Scheme scheme, int level) {
    long double total = 0, grow = std::pow(4.0L, level);
    for (uint32_t k : cage.faceSizes) {
        if (level == 0)
            total += 1;
        else if (scheme == Scheme::Loop || k == 4)
            total += grow;
        else
            total += (long double)k * grow / 4; // N-gon: N quads after one level
    }
    return total;
}

// Positions and every morph target's position deltas (vertex data: the
// same masks), through `interpolate(cageValues, refinedValues)`.
template <class Interpolate>
void refineVertexData(const PolygonMesh& cage, PolygonMesh& refined, Interpolate&& interpolate) {
    interpolate(cage.positions, refined.positions);
    refined.morphTargets.resize(cage.morphTargets.size());
    for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
        refined.morphTargets[t].name = cage.morphTargets[t].name;
        interpolate(cage.morphTargets[t].positionDeltas, refined.morphTargets[t].positionDeltas);
    }
}

} // namespace

void Subdivider::Impl::refineUniform(const PolygonMesh& cage, Far::TopologyRefiner& refiner) {
    const int N = settings.level;
    const size_t nSets = cage.uvSets.size();
    detail::Stopwatch sw;
    // Ping-pong through levels 1..N-1, level N straight into refined()'s
    // arrays: every buffer keeps its capacity from the previous build, so a
    // rebuild touches no fresh pages.
    const Far::TopologyLevel& last = refiner.GetLevel(N);
    auto interpolateVec3 = [&](const std::vector<glm::vec3>& control, std::vector<glm::vec3>& out) {
        Far::PrimvarRefiner primvar(refiner);
        if (N == 0) {
            out = control;
            return;
        }
        const glm::vec3* src = control.data();
        for (int l = 1; l <= N; ++l) {
            std::vector<glm::vec3>& dstBuf = l == N ? out : (l % 2 ? bufA : bufB);
            dstBuf.resize(size_t(refiner.GetLevel(l).GetNumVertices()));
            PrimvarView<const glm::vec3> s{src};
            PrimvarView<glm::vec3> d{dstBuf.data()};
            primvar.Interpolate(l, s, d);
            src = dstBuf.data();
        }
    };
    refineVertexData(cage, refined, interpolateVec3);
    refined.uvSets.resize(nSets);
    for (size_t s = 0; s < nSets; ++s) {
        if (N == 0) {
            refined.uvSets[s].values = cage.uvSets[s].values;
            continue;
        }
        Far::PrimvarRefiner primvar(refiner);
        const glm::vec2* src = cage.uvSets[s].values.data();
        for (int l = 1; l <= N; ++l) {
            std::vector<glm::vec2>& dstBuf =
                l == N ? refined.uvSets[s].values : (l % 2 ? uvA : uvB);
            dstBuf.resize(size_t(refiner.GetLevel(l).GetNumFVarValues(int(s))));
            PrimvarView<const glm::vec2> sv{src};
            PrimvarView<glm::vec2> dv{dstBuf.data()};
            primvar.InterpolateFaceVarying(l, sv, dv, int(s));
            src = dstBuf.data();
        }
    }
    timings.interpolate = sw.lap();

    // Level-N polygons without holes; vertices compacted to those used.
    const int nF = last.GetNumFaces();
    refined.faceSizes.clear();
    refined.faceVertices.clear();
    refined.faceSizes.reserve(size_t(nF));
    refined.faceVertices.reserve(size_t(nF) * (settings.options.scheme == Scheme::Loop ? 3 : 4));
    for (size_t s = 0; s < nSets; ++s) {
        refined.uvSets[s].name = cage.uvSets[s].name;
        refined.uvSets[s].indices.clear();
    }
    const bool anyHole = !cage.holes.empty();
    levelToRefined.assign(size_t(last.GetNumVertices()), anyHole ? UINT32_MAX : 0);
    uint32_t used = 0;
    if (!anyHole) {
        for (uint32_t v = 0; v < levelToRefined.size(); ++v) levelToRefined[v] = v;
        used = uint32_t(levelToRefined.size());
    }
    for (int f = 0; f < nF; ++f) {
        if (anyHole && last.IsFaceHole(f)) continue;
        Far::ConstIndexArray fv = last.GetFaceVertices(f);
        refined.faceSizes.push_back(uint32_t(fv.size()));
        for (int k = 0; k < fv.size(); ++k) {
            uint32_t& m = levelToRefined[size_t(fv[k])];
            if (m == UINT32_MAX) m = used++;
            refined.faceVertices.push_back(m);
        }
        for (size_t s = 0; s < nSets; ++s) {
            Far::ConstIndexArray fvv = last.GetFaceFVarValues(f, int(s));
            for (int k = 0; k < fvv.size(); ++k)
                refined.uvSets[s].indices.push_back(uint32_t(fvv[k]));
        }
    }
    auto compact = [&](std::vector<glm::vec3>& values) {
        if (!anyHole) return;
        bufA.resize(used);
        for (size_t v = 0; v < levelToRefined.size(); ++v) {
            if (levelToRefined[v] != UINT32_MAX) bufA[levelToRefined[v]] = values[v];
        }
        values.swap(bufA);
    };
    compact(refined.positions);
    for (size_t t = 0; t < cage.morphTargets.size(); ++t)
        compact(refined.morphTargets[t].positionDeltas);
    refined.morphWeights = cage.morphWeights;
    timings.convertOut = sw.lap();
}

void Subdivider::Impl::refineUniformFast(const PolygonMesh& cage) {
    // As refineUniform, from the specialised refiner: no holes, every level-N
    // vertex is used, so refined() numbers them as level N does.
    const int N = settings.level;
    const size_t nSets = cage.uvSets.size();
    detail::Stopwatch sw;
    // Levels 1..N-1 as 4-float values (detail::Vec4Writer), one buffer per
    // level so none is shrunk and re-zeroed between builds.
    if (levelPoints.size() < size_t(N)) levelPoints.resize(size_t(N));
    auto interpolateVec3 = [&](const std::vector<glm::vec3>& control, std::vector<glm::vec3>& out) {
        out.resize(fast.level(N).numVerts);
        if (N == 1) {
            fast.interpolate(
                1, detail::Vec4Writer<glm::vec3, glm::vec3>{control.data(), out.data()}, par);
            return;
        }
        levelPoints[1].resize(fast.level(1).numVerts);
        fast.interpolate(
            1, detail::Vec4Writer<glm::vec3, glm::vec4>{control.data(), levelPoints[1].data()},
            par);
        for (int l = 2; l < N; ++l) {
            levelPoints[size_t(l)].resize(fast.level(l).numVerts);
            fast.interpolate(l,
                             detail::Vec4Writer<glm::vec4, glm::vec4>{
                                 levelPoints[size_t(l) - 1].data(), levelPoints[size_t(l)].data()},
                             par);
        }
        fast.interpolate(
            N,
            detail::Vec4Writer<glm::vec4, glm::vec3>{levelPoints[size_t(N) - 1].data(), out.data()},
            par);
    };
    refineVertexData(cage, refined, interpolateVec3);
    refined.uvSets.resize(nSets);
    for (size_t s = 0; s < nSets; ++s) {
        refined.uvSets[s].name = cage.uvSets[s].name;
        const glm::vec2* src = cage.uvSets[s].values.data();
        if (levelValues.size() < size_t(N)) levelValues.resize(size_t(N));
        for (int l = 1; l <= N; ++l) {
            std::vector<glm::vec2>& dstBuf =
                l == N ? refined.uvSets[s].values : levelValues[size_t(l)];
            dstBuf.resize(fast.numFVarValues(l, int(s)));
            fast.interpolateFaceVarying(
                l, detail::ArrayWriter<glm::vec2>{src, dstBuf.data(), glm::vec2(0.0f)}, int(s),
                par);
            src = dstBuf.data();
        }
    }
    timings.interpolate = sw.lap();
    const detail::RefineLevel& last = fast.level(N);
    refined.faceSizes.assign(last.numFaces, 4u);
    fast.takeLastFaceVertices(refined.faceVertices);
    for (size_t s = 0; s < nSets; ++s) fast.takeLastFaceValues(int(s), refined.uvSets[s].indices);
    levelToRefined.resize(last.numVerts);
    par.each(last.numVerts, [&](size_t v) { levelToRefined[v] = uint32_t(v); });
    refined.morphWeights = cage.morphWeights;
    timings.convertOut = sw.lap();
}

void Subdivider::Impl::collectCreases(const Far::TopologyRefiner& refiner) {
    // The sharpness left after N levels, on interior edges (boundary edges
    // carry the boundary rule, not a tag) and on vertices that are tagged
    // corners (a boundary corner under EdgeAndCorner is the rule again).
    const Far::TopologyLevel& last = refiner.GetLevel(settings.level);
    refined.creases.clear();
    refined.corners.clear();
    for (int e = 0; e < last.GetNumEdges(); ++e) {
        float s = last.GetEdgeSharpness(e);
        if (s <= 0.0f || last.IsEdgeBoundary(e)) continue;
        Far::ConstIndexArray ev = last.GetEdgeVertices(e);
        uint32_t a = levelToRefined[size_t(ev[0])], b = levelToRefined[size_t(ev[1])];
        if (a == UINT32_MAX || b == UINT32_MAX) continue;
        refined.creases.push_back({a, b, s});
    }
    const bool ruleCorners = settings.options.boundary == BoundaryInterpolation::EdgeAndCorner;
    for (int v = 0; v < last.GetNumVertices(); ++v) {
        float s = last.GetVertexSharpness(v);
        if (s <= 0.0f || (ruleCorners && last.IsVertexBoundary(v))) continue;
        uint32_t m = levelToRefined[size_t(v)];
        if (m != UINT32_MAX) refined.corners.push_back({m, s});
    }
}

std::vector<uint32_t> Subdivider::Impl::sectors(const std::vector<uint32_t>& offsets) const {
    // Union-find over corners across interior edges that are not infinitely
    // sharp: each root is one smooth sector around a vertex. The infinitely
    // sharp interior edges of level N are refined().creases with infinite
    // sharpness (collectCreases / UniformRefiner::lastLevelCreases).
    std::vector<uint64_t> sharp;
    for (const EdgeCrease& c : refined.creases) {
        if (c.sharpness >= kInfiniteSharpness) sharp.push_back(detail::edgeKey(c.v0, c.v1));
    }
    std::vector<uint32_t> sector(refined.faceVertices.size());
    if (sharp.empty()) {
        for (size_t c = 0; c < sector.size(); ++c) sector[c] = refined.faceVertices[c];
        return sector; // one sector per vertex
    }
    std::sort(sharp.begin(), sharp.end());
    std::vector<detail::FaceEdge> edges = detail::sortedFaceEdges(refined, offsets);
    detail::UnionFind uf(refined.faceVertices.size());
    for (size_t i = 0; i + 1 < edges.size(); ++i) {
        const detail::FaceEdge &a = edges[i], &b = edges[i + 1];
        if (a.key != b.key || (i + 2 < edges.size() && edges[i + 2].key == a.key))
            continue; // manifold pairs only
        if (a.forward == b.forward || std::binary_search(sharp.begin(), sharp.end(), a.key))
            continue;
        uf.unite(a.corner, b.next);
        uf.unite(a.next, b.corner);
    }
    for (uint32_t c = 0; c < sector.size(); ++c) sector[c] = uf.find(c);
    return sector;
}

void Subdivider::Impl::locateCorners(const Far::TopologyRefiner& refiner,
                                     std::vector<uint32_t>& cornerPtex,
                                     std::vector<glm::vec2>& cornerUV) const {
    // Home location of every level-N face corner: ptex face and (u,v).
    // Level 0: a quad (or a Loop triangle) is one ptex face with corners at
    // (0,0),(1,0),(1,1),(0,1) ((0,0),(1,0),(0,1)); any other polygon has one
    // ptex sub-face per corner: sub-face j has (0,0) at corner j, (1,0) at
    // the midpoint of the edge to corner j+1, (1,1) at the centre and (0,1)
    // at the midpoint of the edge from corner j-1 (OpenSubdiv's quad
    // sub-face parameterization; the tests check it against PrimvarRefiner::
    // Limit). Each further level places child vertices at the parameter of
    // their parent vertex, the midpoint of their parent edge or the centre of
    // their parent face.
    const bool loop = settings.options.scheme == Scheme::Loop;
    const Far::TopologyLevel& base = refiner.GetLevel(0);
    Far::PtexIndices ptex(refiner);
    const int N = settings.level;
    // Per face of the current level: ptex face and corner params (flat).
    std::vector<uint32_t> facePtex, faceFirst;
    std::vector<glm::vec2> uv;
    std::vector<uint32_t> nextPtex, nextFirst;
    std::vector<glm::vec2> nextUV;
    const glm::vec2 kQuad[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const glm::vec2 kTri[3] = {{0, 0}, {1, 0}, {0, 1}};
    // Level 0 (N-gons keep their corners' sub-face ids in cornerSub).
    std::vector<uint32_t> cornerSub; // level 0 only: ptex face per corner
    for (int f = 0; f < base.GetNumFaces(); ++f) {
        int k = base.GetFaceVertices(f).size();
        faceFirst.push_back(uint32_t(uv.size()));
        facePtex.push_back(uint32_t(ptex.GetFaceId(f)));
        bool regular = loop ? k == 3 : k == 4;
        for (int j = 0; j < k; ++j) {
            uv.push_back(regular ? (loop ? kTri[j] : kQuad[j]) : glm::vec2(0.0f));
            cornerSub.push_back(uint32_t(ptex.GetFaceId(f) + (regular ? 0 : j)));
        }
    }
    for (int l = 0; l < N; ++l) {
        const Far::TopologyLevel& P = refiner.GetLevel(l);
        const Far::TopologyLevel& C = refiner.GetLevel(l + 1);
        nextPtex.assign(size_t(C.GetNumFaces()), 0);
        nextFirst.assign(size_t(C.GetNumFaces()), 0);
        nextUV.assign(size_t(C.GetNumFaces()) * (loop ? 3 : 4), glm::vec2(0.0f));
        for (int f = 0; f < P.GetNumFaces(); ++f) {
            Far::ConstIndexArray fv = P.GetFaceVertices(f), fe = P.GetFaceEdges(f),
                                 children = P.GetFaceChildFaces(f);
            const int k = fv.size();
            const bool nonQuad = l == 0 && !loop && k != 4;
            const uint32_t first = faceFirst[size_t(f)];
            glm::vec2 centre(0.0f);
            for (int j = 0; j < k; ++j) centre += uv[first + uint32_t(j)];
            centre /= float(k);
            const int faceChild = loop ? -1 : P.GetFaceChildVertex(f);
            for (int ci = 0; ci < children.size(); ++ci) {
                const int c = children[ci];
                Far::ConstIndexArray cv = C.GetFaceVertices(c);
                // Which corner of the parent does this child touch (N-gon sub-face)?
                int sub = 0;
                if (nonQuad) {
                    for (int j = 0; j < k; ++j) {
                        for (int m = 0; m < cv.size(); ++m) {
                            if (cv[m] == P.GetVertexChildVertex(fv[j])) sub = j;
                        }
                    }
                }
                nextPtex[size_t(c)] =
                    nonQuad ? cornerSub[first + uint32_t(sub)] : facePtex[size_t(f)];
                nextFirst[size_t(c)] = uint32_t(c) * (loop ? 3u : 4u);
                for (int m = 0; m < cv.size(); ++m) {
                    const int v = cv[m];
                    glm::vec2 p(0.0f);
                    if (v == faceChild) {
                        p = nonQuad ? glm::vec2(1.0f, 1.0f) : centre;
                    } else {
                        for (int j = 0; j < k; ++j) {
                            const int jn = (j + 1) % k;
                            if (v == P.GetVertexChildVertex(fv[j])) {
                                p = nonQuad ? glm::vec2(0.0f) : uv[first + uint32_t(j)];
                                break;
                            }
                            if (v == P.GetEdgeChildVertex(fe[j])) {
                                // Edge j joins corners j and j+1.
                                // Sub-face `sub` touches edge sub (to its (1,0)) and edge sub-1 (to
                                // its (0,1)).
                                if (nonQuad)
                                    p = j == sub ? glm::vec2(1.0f, 0.0f) : glm::vec2(0.0f, 1.0f);
                                else
                                    p = 0.5f * (uv[first + uint32_t(j)] + uv[first + uint32_t(jn)]);
                                break;
                            }
                        }
                    }
                    nextUV[nextFirst[size_t(c)] + uint32_t(m)] = p;
                }
            }
        }
        facePtex.swap(nextPtex);
        faceFirst.swap(nextFirst);
        uv.swap(nextUV);
    }
    // Flatten onto refined() corners (non-hole faces in order).
    const Far::TopologyLevel& last = refiner.GetLevel(N);
    cornerPtex.clear();
    cornerUV.clear();
    cornerPtex.reserve(refined.faceVertices.size());
    cornerUV.reserve(refined.faceVertices.size());
    const bool anyHole = cageHasHoles;
    uint32_t level0Corner = 0;
    for (int f = 0; f < last.GetNumFaces(); ++f) {
        const int k = last.GetFaceVertices(f).size();
        if (!(anyHole && last.IsFaceHole(f))) {
            for (int m = 0; m < k; ++m) {
                cornerPtex.push_back(N == 0 ? cornerSub[level0Corner + uint32_t(m)]
                                            : facePtex[size_t(f)]);
                cornerUV.push_back(uv[faceFirst[size_t(f)] + uint32_t(m)]);
            }
        }
        level0Corner += uint32_t(k);
    }
}

void Subdivider::Impl::buildRender() {
    std::vector<uint32_t> offsets = faceOffsets(refined);
    std::vector<uint32_t> sector;
    const bool needSectors = !refined.creases.empty();
    if (needSectors) sector = sectors(offsets);
    detail::splitRenderVertices(refined, offsets, needSectors ? sector.data() : nullptr, split);
    const size_t nR = split.renderSourceVertex.size();
    renderToRefined = split.renderSourceVertex;
    render.name = refined.name;
    render.positions.resize(nR);
    render.uvSets.resize(refined.uvSets.size());
    for (size_t s = 0; s < refined.uvSets.size(); ++s) render.uvSets[s].resize(nR);
    copyToRender();
    render.indices = split.indices;
    render.tangents.clear();
    render.tangentUvSet = -1;
    positionRep.resize(nR);
    {
        std::vector<uint32_t> first(refined.positions.size(), UINT32_MAX);
        for (uint32_t r = 0; r < nR; ++r) {
            uint32_t& f = first[renderToRefined[r]];
            if (f == UINT32_MAX) f = r;
            positionRep[r] = f;
        }
    }
    smoothGroups(needSectors ? sector.data() : nullptr);
    render.normals.assign(nR, glm::vec3(0.0f));
    normalGroups();
    polygonNormals(render.positions.data(), render.normals.data(), normalScratch);
    render.morphTargets.resize(refined.morphTargets.size());
    for (size_t t = 0; t < refined.morphTargets.size(); ++t) {
        render.morphTargets[t].name = refined.morphTargets[t].name;
        render.morphTargets[t].normalDeltas.clear();
        render.morphTargets[t].tangentDeltas.clear();
        render.morphTargets[t].positionDeltas.resize(nR);
        par.each(nR, [&](size_t r) {
            render.morphTargets[t].positionDeltas[r] =
                refined.morphTargets[t].positionDeltas[renderToRefined[r]];
        });
    }
    render.morphWeights = refined.morphWeights;
    if (!render.morphTargets.empty() && render.morphWeights.empty())
        render.morphWeights.assign(render.morphTargets.size(), 0.0f);
    std::vector<uint32_t> refinedToLevel(refined.positions.size(), 0);
    for (uint32_t v = 0; v < levelToRefined.size(); ++v) {
        if (levelToRefined[v] != UINT32_MAX) refinedToLevel[levelToRefined[v]] = v;
    }
    renderToLevel.resize(nR);
    par.each(nR, [&](size_t r) { renderToLevel[r] = refinedToLevel[renderToRefined[r]]; });
    // refined() normals: per vertex, from the first render vertex using it.
    refined.normals.assign(refined.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
    for (size_t r = nR; r-- > 0;) refined.normals[renderToRefined[r]] = render.normals[r];
    refined.normalIndices = refined.faceVertices;
}

bool Subdivider::Impl::sameTopology(const PolygonMesh& cage) const {
    const SubdivOptions& o = settings.options;
    if (!keyValid || keyLevel != settings.level || keyOptions.scheme != o.scheme ||
        keyOptions.boundary != o.boundary || keyOptions.fvar != o.fvar ||
        keyOptions.creaseMethod != o.creaseMethod || keyOptions.triangles != o.triangles) {
        return false;
    }
    auto sameCreases = [](const std::vector<EdgeCrease>& a, const std::vector<EdgeCrease>& b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                                  [](const EdgeCrease& x, const EdgeCrease& y) {
                                                      return x.v0 == y.v0 && x.v1 == y.v1 &&
                                                             x.sharpness == y.sharpness;
                                                  });
    };
    auto sameCorners = [](const std::vector<VertexCorner>& a, const std::vector<VertexCorner>& b) {
        return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(),
                                                  [](const VertexCorner& x, const VertexCorner& y) {
                                                      return x.vertex == y.vertex &&
                                                             x.sharpness == y.sharpness;
                                                  });
    };
    if (cage.positions.size() != key.positions.size() || cage.faceSizes != key.faceSizes ||
        cage.faceVertices != key.faceVertices || cage.holes != key.holes ||
        !sameCreases(cage.creases, key.creases) || !sameCorners(cage.corners, key.corners) ||
        cage.uvSets.size() != key.uvSets.size() ||
        cage.morphTargets.size() != key.morphTargets.size()) {
        return false;
    }
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        if (cage.uvSets[s].indices != key.uvSets[s].indices ||
            cage.uvSets[s].values.size() != key.uvSets[s].values.size())
            return false;
    }
    return true;
}

void Subdivider::Impl::recordUniformStencils(const Far::TopologyRefiner* far,
                                             const PolygonMesh& cage) {
    const int N = settings.level;
    auto numVerts = [&](int l) {
        return far ? uint32_t(far->GetLevel(l).GetNumVertices()) : fast.level(l).numVerts;
    };
    // Level 0 holds the cage's UV values (Far indexes them as given).
    auto numValues = [&](int l, int s) {
        if (l == 0) return uint32_t(cage.uvSets[size_t(s)].values.size());
        return far ? uint32_t(far->GetLevel(l).GetNumFVarValues(s)) : fast.numFVarValues(l, s);
    };
    auto record = [&](FactoredStencils& f, int l, uint32_t srcBase, uint32_t dstBase, int channel) {
        if (far)
            f.recordLevel(*far, l, srcBase, dstBase, channel);
        else
            f.recordLevel(fast, l, srcBase, dstBase, channel);
    };
    uniformStencils = FactoredStencils();
    uniformStencils.numControl = uint32_t(cage.positions.size());
    uint32_t base = 0;
    for (int l = 1; l <= N; ++l) {
        uint32_t next = base + numVerts(l - 1);
        record(uniformStencils, l, base, next, -1);
        base = next;
    }
    uniformStencils.numPoints = base + numVerts(N);
    fvarStencils.assign(cage.uvSets.size(), FactoredStencils());
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        FactoredStencils& f = fvarStencils[s];
        f.numControl = uint32_t(cage.uvSets[s].values.size());
        uint32_t b = 0;
        for (int l = 1; l <= N; ++l) {
            uint32_t next = b + numValues(l - 1, int(s));
            record(f, l, b, next, int(s));
            b = next;
        }
        f.numPoints = b + numValues(N, int(s));
    }
    stencilsRecorded = true;
}

void Subdivider::Impl::rebuildValues(const PolygonMesh& cage) {
    // Same topology as the kept build: only values change. refined()'s
    // faces, UV indices, tags and the render split stay as they are.
    detail::Stopwatch sw;
    if (!stencilsRecorded) recordUniformStencils(fastBuilt ? nullptr : keptRefiner.get(), cage);
    timings.stencils = sw.lap();
    const size_t nLevel = levelToRefined.size();
    auto refineVec3 = [&](const std::vector<glm::vec3>& control, std::vector<glm::vec3>& out) {
        points.resize(uniformStencils.numPoints);
        std::copy(control.begin(), control.end(), points.begin());
        uniformStencils.apply(points.data(), par);
        const glm::vec3* levelN = points.data() + (uniformStencils.numPoints - nLevel);
        out.resize(refined.positions.size());
        par.each(nLevel, [&](size_t v) {
            if (levelToRefined[v] != UINT32_MAX) out[levelToRefined[v]] = levelN[v];
        });
    };
    refineVec3(cage.positions, refined.positions);
    for (size_t t = 0; t < cage.morphTargets.size(); ++t)
        refineVec3(cage.morphTargets[t].positionDeltas, refined.morphTargets[t].positionDeltas);
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        const FactoredStencils& f = fvarStencils[s];
        uvPoints.resize(f.numPoints);
        std::copy(cage.uvSets[s].values.begin(), cage.uvSets[s].values.end(), uvPoints.begin());
        f.apply(uvPoints.data(), par);
        std::vector<glm::vec2>& values = refined.uvSets[s].values;
        values.assign(uvPoints.end() - std::ptrdiff_t(values.size()), uvPoints.end());
    }
    refined.morphWeights = cage.morphWeights;
    timings.interpolate = sw.lap();
    if (!settings.buildRenderMesh) {
        // As in a fresh build without a render mesh: no normals (the kept
        // ones belong to the old positions).
        refined.normals.clear();
        refined.normalIndices.clear();
        renderValid = false;
    } else {
        if (renderValid) {
            const size_t nR = renderToRefined.size();
            copyToRender();
            for (size_t t = 0; t < refined.morphTargets.size(); ++t) {
                par.each(nR, [&](size_t r) {
                    render.morphTargets[t].positionDeltas[r] =
                        refined.morphTargets[t].positionDeltas[renderToRefined[r]];
                });
            }
            render.morphWeights = refined.morphWeights;
            polygonNormals(render.positions.data(), render.normals.data(), normalScratch);
            for (size_t r = nR; r-- > 0;) refined.normals[renderToRefined[r]] = render.normals[r];
        } else {
            buildRender();
            renderValid = true;
        }
        timings.render = sw.lap();
    }
}

// Refuses a build whose estimated peak memory is above the budget, before
// OpenSubdiv or the specialised refiner allocates (the estimate and its
// test: subdivision_budget.cpp, tests/mesh/subdivision_budget_test.cpp).
void Subdivider::Impl::checkMemoryBudget(const PolygonMesh& cage) const {
    const uint64_t budget =
        settings.memoryBudget ? settings.memoryBudget : defaultSubdivisionBudget();
    const SubdivisionCost cost = estimateSubdivisionCost(cage, settings);
    if (cost.bytes <= budget) return;
    std::string what = std::to_string(cost.faces) + " faces";
    if (settings.limit) what += " with limit evaluation";
    if (settings.animate) what += " and animation stencils";
    throw InputError(file, "level " + std::to_string(settings.level),
                     "would make " + what + " and need about " + formatByteSize(cost.bytes) +
                         " of memory; the limit is " + formatByteSize(budget) +
                         (settings.memoryBudgetHint.empty()
                              ? std::string()
                              : " (raise it with " + settings.memoryBudgetHint + ")"));
}

// What build() refuses before refining: a level out of range, an empty
// cage, non-triangles under Loop, and refinements beyond
// settings.maxRefinedFaces.
void Subdivider::Impl::checkBuildable(const PolygonMesh& cage) const {
    const SubdivOptions& o = settings.options;
    const int N = settings.level;
    if (N < 0 || N > kMaxSubdivisionLevel) {
        throw InputError(file, "level",
                         std::to_string(N) + " is outside 0.." +
                             std::to_string(kMaxSubdivisionLevel));
    }
    if (cage.faceSizes.empty()) throw InputError(file, "", "empty mesh: no faces");
    if (o.scheme == Scheme::Loop) {
        for (size_t f = 0; f < cage.faceSizes.size(); ++f) {
            if (cage.faceSizes[f] != 3) {
                throw InputError(
                    file, "face " + std::to_string(f),
                    "has " + std::to_string(cage.faceSizes[f]) +
                        " corners; the Loop scheme takes triangles only (use catmark or bilinear)");
            }
        }
    }
    long double estimate = refinedFaceEstimate(cage, o.scheme, N);
    if (estimate > (long double)settings.maxRefinedFaces) {
        throw InputError(file, "level " + std::to_string(N),
                         "would make about " + std::to_string((unsigned long long)estimate) +
                             " faces; the limit is " + std::to_string(settings.maxRefinedFaces));
    }
}

// What a rebuild of the same topology needs (sameTopology): the topology,
// tags and value counts of this cage (its values are not kept).
void Subdivider::Impl::keepTopologyKey(const PolygonMesh& cage) {
    keyValid = true;
    keyLevel = settings.level;
    keyOptions = settings.options;
    renderValid = settings.buildRenderMesh;
    key.positions.resize(cage.positions.size());
    key.faceSizes = cage.faceSizes;
    key.faceVertices = cage.faceVertices;
    key.holes = cage.holes;
    key.creases = cage.creases;
    key.corners = cage.corners;
    key.morphTargets.resize(cage.morphTargets.size());
    key.uvSets.resize(cage.uvSets.size());
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        key.uvSets[s].indices = cage.uvSets[s].indices;
        key.uvSets[s].values.resize(cage.uvSets[s].values.size());
    }
}

void Subdivider::Impl::build(const PolygonMesh& cage) {
    timings = SubdivisionTimings();
    const SubdivOptions& o = settings.options;
    const int N = settings.level;
    checkBuildable(cage);
    cageVertices = cage.positions.size();
    if (!settings.limit && settings.reuseTopology && sameTopology(cage)) {
        rebuildValues(cage);
        return;
    }
    checkMemoryBudget(cage);
    keyValid = false;
    stencilsRecorded = false;
    renderValid = false;
    fastBuilt = false;
    fastDeclined.clear();
    // Free the previous refiner before OpenSubdiv allocates the next one, so
    // malloc hands the same pages back instead of faulting in new ones.
    keptRefiner.reset();
    detail::Stopwatch sw;
    descriptor.build(cage);
    timings.convertIn = sw.lap();
    // Level 0 (OpenSubdiv's factory: validation, edges, tags, face-varying
    // channels) is shared by both refiners.
    std::unique_ptr<Far::TopologyRefiner> refiner = createRefiner(descriptor, o, file);
    const bool tags = !cage.creases.empty() || !cage.corners.empty();
    refined.name = cage.name;
    refined.options = o;
    refined.explicitTags = cage.explicitTags;
    refined.holes.clear();
    refined.normals.clear();
    refined.normalIndices.clear();
    cageHasHoles = !cage.holes.empty();
    if (settings.specializedRefiner && !settings.limit && N >= 1) {
        fastBuilt = fast.accept(*refiner, cage, fastDeclined);
    } else {
        fastDeclined = settings.limit ? "limit evaluation" : (N < 1 ? "level 0" : "not asked");
    }
    if (fastBuilt) {
        fast.refine(N, par);
        timings.topology = sw.lap();
        refineUniformFast(cage);
        sw.lap();
        if (tags)
            fast.lastLevelCreases(refined.creases, refined.corners,
                                  o.boundary == BoundaryInterpolation::EdgeAndCorner);
        else {
            refined.creases.clear();
            refined.corners.clear();
        }
        timings.convertOut += sw.lap();
    } else {
        Far::TopologyRefiner::UniformOptions uo(N);
        // Edges of the last level are needed only for crease tags and sharp sectors.
        uo.fullTopologyInLastLevel = tags;
        refiner->RefineUniform(uo);
        timings.topology = sw.lap();
        refineUniform(cage, *refiner);
        sw.lap();
        if (tags)
            collectCreases(*refiner);
        else {
            refined.creases.clear();
            refined.corners.clear();
        }
        timings.convertOut += sw.lap();
    }

    render = RenderMesh();
    frame = LimitFrame();
    split = detail::RenderSplit();
    renderToRefined.clear();
    if (settings.limit) {
        std::vector<uint8_t> drop;
        // evaluateLimit builds the render mesh over faces that have patches.
        evaluateLimit(cage, *refiner, drop);
        // Faces without patches (only boundary faces under
        // BoundaryInterpolation::None, which OpenSubdiv leaves out of the limit
        // surface) are now refined().holes.
        if (!settings.buildRenderMesh) {
            render = RenderMesh();
            frame = LimitFrame();
        }
    } else if (settings.buildRenderMesh) {
        sw.lap();
        buildRender();
        timings.render = sw.lap();
    }
    if (settings.animate && !settings.limit) {
        sw.lap();
        recordUniformStencils(fastBuilt ? nullptr : refiner.get(), cage);
        timings.stencils = sw.lap();
    }
    // Keep what a rebuild of the same topology needs (uniform builds only:
    // a limit build turns faces without patches into holes of refined()).
    // A specialised build keeps its levels in `fast`.
    if (!settings.limit && settings.reuseTopology) {
        if (!fastBuilt) keptRefiner = std::move(refiner);
        keepTopologyKey(cage);
    }
}

// ---- Public ----------------------------------------------------------------------

Subdivider::Subdivider() : impl_(std::make_unique<Impl>()) {}
Subdivider::Subdivider(const PolygonMesh& cage, const SubdivisionSettings& settings,
                       const std::string& file)
    : Subdivider() {
    build(cage, settings, file);
}
Subdivider::~Subdivider() = default;
Subdivider::Subdivider(Subdivider&&) noexcept = default;
Subdivider& Subdivider::operator=(Subdivider&&) noexcept = default;

// Elements per task with serialBelowFaces = 0: small cages then exercise
// many block boundaries.
constexpr size_t kTestGrain = 16;

void Subdivider::build(const PolygonMesh& cage, const SubdivisionSettings& settings,
                       const std::string& file) {
    SG_EXPECTS(settings.threads >= 0 && settings.threads <= kMaxThreads,
               "SubdivisionSettings::threads is 0 (all cores) or 1..1024");
    impl_->settings = settings;
    impl_->file = file.empty() ? (cage.name.empty() ? std::string("(mesh)") : cage.name) : file;
    // Threads only where they pay: a refined mesh below serialBelowFaces
    // stays on the calling thread (the estimate is the budget check's).
    const long double faces =
        settings.level >= 0 && settings.level <= kMaxSubdivisionLevel
            ? refinedFaceEstimate(cage, settings.options.scheme, settings.level)
            : 0.0L;
    impl_->par.on = settings.threads != 1 && faces >= (long double)settings.serialBelowFaces;
    impl_->par.grain = settings.serialBelowFaces == 0 ? kTestGrain : detail::kGrain;
    if (impl_->par.on)
        runWithThreads(settings.threads, [&] { impl_->build(cage); });
    else
        impl_->build(cage);
}

const SubdivisionSettings& Subdivider::settings() const {
    return impl_->settings;
}
const PolygonMesh& Subdivider::refined() const {
    return impl_->refined;
}
const RenderMesh& Subdivider::renderMesh() const {
    return impl_->render;
}
const std::vector<uint32_t>& Subdivider::renderToRefinedVertex() const {
    return impl_->renderToRefined;
}
const LimitFrame& Subdivider::limitFrame() const {
    return impl_->frame;
}
const SubdivisionTimings& Subdivider::timings() const {
    return impl_->timings;
}
bool Subdivider::usedSpecializedRefiner() const {
    return impl_->fastBuilt;
}
const std::string& Subdivider::specializedRefinerDeclined() const {
    return impl_->fastDeclined;
}
size_t Subdivider::cageVertexCount() const {
    return impl_->cageVertices;
}
size_t Subdivider::stencilWeightCount() const {
    const Impl& m = *impl_;
    if (m.settings.limit) return m.limitStencils.weightCount() + m.samples.point.size();
    return m.uniformStencils.weightCount();
}

void Subdivider::update(std::span<const glm::vec3> cagePositions, RenderMesh& out,
                        LimitFrame* frame, bool recomputeNormals) const {
    const Impl& m = *impl_;
    SG_EXPECTS(m.settings.animate, "the Subdivider was built with SubdivisionSettings::animate");
    SG_EXPECTS(cagePositions.size() == m.cageVertices, "one position per cage vertex");
    SG_EXPECTS(out.positions.size() == m.render.positions.size(),
               "`out` starts as a copy of renderMesh()");
    if (m.par.on)
        runWithThreads(m.settings.threads,
                       [&] { m.update(cagePositions, out, frame, recomputeNormals); });
    else
        m.update(cagePositions, out, frame, recomputeNormals);
}

void Subdivider::Impl::update(std::span<const glm::vec3> cagePositions, RenderMesh& out,
                              LimitFrame* outFrame, bool recomputeNormals) const {
    const size_t nR = out.positions.size();
    if (settings.limit) {
        // Relative to the box centre, as a build evaluates them.
        const glm::vec3 origin = boxCentre(cagePositions.data(), cagePositions.size());
        points4.resize(limitStencils.numPoints);
        par.each(cagePositions.size(),
                 [&](size_t v) { points4[v] = glm::vec4(cagePositions[v] - origin, 0.0f); });
        limitStencils.apply(points4.data(), par);
        glm::vec3 *du, *dv;
        std::vector<glm::vec3> tmpU, tmpV;
        if (outFrame) {
            outFrame->dPdu.resize(nR);
            outFrame->dPdv.resize(nR);
            du = outFrame->dPdu.data();
            dv = outFrame->dPdv.data();
        } else {
            tmpU.resize(nR);
            tmpV.resize(nR);
            du = tmpU.data();
            dv = tmpV.data();
        }
        samples.evaluate(points4.data(), out.positions.data(), du, dv, par);
        par.each(nR, [&](size_t r) { out.positions[r] += origin; });
        out.normals.resize(nR);
        if (recomputeNormals) {
            par.each(nR,
                     [&](size_t r) { out.normals[r] = safeNormal(du[r], dv[r], out.normals[r]); });
        }
        unifyCopies(out.positions.data(), out.normals.data());
        return;
    }
    points4.resize(uniformStencils.numPoints);
    par.each(cagePositions.size(),
             [&](size_t v) { points4[v] = glm::vec4(cagePositions[v], 0.0f); });
    uniformStencils.apply(points4.data(), par);
    const glm::vec4* levelN = points4.data() + (uniformStencils.numPoints - levelToRefined.size());
    par.each(nR, [&](size_t r) { out.positions[r] = glm::vec3(levelN[renderToLevel[r]]); });
    if (recomputeNormals) polygonNormals(out.positions.data(), out.normals.data(), normalScratch);
}

} // namespace sg::mesh

// Limit evaluation of a uniform subdivision (docs/mesh.md, "Limit
// evaluation"; surfgrad/mesh/subdivision.h, SubdivisionSettings::limit): an
// adaptively refined copy of the cage and its PatchTable with face-varying
// patches (Gregory-basis end caps), the stencils from the cage to the patch
// points, every render vertex's home location (ptex face, u, v), one sample
// of basis weights per location (PatchTable::EvaluateBasis /
// EvaluateBasisFaceVarying), then positions, normals, morph deltas and UVs
// with their derivatives.
#include "subdivision_impl.h"

namespace sg::mesh {

using io::InputError;
using namespace detail;
namespace Far = OpenSubdiv::Far;

namespace {

// UV set s's values at every adaptive point: UVs are static, so they are
// interpolated once.
std::vector<glm::vec2> limitUvPoints(const PolygonMesh& cage, const LimitPatches& lp, size_t s) {
    return fvarPatchPoints(*lp.adaptive, *lp.patches, cage.uvSets[s].values, int(s));
}

} // namespace

// Isolation: at least N (every level-N vertex on a patch corner, where
// patches interpolate the limit exactly) and at least the largest finite
// crease/corner sharpness (semi-sharp features are exact only when isolated
// that deep); OpenSubdiv caps it at 10. At least 5: Gregory end caps
// approximate the tangent plane around extraordinary vertices, better the
// deeper they sit, while float patch points lose precision the deeper they
// sit. On spot, vs OpenSubdiv's limit masks, the worst normal is off by
// 4.5e-3 rad at isolation 3, 1.6e-3 at 4, 9.7e-4 at 5 and 3.4e-3 at 6
// (tests/mesh/subdivision_test.cpp).
LimitPatches Subdivider::Impl::buildPatches(const PolygonMesh& cage) const {
    float maxSharp = 0.0f;
    for (const EdgeCrease& c : cage.creases) {
        if (c.sharpness < kInfiniteSharpness) maxSharp = std::max(maxSharp, c.sharpness);
    }
    for (const VertexCorner& c : cage.corners) {
        if (c.sharpness < kInfiniteSharpness) maxSharp = std::max(maxSharp, c.sharpness);
    }
    const int isolation =
        std::clamp(std::max({settings.level, 5, int(std::ceil(maxSharp))}), 5, 10);
    LimitPatches lp;
    lp.adaptive = createRefiner(descriptor, settings.options, file);
    Far::PatchTableFactory::Options popt(static_cast<unsigned>(isolation));
    popt.SetEndCapType(Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS);
    popt.useInfSharpPatch = true;
    popt.generateFVarTables = !cage.uvSets.empty();
    popt.generateFVarLegacyLinearPatches = false; // smooth UV patches where the rules say smooth
    popt.generateLegacySharpCornerPatches = false;
    popt.generateVaryingTables = false;
    lp.adaptive->RefineAdaptive(popt.GetRefineAdaptiveOptions());
    lp.patches.reset(Far::PatchTableFactory::Create(*lp.adaptive, popt));
    if (!lp.patches)
        throw InputError(file, "limit", "OpenSubdiv could not build patches: " + tFarError);
    lp.patchMap = std::make_unique<Far::PatchMap>(*lp.patches);
    return lp;
}

// Cage -> every adaptive point, then the patch table's local points.
void Subdivider::Impl::recordLimitStencils(const PolygonMesh& cage, const LimitPatches& lp) {
    const Far::TopologyRefiner& adaptive = *lp.adaptive;
    limitStencils = FactoredStencils();
    limitStencils.numControl = uint32_t(cage.positions.size());
    std::vector<uint32_t> levelBase(size_t(adaptive.GetNumLevels()) + 1, 0);
    for (int l = 0; l < adaptive.GetNumLevels(); ++l) {
        levelBase[size_t(l) + 1] =
            levelBase[size_t(l)] + uint32_t(adaptive.GetLevel(l).GetNumVertices());
    }
    for (int l = 1; l < adaptive.GetNumLevels(); ++l)
        limitStencils.recordLevel(adaptive, l, levelBase[size_t(l) - 1], levelBase[size_t(l)]);
    const uint32_t refinedTotal = levelBase.back();
    uint32_t localCount = 0;
    if (const Far::StencilTableReal<float>* local =
            lp.patches->GetLocalPointStencilTable<float>()) {
        limitStencils.appendTable(*local, refinedTotal);
        localCount = uint32_t(local->GetNumStencils());
    }
    limitStencils.numPoints = refinedTotal + localCount;
}

// Home location (ptex face, (u,v) clamped, patch) of each corner of
// refined(); faces with a corner off every patch (boundary faces under
// BoundaryInterpolation::None) leave the limit mesh: dropFace, and holes of
// refined() so the render split skips them.
void Subdivider::Impl::locateHomes(const Far::TopologyRefiner& uniform, const LimitPatches& lp,
                                   LimitHomes& homes, std::vector<uint8_t>& dropFace) {
    locateCorners(uniform, homes.cornerPtex, homes.cornerUV);
    homes.offsets = faceOffsets(refined);
    dropFace.assign(refined.faceSizes.size(), 0);
    homes.cornerHandle.assign(homes.cornerPtex.size(), nullptr);
    par.each(refined.faceSizes.size(), [&](size_t f) {
        for (uint32_t c = homes.offsets[f]; c < homes.offsets[f + 1]; ++c) {
            glm::vec2& uv = homes.cornerUV[c];
            uv = glm::vec2(clampParam(uv.x), clampParam(uv.y));
            homes.cornerHandle[c] = lp.patchMap->FindPatch(int(homes.cornerPtex[c]), uv.x, uv.y);
            if (!homes.cornerHandle[c]) dropFace[f] = 1;
        }
    });
    refined.holes.clear();
    for (uint32_t f = 0; f < dropFace.size(); ++f) {
        if (dropFace[f]) refined.holes.push_back(f);
    }
}

// Per render vertex: the derivative location and the sample's basis
// weights (value at the home corner, derivatives at the derivative
// location), and the LimitFrame's home location.
//
// Derivative locations: the corner moved kInward of the way to its face's
// centre. At the corner itself the derivatives of an end-cap patch can be
// singular (Gregory weights are 0/0 there; a sharp corner of a one-face
// sector came out with a flipped normal), and a corner on a sharp crease
// belongs to patches on both sides: a point just inside the home face picks
// that face's side. The shift is 2^-12 of the face's size, so derivatives
// move by O(2^-12 h |P''|), far below float noise in the tangent plane.
void Subdivider::Impl::buildSamples(const LimitPatches& lp, LimitHomes& homes) {
    const std::vector<uint32_t>& offsets = homes.offsets;
    const size_t nR = split.renderFirstCorner.size();
    const std::vector<uint32_t> faceOf = detail::cornerFaces(offsets);
    homes.derivUV.resize(nR);
    homes.derivHandle.resize(nR);
    samples.clear();
    frame = LimitFrame();
    frame.ptexFace.resize(nR);
    frame.ptexUV.resize(nR);
    // Fixed blocks of render vertices, each its own table, appended in
    // block order: the same table for every thread count.
    std::vector<SampleTable> block((nR + detail::kFixedBlock - 1) / detail::kFixedBlock);
    par.fixedBlocks(nR, [&](size_t k, size_t begin, size_t end) {
        SampleTable& t = block[k];
        t.clear();
        for (size_t r = begin; r < end; ++r) addSample(lp, homes, faceOf, r, t);
    });
    for (const SampleTable& t : block) samples.append(t);
}

// buildSamples for render vertex r, appended to `table`.
void Subdivider::Impl::addSample(const LimitPatches& lp, LimitHomes& homes,
                                 const std::vector<uint32_t>& faceOf, size_t r,
                                 SampleTable& table) {
    constexpr float kInward = 1.0f / 4096.0f;
    const Far::PatchTable& patches = *lp.patches;
    const std::vector<uint32_t>& offsets = homes.offsets;
    float wP[20], wDu[20], wDv[20];
    uint32_t c = split.renderFirstCorner[r];
    uint32_t f = faceOf[c];
    glm::vec2 centre(0.0f);
    bool onePtex = true;
    for (uint32_t k = offsets[f]; k < offsets[f + 1]; ++k) {
        centre += homes.cornerUV[k];
        onePtex &= homes.cornerPtex[k] == homes.cornerPtex[c];
    }
    centre /= float(offsets[f + 1] - offsets[f]);
    // A level-0 polygon that is not a quad spans one ptex sub-face per
    // corner; the corner sits at (0,0) of its sub-face, whose centre is (0.5,0.5).
    if (!onePtex) centre = glm::vec2(0.5f);
    glm::vec2 d = homes.cornerUV[c] + kInward * (centre - homes.cornerUV[c]);
    glm::vec2& derivUV = homes.derivUV[r];
    const Far::PatchMap::Handle*& derivHandle = homes.derivHandle[r];
    derivUV = glm::vec2(clampParam(d.x), clampParam(d.y));
    derivHandle = lp.patchMap->FindPatch(int(homes.cornerPtex[c]), derivUV.x, derivUV.y);
    if (!derivHandle)
        derivHandle = homes.cornerHandle[c]; // cannot happen inside a face with patches

    const Far::PatchMap::Handle* h = homes.cornerHandle[c];
    float u = clampParam(homes.cornerUV[c].x), v = clampParam(homes.cornerUV[c].y);
    float wValue[20];
    patches.EvaluateBasis(*h, u, v, wValue, wDu, wDv);
    // A regular (B-spline) patch has well-defined derivatives at its
    // corners: evaluate the home face's patch at the corner itself (fewer
    // non-zero weights, no shift); end caps keep the shifted point.
    glm::vec2 at = derivUV;
    if (patches.GetPatchDescriptor(*derivHandle).GetType() == Far::PatchDescriptor::REGULAR)
        at = glm::vec2(u, v);
    patches.EvaluateBasis(*derivHandle, at.x, at.y, wP, wDu, wDv);
    int n = patches.GetPatchVertices(*derivHandle).size();
    toPtexUnits(patches.GetPatchParam(*derivHandle), n, wDu, wDv);
    table.add(patches.GetPatchVertices(*h), wValue, patches.GetPatchVertices(*derivHandle), wDu,
              wDv);
    frame.ptexFace[r] = homes.cornerPtex[c];
    frame.ptexUV[r] = glm::vec2(u, v);
}

// Limit positions, dP/du, dP/dv and normals of the render vertices, and the
// same for every morph target's deltas.
void Subdivider::Impl::evaluatePositions(const PolygonMesh& cage) {
    const size_t nR = split.renderFirstCorner.size();
    points.resize(limitStencils.numPoints);
    // Positions relative to `origin` (boxCentre: morph deltas need none).
    auto evalVec3 = [&](const std::vector<glm::vec3>& control, glm::vec3 origin, glm::vec3* value,
                        std::vector<glm::vec3>& du, std::vector<glm::vec3>& dv) {
        par.each(control.size(), [&](size_t v) { points[v] = control[v] - origin; });
        limitStencils.apply(points.data(), par);
        du.resize(nR);
        dv.resize(nR);
        samples.evaluate(points.data(), value, du.data(), dv.data(), par);
        par.each(nR, [&](size_t r) { value[r] += origin; });
    };
    evalVec3(cage.positions, boxCentre(cage.positions.data(), cage.positions.size()),
             render.positions.data(), frame.dPdu, frame.dPdv);
    render.normals.resize(nR);
    par.each(nR, [&](size_t r) {
        // Fallback for a degenerate limit point: the refined face normal.
        render.normals[r] = safeNormal(frame.dPdu[r], frame.dPdv[r], render.normals[r]);
    });
    unifyCopies(render.positions.data(), render.normals.data());
    frame.morphDPdu.resize(cage.morphTargets.size());
    frame.morphDPdv.resize(cage.morphTargets.size());
    for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
        evalVec3(cage.morphTargets[t].positionDeltas, glm::vec3(0.0f),
                 render.morphTargets[t].positionDeltas.data(), frame.morphDPdu[t],
                 frame.morphDPdv[t]);
        std::vector<glm::vec3>& d = render.morphTargets[t].positionDeltas;
        par.each(nR, [&](size_t r) {
            if (positionRep[r] != r) d[r] = d[positionRep[r]];
        });
    }
}

// Every UV set's limit value at each render vertex's home corner and its
// derivatives at the derivative location (same locations as the
// positions').
void Subdivider::Impl::evaluateUvSets(const PolygonMesh& cage, const LimitPatches& lp,
                                      const LimitHomes& homes) {
    const Far::PatchTable& patches = *lp.patches;
    const size_t nR = split.renderFirstCorner.size();
    frame.dUVdu.assign(cage.uvSets.size(), {});
    frame.dUVdv.assign(cage.uvSets.size(), {});
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        const int ch = int(s);
        const std::vector<glm::vec2> values = limitUvPoints(cage, lp, s);
        auto evalUv = [&](const Far::PatchMap::Handle* h, glm::vec2 at, glm::vec2& value,
                          glm::vec2& du, glm::vec2& dv) {
            float wP[20], wDu[20], wDv[20];
            patches.EvaluateBasisFaceVarying(*h, at.x, at.y, wP, wDu, wDv, nullptr, nullptr,
                                             nullptr, ch);
            Far::ConstIndexArray cvs = patches.GetPatchFVarValues(*h, ch);
            toPtexUnits(patches.GetPatchFVarPatchParam(*h, ch), cvs.size(), wDu, wDv);
            value = du = dv = glm::vec2(0.0f);
            for (int k = 0; k < cvs.size(); ++k) {
                const glm::vec2& x = values[size_t(cvs[k])];
                value += wP[k] * x;
                du += wDu[k] * x;
                dv += wDv[k] * x;
            }
        };
        std::vector<glm::vec2>& outUV = render.uvSets[s];
        frame.dUVdu[s].resize(nR);
        frame.dUVdv[s].resize(nR);
        par.each(nR, [&](size_t r) {
            uint32_t c = split.renderFirstCorner[r];
            glm::vec2 q, du, dv, unused;
            evalUv(homes.cornerHandle[c],
                   glm::vec2(clampParam(homes.cornerUV[c].x), clampParam(homes.cornerUV[c].y)), q,
                   unused, unused);
            evalUv(homes.derivHandle[r], homes.derivUV[r], unused, du, dv);
            outUV[r] = q;
            frame.dUVdu[s][r] = du;
            frame.dUVdv[s][r] = dv;
        });
    }
}

// refined() gets the limit positions and UVs too (per refined vertex / per
// UV value: from the render vertex that is home to it).
void Subdivider::Impl::copyLimitToRefined(const PolygonMesh& cage) {
    for (size_t r = 0; r < split.renderFirstCorner.size(); ++r) {
        uint32_t c = split.renderFirstCorner[r];
        refined.positions[refined.faceVertices[c]] = render.positions[r];
        refined.normals[refined.faceVertices[c]] = render.normals[r];
        for (size_t t = 0; t < cage.morphTargets.size(); ++t) {
            refined.morphTargets[t].positionDeltas[refined.faceVertices[c]] =
                render.morphTargets[t].positionDeltas[r];
        }
        for (size_t s = 0; s < cage.uvSets.size(); ++s)
            refined.uvSets[s].values[refined.uvSets[s].indices[c]] = render.uvSets[s][r];
    }
}

// Limit evaluation (docs/mesh.md, "Limit evaluation"): patches of an
// adaptively refined copy of the cage, the stencils from the cage to their
// points, every corner's home location, the render mesh over the faces
// that have patches, one sample per render vertex, then positions,
// normals, morph deltas and UVs with their derivatives.
void Subdivider::Impl::evaluateLimit(const PolygonMesh& cage, const Far::TopologyRefiner& uniform,
                                     std::vector<uint8_t>& dropFace) {
    detail::Stopwatch sw;
    const LimitPatches lp = buildPatches(cage);
    recordLimitStencils(cage, lp);
    LimitHomes homes;
    locateHomes(uniform, lp, homes, dropFace);
    timings.limit += sw.lap();
    // Render vertices over the surviving faces (the split needs dropFace).
    buildRender();
    timings.render = sw.lap();
    buildSamples(lp, homes);
    evaluatePositions(cage);
    evaluateUvSets(cage, lp, homes);
    copyLimitToRefined(cage);
    timings.limit += sw.lap();
}

} // namespace sg::mesh

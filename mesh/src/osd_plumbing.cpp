// OpenSubdiv plumbing (osd_plumbing.h).
#include "osd_plumbing.h"

#include <opensubdiv/far/error.h>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/stencilTable.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <mutex>

#include "factored_stencils.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/osd_primvar.h"

namespace sg::mesh::detail {

using io::InputError;

thread_local std::string tFarError;

namespace {

void farError(Far::ErrorType, const char* message) {
    if (tFarError.size() < 400) tFarError += (tFarError.empty() ? "" : "; ") + std::string(message);
}
void farWarning(const char*) {} // warnings are about topology we validated already

} // namespace

void installFarCallbacks() {
    static std::once_flag once;
    std::call_once(once, [] {
        Far::SetErrorCallback(&farError);
        Far::SetWarningCallback(&farWarning);
    });
}

Sdc::SchemeType sdcScheme(Scheme s) {
    switch (s) {
    case Scheme::Loop:
        return Sdc::SCHEME_LOOP;
    case Scheme::Bilinear:
        return Sdc::SCHEME_BILINEAR;
    default:
        return Sdc::SCHEME_CATMARK;
    }
}

Sdc::Options sdcOptions(const SubdivOptions& o) {
    Sdc::Options opt;
    static constexpr Sdc::Options::VtxBoundaryInterpolation kVtx[3] = {
        Sdc::Options::VTX_BOUNDARY_NONE, Sdc::Options::VTX_BOUNDARY_EDGE_ONLY,
        Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER};
    static constexpr Sdc::Options::FVarLinearInterpolation kFVar[6] = {
        Sdc::Options::FVAR_LINEAR_NONE,          Sdc::Options::FVAR_LINEAR_CORNERS_ONLY,
        Sdc::Options::FVAR_LINEAR_CORNERS_PLUS1, Sdc::Options::FVAR_LINEAR_CORNERS_PLUS2,
        Sdc::Options::FVAR_LINEAR_BOUNDARIES,    Sdc::Options::FVAR_LINEAR_ALL};
    opt.SetVtxBoundaryInterpolation(kVtx[int(o.boundary)]);
    opt.SetFVarLinearInterpolation(kFVar[int(o.fvar)]);
    opt.SetCreasingMethod(o.creaseMethod == CreaseMethod::Chaikin ? Sdc::Options::CREASE_CHAIKIN
                                                                  : Sdc::Options::CREASE_UNIFORM);
    opt.SetTriangleSubdivision(o.triangles == TriangleRule::Smooth ? Sdc::Options::TRI_SUB_SMOOTH
                                                                   : Sdc::Options::TRI_SUB_CATMARK);
    return opt;
}

void Descriptor::build(const PolygonMesh& cage) {
    creasePairs.clear();
    creaseWeights.clear();
    for (const EdgeCrease& c : cage.creases) {
        creasePairs.push_back(int(c.v0));
        creasePairs.push_back(int(c.v1));
        creaseWeights.push_back(c.sharpness);
    }
    corners.clear();
    cornerWeights.clear();
    for (const VertexCorner& c : cage.corners) {
        corners.push_back(int(c.vertex));
        cornerWeights.push_back(c.sharpness);
    }
    holes.assign(cage.holes.begin(), cage.holes.end());
    channels.resize(cage.uvSets.size());
    for (size_t s = 0; s < cage.uvSets.size(); ++s) {
        channels[s].numValues = int(cage.uvSets[s].values.size());
        // uint32_t and int may alias (same type, other signedness).
        channels[s].valueIndices =
            reinterpret_cast<const Far::Index*>(cage.uvSets[s].indices.data());
    }
    desc = Far::TopologyDescriptor();
    desc.numVertices = int(cage.positions.size());
    desc.numFaces = int(cage.faceSizes.size());
    desc.numVertsPerFace = reinterpret_cast<const int*>(cage.faceSizes.data());
    desc.vertIndicesPerFace = reinterpret_cast<const Far::Index*>(cage.faceVertices.data());
    desc.numCreases = int(creaseWeights.size());
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseWeights.data();
    desc.numCorners = int(corners.size());
    desc.cornerVertexIndices = corners.data();
    desc.cornerWeights = cornerWeights.data();
    desc.numHoles = int(holes.size());
    desc.holeIndices = holes.data();
    desc.numFVarChannels = int(channels.size());
    desc.fvarChannels = channels.empty() ? nullptr : channels.data();
    desc.isLeftHanded = false;
}

std::unique_ptr<Far::TopologyRefiner> createRefiner(const Descriptor& d, const SubdivOptions& o,
                                                    const std::string& file) {
    installFarCallbacks();
    tFarError.clear();
    using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
    std::unique_ptr<Far::TopologyRefiner> r(
        Factory::Create(d.desc, Factory::Options(sdcScheme(o.scheme), sdcOptions(o))));
    if (!r)
        throw InputError(file, "topology",
                         "OpenSubdiv rejected the mesh: " +
                             (tFarError.empty() ? std::string("no reason given") : tFarError));
    return r;
}

std::vector<glm::vec2> fvarPatchPoints(const Far::TopologyRefiner& adaptive,
                                       const Far::PatchTable& table,
                                       const std::vector<glm::vec2>& cageValues, int ch) {
    std::vector<uint32_t> fvBase(size_t(adaptive.GetNumLevels()) + 1, 0);
    for (int l = 0; l < adaptive.GetNumLevels(); ++l) {
        fvBase[size_t(l) + 1] =
            fvBase[size_t(l)] + uint32_t(adaptive.GetLevel(l).GetNumFVarValues(ch));
    }
    const Far::StencilTableReal<float>* local =
        table.GetLocalPointFaceVaryingStencilTable<float>(ch);
    std::vector<glm::vec2> values(fvBase.back() + (local ? size_t(local->GetNumStencils()) : 0));
    std::copy(cageValues.begin(), cageValues.end(), values.begin());
    Far::PrimvarRefiner primvar(adaptive);
    for (int l = 1; l < adaptive.GetNumLevels(); ++l) {
        PrimvarView<const glm::vec2> src{values.data() + fvBase[size_t(l) - 1]};
        PrimvarView<glm::vec2> dst{values.data() + fvBase[size_t(l)]};
        primvar.InterpolateFaceVarying(l, src, dst, ch);
    }
    if (local) {
        FactoredStencils localPoints;
        localPoints.appendTable(*local, fvBase.back());
        localPoints.apply(values.data());
    }
    return values;
}

} // namespace sg::mesh::detail

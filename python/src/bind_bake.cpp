// Python binding of the limit-surface baker (surfgrad/bake/baker.h, docs/bake.md):
// surfgrad.bake(high, cage, ...) -> dict of numpy grids and counts. Grids
// are (H, W[, C]) with row 0 the bottom row, like every grid of the module.
#include <string>
#include <utility>

#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "grids.h"
#include "mesh_objects.h"
#include "surfgrad/bake/baker.h"

namespace sg::python {

namespace {

py::dict statsDict(const sg::bake::BakeStats& s) {
    py::dict d;
    d["chart_texels"] = s.chartTexels;
    d["hits"] = s.hits;
    d["misses"] = s.misses;
    d["padded"] = s.padded;
    d["overlap_texels"] = s.overlapTexels;
    d["primitives"] = s.patches;
    d["max_uv_residual_texels"] = s.maxUvResidualTexels;
    d["max_distance"] = s.maxDistance;
    d["max_abs_displacement"] = s.maxAbsDisplacement;
    py::dict sec;
    sec["patches"] = s.secondsPatches;
    sec["high_mesh"] = s.secondsHighMesh;
    sec["cover"] = s.secondsCover;
    sec["texels"] = s.secondsTexels;
    sec["pad"] = s.secondsPad;
    d["seconds"] = sec;
    return d;
}

// (W, H) from an int or a (width, height) pair.
std::pair<int, int> sizeArg(py::handle size) {
    if (py::isinstance<py::int_>(size)) {
        const int n = size.cast<int>();
        return {n, n};
    }
    const auto wh = size.cast<std::pair<int, int>>();
    return wh;
}

py::dict bake(const sg::mesh::RenderMesh& high, const sg::mesh::PolygonMesh& cage, py::handle size,
              int uvSet, const std::string& surface, int level, int isolation, double maxDistance,
              int pad, bool residual, int threads, uint64_t memoryBudget) {
    checkRenderMeshArrays(high);
    checkCageArrays(cage);
    sg::bake::BakeSettings s;
    std::tie(s.width, s.height) = sizeArg(size);
    s.uvSet = uvSet;
    if (surface == "limit")
        s.surface = sg::bake::BakeSurface::Limit;
    else if (surface == "refined")
        s.surface = sg::bake::BakeSurface::Refined;
    else
        throwUnknownName("surface", surface, {"limit", "refined"});
    s.refinedLevel = level;
    s.isolation = isolation;
    s.maxDistance = maxDistance;
    s.padTexels = pad;
    s.residual = residual;
    s.threads = requireThreads(threads);
    s.memoryBudget = memoryBudget;
    sg::bake::BakeResult r;
    {
        py::gil_scoped_release release;
        r = sg::bake::bake(cage, high, s, cage.name.empty() ? "cage" : cage.name,
                           high.name.empty() ? "high" : high.name);
    }
    py::dict out;
    out["state"] = gridToArray(std::move(r.state));
    out["displacement"] = gridToArray(std::move(r.displacement));
    out["object_normal"] = gridToArray(std::move(r.objectNormal));
    out["tangent_slopes"] = gridToArray(std::move(r.tangentSlopes));
    if (residual) out["residual_slopes"] = gridToArray(std::move(r.residualSlopes));
    out["position"] = gridToArray(std::move(r.basePosition));
    out["normal"] = gridToArray(std::move(r.baseNormal));
    out["tangent"] = gridToArray(std::move(r.baseTangent));
    out["stats"] = statsDict(r.stats);
    return out;
}

} // namespace

void bindBake(py::module_& m) {
    m.def("bake", &bake, py::arg("high"), py::arg("cage"), py::kw_only(), py::arg("size") = 1024,
          py::arg("uv_set") = 0, py::arg("surface") = "limit", py::arg("level") = 2,
          py::arg("isolation") = 4, py::arg("max_distance") = 0.0, py::arg("pad") = 8,
          py::arg("residual") = false, py::arg("threads") = 0, py::arg("memory_budget") = 0,
          R"(Bake `high` (RenderMesh) onto the limit surface of `cage` (PolygonMesh,
Catmull-Clark; surface="refined": the cage refined to `level` and triangulated,
MikkTSpace frames) in the layout of its UV set `uv_set` (docs/bake.md).
size: N or (width, height). Returns a dict of (H, W[, C]) arrays, row 0 at the
bottom: state (uint8: 0 empty, 1 hit, 2 miss, 3 padding), displacement (object
units along the base normal, + outwards), object_normal (3), tangent_slopes (2,
dh/ds and dh/dt in the base frame: normalmap.normals_from_slopes gives the
tangent-space map), residual_slopes (with residual=True: 2, the residual after displacement in the
same frame; pair it with a height layer of the displacement), position, normal (3) and tangent (4: xyz, sign) of the base
surface at each texel; and stats (counts, seconds). Raises InputError for bad
input (no UV set, a scheme the limit bake cannot take, no ray hitting `high`,
...) and ValueError for bad arguments.)");
}

} // namespace sg::python

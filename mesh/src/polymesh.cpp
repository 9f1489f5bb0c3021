// PolygonMesh <-> OpenMesh::PolyMesh with custom properties
// (surfgrad/mesh/polymesh.h). OpenMesh's add_face returns an invalid handle for a
// face it cannot insert (complex edge or vertex); that becomes an
// InputError here instead of a silently missing face.
#include "surfgrad/mesh/polymesh.h"

#include <map>

#include "mesh_internal.h"

namespace sg::mesh {

using io::InputError;

PolyMesh toPolyMesh(const PolygonMesh& mesh, PolyMeshProperties& props, const std::string& file) {
    PolyMesh pm;
    pm.reserve(mesh.positions.size(), mesh.faceVertices.size() / 2 + 1, mesh.faceSizes.size());
    for (const glm::vec3& p : mesh.positions) pm.add_vertex(PolyMesh::Point(p.x, p.y, p.z));
    props.uvSets.clear();
    for (const FaceVaryingChannel& ch : mesh.uvSets) {
        OpenMesh::HPropHandleT<OpenMesh::Vec2f> h;
        pm.add_property(h, "uv:" + ch.name);
        props.uvSets.push_back(h);
    }
    pm.add_property(props.edgeSharpness, "edge_sharpness");
    pm.add_property(props.cornerSharpness, "corner_sharpness");
    pm.add_property(props.hole, "hole");
    std::vector<PolyMesh::VertexHandle> vh;
    std::vector<uint8_t> isHole(mesh.faceSizes.size(), 0);
    for (uint32_t h : mesh.holes) {
        if (h < isHole.size()) isHole[h] = 1;
    }
    size_t c0 = 0;
    for (size_t f = 0; f < mesh.faceSizes.size(); ++f) {
        uint32_t k = mesh.faceSizes[f];
        vh.clear();
        for (uint32_t j = 0; j < k; ++j)
            vh.push_back(PolyMesh::VertexHandle(int(mesh.faceVertices[c0 + j])));
        // OpenMesh prints "complex edge/vertex" on omerr; the error below says it instead.
        bool errOn = ::omerr().is_enabled();
        ::omerr().disable();
        PolyMesh::FaceHandle fh = pm.add_face(vh);
        if (errOn) ::omerr().enable();
        if (!fh.is_valid()) {
            throw InputError(file, "face " + std::to_string(f),
                             "OpenMesh cannot insert it (complex edge or vertex: non-manifold or "
                             "inconsistently oriented)");
        }
        pm.property(props.hole, fh) = isHole[f] != 0;
        // Corner j's UV goes to the halfedge of this face pointing to vertex j.
        for (PolyMesh::FaceHalfedgeIter it = pm.fh_iter(fh); it.is_valid(); ++it) {
            int to = pm.to_vertex_handle(*it).idx();
            for (uint32_t j = 0; j < k; ++j) {
                if (int(mesh.faceVertices[c0 + j]) != to) continue;
                for (size_t s = 0; s < mesh.uvSets.size(); ++s) {
                    const glm::vec2& t = mesh.uvSets[s].values[mesh.uvSets[s].indices[c0 + j]];
                    pm.property(props.uvSets[s], *it) = OpenMesh::Vec2f(t.x, t.y);
                }
                break;
            }
        }
        c0 += k;
    }
    for (PolyMesh::EdgeHandle e : pm.edges()) pm.property(props.edgeSharpness, e) = 0.0f;
    for (PolyMesh::VertexHandle v : pm.vertices()) pm.property(props.cornerSharpness, v) = 0.0f;
    for (const EdgeCrease& c : mesh.creases) {
        PolyMesh::HalfedgeHandle h =
            pm.find_halfedge(PolyMesh::VertexHandle(int(c.v0)), PolyMesh::VertexHandle(int(c.v1)));
        if (!h.is_valid())
            h = pm.find_halfedge(PolyMesh::VertexHandle(int(c.v1)),
                                 PolyMesh::VertexHandle(int(c.v0)));
        if (!h.is_valid()) {
            throw InputError(file,
                             "crease (" + std::to_string(c.v0) + ", " + std::to_string(c.v1) + ")",
                             "not an edge of the mesh");
        }
        pm.property(props.edgeSharpness, pm.edge_handle(h)) = c.sharpness;
    }
    for (const VertexCorner& k : mesh.corners) {
        pm.property(props.cornerSharpness, PolyMesh::VertexHandle(int(k.vertex))) = k.sharpness;
    }
    return pm;
}

PolygonMesh fromPolyMesh(const PolyMesh& pm, const PolyMeshProperties& props) {
    PolygonMesh out;
    out.positions.reserve(pm.n_vertices());
    for (PolyMesh::VertexHandle v : pm.vertices()) {
        const PolyMesh::Point& p = pm.point(v);
        out.positions.push_back(glm::vec3(p[0], p[1], p[2]));
    }
    out.uvSets.resize(props.uvSets.size());
    for (size_t s = 0; s < props.uvSets.size(); ++s)
        out.uvSets[s].name = pm.property(props.uvSets[s]).name();
    // Per (vertex, uv set): distinct values seen so far, for deduplication.
    std::vector<std::vector<std::map<std::pair<float, float>, uint32_t>>> seen(props.uvSets.size());
    for (auto& s : seen) s.resize(pm.n_vertices());
    for (PolyMesh::FaceHandle f : pm.faces()) {
        uint32_t k = 0;
        for (PolyMesh::FaceHalfedgeIter it = pm.cfh_iter(f); it.is_valid(); ++it, ++k) {
            uint32_t v = uint32_t(pm.to_vertex_handle(*it).idx());
            out.faceVertices.push_back(v);
            for (size_t s = 0; s < props.uvSets.size(); ++s) {
                const OpenMesh::Vec2f& t = pm.property(props.uvSets[s], *it);
                auto [pos, inserted] = seen[s][v].emplace(std::make_pair(t[0], t[1]),
                                                          uint32_t(out.uvSets[s].values.size()));
                if (inserted) out.uvSets[s].values.push_back(glm::vec2(t[0], t[1]));
                out.uvSets[s].indices.push_back(pos->second);
            }
        }
        out.faceSizes.push_back(k);
        if (pm.property(props.hole, f)) out.holes.push_back(uint32_t(f.idx()));
    }
    // OpenMesh's face halfedge loop starts at the face's halfedge, which may
    // not be the first corner given to add_face: rotation does not change
    // the face, so this is fine for every consumer.
    for (PolyMesh::EdgeHandle e : pm.edges()) {
        float s = pm.property(props.edgeSharpness, e);
        if (s > 0.0f) {
            PolyMesh::HalfedgeHandle h = pm.halfedge_handle(e, 0);
            out.creases.push_back({uint32_t(pm.from_vertex_handle(h).idx()),
                                   uint32_t(pm.to_vertex_handle(h).idx()), s});
        }
    }
    for (PolyMesh::VertexHandle v : pm.vertices()) {
        float s = pm.property(props.cornerSharpness, v);
        if (s > 0.0f) out.corners.push_back({uint32_t(v.idx()), s});
    }
    return out;
}

} // namespace sg::mesh

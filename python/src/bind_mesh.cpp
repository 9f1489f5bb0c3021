// Python bindings of mesh/ (surfgrad/mesh/render_mesh.h, polygon_mesh.h,
// mesh_io.h): the two mesh types with numpy views of their arrays, loading
// every format the CLI reads, writing, validation and conversions.
//
// Views and safety: an array attribute (mesh.positions, ...) is a numpy view
// of the C++ vector whose base is the mesh object. A view must never outlive
// its buffer, so nothing the module does reallocates a vector of a mesh
// Python can see: assignment copies into the existing buffer (same shape),
// fills an optional array that was empty, or clears it (the capacity stays);
// operations that change the vertex count (weld, tangent splits, repair)
// return a NEW mesh.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.h"
#include "bindings.h"
#include "mesh_objects.h"
#include "surfgrad/mesh/mesh_io.h"

namespace sg::python {

using sg::mesh::PolygonMesh;
using sg::mesh::RenderMesh;

namespace {

template <class V>
constexpr size_t widthOf() {
    return sizeof(V) / sizeof(float);
}

// Assigns `value` (a (rows, width) float32 array) to `target` without
// reallocating a buffer a view may hold (see the file comment): same row
// count -> copy in place; an empty optional array -> filled (rows must be
// `optionalRows`); zero rows -> cleared (capacity kept).
template <class V>
void assignRows(std::vector<V>& target, py::handle value, const char* arg, size_t optionalRows,
                bool optional) {
    auto a = requireArray<float>(value, arg, {{kAny, "V"}, {py::ssize_t(widthOf<V>())}});
    requireFinite(a, arg);
    const auto rows = rowsOf<V>(a);
    if (rows.size() == target.size()) {
        std::copy(rows.begin(), rows.end(), target.begin());
    } else if (optional && rows.empty()) {
        target.clear();
    } else if (optional && target.empty() && rows.size() == optionalRows) {
        target.assign(rows.begin(), rows.end());
    } else {
        throw py::value_error(
            std::string(arg) + ": expected " + std::to_string(target.size()) + " rows" +
            (optional ? " (or " + std::to_string(optionalRows) + ", or 0)" : "") + ", got " +
            std::to_string(rows.size()) + "; build a new mesh to change the vertex count");
    }
}

// Topology views are read-only: the cage was validated with these indices.
py::array readOnly(py::array a) {
    a.attr("flags").attr("writeable") = false;
    return a;
}

template <class V>
py::array rowsView(std::vector<V>& v, py::handle owner) {
    return viewOf(reinterpret_cast<float*>(v.data()), v.size(), widthOf<V>(), owner);
}

template <class V>
void requireFiniteRows(const std::vector<V>& rows, const char* arg) {
    const auto* v = reinterpret_cast<const float*>(rows.data());
    const size_t width = widthOf<V>();
    for (size_t k = 0; k < rows.size() * width; ++k) {
        if (!std::isfinite(v[k])) {
            throw py::value_error(std::string(arg) + ": value at row " + std::to_string(k / width) +
                                  ", column " + std::to_string(k % width) + " is not finite");
        }
    }
}

// Arrays a view may have changed since the mesh was built are checked again
// before C++ reads them: indices in range, values finite, sizes agree.
void checkRenderMesh(const RenderMesh& m) {
    const size_t n = m.positions.size();
    if (m.indices.size() % 3 != 0) throw py::value_error("indices: not 3 per triangle");
    requireFiniteRows(m.positions, "positions");
    requireFiniteRows(m.normals, "normals");
    requireFiniteRows(m.tangents, "tangents");
    for (const auto& s : m.uvSets) requireFiniteRows(s, "uv_sets");
    requireIndicesBelow(m.indices, n, "indices", "vertices");
    if (!m.normals.empty() && m.normals.size() != n) {
        throw py::value_error("normals: expected " + std::to_string(n) + " rows (one per vertex)");
    }
    if (!m.tangents.empty() && m.tangents.size() != n) {
        throw py::value_error("tangents: expected " + std::to_string(n) + " rows (one per vertex)");
    }
    for (size_t s = 0; s < m.uvSets.size(); ++s) {
        if (m.uvSets[s].size() != n) {
            throw py::value_error("uv_sets[" + std::to_string(s) + "]: expected " +
                                  std::to_string(n) + " rows (one per vertex)");
        }
    }
    // A glTF file may carry TANGENT without the TEXCOORD it was made for:
    // tangent_uv_set then names a set the mesh does not have (kept as read).
    if (m.tangentUvSet < -1) {
        throw py::value_error("tangent_uv_set: " + std::to_string(m.tangentUvSet) +
                              " is not -1 or a UV set index");
    }
}

RenderMesh makeRenderMesh(py::handle positions, py::handle indices, py::handle normals,
                          const py::sequence& uvSets, py::handle tangents, int tangentUvSet,
                          const std::string& name) {
    RenderMesh m;
    m.name = name;
    auto p = requireArray<float>(positions, "positions", {{kAny, "V"}, {3}});
    requireFinite(p, "positions");
    m.positions = copyRows<glm::vec3>(p);
    auto idx = requireRows<uint32_t>(indices, "indices", 3);
    m.indices.assign(idx.data(), idx.data() + idx.size());
    if (!normals.is_none()) {
        auto nrm = requireArray<float>(normals, "normals", {{kAny, "V"}, {3}});
        requireFinite(nrm, "normals");
        m.normals = copyRows<glm::vec3>(nrm);
    }
    for (size_t s = 0; s < uvSets.size(); ++s) {
        const std::string arg = "uv_sets[" + std::to_string(s) + "]";
        auto uv = requireArray<float>(uvSets[s], arg.c_str(), {{kAny, "V"}, {2}});
        requireFinite(uv, arg.c_str());
        m.uvSets.push_back(copyRows<glm::vec2>(uv));
    }
    if (!tangents.is_none()) {
        auto t = requireArray<float>(tangents, "tangents", {{kAny, "V"}, {4}});
        requireFinite(t, "tangents");
        m.tangents = copyRows<glm::vec4>(t);
    }
    m.tangentUvSet = tangentUvSet;
    checkRenderMesh(m);
    return m;
}

py::dict reportDict(const sg::mesh::LoadReport& r) {
    py::dict d;
    d["notes"] = r.notes;
    d["degenerate_faces_dropped"] = r.degenerateFacesDropped;
    d["duplicate_vertices_welded"] = r.duplicateVerticesWelded;
    d["isolated_vertices"] = r.isolatedVertices;
    return d;
}

py::dict describeDict(const sg::mesh::MeshInfo& i) {
    py::dict d;
    d["vertices"] = i.vertices;
    d["faces"] = i.faces;
    d["corners"] = i.corners;
    d["isolated_vertices"] = i.isolatedVertices;
    d["face_degree_histogram"] = i.faceDegreeHistogram;
    d["edges"] = i.edges;
    d["boundary_edges"] = i.boundaryEdges;
    d["boundary_loops"] = i.boundaryLoops;
    d["non_manifold_edges"] = i.nonManifoldEdges;
    d["non_manifold_vertices"] = i.nonManifoldVertices;
    d["creases"] = i.creases;
    d["infinite_creases"] = i.infiniteCreases;
    d["corner_tags"] = i.cornerTags;
    d["holes"] = i.holes;
    d["manifold"] = i.manifold;
    d["euler_characteristic"] = i.eulerCharacteristic;
    return d;
}

sg::mesh::LoadOptions loadOptions(bool repair, int threads, bool allowOutside) {
    sg::mesh::LoadOptions o;
    o.repair = repair;
    o.threads = requireThreads(threads);
    o.limits.allowOutsideFolder = allowOutside;
    return o;
}

PolygonMesh makeCage(py::handle positions, py::handle faceSizes, py::handle faceVertices,
                     const py::sequence& uvSets, const std::string& scheme,
                     const std::vector<std::tuple<uint32_t, uint32_t, float>>& creases,
                     const std::vector<std::tuple<uint32_t, float>>& corners,
                     const std::vector<uint32_t>& holes, const std::string& name) {
    PolygonMesh m;
    m.name = name;
    auto p = requireArray<float>(positions, "positions", {{kAny, "V"}, {3}});
    m.positions = copyRows<glm::vec3>(p);
    auto fs = requireArray<uint32_t>(faceSizes, "face_sizes", {{kAny, "F"}});
    m.faceSizes.assign(fs.data(), fs.data() + fs.size());
    auto fv = requireArray<uint32_t>(faceVertices, "face_vertices", {{kAny, "C"}});
    m.faceVertices.assign(fv.data(), fv.data() + fv.size());
    for (size_t s = 0; s < uvSets.size(); ++s) {
        auto t = uvSets[s].cast<py::tuple>();
        if (t.size() != 3) {
            throw py::value_error("uv_sets[" + std::to_string(s) +
                                  "]: expected (name, values (K, 2), indices (C,))");
        }
        sg::mesh::FaceVaryingChannel ch;
        ch.name = t[0].cast<std::string>();
        auto values = requireArray<float>(t[1], "uv_sets values", {{kAny, "K"}, {2}});
        ch.values = copyRows<glm::vec2>(values);
        auto idx = requireArray<uint32_t>(t[2], "uv_sets indices", {{kAny, "C"}});
        ch.indices.assign(idx.data(), idx.data() + idx.size());
        m.uvSets.push_back(std::move(ch));
    }
    if (!sg::mesh::parseScheme(scheme, m.options.scheme)) {
        throwUnknownName("scheme", scheme, {"catmark", "loop", "bilinear"});
    }
    m.explicitTags |= sg::mesh::kTagScheme;
    for (const auto& [v0, v1, s] : creases) m.creases.push_back({v0, v1, s});
    for (const auto& [v, s] : corners) m.corners.push_back({v, s});
    m.holes = holes;
    // The loaders' checks (InputError naming the face, vertex or tag): a
    // cage built here is as valid as a loaded one.
    sg::mesh::validate(m, name.empty() ? "PolygonMesh" : name);
    return m;
}

void bindRenderMesh(py::module_& m) {
    py::class_<sg::mesh::MorphTarget>(m, "MorphTarget",
                                      "A blendshape of a RenderMesh: per-vertex deltas, object "
                                      "space (arrays are copies).")
        .def_readonly("name", &sg::mesh::MorphTarget::name)
        .def_property_readonly(
            "position_deltas",
            [](const sg::mesh::MorphTarget& t) { return copyToArray(t.positionDeltas); })
        .def_property_readonly(
            "normal_deltas",
            [](const sg::mesh::MorphTarget& t) { return copyToArray(t.normalDeltas); })
        .def_property_readonly("tangent_deltas", [](const sg::mesh::MorphTarget& t) {
            return copyToArray(t.tangentDeltas);
        });

    py::class_<RenderMesh> c(m, "RenderMesh", R"(Indexed triangle mesh with split vertices
(glTF's model): every per-vertex array has vertex_count rows. Object space,
right-handed, triangles counter-clockwise from the front; UV (0, 0) at the
lower left, t up; tangents xyz along +s with w = +-1 (bitangent =
w cross(normal, tangent)). Array attributes are views (writes go through,
the view keeps the mesh alive); assignment copies after checking dtype and
shape and never changes the vertex count.)");
    c.def(py::init(&makeRenderMesh), py::arg("positions"), py::arg("indices"),
          py::arg("normals") = py::none(), py::arg("uv_sets") = py::tuple(),
          py::arg("tangents") = py::none(), py::arg("tangent_uv_set") = -1, py::arg("name") = "")
        .def_readwrite("name", &RenderMesh::name)
        .def_property(
            "positions",
            [](py::object self) { return rowsView(self.cast<RenderMesh&>().positions, self); },
            [](RenderMesh& r, py::handle v) { assignRows(r.positions, v, "positions", 0, false); },
            "(V, 3) float32 view: object-space positions")
        .def_property(
            "normals",
            [](py::object self) { return rowsView(self.cast<RenderMesh&>().normals, self); },
            [](RenderMesh& r, py::handle v) {
                assignRows(r.normals, v, "normals", r.positions.size(), true);
            },
            "(V, 3) or (0, 3) float32 view: unit normals")
        .def_property(
            "tangents",
            [](py::object self) { return rowsView(self.cast<RenderMesh&>().tangents, self); },
            [](RenderMesh& r, py::handle v) {
                assignRows(r.tangents, v, "tangents", r.positions.size(), true);
            },
            "(V, 4) or (0, 4) float32 view: (tangent, sign)")
        .def_property(
            "tangent_uv_set", [](const RenderMesh& r) { return r.tangentUvSet; },
            [](RenderMesh& r, int s) {
                if (s < -1) {
                    throw py::value_error("tangent_uv_set: " + std::to_string(s) +
                                          " is not -1 or the index of a UV set");
                }
                r.tangentUvSet = s;
            })
        .def_property(
            "indices",
            [](py::object self) {
                auto& r = self.cast<RenderMesh&>();
                return viewOf(r.indices.data(), r.indices.size() / 3, 3, self);
            },
            [](RenderMesh& r, py::handle v) {
                auto a = requireArray<uint32_t>(v, "indices",
                                                {{py::ssize_t(r.indices.size() / 3), "T"}, {3}});
                requireIndicesBelow(valuesOf(a), r.positions.size(), "indices", "vertices");
                std::copy(a.data(), a.data() + a.size(), r.indices.begin());
            },
            "(T, 3) uint32 view: vertex indices, counter-clockwise")
        .def_property_readonly(
            "uv_sets",
            [](py::object self) {
                py::list sets;
                for (auto& s : self.cast<RenderMesh&>().uvSets) sets.append(rowsView(s, self));
                return sets;
            },
            "list of (V, 2) float32 views, one per UV set (set_uv_set replaces one)")
        .def(
            "set_uv_set",
            [](RenderMesh& r, int index, py::handle v) {
                if (index < 0 || index > int(r.uvSets.size())) {
                    throw py::value_error("index: " + std::to_string(index) + " is not 0.." +
                                          std::to_string(r.uvSets.size()));
                }
                if (index == int(r.uvSets.size())) {
                    r.uvSets
                        .emplace_back(); // moves the other sets' buffers, never reallocates them
                    try {
                        assignRows(r.uvSets.back(), v, "uvs", r.positions.size(), true);
                    } catch (...) {
                        r.uvSets.pop_back();
                        throw;
                    }
                    if (r.uvSets.back().empty()) r.uvSets.pop_back();
                } else {
                    assignRows(r.uvSets[size_t(index)], v, "uvs", 0, false);
                }
            },
            py::arg("index"), py::arg("uvs"),
            "Replaces UV set `index` with (V, 2) float32 `uvs` (index == len(uv_sets) appends).")
        .def_property_readonly("morph_targets", [](const RenderMesh& r) { return r.morphTargets; })
        .def_property_readonly("morph_weights",
                               [](const RenderMesh& r) { return copyToArray(r.morphWeights); })
        .def_property_readonly("vertex_count", &RenderMesh::vertexCount)
        .def_property_readonly("triangle_count", &RenderMesh::triangleCount)
        .def("copy", [](const RenderMesh& r) { return RenderMesh(r); })
        .def("__repr__", [](const RenderMesh& r) {
            return "<surfgrad.RenderMesh '" + r.name + "': " + std::to_string(r.vertexCount()) +
                   " vertices, " + std::to_string(r.triangleCount()) + " triangles, " +
                   std::to_string(r.uvSets.size()) + " UV sets" +
                   (r.tangents.empty() ? "" : ", tangents") + ">";
        });
}

void bindPolygonMesh(py::module_& m) {
    py::class_<PolygonMesh> c(m, "PolygonMesh", R"(A control cage: polygons with face-varying UV
sets and OpenSubdiv tags (what the loaders read and the Subdivider refines).
positions, face_sizes and face_vertices are views (positions assignable in
place); the other attributes are copies. The constructor validates the cage
like a loader (InputError naming the face, vertex or tag).)");
    c.def(py::init(&makeCage), py::arg("positions"), py::arg("face_sizes"),
          py::arg("face_vertices"), py::arg("uv_sets") = py::tuple(), py::arg("scheme") = "catmark",
          py::arg("creases") = std::vector<std::tuple<uint32_t, uint32_t, float>>{},
          py::arg("corners") = std::vector<std::tuple<uint32_t, float>>{},
          py::arg("holes") = std::vector<uint32_t>{}, py::arg("name") = "")
        .def_readwrite("name", &PolygonMesh::name)
        .def_property(
            "positions",
            [](py::object self) { return rowsView(self.cast<PolygonMesh&>().positions, self); },
            [](PolygonMesh& r, py::handle v) { assignRows(r.positions, v, "positions", 0, false); })
        .def_property_readonly("face_sizes",
                               [](py::object self) {
                                   auto& r = self.cast<PolygonMesh&>();
                                   return readOnly(
                                       viewOf(r.faceSizes.data(), r.faceSizes.size(), 1, self));
                               })
        .def_property_readonly(
            "face_vertices",
            [](py::object self) {
                auto& r = self.cast<PolygonMesh&>();
                return readOnly(viewOf(r.faceVertices.data(), r.faceVertices.size(), 1, self));
            })
        .def_property_readonly("normals",
                               [](const PolygonMesh& r) { return copyToArray(r.normals); })
        .def_property_readonly("normal_indices",
                               [](const PolygonMesh& r) { return copyToArray(r.normalIndices); })
        .def_property_readonly(
            "scheme", [](const PolygonMesh& r) { return sg::mesh::toString(r.options.scheme); })
        .def_property_readonly("uv_sets",
                               [](const PolygonMesh& r) {
                                   py::list sets;
                                   for (const auto& ch : r.uvSets) {
                                       sets.append(py::make_tuple(ch.name, copyToArray(ch.values),
                                                                  copyToArray(ch.indices)));
                                   }
                                   return sets;
                               })
        .def_property_readonly("creases",
                               [](const PolygonMesh& r) {
                                   py::list out;
                                   for (const auto& e : r.creases)
                                       out.append(py::make_tuple(e.v0, e.v1, e.sharpness));
                                   return out;
                               })
        .def_property_readonly("corners",
                               [](const PolygonMesh& r) {
                                   py::list out;
                                   for (const auto& e : r.corners)
                                       out.append(py::make_tuple(e.vertex, e.sharpness));
                                   return out;
                               })
        .def_readonly("holes", &PolygonMesh::holes)
        .def_property_readonly("morph_targets",
                               [](const PolygonMesh& r) {
                                   py::list out;
                                   for (const auto& t : r.morphTargets) {
                                       out.append(
                                           py::make_tuple(t.name, copyToArray(t.positionDeltas)));
                                   }
                                   return out;
                               })
        .def_property_readonly("morph_weights",
                               [](const PolygonMesh& r) { return copyToArray(r.morphWeights); })
        .def_property_readonly("vertex_count", &PolygonMesh::vertexCount)
        .def_property_readonly("face_count", &PolygonMesh::faceCount)
        .def_property_readonly("corner_count", &PolygonMesh::cornerCount)
        .def("copy", [](const PolygonMesh& r) { return PolygonMesh(r); })
        .def("__repr__", [](const PolygonMesh& r) {
            return "<surfgrad.PolygonMesh '" + r.name + "': " + std::to_string(r.vertexCount()) +
                   " vertices, " + std::to_string(r.faceCount()) + " faces, " +
                   sg::mesh::toString(r.options.scheme) + ">";
        });
}

void bindMeshIo(py::module_& m) {
    m.def(
        "load_mesh",
        [](const std::filesystem::path& path, bool repair, int threads, bool allowOutside) {
            const auto options = loadOptions(repair, threads, allowOutside);
            py::gil_scoped_release release;
            return sg::mesh::loadRenderMesh(path, options);
        },
        py::arg("path"), py::kw_only(), py::arg("repair") = false, py::arg("threads") = 0,
        py::arg("allow_outside_folder") = false,
        "Any of .obj .off .ply .stl .gltf .glb as a triangle mesh (polygons fanned, vertices split "
        "at UV and normal seams; glTF primitives merged in world space). InputError for a "
        "malformed or invalid file.");
    m.def(
        "load_cage",
        [](const std::filesystem::path& path, bool repair, int threads, bool allowOutside) {
            const auto options = loadOptions(repair, threads, allowOutside);
            py::gil_scoped_release release;
            return sg::mesh::loadPolygonMesh(path, options);
        },
        py::arg("path"), py::kw_only(), py::arg("repair") = false, py::arg("threads") = 0,
        py::arg("allow_outside_folder") = false, "Any supported file as a validated control cage.");
    m.def(
        "load_report",
        [](const std::filesystem::path& path, bool repair) {
            const auto options = loadOptions(repair, 0, false);
            sg::mesh::LoadReport report;
            {
                py::gil_scoped_release release;
                sg::mesh::loadPolygonMesh(path, options, &report);
            }
            return reportDict(report);
        },
        py::arg("path"), py::kw_only(), py::arg("repair") = false,
        "What loading `path` as a cage noted and repaired: notes, degenerate_faces_dropped, "
        "duplicate_vertices_welded, isolated_vertices.");
    m.def(
        "save_mesh",
        [](const std::filesystem::path& path, const RenderMesh& mesh, bool morphs) {
            checkRenderMesh(mesh);
            sg::mesh::WriteOptions o;
            o.writeMorphTargets = morphs;
            py::gil_scoped_release release;
            return sg::mesh::writeRenderMesh(path, mesh, o);
        },
        py::arg("path"), py::arg("mesh"), py::kw_only(), py::arg("write_morph_targets") = true,
        "Writes .gltf .glb .obj .ply atomically; returns one note per kind of data the format "
        "cannot hold.");
    m.def(
        "save_mesh",
        [](const std::filesystem::path& path, const PolygonMesh& mesh, bool morphs) {
            checkCageArrays(mesh);
            sg::mesh::WriteOptions o;
            o.writeMorphTargets = morphs;
            py::gil_scoped_release release;
            return sg::mesh::writePolygonMesh(path, mesh, o);
        },
        py::arg("path"), py::arg("mesh"), py::kw_only(), py::arg("write_morph_targets") = true);
    m.def(
        "validate",
        [](const PolygonMesh& cage, const std::string& name) {
            PolygonMesh copy = cage; // validate() without repair changes nothing; the copy
                                     // keeps that true whatever it becomes
            sg::mesh::LoadReport report;
            sg::mesh::validate(copy, name, false, &report);
            return reportDict(report);
        },
        py::arg("cage"), py::kw_only(), py::arg("name") = "mesh",
        "Checks a cage; raises InputError naming the first problem (element and reason). Returns "
        "the report.");
    m.def(
        "repaired",
        [](const PolygonMesh& cage, const std::string& name) {
            PolygonMesh copy = cage;
            sg::mesh::LoadReport report;
            sg::mesh::validate(copy, name, true, &report);
            return py::make_tuple(std::move(copy), reportDict(report));
        },
        py::arg("cage"), py::kw_only(), py::arg("name") = "mesh",
        "A repaired copy (bitwise-equal vertices welded, degenerate faces dropped) and the "
        "report; raises InputError for what repair cannot fix (non-manifold topology).");
    m.def(
        "describe", [](const PolygonMesh& cage) { return describeDict(sg::mesh::describe(cage)); },
        py::arg("cage"),
        "Topology summary (vertices, faces, edges, boundary loops, manifold, ...).");
    m.def(
        "weld",
        [](const RenderMesh& mesh, int threads) {
            requireThreads(threads);
            checkRenderMesh(mesh);
            RenderMesh out = mesh;
            size_t removed = 0;
            {
                py::gil_scoped_release release;
                removed = sg::mesh::weldVerticesByValue(out, threads);
            }
            return py::make_tuple(std::move(out), removed);
        },
        py::arg("mesh"), py::kw_only(), py::arg("threads") = 0,
        "(welded copy, vertices removed): vertices whose every attribute is bitwise equal become "
        "one, numbered in order of first occurrence.");
    m.def(
        "to_render_mesh",
        [](const PolygonMesh& cage) {
            checkCageArrays(cage);
            py::gil_scoped_release release;
            return sg::mesh::toRenderMesh(cage);
        },
        py::arg("cage"),
        "Triangulated (fans from corner 0, holes skipped), vertices split where a UV or normal "
        "index differs.");
    m.def(
        "to_polygon_mesh",
        [](const RenderMesh& mesh) {
            checkRenderMesh(mesh);
            PolygonMesh cage;
            {
                py::gil_scoped_release release;
                cage = sg::mesh::toPolygonMesh(mesh);
            }
            // A cage is what Subdivider takes: checked like a loaded one
            // (InputError for non-manifold or degenerate triangles).
            sg::mesh::validate(cage, mesh.name.empty() ? "RenderMesh" : mesh.name);
            return cage;
        },
        py::arg("mesh"),
        "The cage of a triangle mesh: vertices welded by bitwise-equal position, UV sets and "
        "normals face-varying; validated (InputError for non-manifold or degenerate triangles).");
}

} // namespace

void checkRenderMeshArrays(const RenderMesh& mesh) {
    checkRenderMesh(mesh);
}
void checkCageArrays(const PolygonMesh& cage) {
    requireFiniteRows(cage.positions, "positions");
}

void bindMesh(py::module_& m) {
    bindRenderMesh(m);
    bindPolygonMesh(m);
    bindMeshIo(m);
}

} // namespace sg::python

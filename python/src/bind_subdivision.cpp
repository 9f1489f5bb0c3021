// Python bindings of subdivision and blendshapes (surfgrad/mesh/subdivision.h,
// surfgrad/mesh/morph.h): OpenSubdiv uniform refinement, the limit surface with
// its derivatives (LimitFrame), stencil updates of animated cages, and
// glTF morph targets (sec. 3.7.2.2: P = P0 + sum_i w_i dP_i).
// Math: Catmull-Clark 1978, Loop 1987, DeRose-Kass-Truong 1998 (creases),
// as implemented by OpenSubdiv 3.5; docs/subdivision.md.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "mesh_objects.h"
#include "surfgrad/mesh/morph.h"
#include "surfgrad/mesh/subdivision.h"

namespace sg::python {

using sg::mesh::LimitFrame;
using sg::mesh::PolygonMesh;
using sg::mesh::RenderMesh;

namespace {

py::list copiesOf(const std::vector<std::vector<glm::vec2>>& sets) {
    py::list out;
    for (const auto& s : sets) out.append(copyToArray(s));
    return out;
}

sg::mesh::SubdivisionSettings makeSettings(const PolygonMesh& cage, int level, bool limit,
                                           bool animate, const std::optional<std::string>& scheme,
                                           const std::optional<std::string>& boundary,
                                           const std::optional<std::string>& fvar, int threads,
                                           uint64_t memoryBudget) {
    if (level < 0 || level > sg::mesh::kMaxSubdivisionLevel) {
        throw py::value_error("level: " + std::to_string(level) + " is not 0.." +
                              std::to_string(sg::mesh::kMaxSubdivisionLevel));
    }
    sg::mesh::SubdivisionSettings s;
    s.level = level;
    s.options = cage.options;
    s.limit = limit;
    s.animate = animate;
    s.threads = requireThreads(threads);
    s.memoryBudget = memoryBudget;
    s.memoryBudgetHint = "memory_budget=BYTES";
    if (scheme && !sg::mesh::parseScheme(*scheme, s.options.scheme)) {
        throwUnknownName("scheme", *scheme, {"catmark", "loop", "bilinear"});
    }
    if (boundary && !sg::mesh::parseBoundaryInterpolation(*boundary, s.options.boundary)) {
        throwUnknownName("boundary", *boundary, {"none", "edge-only", "edge-and-corner"});
    }
    if (fvar && !sg::mesh::parseFVarInterpolation(*fvar, s.options.fvar)) {
        throwUnknownName(
            "fvar", *fvar,
            {"smooth", "corners-only", "corners-plus1", "corners-plus2", "boundaries", "all"});
    }
    return s;
}

// A Subdivider that owns its cage's vertex count and the settings it was
// built with (update() checks them before the C++ preconditions).
class PySubdivider {
public:
    PySubdivider(const PolygonMesh& cage, int level, bool limit, bool animate,
                 const std::optional<std::string>& scheme,
                 const std::optional<std::string>& boundary, const std::optional<std::string>& fvar,
                 int threads, uint64_t memoryBudget) {
        checkCageArrays(cage);
        const auto settings = makeSettings(cage, level, limit, animate, scheme, boundary, fvar,
                                           threads, memoryBudget);
        py::gil_scoped_release release;
        sub_.build(cage, settings, cage.name.empty() ? "cage" : cage.name);
    }

    const sg::mesh::Subdivider& get() const { return sub_; }

    py::object update(py::handle cagePositions, py::object out, bool normals, bool withFrame) {
        if (!sub_.settings().animate) {
            throw py::value_error("update: build the Subdivider with animate=True");
        }
        if (withFrame && sub_.limitFrame().empty()) {
            throw py::value_error("update: frame=True needs a Subdivider built with limit=True");
        }
        const auto cageCount = py::ssize_t(sub_.cageVertexCount());
        auto p = requireArray<float>(cagePositions, "cage_positions", {{cageCount, "V"}, {3}});
        requireFinite(p, "cage_positions");
        const RenderMesh& base = sub_.renderMesh();
        RenderMesh result;
        RenderMesh* target = &result;
        if (!out.is_none()) {
            target = &out.cast<RenderMesh&>();
            // update() writes positions and normals in place when their sizes
            // already match, so views of `out` stay valid.
            if (target->positions.size() != base.positions.size() ||
                (normals && target->normals.size() != base.normals.size())) {
                throw py::value_error("out: expected a copy of render_mesh (" +
                                      std::to_string(base.positions.size()) +
                                      " vertices with normals)");
            }
        } else {
            result = base;
        }
        std::optional<LimitFrame> frame;
        if (withFrame) frame = sub_.limitFrame(); // update() rewrites dPdu and dPdv
        {
            py::gil_scoped_release release;
            sub_.update(rowsOf<glm::vec3>(p), *target, frame ? &*frame : nullptr, normals);
        }
        py::object mesh = out.is_none() ? py::cast(std::move(result)) : out;
        if (frame) return py::make_tuple(mesh, std::move(*frame));
        return mesh;
    }

private:
    sg::mesh::Subdivider sub_;
};

py::dict timingsDict(const sg::mesh::SubdivisionTimings& t) {
    py::dict d;
    d["convert_in"] = t.convertIn;
    d["topology"] = t.topology;
    d["interpolate"] = t.interpolate;
    d["convert_out"] = t.convertOut;
    d["limit"] = t.limit;
    d["render"] = t.render;
    d["stencils"] = t.stencils;
    return d;
}

void bindLimitFrame(py::module_& m) {
    py::class_<LimitFrame>(m, "LimitFrame", R"(Limit-surface derivatives aligned with a render
mesh's vertices, each w.r.t. the vertex's ptex (u, v): dPdu in object units
per unit parameter, dUVdu in UV units (t up). Arrays are copies.)")
        .def_property_readonly("dpdu", [](const LimitFrame& f) { return copyToArray(f.dPdu); })
        .def_property_readonly("dpdv", [](const LimitFrame& f) { return copyToArray(f.dPdv); })
        .def_property_readonly("duvdu", [](const LimitFrame& f) { return copiesOf(f.dUVdu); })
        .def_property_readonly("duvdv", [](const LimitFrame& f) { return copiesOf(f.dUVdv); })
        .def_property_readonly("ptex_face",
                               [](const LimitFrame& f) { return copyToArray(f.ptexFace); })
        .def_property_readonly("ptex_uv",
                               [](const LimitFrame& f) { return copyToArray(f.ptexUV); });
}

void bindSubdivider(py::module_& m) {
    py::class_<PySubdivider>(m, "Subdivider", R"(OpenSubdiv refinement of a cage to `level`
(uniform), optionally with limit evaluation (positions, normals and UVs on the
limit surface, derivatives in limit_frame), optionally with stencil tables for
animated cages (animate=True, then update()). scheme, boundary ("none",
"edge-only", "edge-and-corner") and fvar ("smooth", "corners-only",
"corners-plus1", "corners-plus2", "boundaries", "all") override the cage's
tags. A build whose estimated peak memory exceeds memory_budget (0: half the
machine) raises InputError before allocating.)")
        .def(py::init<const PolygonMesh&, int, bool, bool, const std::optional<std::string>&,
                      const std::optional<std::string>&, const std::optional<std::string>&, int,
                      uint64_t>(),
             py::arg("cage"), py::arg("level") = 2, py::kw_only(), py::arg("limit") = false,
             py::arg("animate") = false, py::arg("scheme") = py::none(),
             py::arg("boundary") = py::none(), py::arg("fvar") = py::none(), py::arg("threads") = 0,
             py::arg("memory_budget") = 0)
        .def_property_readonly(
            "refined", [](const PySubdivider& s) { return s.get().refined(); },
            "Level-N polygons (a copy).")
        .def_property_readonly(
            "render_mesh", [](const PySubdivider& s) { return s.get().renderMesh(); },
            "Triangulated refined mesh, split at UV seams and sharp creases (a "
            "copy).")
        .def_property_readonly("limit_frame",
                               [](const PySubdivider& s) -> std::optional<LimitFrame> {
                                   if (s.get().limitFrame().empty()) return std::nullopt;
                                   return s.get().limitFrame();
                               })
        .def_property_readonly(
            "render_to_refined_vertex",
            [](const PySubdivider& s) { return copyToArray(s.get().renderToRefinedVertex()); })
        .def("update", &PySubdivider::update, py::arg("cage_positions"), py::kw_only(),
             py::arg("out") = py::none(), py::arg("normals") = true, py::arg("frame") = false,
             "Positions and normals of render_mesh for new (V, 3) cage positions through the "
             "stencil tables (animate=True). `out` (a copy of render_mesh) is written in place "
             "and returned; otherwise a new mesh. frame=True (limit=True) returns (mesh, "
             "LimitFrame) with the moved surface's dpdu, dpdv (the UV derivatives do not change).")
        .def_property_readonly("timings",
                               [](const PySubdivider& s) { return timingsDict(s.get().timings()); })
        .def_property_readonly(
            "used_specialized_refiner",
            [](const PySubdivider& s) { return s.get().usedSpecializedRefiner(); })
        .def_property_readonly("stencil_weight_count",
                               [](const PySubdivider& s) { return s.get().stencilWeightCount(); });

    m.def(
        "estimate_subdivision_cost",
        [](const PolygonMesh& cage, int level, bool limit) {
            checkCageArrays(cage);
            const auto settings = makeSettings(cage, level, limit, false, std::nullopt,
                                               std::nullopt, std::nullopt, 0, 0);
            const auto c = sg::mesh::estimateSubdivisionCost(cage, settings);
            py::dict d;
            d["faces"] = c.faces;
            d["vertices"] = c.vertices;
            d["edges"] = c.edges;
            d["corners"] = c.corners;
            d["fvar_values"] = c.fvarValues;
            d["render_vertices"] = c.renderVertices;
            d["bytes"] = c.bytes;
            return d;
        },
        py::arg("cage"), py::arg("level"), py::kw_only(), py::arg("limit") = false,
        "Level-N counts and the peak bytes of a build, from the cage alone.");
}

std::vector<float> checkedWeights(py::handle weights, size_t targets) {
    auto w = requireArray<float>(weights, "weights", {{py::ssize_t(targets), "K"}});
    requireFinite(w, "weights");
    return {w.data(), w.data() + w.size()};
}

// A Morpher that owns its base mesh and frame.
class PyMorpher {
public:
    PyMorpher(const RenderMesh& mesh, std::optional<LimitFrame> frame)
        : base_(std::make_unique<RenderMesh>(mesh)),
          frame_(frame ? std::make_unique<LimitFrame>(std::move(*frame)) : nullptr) {
        checkRenderMeshArrays(*base_);
        if (frame_ && (frame_->dPdu.size() != base_->positions.size() ||
                       frame_->morphDPdu.size() != base_->morphTargets.size())) {
            throw py::value_error("frame: not the limit frame of this mesh");
        }
        morpher_ = std::make_unique<sg::mesh::Morpher>(*base_, frame_.get());
    }

    RenderMesh apply(py::handle weights, const std::string& normals) const {
        auto w = checkedWeights(weights, base_->morphTargets.size());
        sg::mesh::MorphNormals mode{};
        if (normals == "recompute") {
            mode = sg::mesh::MorphNormals::Recompute;
        } else if (normals == "blend") {
            mode = sg::mesh::MorphNormals::Blend;
        } else {
            throwUnknownName("normals", normals, {"recompute", "blend"});
        }
        RenderMesh out;
        py::gil_scoped_release release;
        morpher_->apply(w, mode, out);
        return out;
    }

private:
    std::unique_ptr<RenderMesh> base_;
    std::unique_ptr<LimitFrame> frame_;
    std::unique_ptr<sg::mesh::Morpher> morpher_;
};

void bindMorph(py::module_& m) {
    m.def(
        "morph_cage_positions",
        [](const PolygonMesh& cage, py::handle weights) {
            checkCageArrays(cage);
            auto w = checkedWeights(weights, cage.morphTargets.size());
            std::vector<glm::vec3> out;
            sg::mesh::morphCagePositions(cage, w, out);
            return moveToArray(std::move(out));
        },
        py::arg("cage"), py::arg("weights"),
        "cage.positions + sum_i weights[i] * morph target i's deltas ((V, 3) float32).");
    py::class_<PyMorpher>(m, "Morpher",
                          "Per-frame morphing of a RenderMesh (its morph_targets), with the limit "
                          "frame carried along when given.")
        .def(py::init<const RenderMesh&, std::optional<LimitFrame>>(), py::arg("mesh"),
             py::arg("frame") = py::none())
        .def("apply", &PyMorpher::apply, py::arg("weights"), py::arg("normals") = "recompute",
             "The morphed mesh: P = P0 + sum w_i dP_i; normals \"recompute\" (from the morphed "
             "geometry; tangents cleared) or \"blend\" (glTF's rule).");
}

} // namespace

void bindSubdivision(py::module_& m) {
    bindLimitFrame(m);
    bindSubdivider(m);
    bindMorph(m);
}

} // namespace sg::python

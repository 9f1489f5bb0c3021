// Python bindings of the tangent generators (surfgrad/mesh/tangents.h):
// MikkTSpace-exact tangents on plain arrays (read in place) and on meshes,
// the limit-surface tangent frame, and the reusable generator.
// Math: Mikkelsen 2008 (MikkTSpace) and 2019 (surface gradients, sec. 2.3
// for the limit frame's chain rule); docs/tangents.md.
#include <chrono>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "mesh_objects.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::python {

using sg::mesh::MikkTSpaceFrame;
using sg::mesh::MikkTSpaceGenerator;
using sg::mesh::MikkTSpaceInput;
using sg::mesh::RenderMesh;

namespace {

// The arrays of one MikkTSpace call, checked (dtype, shape, the
// preconditions of MikkTSpaceInput) and held while the C++ call reads them.
struct MikkArrays {
    py::array_t<float> positions, normals, uvs;
    py::array_t<uint32_t> corners, faceSizes;
    MikkTSpaceInput input;

    MikkArrays(py::handle p, py::handle n, py::handle uv, py::handle c, py::handle fs) {
        positions = requireArray<float>(p, "positions", {{kAny, "V"}, {3}});
        const py::ssize_t v = positions.shape(0);
        normals = requireArray<float>(n, "normals", {{v, "V"}, {3}});
        uvs = requireArray<float>(uv, "uvs", {{v, "V"}, {2}});
        if (fs.is_none()) {
            corners = requireRows<uint32_t>(c, "corner_vertices", 3);
        } else {
            corners = requireArray<uint32_t>(c, "corner_vertices", {{kAny, "C"}});
            faceSizes = requireArray<uint32_t>(fs, "face_sizes", {{kAny, "F"}});
        }
        input.positions = rowsOf<glm::vec3>(positions);
        input.normals = rowsOf<glm::vec3>(normals);
        input.uvs = rowsOf<glm::vec2>(uvs);
        input.cornerVertices = valuesOf(corners);
        if (!fs.is_none()) input.faceSizes = valuesOf(faceSizes);
        // One scan of the preconditions (finite, |p|, |uv| <= 2^60, |n| <=
        // 16, indices, face sizes); when it finds a problem, the checks per
        // argument name the array, row and column.
        const std::string problem = sg::mesh::mikktspaceInputProblem(input);
        if (!problem.empty()) {
            requireBounded(positions, "positions", 0x1p60f);
            requireBounded(normals, "normals", 16.0f);
            requireBounded(uvs, "uvs", 0x1p60f);
            requireIndicesBelow(valuesOf(corners), size_t(v), "corner_vertices", "vertices");
            throw py::value_error("mikktspace input: " + problem);
        }
    }
};

py::dict framesDict(std::vector<MikkTSpaceFrame>&& frames) {
    const size_t n = frames.size();
    std::vector<glm::vec3> tangent(n), bitangent(n);
    std::vector<float> magS(n), magT(n), sign(n);
    for (size_t k = 0; k < n; ++k) {
        tangent[k] = frames[k].tangent;
        bitangent[k] = frames[k].bitangent;
        magS[k] = frames[k].magS;
        magT[k] = frames[k].magT;
        sign[k] = frames[k].sign;
    }
    const auto rows = py::ssize_t(n);
    py::dict d;
    d["tangent"] = moveToArray(std::move(tangent));
    d["mag_s"] = moveToArray(std::move(magS), {rows});
    d["bitangent"] = moveToArray(std::move(bitangent));
    d["mag_t"] = moveToArray(std::move(magT), {rows});
    d["sign"] = moveToArray(std::move(sign), {rows});
    return d;
}

sg::mesh::TangentMethod parseMethod(const std::string& name) {
    auto method = sg::mesh::parseTangentMethod(name);
    if (!method) throwUnknownName("method", name, {"mikktspace", "limit", "pixel"});
    return *method;
}

// A MikkTSpaceGenerator with its thread count, for Python (one per thread:
// generate() is not reentrant; the GIL-released call is guarded by `busy`).
class Generator {
public:
    explicit Generator(int threads) { gen_.setThreads(requireThreads(threads)); }

    py::array generate(py::handle p, py::handle n, py::handle uv, py::handle c, py::handle fs,
                       py::handle out) {
        MikkArrays arrays(p, n, uv, c, fs);
        const auto corners = py::ssize_t(arrays.input.cornerVertices.size());
        // (A default py::array_t is an empty array, not a null handle.)
        std::optional<py::array_t<float>> target;
        if (!out.is_none()) target = requireArray<float>(out, "out", {{corners, "C"}, {4}});
        if (busy_) throw py::value_error("MikkTSpaceGenerator.generate: already running");
        busy_ = true;
        {
            py::gil_scoped_release release;
            const auto t0 = std::chrono::steady_clock::now();
            gen_.generate(arrays.input, tangents_);
            lastMs_ =
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count();
        }
        busy_ = false;
        if (target) {
            std::memcpy(target->mutable_data(), tangents_.data(),
                        tangents_.size() * sizeof(glm::vec4));
            return *target;
        }
        auto result = moveToArray(std::move(tangents_));
        tangents_ = {};
        return result;
    }

    py::list stepTimes() const {
        py::list out;
        for (const auto& s : gen_.lastStepTimes()) out.append(py::make_tuple(s.step, s.ms));
        return out;
    }

    double lastMs() const { return lastMs_; }

private:
    MikkTSpaceGenerator gen_;
    double lastMs_ = 0.0;
    std::vector<glm::vec4> tangents_;
    bool busy_ = false;
};

} // namespace

void bindTangents(py::module_& m) {
    m.def(
        "mikktspace",
        [](py::handle p, py::handle n, py::handle uv, py::handle c, py::handle fs, int threads,
           bool frames) -> py::object {
            requireThreads(threads);
            MikkArrays arrays(p, n, uv, c, fs);
            std::vector<glm::vec4> tangents;
            std::vector<MikkTSpaceFrame> full;
            {
                py::gil_scoped_release release;
                MikkTSpaceGenerator gen;
                gen.setThreads(threads);
                gen.generate(arrays.input, tangents, frames ? &full : nullptr);
            }
            if (frames) return framesDict(std::move(full));
            return moveToArray(std::move(tangents));
        },
        py::arg("positions"), py::arg("normals"), py::arg("uvs"), py::arg("corner_vertices"),
        py::arg("face_sizes") = py::none(), py::kw_only(), py::arg("threads") = 0,
        py::arg("frames") = false,
        R"(MikkTSpace tangents per face corner, bit-identical to the reference mikktspace.c.
positions, normals (V, 3) float32 (normals unit, object space), uvs (V, 2);
corner_vertices uint32 (C,) or (T, 3); face_sizes (F,) of 3 or 4 (None: all
triangles). Returns (C, 4) = (tangent, sign); frames=True returns a dict with
tangent (C, 3), mag_s (C,), bitangent (C, 3), mag_t (C,), sign (C,).)");

    py::class_<Generator>(m, "MikkTSpaceGenerator",
                          "MikkTSpace with scratch buffers kept between calls (many meshes or "
                          "animation frames). Not for concurrent use from several Python threads.")
        .def(py::init<int>(), py::arg("threads") = 0)
        .def("generate", &Generator::generate, py::arg("positions"), py::arg("normals"),
             py::arg("uvs"), py::arg("corner_vertices"), py::arg("face_sizes") = py::none(),
             py::arg("out") = py::none(),
             "As mikktspace(); `out` ((C, 4) float32) is filled and returned.")
        .def("last_step_times", &Generator::stepTimes,
             "(step, milliseconds) of the last generate(), in order.")
        .def("last_generate_ms", &Generator::lastMs,
             "Wall milliseconds of the C++ MikkTSpaceGenerator::generate() call inside the last "
             "generate() (the binding's checks and conversions excluded): what the binding adds "
             "is the Python-side time minus this.");

    m.def(
        "generate_tangents",
        [](const RenderMesh& mesh, const std::string& methodName, int uvSet,
           const sg::mesh::LimitFrame* frame, int threads) {
            requireThreads(threads);
            checkRenderMeshArrays(mesh);
            const auto method = parseMethod(methodName);
            const std::string problem = sg::mesh::tangentInputProblem(mesh, method, uvSet, frame);
            if (!problem.empty()) throw py::value_error("generate_tangents: " + problem);
            RenderMesh out = mesh;
            size_t count = 0;
            {
                py::gil_scoped_release release;
                count = sg::mesh::generateTangents(out, method, uvSet, frame, threads);
            }
            return py::make_tuple(std::move(out), count);
        },
        py::arg("mesh"), py::arg("method") = "mikktspace", py::arg("uv_set") = 0,
        py::arg("frame") = nullptr, py::kw_only(), py::arg("threads") = 0,
        R"((mesh with tangents, count): "mikktspace" splits vertices whose corners disagree
(count = vertices added); "limit" needs the Subdivider's limit frame (count =
irregular vertices); "pixel" clears them (the shader builds the frame).)");

    m.def(
        "limit_tangents",
        [](py::handle dpdu, py::handle dpdv, py::handle dstdu, py::handle dstdv) {
            auto u = requireArray<float>(dpdu, "dpdu", {{kAny, "N"}, {3}});
            const py::ssize_t n = u.shape(0);
            auto v = requireArray<float>(dpdv, "dpdv", {{n, "N"}, {3}});
            auto su = requireArray<float>(dstdu, "dstdu", {{n, "N"}, {2}});
            auto sv = requireArray<float>(dstdv, "dstdv", {{n, "N"}, {2}});
            requireFinite(u, "dpdu");
            requireFinite(v, "dpdv");
            requireFinite(su, "dstdu");
            requireFinite(sv, "dstdv");
            std::vector<glm::vec4> tangents(static_cast<size_t>(n));
            std::vector<uint8_t> cases(static_cast<size_t>(n));
            {
                py::gil_scoped_release release;
                auto pu = rowsOf<glm::vec3>(u), pv = rowsOf<glm::vec3>(v);
                auto tu = rowsOf<glm::vec2>(su), tv = rowsOf<glm::vec2>(sv);
                for (size_t k = 0; k < size_t(n); ++k) {
                    sg::mesh::LimitTangentCase c{};
                    tangents[k] = sg::mesh::limitTangent(pu[k], pv[k], tu[k], tv[k], &c);
                    cases[k] = uint8_t(c);
                }
            }
            return py::make_tuple(moveToArray(std::move(tangents)),
                                  moveToArray(std::move(cases), {n}));
        },
        py::arg("dpdu"), py::arg("dpdv"), py::arg("dstdu"), py::arg("dstdv"),
        R"(The tangent frame of a parametric surface from first derivatives, per point:
(N, 4) tangents (unit xyz along dP/ds, w = sign det J) and (N,) uint8 cases
(0 regular, 1 degenerate UV, 2 degenerate surface).)");

    m.def(
        "uv_area_within_rounding",
        [](const RenderMesh& mesh, int uvSet) {
            checkRenderMeshArrays(mesh);
            if (uvSet < 0 || uvSet >= int(mesh.uvSets.size())) {
                throw py::value_error("uv_set: " + std::to_string(uvSet) +
                                      " is not a UV set of the mesh (it has " +
                                      std::to_string(mesh.uvSets.size()) + ")");
            }
            return sg::mesh::uvAreaWithinRounding(mesh, uvSet);
        },
        py::arg("mesh"), py::arg("uv_set") = 0,
        "Triangles whose UV area is within the rounding of their coordinates (their MikkTSpace "
        "frame follows the rounding of the file).");
}

} // namespace sg::python

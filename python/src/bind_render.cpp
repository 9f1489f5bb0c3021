// Python bindings of the renderers (surfgrad/render.h) and of the shared
// shader functions' evaluation table (surfgrad/bump/eval_kernels.h): a scene to
// a numpy image, and any function of shaders/sg/eval/kernels.glsl over
// arrays (the C++ build of the same source the GPU runs; Mikkelsen 2019's
// listings and Loviscach 2008's operations).
#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>
#include <tbb/parallel_for.h>

#include "arrays.h"
#include "bindings.h"
#include "surfgrad/bump/eval_kernels.h"
#include "surfgrad/bump/eval_line.h"
#include "surfgrad/gl/context.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/render.h"

namespace sg::python {

namespace {

// A scene from what render() takes: None (the built-in scene), a dict (the
// scene-file schema; relative paths resolve against the working folder), a
// str holding JSON text (it starts with '{'), or a path: .json is a scene
// file, a mesh format a model framed by a default camera.
sg::render::Scene sceneFrom(py::handle scene) {
    if (scene.is_none()) return sg::render::defaultScene();
    if (py::isinstance<py::dict>(scene)) {
        const auto text = py::module_::import("json").attr("dumps")(scene).cast<std::string>();
        return sg::render::parseScene(text, "scene (dict)", std::filesystem::current_path());
    }
    if (py::isinstance<py::str>(scene)) {
        const auto text = scene.cast<std::string>();
        const auto first = text.find_first_not_of(" \t\r\n");
        if (first != std::string::npos && text[first] == '{') {
            return sg::render::parseScene(text, "scene (JSON text)",
                                          std::filesystem::current_path());
        }
    }
    if (!py::isinstance<py::str>(scene) && !py::hasattr(scene, "__fspath__")) {
        throw py::type_error("scene: expected None, a dict, JSON text or a path, got " +
                             std::string(py::str(py::type::of(scene).attr("__name__"))));
    }
    const auto path = scene.cast<std::filesystem::path>();
    if (sg::mesh::meshFormat(path) == ".json") return sg::render::loadScene(path);
    if (sg::mesh::isMeshFormat(path)) return sg::render::sceneForModel(path);
    throw py::value_error("scene: " + path.string() + ": expected a scene (.json) or a model (" +
                          std::string(sg::mesh::kMeshFormatsText) + ")");
}

py::array renderScene(py::handle sceneArg, int width, int height, const std::string& aovName,
                      const std::string& renderer, double seconds, const py::object& progress) {
    using namespace sg::render;
    const auto aov = parseAov(aovName);
    if (!aov) {
        throwUnknownName("aov", aovName,
                         {"color", "normal", "surfgrad", "tangent", "bitangent", "basenormal", "uv",
                          "primid", "patch"});
    }
    if (renderer != "cpu" && renderer != "gl")
        throwUnknownName("renderer", renderer, {"cpu", "gl"});
    for (auto [arg, v] : {std::pair{"width", width}, std::pair{"height", height}}) {
        if (v < 0 || v > kMaxImageSize) {
            throw py::value_error(std::string(arg) + ": " + std::to_string(v) + " is not 0.." +
                                  std::to_string(kMaxImageSize) + " (0: the scene's size)");
        }
    }
    if (!std::isfinite(seconds)) throw py::value_error("seconds: not finite");
    Scene scene = sceneFrom(sceneArg);
    PyCallback callback(progress);
    const auto report = callback.bind<int, int>([](int done, int total) {
        return py::make_tuple(double(done) / double(std::max(total, 1)));
    });
    Image image;
    {
        py::gil_scoped_release release;
        SceneAssets assets = loadAssets(scene);
        applyFrame(scene, assets, float(seconds));
        const View view = makeView(scene, assets, width, height, *aov);
        if (renderer == "gl") {
            sg::gl::HeadlessContext context;
            GlRenderer gl;
            gl.setProgress(report);
            image = gl.render(scene, assets, view);
        } else {
            CpuOptions options;
            options.progress = report;
            image = renderCpu(scene, assets, view, options);
        }
    }
    callback.rethrow();
    const int imageHeight = image.height, imageWidth = image.width;
    return moveToArray(std::move(image.samples), {imageHeight, imageWidth, 4});
}

// ---- eval ------------------------------------------------------------------

const sg::eval::Entry& findEntry(const std::string& name) {
    const auto* e = sg::eval::findEntry(name);
    if (!e) {
        std::string names;
        for (const auto& x : sg::eval::entries()) names += (names.empty() ? "" : ", ") + x.name;
        throw py::value_error("eval: unknown function '" + name + "' (one of: " + names + ")");
    }
    return *e;
}

py::dict signature(const sg::eval::Entry& e) {
    auto fields = [](const std::vector<sg::eval::Field>& fs) {
        py::list out;
        for (const auto& f : fs) {
            py::dict d;
            d["key"] = f.key;
            d["width"] = f.width;
            d["kind"] = f.kind == sg::eval::FieldKind::Float  ? "float"
                        : f.kind == sg::eval::FieldKind::Bool ? "bool"
                                                              : "int";
            d["optional"] = f.optional;
            d["default"] = f.defaultValue;
            d["doc"] = f.doc;
            out.append(d);
        }
        return out;
    };
    py::dict d;
    d["name"] = e.name;
    d["summary"] = e.summary;
    d["inputs"] = fields(e.inputs);
    d["outputs"] = fields(e.outputs);
    return d;
}

// The record axes of an input: its shape without the trailing width axis
// (width-1 inputs may have one of length 1, or none).
py::tuple leadingShape(const py::array& a, int width) {
    py::tuple shape = a.attr("shape");
    if (width == 1 && (a.ndim() == 0 || a.shape(a.ndim() - 1) != 1)) return shape;
    return shape[py::slice(0, a.ndim() - 1, 1)];
}

py::dict evalArrays(const std::string& name, const py::kwargs& kwargs) {
    const auto& e = findEntry(name);
    py::module_ np = py::module_::import("numpy");
    std::vector<std::pair<const sg::eval::Field*, py::array>> given;
    std::vector<py::tuple> shapes;
    for (const auto& item : kwargs) {
        const auto key = item.first.cast<std::string>();
        const sg::eval::Field* field = nullptr;
        for (const auto& f : e.inputs) {
            if (f.key == key) field = &f;
        }
        if (!field) {
            std::string keys;
            for (const auto& f : e.inputs) keys += (keys.empty() ? "" : ", ") + f.key;
            throw py::value_error("eval " + name + ": unknown input '" + key +
                                  "' (inputs: " + keys + ")");
        }
        py::array a = np.attr("asarray")(item.second, "float32");
        py::tuple lead = leadingShape(a, field->width);
        if (field->width > 1 && (a.ndim() == 0 || a.shape(a.ndim() - 1) != field->width)) {
            throw py::value_error("eval " + name + ": input '" + key +
                                  "' needs a last dimension of " + std::to_string(field->width) +
                                  ", got shape " + std::string(py::str(a.attr("shape"))));
        }
        given.emplace_back(field, a);
        shapes.push_back(lead);
    }
    for (const auto& f : e.inputs) {
        bool found = false;
        for (const auto& g : given) found = found || g.first == &f;
        if (!found && !f.optional) {
            throw py::value_error("eval " + name + ": input '" + f.key + "' is required (" + f.doc +
                                  ")");
        }
    }
    py::tuple lead;
    try {
        if (!shapes.empty()) lead = py::tuple(np.attr("broadcast_shapes")(*py::cast(shapes)));
    } catch (py::error_already_set&) {
        std::string which;
        for (size_t k = 0; k < given.size(); ++k) {
            which += (k ? ", " : "") + given[k].first->key + " " + std::string(py::str(shapes[k]));
        }
        throw py::value_error("eval " + name + ": the inputs' record shapes do not broadcast (" +
                              which + ")");
    }
    size_t rows = 1;
    for (auto d : lead) rows *= d.cast<size_t>();
    const size_t inStride = size_t(sg::eval::inStride()), outStride = size_t(sg::eval::outStride());
    std::vector<float> records(rows * inStride, 0.0f);
    for (size_t r = 0; r < rows; ++r) {
        for (const auto& f : e.inputs) {
            for (int c = 0; c < f.width; ++c)
                records[r * inStride + size_t(f.slot + c)] = f.defaultValue;
        }
    }
    for (const auto& [field, a] : given) {
        // The input reshaped to (records..., width), then broadcast.
        py::tuple own = leadingShape(a, field->width);
        py::array shaped = a.attr("reshape")(py::tuple(own + py::make_tuple(field->width)));
        py::tuple full = py::tuple(lead + py::make_tuple(field->width));
        auto b = py::array_t<float, py::array::c_style | py::array::forcecast>(
            np.attr("ascontiguousarray")(np.attr("broadcast_to")(shaped, full)));
        const float* v = b.data();
        for (size_t r = 0; r < rows; ++r) {
            for (int c = 0; c < field->width; ++c) {
                const float x = v[r * size_t(field->width) + size_t(c)];
                if (!std::isfinite(x) || std::fabs(double(x)) > sg::eval::kMaxInputMagnitude) {
                    throw py::value_error("eval " + name + ": input '" + field->key + "' row " +
                                          std::to_string(r) + ": " + std::to_string(x) +
                                          " is outside the input domain (finite, |x| <= 1e18)");
                }
                if (field->kind == sg::eval::FieldKind::Bool && x != 0.0f && x != 1.0f) {
                    throw py::value_error("eval " + name + ": input '" + field->key + "' row " +
                                          std::to_string(r) + ": " + std::to_string(x) +
                                          " is not a bool (0 or 1)");
                }
                if (field->kind == sg::eval::FieldKind::Int &&
                    (x != std::floor(x) || x < float(field->minValue) ||
                     x > float(field->maxValue))) {
                    throw py::value_error(
                        "eval " + name + ": input '" + field->key + "' row " + std::to_string(r) +
                        ": " + std::to_string(x) + " is not an integer in " +
                        std::to_string(field->minValue) + ".." + std::to_string(field->maxValue));
                }
                records[r * inStride + size_t(field->slot + c)] = x;
            }
        }
    }
    std::vector<float> out(rows * outStride);
    {
        py::gil_scoped_release release;
        tbb::parallel_for(size_t(0), rows, [&](size_t r) {
            sg::eval::evalCpu(e, &records[r * inStride], &out[r * outStride]);
        });
    }
    py::dict result;
    for (const auto& f : e.outputs) {
        std::vector<float> column(rows * size_t(f.width));
        for (size_t r = 0; r < rows; ++r) {
            for (int c = 0; c < f.width; ++c)
                column[r * size_t(f.width) + size_t(c)] = out[r * outStride + size_t(f.slot + c)];
        }
        std::vector<py::ssize_t> shape;
        for (auto d : lead) shape.push_back(d.cast<py::ssize_t>());
        if (f.width > 1) shape.push_back(f.width);
        result[py::str(f.key)] = moveToArray(std::move(column), shape);
    }
    return result;
}

} // namespace

void bindRender(py::module_& m) {
    m.def("render", &renderScene, py::arg("scene") = py::none(), py::kw_only(),
          py::arg("width") = 0, py::arg("height") = 0, py::arg("aov") = "color",
          py::arg("renderer") = "cpu", py::arg("seconds") = 0.0, py::arg("progress") = py::none(),
          R"(Renders a scene to (H, W, 4) float32 RGBA, row 0 at the bottom (linear values; the
colour AOV before tone mapping). scene: None (the built-in scene), a dict in the
scene-file schema, its JSON text, or a path (.json scene, or a model file
framed by a default camera). renderer: "cpu" (the reference renderer) or
"gl" (OpenGL 4.5 through EGL). aov: color, normal, surfgrad, tangent,
bitangent, basenormal, uv, primid, patch. seconds: the animation time (morph
weights). progress(fraction) is called now and then (with the GIL).)");
    m.def(
        "eval_functions",
        [] {
            std::vector<std::string> names;
            for (const auto& e : sg::eval::entries()) names.push_back(e.name);
            return names;
        },
        "Names of the shared shader functions eval() runs.");
    m.def(
        "eval_signature", [](const std::string& name) { return signature(findEntry(name)); },
        py::arg("name"), "summary, inputs and outputs (key, width, kind, optional, default, doc).");
    m.def("eval", &evalArrays, py::arg("name"),
          R"(Runs a shared shader function (the C++ build of shaders/sg) over arrays. Each
input is array-like of shape (..., width) (width-1 inputs: (..., 1) or (...));
the record axes (...) broadcast against the other inputs'; omitted optional
inputs take their defaults. Returns a dict of outputs, each (..., width)
((...) for width 1). Inputs must be finite with |x| <= 1e18; bool inputs 0
or 1, int inputs integers in their range.)");
}

} // namespace sg::python

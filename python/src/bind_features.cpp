// Python bindings of feature-curve maps (surfgrad/features/curves.h,
// surfgrad/features/feature_maps.h): curves from SVG, fonts and JSON networks baked
// into maps that reconstruct the distance to the curves exactly at any
// magnification (Parilov, Rosenberg & Zorin 2005; Parilov & Zorin 2008,
// sec. 4-5 for the quadratic mode and its signature optimisation), and
// sampling them with the C++ build of the shader's evaluator
// (shaders/sg/features/).
#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.h"
#include "bindings.h"
#include "surfgrad/features/curves.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"

namespace sg::python {

namespace fm = sg::features;

namespace {

py::dict statsDict(const fm::BakeStats& st) {
    py::dict d;
    d["size"] = st.size;
    d["input_to_texel_scale"] = py::make_tuple(st.inputToTexel.scale.x, st.inputToTexel.scale.y);
    d["input_to_texel_offset"] = py::make_tuple(st.inputToTexel.offset.x, st.inputToTexel.offset.y);
    d["texels_with_features"] = st.texelsWithFeatures;
    d["texels_with_segments"] = st.texelsWithSegments;
    d["segments_kept"] = st.segmentsKept;
    d["segments_dropped"] = st.segmentsDropped;
    d["curved_segments"] = st.curvedSegments;
    d["invalid_texels"] = st.invalidTexels;
    d["optimized_texels"] = st.optimizedTexels;
    d["fallback_texels"] = st.fallbackTexels;
    d["near_pieces"] = st.nearPieces;
    d["threads"] = st.threads;
    d["seconds"] = st.seconds;
    return d;
}

// Baked (or loaded) maps with their GPU layout, which sampling reads.
class PyFeatureMaps {
public:
    PyFeatureMaps(fm::FeatureMaps maps, std::optional<fm::BakeStats> stats)
        : maps_(std::move(maps)), stats_(std::move(stats)) {
        py::gil_scoped_release release;
        gpu_ = maps_.packGpu();
    }

    int size() const { return maps_.size; }
    std::string mode() const { return fm::toString(maps_.mode); }
    bool hasNearField() const { return maps_.hasNearField(); }
    py::object stats() const {
        return stats_ ? py::object(statsDict(*stats_)) : py::object(py::none());
    }

    py::array distance() const {
        auto d = maps_.dist;
        const py::ssize_t n = maps_.gridSize();
        return moveToArray(std::move(d), {n, n});
    }

    py::dict sample(py::handle pointsArg, const std::string& near) const {
        fm::NearMode mode{};
        if (near == "exact")
            mode = fm::NearMode::Exact;
        else if (near == "paper")
            mode = fm::NearMode::Paper;
        else
            throwUnknownName("near", near, {"exact", "paper"});
        auto pts = requireArray<float>(pointsArg, "points", {{kAny, "M"}, {2}});
        requireFinite(pts, "points");
        const auto p = rowsOf<glm::vec2>(pts);
        for (size_t k = 0; k < p.size(); ++k) {
            if (std::fabs(p[k].x) > 1e30f || std::fabs(p[k].y) > 1e30f) {
                throw py::value_error("points: row " + std::to_string(k) +
                                      " is beyond +-1e30 texels");
            }
        }
        const size_t m = p.size();
        std::vector<float> dist(m), side(m), width(m);
        std::vector<glm::vec2> grad(m);
        std::vector<int32_t> profile(m);
        {
            py::gil_scoped_release release;
            for (size_t k = 0; k < m; ++k) {
                const auto r = fm::sample(gpu_, p[k], mode);
                dist[k] = r.dist;
                grad[k] = {r.grad.x, r.grad.y};
                side[k] = r.side;
                profile[k] = r.profile;
                width[k] = r.width;
            }
        }
        const auto rows = py::ssize_t(m);
        py::dict d;
        d["dist"] = moveToArray(std::move(dist), {rows});
        d["grad"] = moveToArray(std::move(grad));
        d["side"] = moveToArray(std::move(side), {rows});
        d["profile"] = moveToArray(std::move(profile), {rows});
        d["width"] = moveToArray(std::move(width), {rows});
        return d;
    }

    void save(const std::filesystem::path& path) const {
        py::gil_scoped_release release;
        fm::save(maps_, path);
    }

private:
    fm::FeatureMaps maps_;
    fm::GpuFeatureMaps gpu_;
    std::optional<fm::BakeStats> stats_;
};

fm::CurveNetwork networkFrom(const std::optional<std::filesystem::path>& source,
                             const std::optional<std::string>& svg,
                             const std::optional<std::string>& json,
                             const std::optional<std::filesystem::path>& font,
                             const std::optional<std::string>& text) {
    const int given = int(source.has_value()) + int(svg.has_value()) + int(json.has_value()) +
                      int(font.has_value());
    if (given != 1) {
        throw py::value_error("bake: give exactly one of source (a .svg or .json file), svg= "
                              "(SVG text), json= (JSON text) and font= (a font file, with text=)");
    }
    if (font.has_value() != text.has_value()) {
        throw py::value_error("bake: font= and text= go together");
    }
    if (svg) return fm::parseSvg(*svg, "svg (text)");
    if (json) return fm::parseCurvesJson(*json, "json (text)");
    if (font) return fm::loadFont(*font, *text);
    std::string ext = source->extension().string();
    for (auto& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
    if (ext == ".svg") return fm::loadSvg(*source);
    if (ext == ".json") return fm::loadCurvesJson(*source);
    throw py::value_error("source: " + source->string() +
                          ": expected a .svg or .json file (fonts: font= and text=)");
}

PyFeatureMaps
bakeMaps(const std::optional<std::filesystem::path>& source, const std::optional<std::string>& svg,
         const std::optional<std::string>& json, const std::optional<std::filesystem::path>& font,
         const std::optional<std::string>& text, int size, const std::string& mode, double margin,
         double band, int smooth, bool nearField, int threads, const py::object& progress) {
    fm::BakeOptions opt;
    opt.size = size;
    if (mode == "linear")
        opt.mode = fm::BakeMode::Linear;
    else if (mode == "quadratic")
        opt.mode = fm::BakeMode::Quadratic;
    else
        throwUnknownName("mode", mode, {"linear", "quadratic"});
    opt.marginTexels = margin;
    opt.bandTexels = band;
    opt.smoothIterations = smooth;
    opt.nearField = nearField;
    opt.threads = requireThreads(threads);
    PyCallback callback(progress);
    opt.progress = callback.bind<const char*, double>(
        [](const char* phase, double fraction) { return py::make_tuple(phase, fraction); });
    fm::FeatureMaps maps;
    fm::BakeStats stats;
    const fm::CurveNetwork net = networkFrom(source, svg, json, font, text);
    {
        py::gil_scoped_release release;
        maps = fm::bake(net, opt, &stats);
    }
    callback.rethrow();
    return PyFeatureMaps(std::move(maps), stats);
}

} // namespace

void bindFeatures(py::module_& m) {
    py::class_<PyFeatureMaps>(m, "FeatureMaps",
                              "Baked feature maps of size N (texels per side) and their GPU "
                              "layout. Texel space: (0, 0) the lower-left corner, y up.")
        .def_property_readonly("size", &PyFeatureMaps::size)
        .def_property_readonly("mode", &PyFeatureMaps::mode)
        .def_property_readonly("has_near_field", &PyFeatureMaps::hasNearField)
        .def_property_readonly("stats", &PyFeatureMaps::stats,
                               "What the bake did (None when loaded).")
        .def("distance", &PyFeatureMaps::distance,
             "(N + 1, N + 1) float32 corner distances (texels, clamped to the band), row 0 at the "
             "bottom.")
        .def("sample", &PyFeatureMaps::sample, py::arg("points"), py::arg("near") = "exact",
             "What the shader computes at (M, 2) float32 texel positions: dist (M,) texels, grad "
             "(M, 2) unit, side (M,) +-1, profile (M,) int32, width (M,) texels.")
        .def("save", &PyFeatureMaps::save, py::arg("path"), "Writes the maps as OpenEXR (atomic).");
    m.def(
        "load",
        [](const std::filesystem::path& path) {
            fm::FeatureMaps maps;
            {
                py::gil_scoped_release release;
                maps = fm::load(path);
            }
            return PyFeatureMaps(std::move(maps), std::nullopt);
        },
        py::arg("path"), "Reads feature maps saved by save() or `surfgrad features bake`.");
    m.def("bake", &bakeMaps, py::arg("source") = py::none(), py::kw_only(),
          py::arg("svg") = py::none(), py::arg("json") = py::none(), py::arg("font") = py::none(),
          py::arg("text") = py::none(), py::arg("size") = 512, py::arg("mode") = "linear",
          py::arg("margin") = 8.0, py::arg("band") = 16.0, py::arg("smooth_iterations") = 10,
          py::arg("near_field") = false, py::arg("threads") = 0, py::arg("progress") = py::none(),
          R"(Bakes curves from a file (.svg or .json), from SVG or JSON text, or from a font
and text, fitted into [margin, size - margin]^2 texels. mode "linear" (TR 2005)
or "quadratic" (TOG 2008); band: exact distances up to this many texels;
near_field keeps the input pieces for exact distances near the curves.
progress(phase, fraction) is called now and then. InputError for malformed
input or options.)");
    m.def("profile_names", &fm::profileNames, "Names of the built-in feature profiles.");
}

} // namespace sg::python

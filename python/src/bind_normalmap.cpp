// Python bindings of the normal-map toolkit (surfgrad/normalmap/operations.h):
// Loviscach, "Care and Feeding of Normal Vectors" (GDC 2008) on numpy
// grids: encodings, height <-> slopes (Poisson), the "Feeding" operations
// (scale, add, blend, modulate, curves, deform), LEAN/Toksvig MIP chains
// ("Care: Antialiasing") and the mesh's per-texel frames for object space.
//
// Grids are (H, W[, C]) float32 with row 0 the bottom row, as the C++
// Grid. The C++ operations take grids that own their storage, so an input
// grid is copied once; results are moved into numpy without a copy.
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <optional>
#include <string>
#include <vector>

#include <pybind11/functional.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "arrays.h"
#include "bindings.h"
#include "grids.h"
#include "mesh_objects.h"
#include "surfgrad/normalmap/operations.h"
#include "surfgrad/mesh/render_mesh.h"
#include "surfgrad/mesh/tangents.h"

namespace sg::python {

namespace nm = sg::normalmap;

namespace {

void checkSide(py::ssize_t w, py::ssize_t h, const char* arg) {
    if (w < 1 || h < 1 || w > nm::kMaxImageSide || h > nm::kMaxImageSide ||
        size_t(w) * size_t(h) > nm::kMaxImageTexels) {
        throw py::value_error(std::string(arg) + ": " + std::to_string(h) + " x " +
                              std::to_string(w) + " texels is outside 1.." +
                              std::to_string(nm::kMaxImageSide) + " per side");
    }
}

// A grid of T (float, vec2, vec3, vec4) from an (H, W[, C]) float32 array.
template <class T>
nm::Grid<T> gridArg(py::handle obj, const char* arg) {
    constexpr size_t c = sizeof(T) / sizeof(float);
    py::array_t<float> a =
        c == 1 ? requireArray<float>(obj, arg, {{kAny, "H"}, {kAny, "W"}})
               : requireArray<float>(obj, arg, {{kAny, "H"}, {kAny, "W"}, {py::ssize_t(c)}});
    checkSide(a.shape(1), a.shape(0), arg);
    requireFinite(a, arg);
    nm::Grid<T> g;
    g.width = int(a.shape(1));
    g.height = int(a.shape(0));
    const auto* p = reinterpret_cast<const T*>(a.data());
    g.v.assign(p, p + size_t(g.width) * size_t(g.height));
    return g;
}

template <class A, class B>
void requireSameSize(const nm::Grid<A>& a, const char* argA, const nm::Grid<B>& b,
                     const char* argB) {
    if (a.width != b.width || a.height != b.height) {
        throw py::value_error(std::string(argB) + ": " + std::to_string(b.height) + " x " +
                              std::to_string(b.width) + " differs from " + argA + "'s " +
                              std::to_string(a.height) + " x " + std::to_string(a.width));
    }
}

nm::Image imageArg(py::handle obj, const char* arg, bool isFloat) {
    if (!py::isinstance<py::array>(obj))
        requireArray<float>(obj, arg, {{kAny, "H"}, {kAny, "W"}, {kAny, "C"}});
    const auto rank = py::reinterpret_borrow<py::array>(obj).ndim();
    auto a = rank == 2 ? requireArray<float>(obj, arg, {{kAny, "H"}, {kAny, "W"}})
                       : requireArray<float>(obj, arg, {{kAny, "H"}, {kAny, "W"}, {kAny, "C"}});
    checkSide(a.shape(1), a.shape(0), arg);
    requireFinite(a, arg);
    nm::Image img;
    img.height = int(a.shape(0));
    img.width = int(a.shape(1));
    img.channels = rank == 2 ? 1 : int(a.shape(2));
    if (img.channels < 1 || img.channels > 64) {
        throw py::value_error(std::string(arg) + ": " + std::to_string(img.channels) +
                              " channels is outside 1..64");
    }
    img.isFloat = isFloat;
    img.samples.assign(a.data(), a.data() + a.size());
    return img;
}

py::array imageToArray(nm::Image&& img) {
    return moveToArray(std::move(img.samples), {img.height, img.width, img.channels});
}

nm::Wrap parseWrap(const std::string& s) {
    if (s == "repeat") return nm::Wrap::Repeat;
    if (s == "clamp") return nm::Wrap::Clamp;
    throwUnknownName("wrap", s, {"repeat", "clamp"});
}

nm::MapFormat parseFormat(const std::string& encoding, const std::string& green, float derivRange) {
    nm::MapFormat f;
    if (encoding == "rgb")
        f.encoding = nm::Encoding::Rgb;
    else if (encoding == "rg")
        f.encoding = nm::Encoding::Rg;
    else if (encoding == "ag")
        f.encoding = nm::Encoding::Ag;
    else if (encoding == "signed")
        f.encoding = nm::Encoding::Signed;
    else if (encoding == "deriv")
        f.encoding = nm::Encoding::Deriv;
    else
        throwUnknownName("encoding", encoding, {"rgb", "rg", "ag", "signed", "deriv"});
    if (green == "gl")
        f.green = nm::Green::Gl;
    else if (green == "dx")
        f.green = nm::Green::Dx;
    else
        throwUnknownName("green", green, {"gl", "dx"});
    if (!(derivRange > 0.0f) || !std::isfinite(derivRange)) {
        throw py::value_error("deriv_range: expected a finite value > 0");
    }
    f.derivRange = derivRange;
    return f;
}

nm::ScalarField heightOr(const py::object& height, const nm::DerivField& d, nm::Wrap wrap,
                         const char* arg) {
    if (height.is_none()) {
        py::gil_scoped_release release;
        return nm::toHeight(d, wrap);
    }
    auto h = gridArg<float>(height, arg);
    requireSameSize(d, "slopes", h, arg);
    return h;
}

std::string layoutName(const std::string& layout) {
    if (layout == "lean") return nm::kLeanLayout;
    if (layout == "toksvig") return nm::kToksvigLayout;
    if (layout == "naive") return nm::kNaiveMipLayout;
    throwUnknownName("layout", layout, {"lean", "toksvig", "naive"});
}

nm::TexelFrames framesArg(const py::dict& frames) {
    for (const char* key : {"normal", "tangent", "covered"}) {
        if (!frames.contains(key)) {
            throw py::value_error(std::string("frames: missing '") + key +
                                  "' (pass what rasterize_frames returned)");
        }
    }
    nm::TexelFrames f;
    f.normal = gridArg<glm::vec3>(frames["normal"], "frames['normal']");
    f.tangent = gridArg<glm::vec4>(frames["tangent"], "frames['tangent']");
    auto covered =
        py::array_t<uint8_t, py::array::c_style | py::array::forcecast>(frames["covered"]);
    if (covered.ndim() != 2 || covered.shape(0) != f.normal.height ||
        covered.shape(1) != f.normal.width) {
        throw py::value_error("frames['covered']: expected (H, W) like frames['normal']");
    }
    requireSameSize(f.normal, "frames['normal']", f.tangent, "frames['tangent']");
    f.covered.width = f.normal.width;
    f.covered.height = f.normal.height;
    f.covered.v.assign(covered.data(), covered.data() + covered.size());
    return f;
}

void bindImages(py::module_& m) {
    m.def(
        "read_image",
        [](const std::filesystem::path& path) {
            nm::SampleType type{};
            nm::Image img;
            {
                py::gil_scoped_release release;
                img = nm::readImage(path, &type);
            }
            const char* bits = type == nm::SampleType::U8     ? "8"
                               : type == nm::SampleType::U16  ? "16"
                               : type == nm::SampleType::Half ? "half"
                                                              : "float";
            return py::make_tuple(imageToArray(std::move(img)), bits);
        },
        py::arg("path"),
        "(H, W, C) float32 raw channel values (integers as [0, 1], row 0 the bottom row) and the "
        "file's sample type (\"8\", \"16\", \"half\", \"float\").");
    m.def(
        "write_image",
        [](const std::filesystem::path& path, py::handle image,
           const std::optional<std::string>& bits,
           const std::map<std::string, std::string>& attributes) {
            const nm::SampleType type =
                bits ? nm::parseSampleType(*bits) : nm::defaultSampleType(path, false);
            auto img = imageArg(image, "image",
                                type == nm::SampleType::Half || type == nm::SampleType::Float);
            std::vector<std::pair<std::string, std::string>> attrs(attributes.begin(),
                                                                   attributes.end());
            py::gil_scoped_release release;
            nm::writeImage(path, img, type, attrs);
        },
        py::arg("path"), py::arg("image"), py::arg("bits") = py::none(),
        py::arg("attributes") = std::map<std::string, std::string>{},
        "Writes (H, W[, C]) atomically (.png .tga .tif .exr); bits \"8\", \"16\", \"half\", "
        "\"float\" (None: 8 for .png and .tga, 16 for .tif, float for .exr).");
    m.def(
        "shade",
        [](py::handle normals, std::array<float, 3> light) {
            auto n = gridArg<glm::vec3>(normals, "normals");
            return imageToArray(nm::shade(n, {light[0], light[1], light[2]}));
        },
        py::arg("normals"), py::arg("light") = std::array<float, 3>{0.4f, 0.5f, 0.77f},
        "Lambert preview of tangent-space normals lit from `light` (tangent space): (H, W, 3) in "
        "[0, 1].");
}

void bindEncodings(py::module_& m) {
    m.def(
        "decode_slopes",
        [](py::handle image, const std::string& enc, const std::string& green, float range,
           bool isFloat) {
            auto img = imageArg(image, "image", isFloat);
            return gridToArray(nm::decodeSlopes(img, parseFormat(enc, green, range), "image"));
        },
        py::arg("image"), py::arg("encoding") = "rgb", py::arg("green") = "gl",
        py::arg("deriv_range") = 8.0f, py::arg("is_float") = false,
        "(H, W, 2) slopes of a tangent-space map image (listing 4 for normal encodings).");
    m.def(
        "decode_normals",
        [](py::handle image, const std::string& enc, const std::string& green, float range,
           bool isFloat) {
            auto img = imageArg(image, "image", isFloat);
            return gridToArray(nm::decodeNormals(img, parseFormat(enc, green, range), "image"));
        },
        py::arg("image"), py::arg("encoding") = "rgb", py::arg("green") = "gl",
        py::arg("deriv_range") = 8.0f, py::arg("is_float") = false,
        "(H, W, 3) unit normals an image holds.");
    m.def(
        "encode_slopes",
        [](py::handle slopes, const std::string& enc, const std::string& green, float range,
           bool isFloat) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            return imageToArray(nm::encodeSlopes(d, parseFormat(enc, green, range), isFloat));
        },
        py::arg("slopes"), py::arg("encoding") = "rgb", py::arg("green") = "gl",
        py::arg("deriv_range") = 8.0f, py::arg("is_float") = false);
    m.def(
        "encode_normals",
        [](py::handle normals, const std::string& enc, const std::string& green, float range,
           bool isFloat) {
            auto n = gridArg<glm::vec3>(normals, "normals");
            return imageToArray(nm::encodeNormals(n, parseFormat(enc, green, range), isFloat));
        },
        py::arg("normals"), py::arg("encoding") = "rgb", py::arg("green") = "gl",
        py::arg("deriv_range") = 8.0f, py::arg("is_float") = false);
    m.def(
        "normals_from_slopes",
        [](py::handle slopes) {
            return gridToArray(nm::normalsFromSlopes(gridArg<glm::vec2>(slopes, "slopes")));
        },
        py::arg("slopes"), "n = normalize(-d.x, -d.y, 1) per texel.");
    m.def(
        "slopes_from_normals",
        [](py::handle normals) {
            return gridToArray(nm::slopesFromNormals(gridArg<glm::vec3>(normals, "normals")));
        },
        py::arg("normals"), "Slopes of unit normals (listing 4: |d| <= 128 per component).");
}

void bindFeeding(py::module_& m) {
    m.def(
        "from_height",
        [](py::handle height, float scale, const std::string& wrap) {
            auto h = gridArg<float>(height, "height");
            if (!std::isfinite(scale)) throw py::value_error("scale: not finite");
            return gridToArray(nm::fromHeight(h, scale, parseWrap(wrap)));
        },
        py::arg("height"), py::arg("scale") = 1.0f, py::arg("wrap") = "repeat",
        "Central-difference slopes of scale * height (texels).");
    m.def(
        "to_height",
        [](py::handle slopes, const std::string& wrap, py::object progress) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            const auto w = parseWrap(wrap);
            PyCallback p(std::move(progress));
            const nm::Progress report = p.bind<double>([](double f) { return py::make_tuple(f); });
            nm::ScalarField h;
            {
                py::gil_scoped_release release;
                h = nm::toHeight(d, w, report);
            }
            p.rethrow();
            return gridToArray(std::move(h));
        },
        py::arg("slopes"), py::arg("wrap") = "repeat", py::arg("progress") = py::none(),
        "The least-squares (Poisson) height of the slopes, in texels, min = 0.");
    m.def(
        "scale",
        [](py::handle slopes, float alpha) {
            if (!std::isfinite(alpha)) throw py::value_error("alpha: not finite");
            return gridToArray(nm::scale(gridArg<glm::vec2>(slopes, "slopes"), alpha));
        },
        py::arg("slopes"), py::arg("alpha"), "Slopes of alpha h.");
    m.def(
        "add",
        [](py::handle a, float wa, py::handle b, float wb) {
            auto da = gridArg<glm::vec2>(a, "a");
            auto db = gridArg<glm::vec2>(b, "b");
            requireSameSize(da, "a", db, "b");
            if (!std::isfinite(wa) || !std::isfinite(wb))
                throw py::value_error("wa, wb: not finite");
            return gridToArray(nm::add(da, wa, db, wb));
        },
        py::arg("a"), py::arg("wa"), py::arg("b"), py::arg("wb"), "Slopes of wa hA + wb hB.");
    m.def(
        "blend",
        [](py::handle a, py::handle b, py::handle mask, const std::string& wrap, py::object ha,
           py::object hb) {
            auto da = gridArg<glm::vec2>(a, "a");
            auto db = gridArg<glm::vec2>(b, "b");
            auto mk = gridArg<float>(mask, "mask");
            requireSameSize(da, "a", db, "b");
            requireSameSize(da, "a", mk, "mask");
            const auto w = parseWrap(wrap);
            auto hA = heightOr(ha, da, w, "height_a");
            auto hB = heightOr(hb, db, w, "height_b");
            return gridToArray(nm::blend(da, hA, db, hB, mk, w));
        },
        py::arg("a"), py::arg("b"), py::arg("mask"), py::arg("wrap") = "repeat",
        py::arg("height_a") = py::none(), py::arg("height_b") = py::none(),
        "Slopes of (1 - m) hA + m hB (product rule; heights integrated from the slopes when not "
        "given).");
    m.def(
        "modulate",
        [](py::handle slopes, py::handle gain, const std::string& wrap, py::object height) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            auto g = gridArg<float>(gain, "gain");
            requireSameSize(d, "slopes", g, "gain");
            const auto w = parseWrap(wrap);
            auto h = heightOr(height, d, w, "height");
            return gridToArray(nm::modulate(d, h, g, w));
        },
        py::arg("slopes"), py::arg("gain"), py::arg("wrap") = "repeat",
        py::arg("height") = py::none(),
        "Slopes of h g (the gain's slopes by central differences).");
    m.def(
        "curves",
        [](py::handle slopes, py::object points, std::optional<std::pair<float, float>> boost,
           py::object height) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            if (points.is_none() == !boost.has_value()) {
                throw py::value_error("curves: give exactly one of points and boost");
            }
            nm::Curve curve;
            if (boost) {
                if (!std::isfinite(boost->first) || !std::isfinite(boost->second)) {
                    throw py::value_error("boost: not finite");
                }
                curve = nm::boostCurve(boost->first, boost->second);
            } else if (py::isinstance<py::str>(points)) {
                curve = nm::parseCurvePoints(points.cast<std::string>(), "points");
            } else {
                // Through the text parser, so points get its checks; nine
                // significant digits round-trip every float.
                std::ostringstream text;
                text.precision(9);
                for (auto p : points) {
                    auto xy = p.cast<std::pair<double, double>>();
                    text << xy.first << "," << xy.second << " ";
                }
                curve = nm::parseCurvePoints(text.str(), "points");
            }
            auto h = heightOr(height, d, nm::Wrap::Repeat, "height");
            return gridToArray(nm::applyCurve(d, h, curve));
        },
        py::arg("slopes"), py::arg("points") = py::none(), py::arg("boost") = py::none(),
        py::arg("height") = py::none(),
        "Slopes f'(x) d of a height curve f through points (monotone cubic) or the paper's boost "
        "(P, H); x is the normalised elevation of `height` (integrated, repeat, when None).");
    m.def(
        "deform",
        [](py::handle slopes, const std::string& warp, const std::string& wrap) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            return gridToArray(nm::deform(d, nm::parseWarp(warp), parseWrap(wrap)));
        },
        py::arg("slopes"), py::arg("warp"), py::arg("wrap") = "repeat",
        "The slopes of h(warp(u, v)); warp \"sine:A,B\" or \"rotate:DEG\".");
}

void bindMips(py::module_& m) {
    m.def(
        "mips",
        [](py::handle slopes, const std::string& layout, py::object progress) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            const std::string name = layoutName(layout);
            PyCallback p(std::move(progress));
            const nm::Progress report = p.bind<double>([](double f) { return py::make_tuple(f); });
            std::vector<nm::Image> levels;
            {
                py::gil_scoped_release release;
                if (name == nm::kLeanLayout) {
                    levels = nm::mipChain(nm::leanLevel0(d), report);
                } else if (name == nm::kToksvigLayout) {
                    levels = nm::mipChain(nm::toksvigLevel0(nm::normalsFromSlopes(d)), report);
                    nm::finishToksvig(levels);
                } else {
                    levels = nm::mipChain(nm::naiveMipLevel0(nm::normalsFromSlopes(d)), report);
                    nm::finishNaiveMips(levels);
                }
            }
            p.rethrow();
            py::list out;
            for (auto& l : levels) out.append(imageToArray(std::move(l)));
            return out;
        },
        py::arg("slopes"), py::arg("layout") = "lean", py::arg("progress") = py::none(),
        "MIP chain (level 0 first, box filter, round-down sizes) of a layout: \"lean\" (dx, dy, "
        "dxx, dyy, dxy), \"toksvig\" (nx, ny, nz, s2) or \"naive\" (nx, ny, nz).");
    m.def(
        "write_mips",
        [](const std::filesystem::path& path, const std::vector<py::object>& levelArrays,
           const std::string& layout, const std::string& wrap) {
            const std::string name = layoutName(layout);
            const auto names = nm::mipChannelNames(name);
            std::vector<nm::Image> levels;
            for (size_t k = 0; k < levelArrays.size(); ++k) {
                const std::string arg = "levels[" + std::to_string(k) + "]";
                auto img = imageArg(levelArrays[k], arg.c_str(), true);
                if (size_t(img.channels) != names.size()) {
                    throw py::value_error(arg + ": expected " + std::to_string(names.size()) +
                                          " channels for layout " + layout);
                }
                levels.push_back(std::move(img));
            }
            if (levels.empty()) throw py::value_error("levels: empty");
            const auto sizes = nm::mipSizes(levels[0].width, levels[0].height);
            if (sizes.size() != levels.size()) {
                throw py::value_error("levels: expected the full chain of " +
                                      std::to_string(sizes.size()) + " levels");
            }
            for (size_t k = 0; k < levels.size(); ++k) {
                if (levels[k].width != sizes[k].first || levels[k].height != sizes[k].second) {
                    throw py::value_error("levels[" + std::to_string(k) + "]: expected " +
                                          std::to_string(sizes[k].second) + " x " +
                                          std::to_string(sizes[k].first));
                }
            }
            const auto w = parseWrap(wrap);
            py::gil_scoped_release release;
            nm::writeMipChain(path, levels, names, name, w);
        },
        py::arg("path"), py::arg("levels"), py::arg("layout") = "lean", py::arg("wrap") = "repeat",
        "Writes a chain as one tiled, MIP-mapped OpenEXR file (atomic).");
    m.def(
        "read_mips",
        [](const std::filesystem::path& path) {
            std::vector<std::string> names;
            std::string layout;
            std::vector<nm::Image> levels;
            {
                py::gil_scoped_release release;
                levels = nm::readMipChain(path, &names, &layout);
            }
            py::list out;
            for (auto& l : levels) out.append(imageToArray(std::move(l)));
            // The names mips() and write_mips() take; another layout as stored.
            if (layout == nm::kLeanLayout)
                layout = "lean";
            else if (layout == nm::kToksvigLayout)
                layout = "toksvig";
            else if (layout == nm::kNaiveMipLayout)
                layout = "naive";
            return py::make_tuple(out, names, layout);
        },
        py::arg("path"),
        "(levels, channel names, layout) of a MIP-chain file: layout \"lean\", \"toksvig\", "
        "\"naive\", or the file's surfgrad:layout attribute as stored (empty for a plain EXR, "
        "read as one level per MIP level with its channels in file order).");
}

void bindFrames(py::module_& m) {
    m.def(
        "rasterize_frames",
        [](const sg::mesh::RenderMesh& mesh, int uvSet, int width, int height, int dilate) {
            checkRenderMeshArrays(mesh);
            checkSide(width, height, "width, height");
            if (uvSet < 0 || uvSet >= int(mesh.uvSets.size())) {
                throw py::value_error("uv_set: " + std::to_string(uvSet) +
                                      " is not a UV set of the mesh");
            }
            if (mesh.normals.empty()) throw py::value_error("mesh: has no vertex normals");
            if (mesh.tangents.empty() || mesh.tangentUvSet != uvSet) {
                const auto problem =
                    sg::mesh::tangentInputProblem(mesh, sg::mesh::TangentMethod::MikkTSpace, uvSet);
                if (!problem.empty()) throw py::value_error("mesh: " + problem);
            }
            if (dilate < 0 || dilate > 4096) throw py::value_error("dilate_texels: not 0..4096");
            nm::TexelFrames f;
            {
                py::gil_scoped_release release;
                f = nm::rasterizeFrames(mesh, uvSet, width, height, dilate);
            }
            py::dict d;
            const py::ssize_t h = f.covered.height, w = f.covered.width;
            d["normal"] = gridToArray(std::move(f.normal));
            d["tangent"] = gridToArray(std::move(f.tangent));
            d["covered"] = moveToArray(std::move(f.covered.v), {h, w});
            return d;
        },
        py::arg("mesh"), py::arg("uv_set"), py::arg("width"), py::arg("height"),
        py::arg("dilate_texels") = 2,
        "Per-texel interpolated normal (H, W, 3), tangent (H, W, 4) and covered (H, W) uint8 (1 "
        "inside, 2 dilated, 0 none) of a mesh's UV layout.");
    m.def(
        "object_from_tangent",
        [](py::handle slopes, const py::dict& frames) {
            auto d = gridArg<glm::vec2>(slopes, "slopes");
            auto f = framesArg(frames);
            requireSameSize(d, "slopes", f.normal, "frames['normal']");
            return gridToArray(nm::objectFromTangent(d, f));
        },
        py::arg("slopes"), py::arg("frames"),
        "Unit object-space normals of tangent-space slopes through the mikktspace basis.");
    m.def(
        "tangent_from_object",
        [](py::handle normals, const py::dict& frames) {
            auto n = gridArg<glm::vec3>(normals, "normals");
            auto f = framesArg(frames);
            requireSameSize(n, "normals", f.normal, "frames['normal']");
            return gridToArray(nm::tangentFromObject(n, f));
        },
        py::arg("normals"), py::arg("frames"), "Tangent-space slopes of object-space normals.");
}

} // namespace

void bindNormalmap(py::module_& m) {
    bindImages(m);
    bindEncodings(m);
    bindFeeding(m);
    bindMips(m);
    bindFrames(m);
}

} // namespace sg::python

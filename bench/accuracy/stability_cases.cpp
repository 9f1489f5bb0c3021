// The stability cases (stability.h): named inputs, every hard-case family
// crossed with every layer kind, and generated random cases. Their meshes
// and scenes come from stability_inputs.{h,cpp}.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/gtc/matrix_transform.hpp>

#include "layer_kind.h"
#include "stability.h"
#include "stability_inputs.h"

namespace study::stability {

using namespace detail;
using sg::render::Scene;

// ---------------------------------------------------------------------------
// Layer kinds

std::vector<std::pair<std::string, std::string>> kindLayers() {
    std::vector<std::pair<std::string, std::string>> out;
    for (const sg::render::LayerKind* k : sg::render::layerKinds()) {
        const std::string name = k->name;
        std::string layer = R"({"type": ")" + name + R"(")";
        if (name == "post_resolve") {
            out.emplace_back(
                name,
                R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 16}}, )"
                R"({"type": "post_resolve", "layers": [{"type": "noise", "amplitude": 0.02, "frequency": 6}]})");
            continue;
        }
        // uv_normal: a map with slopes everywhere (the example's bumps are
        // flat between them, which a collapsed chart may sample only).
        if (name == "uv_normal")
            layer += R"(, "map": {"procedural": "weave", "size": 32})";
        else if (k->example && *k->example)
            layer += std::string(", ") + k->example;
        out.emplace_back(name, layer + "}");
    }
    return out;
}

namespace {

std::string layerOf(const std::string& kind) {
    for (const auto& [name, json] : kindLayers())
        if (name == kind) return json;
    throw std::runtime_error("no layer kind " + kind);
}

// ---------------------------------------------------------------------------
// Named cases

Case collapsedTriangleCase(const std::string& kind, const std::string& layer) {
    Case c;
    c.id = "collapsed-chart/" + kind;
    c.family = "uv-degenerate";
    c.kind = kind;
    c.input = "a triangle with UVs (2.37,0), (2.37,1), (2.37,1) (chart collapsed to a segment)";
    c.perturbation = "every UV coordinate moved by -2..2 ulps";
    auto spec = [layer](const fs::path& dir, bool perturbed, bool withLayer) {
        ObjMesh m = collapsedTriangle(2.37);
        if (perturbed) m.perturb(11, false, true, false);
        SceneSpec s;
        s.meshFields = fileField(m, dir, "triangle");
        s.layers = withLayer ? layer : "";
        s.eye = {0.4, 0.3, 2.6};
        return sceneOf(s, dir);
    };
    c.build = [spec](bool p, const fs::path& dir) { return spec(dir, p, true); };
    c.expected = [spec](const fs::path& dir) { return spec(dir, false, false); };
    c.expectedWhat = "the same triangle without the layer (the chart has no frame: no bump)";
    return c;
}

Case cylinderCase(const std::string& id, const std::string& kind, const std::string& layer,
                  const std::string& meshExtra, const std::string& what) {
    Case c;
    c.id = "top-projected-cylinder/" + id;
    c.family = "uv-degenerate";
    c.kind = kind;
    c.input = "a cylinder with top-down planar UVs (singular chart on the walls)" + what;
    c.perturbation = "every UV coordinate moved by -2..2 ulps";
    c.build = [layer, meshExtra](bool perturbed, const fs::path& dir) {
        ObjMesh m = topProjectedCylinder(24, 3);
        if (perturbed) m.perturb(23, false, true, false);
        SceneSpec s;
        s.meshFields = fileField(m, dir, "cylinder") + meshExtra;
        s.layers = layer;
        s.eye = {0.0, 0.9, 2.0};
        s.target = {0.0, -0.05, 0.0};
        return sceneOf(s, dir);
    };
    return c;
}

const char* kDecalOnPlane =
    R"({"type": "decal", "map": {"procedural": "scratches", "size": 16}, "position": [0.1, 0, -0.1], )"
    R"("direction": [0, -1, 0], "up": [0, 0, -1], "size": [1.4, 1.4, 0.5]})";
const char* kDecalOnSphere =
    R"({"type": "decal", "map": {"procedural": "scratches", "size": 16}, "position": [0, 0, 1], )"
    R"("direction": [0, 0, -1], "size": [1.2, 1.2, 0.8]})";

// A sphere (procedural, 48 segments) under `layers`, in `spec` fields.
Case sphereCase(const std::string& id, const std::string& family, const std::string& kind,
                const std::string& input, const std::string& perturbation,
                std::function<SceneSpec(bool perturbed)> spec) {
    Case c;
    c.id = id;
    c.family = family;
    c.kind = kind;
    c.input = input;
    c.perturbation = perturbation;
    c.build = [spec](bool perturbed, const fs::path& dir) { return sceneOf(spec(perturbed), dir); };
    return c;
}

const char* kSphereFields =
    R"("procedural": {"type": "sphere", "size": 1, "segments": 48, "uv_sets": 1})";

// The camera moved by 2 ulps of binary32 at its distance from the origin
// (each coordinate, alternating signs).
glm::dvec3 nudgedEye(glm::dvec3 eye) {
    return {moveUlps(eye.x, 2), moveUlps(eye.y, -2), moveUlps(eye.z, 2)};
}

// The eye moved by 2^-21 of its distance to the target in each coordinate
// (alternating signs): a rounding-size change of the view at any distance
// from the origin.
glm::dvec3 nudged(glm::dvec3 eye, glm::dvec3 target) {
    const double d = glm::length(eye - target) * std::ldexp(1.0, -21);
    return eye + glm::dvec3(d, -d, d);
}

// World-unit terrain UVs: a tiling set offset by 1e4.
Case farUvCase() {
    return sphereCase(
        "uv-offset-1e4/uv_normal", "uv-degenerate", "uv_normal",
        "a sphere whose tiling UV set (8 repeats) is offset by (1e4, 1e4), a uv_normal layer on it",
        "camera moved by 2 ulps", [](bool p) {
            SceneSpec s;
            s.meshFields = std::string(kSphereFields) +
                           R"(, "uv_sets": [{"from": 0, "scale": 8, "offset": [10000, 10000]}])";
            s.layers =
                R"({"type": "uv_normal", "uv_set": 1, "map": {"procedural": "bumps", "size": 64}})";
            s.eye = {0.6, 0.5, 2.4};
            if (p) s.eye = nudgedEye(s.eye);
            return s;
        });
}

// An instance flattened to 1e-6 in y, seen from above: object-space volume layers.
Case flattenedCase(const std::string& kind, const std::string& layer) {
    return sphereCase("flattened-1e-6/" + kind, "transforms", kind,
                      "a sphere scaled by (1, 1e-6, 1), object-space " + kind,
                      "camera moved by 2 ulps", [layer](bool p) {
                          SceneSpec s;
                          s.meshFields = kSphereFields;
                          s.transform = R"({"scale": [1, 1e-6, 1]})";
                          s.layers = layer;
                          s.eye = {0.3, 1.8, 1.2};
                          if (p) s.eye = nudgedEye(s.eye);
                          return s;
                      });
}

// A grid whose vertex normals lean `deg` degrees from the face normal (+y)
// towards +z, parallax or POM on it.
Case leaningNormalsCase(double deg, const std::string& kind, const std::string& layer) {
    Case c;
    char name[64];
    std::snprintf(name, sizeof name, "normals-%g-deg-from-face/%s", deg, kind.c_str());
    c.id = name;
    c.family = "horizon";
    c.kind = kind;
    char what[96];
    std::snprintf(what, sizeof what,
                  "a plane whose vertex normals lean %g deg from the face normal", deg);
    c.input = what;
    c.perturbation = "every normal coordinate moved by -2..2 ulps";
    c.normalLeanDeg = deg;
    c.build = [deg, layer](bool p, const fs::path& dir) {
        const double a = deg * 3.14159265358979323846 / 180.0;
        ObjMesh m = grid(4, {0.0, std::cos(a), std::sin(a)});
        if (p) m.perturb(31, false, false, true);
        SceneSpec s;
        s.meshFields = fileField(m, dir, "grid");
        s.layers = layer;
        s.eye = {0.3, 1.6, 1.6};
        return sceneOf(s, dir);
    };
    return c;
}

// A sphere and its camera about 1e6 units from the world origin.
Case farCameraCase() {
    Case c;
    c.id = "camera-at-999990/uv_normal";
    c.family = "far-from-origin-render";
    c.kind = "uv_normal";
    c.input = "a sphere at x = 999990, the camera 0.3 units beside it in x";
    c.perturbation = "camera x moved by 1e-12 of its value (1e-6 units)";
    auto spec = [](glm::dvec3 origin, double dx) {
        SceneSpec s;
        s.meshFields = kSphereFields;
        s.transform = R"({"translate": )" + vec3Json(origin) + "}";
        s.layers = R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 64}})";
        s.eye = origin + glm::dvec3(0.3 + dx, 0.5, 2.6);
        s.target = origin;
        return s;
    };
    const glm::dvec3 far(999990.0, 0.0, 0.0);
    c.build = [spec, far](bool p, const fs::path& dir) {
        return sceneOf(spec(far, p ? 1e-12 * far.x : 0.0), dir);
    };
    c.expected = [spec](const fs::path& dir) { return sceneOf(spec(glm::dvec3(0.0), 0.0), dir); };
    c.expectedWhat = "the same scene at the origin";
    return c;
}

// A decal 1e-6 deep whose middle plane is a tilted plane's.
Case thinDecalCase() {
    Case c;
    c.id = "decal-1e-6-deep-on-the-surface/decal";
    c.family = "decals-parallel";
    c.kind = "decal";
    c.input = "a decal 1e-6 deep whose middle plane is the surface (a plane turned 25 deg about x, "
              "40 about y)";
    c.perturbation = "the decal moved by 1e-7 along its axis";
    c.build = [](bool p, const fs::path& dir) {
        const double a = glm::radians(25.0), b = glm::radians(40.0);
        const glm::dvec3 n(std::sin(a) * std::sin(b), std::cos(a), std::sin(a) * std::cos(b));
        SceneSpec s;
        s.meshFields = fileField(grid(4, {0, 1, 0}), dir, "grid");
        s.transform = R"({"rotate_deg": [25, 40, 0]})";
        s.layers =
            R"({"type": "decal", "map": {"procedural": "scratches", "size": 32}, "position": )" +
            vec3Json(p ? 1e-7 * n : glm::dvec3(0.0)) + R"(, "direction": )" + vec3Json(-n) +
            R"(, "up": [0, 0, 1], "size": [1.5, 1.5, 1e-6]})";
        s.eye = 2.0 * n + glm::dvec3(0.3, 0.0, -0.2);
        return sceneOf(s, dir);
    };
    return c;
}

// A decal whose projection direction lies in the surface (its axis z in
// the plane), without an angle fade ([90, 90]).
Case decalAxisInSurfaceCase() {
    Case c;
    c.id = "decal-axis-in-the-surface/decal";
    c.family = "decals-parallel";
    c.kind = "decal";
    c.input = "a decal projecting along the surface (axis z in the plane), angle fade [90, 90]";
    c.perturbation = "every coordinate of the mesh's positions moved by -2..2 ulps";
    c.build = [](bool p, const fs::path& dir) {
        ObjMesh m = grid(4, {0, 1, 0});
        if (p) m.perturb(41, true, false, false);
        SceneSpec s;
        s.meshFields = fileField(m, dir, "grid");
        s.layers =
            R"({"type": "decal", "map": {"procedural": "scratches", "size": 32}, "position": [0, 0, 0], )"
            R"("direction": [1, 0, 0], "up": [0, 1, 0], "size": [1.6, 1.6, 2], "angle_fade_deg": [90, 90]})";
        s.eye = {0.35, 1.7, 1.4};
        return sceneOf(s, dir);
    };
    return c;
}

// POM pushed to its limits: a deep relief (scale 0.25 on a unit plane), 256
// steps, seen 80 degrees from the normal, and on a sphere's silhouette.
Case extremePomCase(const std::string& id, const std::string& input, bool sphere, glm::dvec3 eye) {
    Case c;
    c.id = "extreme-pom-" + id + "/pom";
    c.family = "parallax-extreme";
    c.kind = "pom";
    c.input = input;
    c.perturbation = "camera moved by 2^-21 of its distance in each coordinate";
    c.build = [sphere, eye](bool p, const fs::path& dir) {
        SceneSpec s;
        s.meshFields =
            sphere ? std::string(kSphereFields) : fileField(grid(4, {0, 1, 0}), dir, "grid");
        s.layers =
            R"({"type": "pom", "map": {"procedural": "bricks", "output": "height", "size": 32}, )"
            R"("scale": 0.25, "steps": 256})";
        s.eye = eye;
        if (p) {
            const double d = glm::length(eye) * std::ldexp(1.0, -21);
            s.eye = eye + glm::dvec3(d, -d, d);
        }
        return sceneOf(s, dir);
    };
    return c;
}

// A tiling map seen minified (64 repeats over a plane at a grazing view):
// which CPU reference agrees with llvmpipe (Case::withDefaultCpu).
Case minifiedCase(const std::string& id, const std::string& kind, const std::string& layer) {
    Case c;
    c.id = "minified-tiling-map-" + id + "/" + kind;
    c.family = "grazing";
    c.kind = kind;
    c.input = "a map tiled 6 times on a plane seen 70 deg from the normal (minified), " + id;
    c.perturbation = "camera moved by 2^-21 of its distance in each coordinate";
    c.withDefaultCpu = true;
    c.build = [layer](bool p, const fs::path& dir) {
        SceneSpec s;
        s.meshFields = fileField(grid(8, {0, 1, 0}), dir, "grid") +
                       R"(, "uv_sets": [{"from": 0, "scale": 6}])";
        s.layers = layer;
        s.eye = {0.0, 0.75, 2.1};
        if (p) s.eye = nudged(s.eye, s.target);
        return sceneOf(s, dir);
    };
    return c;
}

// Back faces in flip mode must be the negation of mode none.
Case flipCase(const std::string& kind, const std::string& layer) {
    Case c;
    c.id = "back-faces-flip-vs-none/" + kind;
    c.family = "back-faces";
    c.kind = kind;
    c.input = "a bumped plane seen from below, double_sided flip";
    c.perturbation = "camera moved by 2 ulps";
    auto spec = [layer](const fs::path& dir, bool p, const char* mode) {
        SceneSpec s;
        s.meshFields = fileField(grid(4, {0, 1, 0}), dir, "grid");
        s.layers = layer;
        s.materialExtra = std::string(R"("double_sided": ")") + mode + R"(", )";
        s.eye = {0.4, -1.7, 1.3};
        if (p) s.eye = nudgedEye(s.eye);
        return sceneOf(s, dir);
    };
    c.build = [spec](bool p, const fs::path& dir) { return spec(dir, p, "flip"); };
    c.expected = [spec](const fs::path& dir) { return spec(dir, false, "none"); };
    c.expectSign = -1.0f;
    c.expectedWhat = "mode none, negated";
    return c;
}

} // namespace

std::vector<Case> namedCases() {
    std::vector<Case> out;
    for (const char* k : {"uv_normal", "deriv_map", "feature"})
        out.push_back(collapsedTriangleCase(k, layerOf(k)));
    const std::string pom =
        R"({"type": "pom", "map": {"procedural": "bricks", "output": "height", "size": 32}, "scale": 0.04})";
    const std::string plx =
        R"({"type": "parallax", "map": {"procedural": "bricks", "output": "height", "size": 32}, "scale": 0.04})";
    const std::string plxNoCorr =
        R"({"type": "parallax", "map": {"procedural": "bricks", "output": "height", "size": 32}, "scale": 0.04, "normal_correction": false})";
    const std::string noise =
        R"({"type": "post_resolve", "layers": [{"type": "noise", "amplitude": 0.01, "frequency": 8}]})";
    const std::string uvn = R"({"type": "uv_normal", "map": {"procedural": "bumps", "size": 32}})";
    out.push_back(cylinderCase("pom", "pom", pom, "", ""));
    out.push_back(cylinderCase("parallax", "parallax", plx, "", ""));
    out.push_back(cylinderCase("parallax-no-correction", "parallax", plxNoCorr, "",
                               ", no normal correction"));
    out.push_back(cylinderCase("pom+noise", "post_resolve", pom + ", " + noise, "",
                               ", POM then a post-resolve noise group"));
    out.push_back(cylinderCase("uv_normal", "uv_normal", uvn, "", ""));
    out.push_back(cylinderCase("uv_normal-mikktspace", "uv_normal", uvn,
                               R"(, "tangents": "mikktspace")", ", MikkTSpace tangents"));
    out.push_back(
        cylinderCase("uv_normal-limit", "uv_normal", uvn,
                     R"(, "subdivision": {"level": 2, "limit": true}, "tangents": "limit")",
                     ", subdivided (level 2, limit), limit tangents"));
    out.push_back(cylinderCase(
        "uv_normal-adaptive-limit", "uv_normal", uvn,
        R"(, "subdivision": {"mode": "adaptive", "pixels_per_edge": 4}, "tangents": "limit")",
        ", adaptive patches, limit tangents"));
    out.push_back(farUvCase());
    out.push_back(flattenedCase(
        "noise", R"({"type": "noise", "space": "object", "amplitude": 0.02, "frequency": 6})"));
    out.push_back(flattenedCase(
        "triplanar",
        R"({"type": "triplanar", "space": "object", "map": {"procedural": "tiles", "size": 32}, "scale": 2})"));
    for (double deg : {88.0, 89.9}) {
        out.push_back(leaningNormalsCase(deg, "parallax", plx));
        out.push_back(leaningNormalsCase(deg, "pom", pom));
    }
    out.push_back(farCameraCase());
    out.push_back(thinDecalCase());
    out.push_back(decalAxisInSurfaceCase());
    out.push_back(extremePomCase(
        "grazing", "POM of scale 0.25, 256 steps, on a plane seen 80 deg from the normal", false,
        {0.0, 0.35, 2.0}));
    const char* bricks = R"("map": {"procedural": "weave", "size": 128}, "uv_set": 1)";
    out.push_back(minifiedCase("uv_normal", "uv_normal",
                               std::string(R"({"type": "uv_normal", )") + bricks + "}"));
    out.push_back(
        minifiedCase("lean", "uv_normal",
                     std::string(R"({"type": "uv_normal", "antialias": "lean", )") + bricks + "}"));
    out.push_back(minifiedCase(
        "pom", "pom",
        R"({"type": "pom", "map": {"procedural": "weave", "output": "height", "size": 128}, "uv_set": 1, "scale": 0.02})"));
    out.push_back(extremePomCase("silhouette",
                                 "POM of scale 0.25, 256 steps, on a sphere (its silhouette)", true,
                                 {0.0, 0.0, 2.6}));
    for (const auto& [kind, layer] : kindLayers())
        out.push_back(flipCase(kind, kind == "decal" ? kDecalOnPlane : layer));
    return out;
}

namespace {

// A hard-case family's input, to be crossed with every layer kind.
struct FamilyInput {
    std::string name;         // the input's id
    std::string family;       // hard-case family id
    std::string input;        // description
    std::string perturbation; // description
    // The decal layer that reaches this input's surface (the registry
    // example projects along -z through the origin).
    std::string decal;
    double inputCondition = 1.0; // Case::inputCondition
    double normalLeanDeg = 0.0;  // Case::normalLeanDeg
    std::function<Scene(const std::string& layers, bool perturbed, const fs::path& dir)> build;
};

// A plane grid scene under `layers` seen from `eye`.
Scene gridScene(const ObjMesh& m, const std::string& layers, glm::dvec3 eye, const fs::path& dir,
                const std::string& materialExtra = "", const std::string& meshExtra = "") {
    SceneSpec s;
    s.meshFields = fileField(m, dir, "grid") + meshExtra;
    s.layers = layers;
    s.materialExtra = materialExtra;
    s.eye = eye;
    return sceneOf(s, dir);
}

FamilyInput meshFamily(std::string name, std::string family, std::string input, ObjMesh (*make)(),
                       glm::dvec3 eye, bool perturbUv, bool perturbPos, bool perturbNormals,
                       std::string decal = kDecalOnPlane, std::string meshExtra = "",
                       std::string materialExtra = "") {
    FamilyInput f;
    f.name = std::move(name);
    f.family = std::move(family);
    f.input = std::move(input);
    std::string what;
    if (perturbPos) what = "positions";
    if (perturbUv) what += std::string(what.empty() ? "" : ", ") + "UVs";
    if (perturbNormals) what += std::string(what.empty() ? "" : ", ") + "normals";
    f.perturbation = "every coordinate of the mesh's " + what + " moved by -2..2 ulps";
    f.decal = std::move(decal);
    f.build = [=](const std::string& layers, bool p, const fs::path& dir) {
        ObjMesh m = make();
        if (p) m.perturb(97, perturbPos, perturbUv, perturbNormals);
        return gridScene(m, layers, eye, dir, materialExtra, meshExtra);
    };
    return f;
}

// A sphere under a transform, the camera nudged.
FamilyInput sphereFamily(std::string name, std::string family, std::string input,
                         std::string transform, glm::dvec3 origin, glm::dvec3 eyeOffset) {
    FamilyInput f;
    f.name = std::move(name);
    f.family = std::move(family);
    f.input = std::move(input);
    f.perturbation = "camera moved by 2^-21 of its distance in each coordinate";
    f.decal =
        std::string(
            R"({"type": "decal", "map": {"procedural": "scratches", "size": 16}, "position": )") +
        vec3Json(origin + glm::dvec3(0, 0, 1)) +
        R"(, "direction": [0, 0, -1], "size": [1.2, 1.2, 0.8]})";
    f.build = [=](const std::string& layers, bool p, const fs::path& dir) {
        SceneSpec s;
        s.meshFields = kSphereFields;
        s.transform = transform;
        s.layers = layers;
        s.target = origin;
        s.eye = origin + eyeOffset;
        if (p) s.eye = nudged(s.eye, s.target);
        return sceneOf(s, dir);
    };
    return f;
}

std::vector<FamilyInput> familyInputs() {
    std::vector<FamilyInput> v;
    const glm::dvec3 side(0.0, 0.9, 2.0), above(0.35, 1.7, 1.4);
    v.push_back(meshFamily(
        "singular-chart", "uv-degenerate",
        "top-projected cylinder: the walls' UV chart is singular",
        [] { return tiltedCylinder(0.0); }, side, true, false, false, kDecalOnSphere));
    v.push_back(meshFamily(
        "near-singular-chart", "uv-degenerate",
        "cylinder projected from 0.06 deg off the axis: near-singular walls",
        [] { return tiltedCylinder(1e-3); }, side, true, false, false, kDecalOnSphere));
    v.push_back(meshFamily("collinear-chart", "uv-degenerate",
                           "a plane whose UVs are collinear on every triangle, (s, t) = (u, u)",
                           collinearGrid, above, true, false, false));
    v.push_back(meshFamily("mirrored-chart", "uv-mirrored", "a plane mirrored in s at x = 0",
                           mirroredGrid, above, true, true, false));
    v.push_back(meshFamily("needles", "needles", "a disk of 720 needle triangles (0.5 deg)",
                           needleFan, above, true, true, false));
    v.push_back(meshFamily("zero-area-faces", "zero-area",
                           "a plane with a third of its quads collapsed to segments", zeroAreaGrid,
                           above, true, true, false));
    v.push_back(meshFamily(
        "normals-at-horizon", "horizon",
        "a plane whose vertex normals lie 89.9 deg from the face normal",
        [] {
            const double a = 89.9 * 3.14159265358979323846 / 180.0;
            return grid(6, {0.0, std::cos(a), std::sin(a)});
        },
        above, false, false, true));
    v.back().normalLeanDeg = 89.9;
    v.push_back(meshFamily("normals-flipping", "horizon",
                           "a plane whose vertex normals alternate between the face normal and "
                           "150 deg from it (behind the surface)",
                           flippingNormalsGrid, above, false, false, true));
    for (const char* mode : {"none", "mirror", "flip"}) {
        v.push_back(meshFamily(
            std::string("back-faces-") + mode, "back-faces",
            std::string("a plane seen from below, double_sided ") + mode,
            [] {
                return grid(6, {0, 1, 0});
            },
            {0.35, -1.7, 1.4}, true, true, false, kDecalOnPlane, "",
            std::string(R"("double_sided": ")") + mode + R"(", )"));
    }
    v.push_back(meshFamily(
        "grazing-view", "grazing", "a plane seen 2 deg above its horizon",
        [] {
            return grid(6, {0, 1, 0});
        },
        {0.0, 0.07, 2.0}, true, true, false));
    v.push_back(sphereFamily(
        "far-from-origin", "far-from-origin-render",
        "a sphere and its camera 1e5 units from the origin in every coordinate",
        R"({"translate": [100000, 100000, 100000]})", glm::dvec3(1e5), {0.6, 0.5, 2.4}));
    // 1e-4 (the named cases take 1e-6 for the volume layers): at 1e-6 the
    // rim is a band of slivers 1e-6 thick whose vertex normals turn 90 deg
    // within a hundredth of a pixel, and an object-space normal map there
    // follows the sub-pixel position of each sample (3.4 deg p99 between
    // the CPU reference and itself under a 2^-21 camera move; llvmpipe's
    // fixed-point vertex snapping hides it), a property of that input.
    v.push_back(sphereFamily("flattened-transform", "transforms",
                             "a sphere scaled by (1, 1e-4, 1), seen from above",
                             R"({"scale": [1, 1e-4, 1]})", glm::dvec3(0.0), {0.3, 1.8, 1.2}));
    v.back().inputCondition = 1e4;
    v.push_back(sphereFamily("mirrored-transform", "transforms", "a sphere scaled by (-1, 1, 1)",
                             R"({"scale": [-1, 1, 1]})", glm::dvec3(0.0), {0.6, 0.5, 2.4}));
    {
        // The grid's +y turned onto n = (1, 1, 1) / sqrt(3): columns e1, n, e1 x n.
        const glm::dvec3 n = glm::normalize(glm::dvec3(1.0)),
                         e1 = glm::normalize(glm::dvec3(1.0, -1.0, 0.0)), e2 = glm::cross(e1, n);
        std::string mat = R"(, "transform": {"matrix": [)";
        for (const glm::dvec3& col : {e1, n, e2})
            mat += num(col.x) + ", " + num(col.y) + ", " + num(col.z) + ", 0, ";
        mat += "0, 0, 0, 1]}";
        const std::string decal =
            R"({"type": "decal", "map": {"procedural": "scratches", "size": 16}, "position": [0, 0, 0], "direction": )" +
            vec3Json(-n) + R"(, "up": [0, 0, 1], "size": [1.4, 1.4, 0.5]})";
        v.push_back(meshFamily(
            "triplanar-diagonal", "triplanar-equal",
            "a plane whose normal is the diagonal (1, 1, 1) / sqrt(3)",
            [] {
                return grid(6, {0, 1, 0});
            },
            2.2 * n + glm::dvec3(0.2, 0, -0.2), true, true, false, decal, mat));
    }
    v.push_back(meshFamily(
        "high-valence-adaptive", "high-valence",
        "adaptive patches of a cage with two valence-64 poles, seen from a pole",
        [] { return poleCage(64); }, {0.4, 2.2, 1.0}, true, true, false, kDecalOnSphere,
        R"(, "subdivision": {"mode": "adaptive", "pixels_per_edge": 6})"));
    return v;
}

} // namespace

std::vector<Case> familyCases() {
    std::vector<Case> out;
    for (const FamilyInput& f : familyInputs()) {
        for (const auto& [kind, layer] : kindLayers()) {
            Case c;
            c.id = f.name + "/" + kind;
            c.family = f.family;
            c.kind = kind;
            c.input = f.input;
            c.perturbation = f.perturbation;
            c.inputCondition = f.inputCondition;
            c.normalLeanDeg = f.normalLeanDeg;
            const std::string l = kind == "decal" ? f.decal : layer;
            const auto build = f.build;
            c.build = [build, l](bool p, const fs::path& dir) { return build(l, p, dir); };
            out.push_back(std::move(c));
        }
    }
    return out;
}

std::vector<Case> generatedCases(uint64_t seed, int count) {
    std::vector<Case> out;
    const auto kinds = kindLayers();
    for (int i = 0; i < count; ++i) {
        Rng rng{seed * 1000003ull + uint64_t(i)};
        std::string what;
        bool uvsOffset = false;
        double leanDeg = 0.0;
        const ObjMesh mesh = randomMesh(rng, what, uvsOffset, leanDeg);
        const auto& [kind, layer] = kinds[size_t(rng.integer(0, int(kinds.size()) - 1))];
        const char* modes[] = {"off", "none", "mirror", "flip"};
        const std::string mode = modes[rng.integer(0, 3)];
        // Transform: rotation, scale (anisotropic, sometimes mirrored), translation.
        const double sx = std::pow(10.0, rng.range(-0.5, 0.5)) * (rng.uniform() < 0.2 ? -1.0 : 1.0);
        const double sy = rng.uniform() < 0.2 ? 1e-4 : std::pow(10.0, rng.range(-0.5, 0.5));
        const double sz = std::pow(10.0, rng.range(-0.5, 0.5));
        const glm::dvec3 rot(rng.range(-180, 180), rng.range(-180, 180), rng.range(-180, 180));
        glm::dvec3 tr(0.0);
        if (rng.uniform() < 0.2)
            tr = glm::dvec3(rng.range(-1e5, 1e5), rng.range(-1e5, 1e5), rng.range(-1e5, 1e5));
        const std::string transform = R"({"scale": )" + vec3Json({sx, sy, sz}) +
                                      R"(, "rotate_deg": )" + vec3Json(rot) + R"(, "translate": )" +
                                      vec3Json(tr) + "}";
        const double az = rng.range(-180.0, 180.0), el = rng.range(-80.0, 80.0);
        // A decal straight down the mesh's own +y (world), through its centre.
        std::string l = layer;
        if (kind == "decal") {
            glm::dmat4 M = glm::translate(glm::dmat4(1.0), tr);
            M = glm::rotate(M, glm::radians(rot.z), glm::dvec3(0, 0, 1));
            M = glm::rotate(M, glm::radians(rot.y), glm::dvec3(0, 1, 0));
            M = glm::rotate(M, glm::radians(rot.x), glm::dvec3(1, 0, 0));
            M = glm::scale(M, glm::dvec3(sx, sy, sz));
            const glm::dvec3 up =
                glm::normalize(glm::transpose(glm::inverse(glm::dmat3(M))) * glm::dvec3(0, 1, 0));
            const glm::dvec3 side =
                std::fabs(up.x) < 0.9 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
            const double ext = 2.0 * std::max({std::fabs(sx), std::fabs(sy), std::fabs(sz)});
            l = R"({"type": "decal", "map": {"procedural": "scratches", "size": 16}, "position": )" +
                vec3Json(tr) + R"(, "direction": )" + vec3Json(-up) + R"(, "up": )" +
                vec3Json(glm::cross(up, side)) + R"(, "size": )" +
                vec3Json(glm::dvec3(ext, ext, ext)) + "}";
        }
        Case c;
        c.id = "generated-" + std::to_string(seed) + "-" + std::to_string(i) + "/" + kind;
        c.family = "generated";
        c.kind = kind;
        c.input = what + ", double_sided " + mode + ", scale " + vec3Json({sx, sy, sz}) +
                  (tr != glm::dvec3(0.0) ? ", translated ~1e5" : "") + ", camera azimuth " +
                  num(std::round(az)) + " elevation " + num(std::round(el));
        // UVs offset by 1e4 are stored to 1e-3: two ulps there move a small
        // chart by percents, a change of the data rather than of its
        // rounding; those cases perturb positions and normals only (the
        // named case "uv-offset-1e4" perturbs a set derived in binary64).
        c.perturbation = uvsOffset
                             ? "every coordinate of the mesh's positions and normals (its UVs "
                               "are offset by 1e4) moved by -2..2 ulps"
                             : "every coordinate of the mesh (positions, UVs, normals) moved "
                               "by -2..2 ulps";
        const double smin = std::min({std::fabs(sx), std::fabs(sy), std::fabs(sz)});
        c.inputCondition = std::max({std::fabs(sx), std::fabs(sy), std::fabs(sz)}) / smin;
        c.normalLeanDeg = leanDeg;
        const uint64_t pseed = rng.next();
        c.build = [=](bool p, const fs::path& dir) {
            ObjMesh m = mesh;
            if (p) m.perturb(pseed, true, !uvsOffset, true);
            const std::string json =
                R"({"output": {"width": 64, "height": 48}, "materials": [{"name": "m", "double_sided": ")" +
                mode + R"(", "layers": [)" + l + R"(]}], "meshes": [{)" +
                fileField(m, dir, "random") + R"(, "transform": )" + transform +
                R"(}], "camera": {"azimuth_deg": )" + num(az) + R"(, "elevation_deg": )" + num(el) +
                "}}";
            return sg::render::parseScene(json, (dir / "scene.json").string(), dir);
        };
        out.push_back(std::move(c));
    }
    return out;
}

} // namespace study::stability

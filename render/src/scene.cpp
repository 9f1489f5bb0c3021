// Scene JSON: parsing and validation (schema in docs/scene.md). Every value
// is checked where it is read, and an error names the field path from the
// document root, e.g. "materials[0].layers[2].strength: expected a number
// >= 0". Unknown fields are errors too (a typo must not be silently
// ignored).
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "layer_kind.h"
#include "render_internal.h"
#include "scene_node.h"
#include "surfgrad/features/feature_maps.h"
#include "surfgrad/base/io.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace fs = std::filesystem;
using json = nlohmann::json;

const char* aovName(Aov a) {
    switch (a) {
    case Aov::Color:
        return "color";
    case Aov::Normal:
        return "normal";
    case Aov::SurfGrad:
        return "surfgrad";
    case Aov::Tangent:
        return "tangent";
    case Aov::Bitangent:
        return "bitangent";
    case Aov::BaseNormal:
        return "basenormal";
    case Aov::Uv:
        return "uv";
    case Aov::PrimId:
        return "primid";
    case Aov::Patch:
        return "patch";
    }
    return "?";
}

std::optional<Aov> parseAov(const std::string& name) {
    for (int i = 0; i <= int(Aov::Patch); ++i) {
        if (name == aovName(Aov(i))) return Aov(i);
    }
    return std::nullopt;
}

std::string TextureSource::key() const {
    if (producer) return producer->key();
    if (moments != TexMoments::None) {
        TextureSource base = *this;
        base.moments = TexMoments::None;
        return base.key() + ":moments" + std::to_string(int(moments)) + ":enc" +
               std::to_string(int(momentsEncoding));
    }
    if (!procedural.empty()) {
        return "proc:" + procedural + ":" + output + ":" + std::to_string(size) + ":" +
               std::to_string(bumpHeight) + (wrap == Wrap::Clamp ? ":clamp" : ":repeat");
    }
    return "file:" + file.lexically_normal().string() +
           (wrap == Wrap::Clamp ? ":clamp" : ":repeat") + (srgb ? ":srgb" : "");
}

namespace detail {

fs::path SceneReader::resolvePath(const SceneNode& n, const std::string& p) const {
    if (p.empty()) n.fail("expected a file path");
    if (p.rfind("data:", 0) == 0) return dataDirectory() / p.substr(5);
    fs::path fp(p);
    return fp.is_absolute() ? fp : baseDir / fp;
}

TextureSource SceneReader::texture(const SceneNode& n, Wrap defaultWrap) const {
    TextureSource t;
    t.fieldPath = n.path();
    t.wrap = defaultWrap;
    if (n.value().is_string()) {
        t.file = resolvePath(n, n.value().get<std::string>());
        return t;
    }
    if (!n.value().is_object()) n.fail("expected a file path or a texture object");
    n.allowOnly({"file", "procedural", "output", "size", "bump_height", "wrap"});
    if (n.has("file") == n.has("procedural"))
        n.fail("expected exactly one of \"file\" or \"procedural\"");
    if (n.has("file")) {
        t.file = resolvePath(n.child("file"), n.string("file", ""));
        if (n.has("output") || n.has("size") || n.has("bump_height")) {
            n.fail("\"output\", \"size\" and \"bump_height\" apply to procedural textures only");
        }
    } else {
        static const char* kinds[] = {"bricks", "tiles", "bumps", "weave", "scratches"};
        int k = n.choice("procedural", 0, {"bricks", "tiles", "bumps", "weave", "scratches"});
        t.procedural = kinds[k];
        static const char* outs[] = {"normal", "height", "derivative"};
        t.output = outs[n.choice("output", 0, {"normal", "height", "derivative"})];
        t.size = n.integer("size", 256, 4, 4096);
        t.bumpHeight = n.num("bump_height", 0.04, 0.0, 10.0);
    }
    t.wrap = n.choice("wrap", defaultWrap == Wrap::Clamp ? 1 : 0, {"repeat", "clamp"}) == 1
                 ? Wrap::Clamp
                 : Wrap::Repeat;
    return t;
}

} // namespace detail

namespace {

using detail::kHuge;
using Node = detail::SceneNode;

struct Parser : detail::SceneReader {
    // [s, t]: two finite numbers in [lo, hi] (`what` names the accepted forms).
    static glm::vec2 vec2(const Node& n, const char* key, glm::vec2 def, double lo, double hi,
                          const char* what = "an array of 2 numbers") {
        if (!n.has(key)) return def;
        const json& v = n.value().at(key);
        auto bad = [&] {
            n.failField(key, std::string("expected ") + what + " of magnitude at most 1e6");
        };
        if (!v.is_array() || v.size() != 2) bad();
        glm::vec2 r;
        for (int i = 0; i < 2; ++i) {
            if (!v[size_t(i)].is_number()) bad();
            double x = v[size_t(i)].get<double>();
            if (!std::isfinite(x) || x < lo || x > hi) bad();
            r[i] = float(x);
        }
        return r;
    }

    Layer parseLayer(const Node& n, bool nestedLayer, const std::string& materialAa = "") const {
        n.requireObject();
        const auto& kinds = layerKinds();
        std::vector<const char*> names;
        std::string list;
        for (size_t k = 0; k < kinds.size(); ++k) {
            names.push_back(kinds[k]->name);
            list += std::string(k == 0                  ? ""
                                : k + 1 == kinds.size() ? " or "
                                                        : ", ") +
                    kinds[k]->name;
        }
        if (!n.has("type")) n.fail("missing \"type\" (" + list + ")");
        Layer L = makeLayer(*kinds[size_t(n.choice("type", 0, names))]);
        L.fieldPath = n.path();
        L.enabled = n.boolean("enabled", true);
        detail::SceneReader reader = *this;
        reader.nested = nestedLayer;
        reader.materialAntialias = materialAa;
        parseLayerParams(*L.kind, n, L, reader);
        return L;
    }

    Material material(const Node& n) const {
        n.allowOnly({"name", "base_color", "base_color_map", "roughness", "double_sided",
                     "antialias", "layers"});
        Material m;
        m.fieldPath = n.path();
        m.name = n.string("name", "");
        m.baseColor = n.vec3("base_color", m.baseColor, 0.0, 1.0);
        m.roughness = n.num("roughness", m.roughness, 0.0, 1.0);
        m.doubleSided = DoubleSided(n.choice("double_sided", 0, {"off", "none", "mirror", "flip"}));
        if (n.has("base_color_map")) {
            Node b = n.child("base_color_map");
            b.allowOnly({"map", "uv_set"});
            if (!b.has("map")) b.fail("missing \"map\"");
            m.baseColorMap = texture(b.child("map"), Wrap::Repeat);
            m.baseColorMap->srgb = true;
            m.baseColorUvSet = b.integer("uv_set", 0, 0, kMaxUvSets - 1);
        }
        // The layers' default "antialias" (ParamSpec::fromMaterial).
        static const char* const kAa[] = {"", "none", "lean", "toksvig"};
        const std::string aa =
            kAa[n.has("antialias") ? 1 + n.choice("antialias", 0, {"none", "lean", "toksvig"}) : 0];
        if (n.has("layers")) {
            n.requireArray("layers", size_t(kMaxLayers));
            Node arr = n.child("layers");
            size_t total = 0;
            bool sawGroup = false;
            for (size_t i = 0; i < arr.value().size(); ++i) {
                m.layers.push_back(parseLayer(arr.item(i), false, aa));
                total += 1 + m.layers.back().children.size();
                bool isGroup = m.layers.back().kind->group;
                if (sawGroup && !isGroup) {
                    arr.item(i).fail("a layer after a post_resolve group belongs inside a group or "
                                     "before the first one (groups resolve in order)");
                }
                sawGroup = sawGroup || isGroup;
            }
            if (total > size_t(kMaxLayers)) {
                n.failField("layers", "too many layers in total (at most " +
                                          std::to_string(kMaxLayers) + ")");
            }
        }
        return m;
    }

    // In binary64, as every scene position (MeshInstance::transform).
    glm::dmat4 transform(const Node& n) const {
        n.allowOnly({"translate", "rotate_deg", "scale", "matrix"});
        if (n.has("matrix")) {
            if (n.has("translate") || n.has("rotate_deg") || n.has("scale")) {
                n.fail("\"matrix\" excludes translate/rotate_deg/scale");
            }
            std::vector<double> m = n.doubles("matrix", -kHuge, kHuge, 16);
            if (m.size() != 16) n.failField("matrix", "expected 16 numbers (column-major)");
            glm::dmat4 r;
            for (int c = 0; c < 4; ++c)
                for (int k = 0; k < 4; ++k) r[c][k] = m[size_t(c * 4 + k)];
            if (std::abs(glm::determinant(glm::dmat3(r))) < 1e-12)
                n.failField("matrix", "is singular");
            return r;
        }
        glm::dvec3 t = n.dvec3("translate", glm::dvec3(0.0), -kHuge, kHuge);
        glm::dvec3 rot = n.dvec3("rotate_deg", glm::dvec3(0.0), -1e4, 1e4);
        glm::dvec3 s(1.0);
        if (n.has("scale")) {
            if (n.value().at("scale").is_number()) {
                s = glm::dvec3(n.number("scale", 1.0, 0.0, kHuge, true));
            } else {
                s = n.dvec3("scale", s, -kHuge, kHuge);
                if (std::abs(s.x * s.y * s.z) < 1e-12)
                    n.failField("scale", "expected non-zero scales");
            }
        }
        glm::dmat4 m = glm::translate(glm::dmat4(1.0), t);
        m = glm::rotate(m, glm::radians(rot.z), glm::dvec3(0, 0, 1));
        m = glm::rotate(m, glm::radians(rot.y), glm::dvec3(0, 1, 0));
        m = glm::rotate(m, glm::radians(rot.x), glm::dvec3(1, 0, 0));
        return glm::scale(m, s);
    }

    // "tangents": a source, or one per UV set.
    void tangents(const Node& n, MeshInstance& m) const {
        const json& t = n.value().at("tangents");
        auto parseOne = [&](const json& v, const std::string& path) {
            if (!v.is_string())
                throw io::InputError(file, path, "expected \"pixel\", \"mikktspace\" or \"limit\"");
            std::string s = v.get<std::string>();
            if (s == "pixel") return TangentSource::Pixel;
            if (s == "mikktspace") return TangentSource::MikkTSpace;
            if (s == "limit") return TangentSource::Limit;
            throw io::InputError(
                file, path, "expected \"pixel\", \"mikktspace\" or \"limit\", got \"" + s + "\"");
        };
        if (t.is_string()) {
            m.tangents.assign(1, parseOne(t, n.sub("tangents")));
        } else if (t.is_array() && t.size() <= size_t(kMaxUvSets)) {
            for (size_t i = 0; i < t.size(); ++i) {
                m.tangents.push_back(
                    parseOne(t[i], n.sub("tangents") + "[" + std::to_string(i) + "]"));
            }
        } else {
            n.failField(
                "tangents",
                "expected a tangent source or an array of them, one per UV set (at most 4)");
        }
        for (auto s : m.tangents) {
            if (s == TangentSource::Limit && !m.drawsLimitSurface()) {
                n.failField("tangents", "\"limit\" tangents need \"subdivision\": {\"limit\": "
                                        "true} or {\"mode\": \"adaptive\"}");
            }
            if (s == TangentSource::MikkTSpace && m.drawsPatches()) {
                n.failField("tangents",
                            "\"mikktspace\" tangents need a vertex list; \"subdivision\": "
                            "{\"mode\": \"adaptive\"} meshes are patches (use \"limit\" or "
                            "\"pixel\", or \"mode\": \"uniform\")");
            }
        }
    }

    // "morph": weights and their animation keys.
    void morph(const Node& n, MeshInstance& m) const {
        Node mo = n.child("morph");
        mo.allowOnly({"weights", "animation"});
        m.morphWeights = mo.floats("weights", -kHuge, kHuge, 64);
        if (mo.has("animation")) {
            Node an = mo.child("animation");
            an.allowOnly({"keys", "loop"});
            m.morphLoop = an.boolean("loop", true);
            if (!an.has("keys")) an.fail("missing \"keys\"");
            an.requireArray("keys", 4096);
            Node keys = an.child("keys");
            if (keys.value().empty()) keys.fail("expected at least one key");
            for (size_t i = 0; i < keys.value().size(); ++i) {
                Node k = keys.item(i);
                k.allowOnly({"time", "weights"});
                MorphKey key;
                key.time = k.num("time", 0.0, 0.0, kHuge);
                key.weights = k.floats("weights", -kHuge, kHuge, 64);
                if (!m.morphKeys.empty() && !(key.time > m.morphKeys.back().time)) {
                    k.failField("time", "key times must increase");
                }
                if (!m.morphKeys.empty() && key.weights.size() != m.morphKeys[0].weights.size()) {
                    k.failField("weights", "every key needs the same number of weights");
                }
                m.morphKeys.push_back(std::move(key));
            }
        }
    }

    MeshInstance mesh(const Node& n, const std::vector<Material>& materials) const {
        n.allowOnly({"name", "file", "procedural", "subdivision", "uv_sets", "tangents", "morph",
                     "transform", "material", "displacement"});
        MeshInstance m;
        m.fieldPath = n.path();
        m.name = n.string("name", "");
        if (n.has("file") == n.has("procedural"))
            n.fail("expected exactly one of \"file\" or \"procedural\"");
        if (n.has("file")) {
            m.file = resolvePath(n.child("file"), n.string("file", ""));
        } else {
            Node p = n.child("procedural");
            p.allowOnly({"type", "size", "minor_radius", "segments", "relief", "uv_sets"});
            Procedural pr;
            static const char* types[] = {"sphere", "plane", "torus", "cube", "terrain"};
            if (!p.has("type")) p.fail("missing \"type\" (sphere, plane, torus, cube or terrain)");
            pr.type = types[p.choice("type", 0, {"sphere", "plane", "torus", "cube", "terrain"})];
            pr.size = p.num("size", 1.0, 0.0, kHuge, true);
            pr.minorRadius = p.num("minor_radius", 0.35, 0.0, kHuge, true);
            pr.segments = p.integer("segments", pr.type == "terrain" ? 256 : 64, 2, 2048);
            pr.terrainHeight = p.num("relief", 0.25, -kHuge, kHuge);
            pr.uvSets = p.integer("uv_sets", 2, 1, kMaxUvSets);
            m.procedural = pr;
        }
        if (n.has("subdivision")) {
            Node s = n.child("subdivision");
            s.allowOnly({"scheme", "mode", "level", "limit", "max_memory_mib", "isolation",
                         "pixels_per_edge"});
            static const char* schemes[] = {"catmark", "loop", "bilinear"};
            m.subdivide = true;
            if (s.has("scheme"))
                m.subdivScheme = schemes[s.choice("scheme", 0, {"catmark", "loop", "bilinear"})];
            m.subdivAdaptive = s.choice("mode", 0, {"uniform", "adaptive"}) == 1;
            // Each mode's own fields; the other mode's are refused, not ignored.
            const std::vector<const char*> uniformOnly = {"level", "limit", "max_memory_mib"};
            const std::vector<const char*> adaptiveOnly = {"isolation", "pixels_per_edge"};
            for (const char* f : m.subdivAdaptive ? uniformOnly : adaptiveOnly) {
                if (s.has(f))
                    s.failField(f, std::string("applies to \"mode\": \"") +
                                       (m.subdivAdaptive ? "uniform" : "adaptive") + "\" only");
            }
            if (m.subdivAdaptive && !m.subdivScheme.empty() && m.subdivScheme != "catmark")
                s.failField("scheme", "\"mode\": \"adaptive\" draws Catmull-Clark "
                                      "(catmark) patches only; " +
                                          m.subdivScheme + " cages take \"mode\": \"uniform\"");
            m.subdivLevel = s.integer("level", 2, 0, 6);
            m.subdivLimit = s.boolean("limit", false);
            if (s.has("max_memory_mib"))
                m.subdivMaxMemory = uint64_t(s.integer("max_memory_mib", 0, 1, 1 << 24)) << 20;
            m.subdivIsolation = s.integer("isolation", 3, 1, 10);
            m.subdivPixelsPerEdge = s.num("pixels_per_edge", 8.0, 0.25, 1024.0);
            if (m.procedural)
                n.failField("subdivision",
                            "applies to mesh files only (procedural meshes take \"segments\")");
        }
        if (n.has("uv_sets")) {
            // Derived sets (DerivedUvSet); whether `from` exists and the
            // total stays <= kMaxUvSets is checked when the mesh is loaded
            // (a file's own set count is not known here).
            n.requireArray("uv_sets", size_t(kMaxUvSets));
            Node arr = n.child("uv_sets");
            for (size_t i = 0; i < arr.value().size(); ++i) {
                Node d = arr.item(i);
                d.allowOnly({"from", "scale", "rotate_deg", "offset"});
                DerivedUvSet u;
                u.fieldPath = d.path();
                u.from = d.integer("from", 0, 0, kMaxUvSets - 1);
                if (d.has("scale") && d.value().at("scale").is_number()) {
                    u.scale = glm::vec2(d.num("scale", 1.0, -kHuge, kHuge));
                } else {
                    u.scale = vec2(d, "scale", glm::vec2(1.0f), -kHuge, kHuge,
                                   "a number or an array of 2 numbers");
                }
                // A zero scale collapses the set (no tangent basis anywhere).
                if (std::abs(u.scale.x) < 1e-6f || std::abs(u.scale.y) < 1e-6f) {
                    d.failField("scale", "expected non-zero scales (magnitude at least 1e-6)");
                }
                u.rotateDeg = d.num("rotate_deg", 0.0, -kHuge, kHuge);
                u.offset = vec2(d, "offset", glm::vec2(0.0f), -kHuge, kHuge);
                m.derivedUvSets.push_back(u);
            }
        }
        if (n.has("displacement")) {
            // Adaptive meshes only: the tessellation evaluation stage moves
            // the limit surface (a uniform mesh's vertices are not resampled).
            if (!m.subdivide || !m.subdivAdaptive)
                n.failField("displacement", "applies to meshes with \"subdivision\": "
                                            "{\"mode\": \"adaptive\"} only");
            Node d = n.child("displacement");
            d.allowOnly({"map", "scale", "offset", "uv_set"});
            if (!d.has("map")) d.fail("missing \"map\" (the height map)");
            Displacement disp;
            disp.fieldPath = d.path();
            disp.map = texture(d.child("map"), Wrap::Repeat);
            disp.scale = float(d.num("scale", 0.01, -kHuge, kHuge));
            disp.offset = float(d.num("offset", 0.0, -kHuge, kHuge));
            disp.uvSet = d.integer("uv_set", 0, 0, kMaxUvSets - 1);
            m.displacement = disp;
        }
        if (n.has("tangents")) tangents(n, m);
        if (n.has("morph")) morph(n, m);
        if (n.has("transform")) m.transform = transform(n.child("transform"));
        if (n.has("material")) {
            const json& mv = n.value().at("material");
            if (mv.is_number_integer()) {
                long long i = mv.get<long long>();
                if (i < 0 || i >= (long long)materials.size()) {
                    n.failField("material", "no material with index " + std::to_string(i) +
                                                " (there are " + std::to_string(materials.size()) +
                                                ")");
                }
                m.material = int(i);
            } else if (mv.is_string()) {
                auto it = std::find_if(materials.begin(), materials.end(), [&](const Material& x) {
                    return x.name == mv.get<std::string>();
                });
                if (it == materials.end()) {
                    n.failField("material", "no material named \"" + mv.get<std::string>() + "\"");
                }
                m.material = int(it - materials.begin());
            } else {
                n.failField("material", "expected a material index or name");
            }
        }
        return m;
    }

    Light light(const Node& n) const {
        n.requireObject();
        Light l;
        if (!n.has("type")) n.fail("missing \"type\" (directional or point)");
        l.point = n.choice("type", 0, {"directional", "point"}) == 1;
        if (l.point) {
            n.allowOnly({"type", "position", "color", "intensity"});
            l.position = n.dvec3("position", glm::dvec3(0, 3, 3), -kHuge, kHuge);
        } else {
            n.allowOnly({"type", "direction", "color", "intensity"});
            l.direction = n.vec3("direction", l.direction, -kHuge, kHuge);
            if (glm::length(l.direction) < 1e-6f)
                n.failField("direction", "expected a non-zero vector");
            l.direction = glm::normalize(l.direction);
        }
        l.color = n.vec3("color", glm::vec3(1.0f), 0.0, kHuge);
        l.intensity = n.num("intensity", 3.0, 0.0, kHuge);
        return l;
    }

    Camera camera(const Node& n) const {
        n.allowOnly({"position", "target", "up", "fov_deg", "near", "far", "azimuth_deg",
                     "elevation_deg", "distance_scale"});
        Camera c;
        c.automatic = !n.has("position");
        if (c.automatic && n.has("target")) n.failField("target", "needs \"position\" as well");
        if (!c.automatic &&
            (n.has("azimuth_deg") || n.has("elevation_deg") || n.has("distance_scale"))) {
            n.fail("azimuth_deg/elevation_deg/distance_scale apply to the automatic camera (no "
                   "\"position\")");
        }
        c.position = n.dvec3("position", c.position, -kHuge, kHuge);
        c.target = n.dvec3("target", c.target, -kHuge, kHuge);
        c.up = n.dvec3("up", c.up, -kHuge, kHuge);
        if (!c.automatic) {
            const glm::dvec3 fwd = c.target - c.position;
            if (glm::length(fwd) < 1e-9) n.failField("target", "must differ from \"position\"");
            if (glm::length(glm::cross(fwd, c.up)) < 1e-9 * glm::length(fwd) ||
                glm::length(c.up) < 1e-9) {
                n.failField("up", "expected a non-zero vector not parallel to the view direction");
            }
        }
        c.fovDeg = n.num("fov_deg", c.fovDeg, 1.0, 170.0);
        c.nearPlane = n.num("near", 0.0, 0.0, kHuge);
        c.farPlane = n.num("far", 0.0, 0.0, kHuge);
        if (c.nearPlane > 0 && c.farPlane > 0 && !(c.farPlane > c.nearPlane)) {
            n.failField("far", "expected a number > near");
        }
        c.azimuthDeg = n.num("azimuth_deg", c.azimuthDeg, -1e4, 1e4);
        c.elevationDeg = n.num("elevation_deg", c.elevationDeg, -89.0, 89.0);
        c.distanceScale = n.num("distance_scale", c.distanceScale, 0.0, 1000.0, true);
        return c;
    }

    Scene scene(const json& root) const {
        Node n(root, "", file);
        n.allowOnly({"meshes", "materials", "lights", "camera", "output", "frames", "ambient"});
        Scene s;
        s.sourceName = file;
        s.baseDir = baseDir;
        if (n.has("materials")) {
            n.requireArray("materials", 256);
            Node arr = n.child("materials");
            for (size_t i = 0; i < arr.value().size(); ++i)
                s.materials.push_back(material(arr.item(i)));
        }
        if (s.materials.empty()) {
            Material def;
            def.name = "default";
            def.fieldPath = "materials";
            s.materials.push_back(def);
        }
        if (!n.has("meshes")) n.fail("missing \"meshes\"");
        n.requireArray("meshes", 1024);
        Node meshes = n.child("meshes");
        if (meshes.value().empty()) meshes.fail("expected at least one mesh");
        for (size_t i = 0; i < meshes.value().size(); ++i)
            s.meshes.push_back(mesh(meshes.item(i), s.materials));
        if (n.has("lights")) {
            n.requireArray("lights", size_t(kMaxLights));
            Node arr = n.child("lights");
            for (size_t i = 0; i < arr.value().size(); ++i) s.lights.push_back(light(arr.item(i)));
        } else {
            s.lights.push_back(Light{});
        }
        if (n.has("camera")) s.camera = camera(n.child("camera"));
        if (n.has("output")) {
            Node o = n.child("output");
            o.allowOnly({"width", "height", "exposure", "background"});
            s.output.width = o.integer("width", s.output.width, 1, kMaxImageSize);
            s.output.height = o.integer("height", s.output.height, 1, kMaxImageSize);
            s.output.exposure = o.num("exposure", 1.0, 0.0, kHuge, true);
            s.output.background = o.vec3("background", s.output.background, 0.0, kHuge);
        }
        if (n.has("frames")) {
            Node f = n.child("frames");
            f.allowOnly({"count", "fps"});
            s.frameCount = f.integer("count", 1, 1, 100000);
            s.fps = f.num("fps", 24.0, 0.0, 1000.0, true);
        }
        s.ambient = n.vec3("ambient", s.ambient, 0.0, kHuge);
        return s;
    }
};

} // namespace

Scene parseScene(const std::string& jsonText, const std::string& sourceName,
                 const fs::path& baseDir) {
    json root;
    try {
        root = json::parse(jsonText);
    } catch (const json::exception& e) {
        // parse_error (nlohmann's message carries "at line L, column C") or
        // out_of_range (a number too large for a double, e.g. 1e999).
        std::string what = e.what();
        auto p = what.find("] ");
        throw io::InputError(sourceName, "",
                             "invalid JSON: " +
                                 (p == std::string::npos ? what : what.substr(p + 2)));
    }
    io::checkJsonKeysUnique(jsonText, sourceName);
    Parser p;
    p.file = sourceName;
    p.baseDir = baseDir;
    p.layer = [&p](const Node& n, bool nested, const std::string& materialAa) {
        return p.parseLayer(n, nested, materialAa);
    };
    return p.scene(root);
}

Scene loadScene(const fs::path& file) {
    std::string text = io::readFile(file, size_t(64) << 20);
    fs::path base = file.parent_path();
    if (base.empty()) base = ".";
    return parseScene(text, file.string(), base);
}

} // namespace sg::render

// Scene assets: meshes (procedural here, files through the mesh module),
// textures (files through texture_file.cpp, or procedural), per-frame
// morphing, and the camera views. Effects on demand: only textures of
// enabled layers are loaded, each once (by TextureSource::key()), and only
// the channels those layers read; all of them within the scene's texture
// budget.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <new>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "layer_kind.h"
#include "render_internal.h"
#include "surfgrad/contract.h"
#include "surfgrad/feature_maps.h"
#include "surfgrad/image_header.h"
#include "surfgrad/io.h"
#include "surfgrad/mesh_io.h"
#include "surfgrad/morph.h"
#include "surfgrad/adaptive_patches.h"
#include "surfgrad/subdivision.h"
#include "surfgrad/tangents.h"
#include "surfgrad/render.h"
#include "surfgrad/render_shaders.h"

namespace sg::render {

namespace fs = std::filesystem;

namespace detail {

namespace {

constexpr float kPi = 3.14159265358979f;

// Makes every triangle counter-clockwise around the average of its vertex
// normals (the generators below then need not track winding by hand).
void orientTriangles(sg::mesh::RenderMesh& m) {
    for (size_t t = 0; t + 2 < m.indices.size(); t += 3) {
        uint32_t a = m.indices[t], b = m.indices[t + 1], c = m.indices[t + 2];
        glm::vec3 n = glm::cross(m.positions[b] - m.positions[a], m.positions[c] - m.positions[a]);
        glm::vec3 vn = m.normals[a] + m.normals[b] + m.normals[c];
        if (glm::dot(n, vn) < 0.0f) std::swap(m.indices[t + 1], m.indices[t + 2]);
    }
}

// A (nu+1) x (nv+1) vertex grid over (u, v) in [0,1]^2 from a callback
// giving position, normal and uv; two triangles per cell.
template <class F>
void addGrid(sg::mesh::RenderMesh& m, int nu, int nv, F&& f) {
    uint32_t base = uint32_t(m.positions.size());
    for (int j = 0; j <= nv; ++j)
        for (int i = 0; i <= nu; ++i) {
            glm::vec3 p, n;
            glm::vec2 uv;
            f(float(i) / float(nu), float(j) / float(nv), p, n, uv);
            m.positions.push_back(p);
            m.normals.push_back(n);
            m.uvSets[0].push_back(uv);
        }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            uint32_t a = base + uint32_t(j * (nu + 1) + i), b = a + 1, c = a + uint32_t(nu + 1),
                     d = c + 1;
            for (uint32_t x : {a, b, d, a, d, c}) m.indices.push_back(x);
        }
}

// Height of the procedural terrain over (x, z) in units of its edge:
// fBm (the shared noise, CPU build) with its analytic gradient.
glm::vec3 terrainHeight(float x, float z, float relief) {
    glm::vec4 n = sg::glsl::sgNoiseOctaves(SG_NOISE_FBM, glm::vec3(x * 3.0f, 0.37f, z * 3.0f), 6,
                                           2.0f, 0.5f, 0.0f);
    // n = (value, d/dx, d/dy, d/dz) w.r.t. the scaled argument.
    return glm::vec3(relief * n.x, relief * 3.0f * n.y, relief * 3.0f * n.w);
}

} // namespace

sg::mesh::RenderMesh makeProceduralMesh(const Procedural& p) {
    sg::mesh::RenderMesh m;
    m.name = p.type;
    m.uvSets.resize(1);
    const int seg = p.segments;
    if (p.type == "sphere") {
        float r = p.size;
        addGrid(m, seg, std::max(2, seg / 2),
                [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
                    float phi = 2.0f * kPi * u, theta = kPi * v; // theta from the south pole
                    n = glm::vec3(std::sin(theta) * std::cos(phi), -std::cos(theta),
                                  -std::sin(theta) * std::sin(phi));
                    pos = r * n;
                    uv = glm::vec2(u, v);
                });
        // Pole rows are degenerate (zero-area triangles): drop them.
        std::vector<uint32_t> keep;
        for (size_t t = 0; t < m.indices.size(); t += 3) {
            glm::vec3 a = m.positions[m.indices[t]], b = m.positions[m.indices[t + 1]],
                      c = m.positions[m.indices[t + 2]];
            if (glm::length(glm::cross(b - a, c - a)) > 1e-12f * r * r) {
                keep.insert(keep.end(), {m.indices[t], m.indices[t + 1], m.indices[t + 2]});
            }
        }
        m.indices = std::move(keep);
    } else if (p.type == "plane") {
        float s = p.size;
        addGrid(m, seg, seg, [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
            pos = glm::vec3((u - 0.5f) * s, 0.0f, (0.5f - v) * s);
            n = glm::vec3(0, 1, 0);
            uv = glm::vec2(u, v);
        });
    } else if (p.type == "terrain") {
        float s = p.size;
        addGrid(m, seg, seg, [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
            float x = u - 0.5f, z = 0.5f - v;
            glm::vec3 h = terrainHeight(x, z, p.terrainHeight / s);
            pos = glm::vec3(x * s, h.x * s, z * s);
            n = glm::normalize(glm::vec3(-h.y, 1.0f, -h.z));
            uv = glm::vec2(u, v);
        });
    } else if (p.type == "torus") {
        float R = p.size, r = p.minorRadius;
        addGrid(m, seg, std::max(3, seg / 2),
                [&](float u, float v, glm::vec3& pos, glm::vec3& n, glm::vec2& uv) {
                    float a = 2.0f * kPi * u, b = 2.0f * kPi * v;
                    glm::vec3 ring(std::cos(a), 0.0f, -std::sin(a));
                    n = std::cos(b) * ring + glm::vec3(0.0f, std::sin(b), 0.0f);
                    pos = R * ring + r * n;
                    uv = glm::vec2(u, v);
                });
    } else { // cube
        float h = 0.5f * p.size;
        int n = std::max(1, seg / 8);
        for (int face = 0; face < 6; ++face) {
            int axis = face / 2;
            float sgn = face % 2 ? -1.0f : 1.0f;
            glm::vec3 nrm(0.0f);
            nrm[axis] = sgn;
            // (tu, tv) span the face so that tu x tv = nrm.
            glm::vec3 tu(0.0f), tv(0.0f);
            tu[(axis + 1) % 3] = 1.0f;
            tv[(axis + 2) % 3] = 1.0f;
            if (glm::dot(glm::cross(tu, tv), nrm) < 0.0f) tu = -tu;
            addGrid(m, n, n, [&](float u, float v, glm::vec3& pos, glm::vec3& nn, glm::vec2& uv) {
                pos = h * (nrm + (2.0f * u - 1.0f) * tu + (2.0f * v - 1.0f) * tv);
                nn = nrm;
                uv = glm::vec2(u, v);
            });
        }
    }
    orientTriangles(m);
    for (int k = 1; k < p.uvSets; ++k) {
        m.uvSets.push_back(m.uvSets[0]);
        for (auto& uv : m.uvSets.back()) uv *= 4.0f;
    }
    return m;
}

void sceneBounds(const Scene& scene, const SceneAssets& assets, glm::vec3& lo, glm::vec3& hi) {
    lo = glm::vec3(1e30f);
    hi = glm::vec3(-1e30f);
    for (size_t i = 0; i < scene.meshes.size() && i < assets.meshes.size(); ++i) {
        const glm::dmat4& M = scene.meshes[i].transform;
        for (const auto& p : assets.meshes[i].mesh.positions) {
            glm::vec3 w = glm::vec3(M * glm::dvec4(glm::dvec3(p), 1.0));
            lo = glm::min(lo, w);
            hi = glm::max(hi, w);
        }
    }
    if (!(lo.x <= hi.x)) lo = hi = glm::vec3(0.0f);
}

io::InputError referencedFileError(const std::string& sceneName, const std::string& field,
                                   const io::InputError& e) {
    const std::string scene = fs::path(sceneName).lexically_normal().string();
    const std::string file = fs::path(e.file()).lexically_normal().string();
    if (file == scene) return e;
    return io::InputError(
        scene, field, file + ": " + (e.element().empty() ? "" : e.element() + ": ") + e.reason());
}

} // namespace detail

namespace {

// Enabled layers whose kind reads feature maps.
void collectFeatures(const Layer& L, std::vector<const Layer*>& out) {
    if (!L.enabled) return;
    if (L.kind->featureSource && L.kind->featureSource(L)) out.push_back(&L);
    for (const auto& c : L.children) collectFeatures(c, out);
}

// Loads or bakes a feature layer's maps (features are not baked unless an
// enabled layer uses them).
std::shared_ptr<const FeatureMapsAsset> loadFeatureMaps(const FeatureSource& f,
                                                        const std::string& sceneName) {
    namespace sf = sg::features;
    static std::atomic<uint64_t> nextUid{1};
    sf::FeatureMaps maps;
    if (!f.mapsFile.empty()) {
        maps = detail::fromReferencedFile(sceneName, f.fieldPath, [&] {
            std::error_code ec;
            if (!fs::is_regular_file(f.mapsFile, ec)) {
                throw io::InputError(f.mapsFile.string(), "",
                                     fs::exists(f.mapsFile, ec) ? "not a regular file"
                                                                : "does not exist");
            }
            return sf::load(f.mapsFile);
        });
    } else {
        sf::CurveNetwork net =
            detail::fromReferencedFile(sceneName, f.fieldPath + "." + f.curvesKind, [&] {
                return f.curvesKind == "svg"    ? sf::loadSvg(f.curvesFile)
                       : f.curvesKind == "json" ? sf::loadCurvesJson(f.curvesFile)
                                                : sf::loadFont(f.curvesFile, f.text);
            });
        sf::BakeOptions opt;
        opt.size = f.size;
        opt.mode = f.quadratic ? sf::BakeMode::Quadratic : sf::BakeMode::Linear;
        opt.marginTexels = f.marginTexels;
        opt.nearField = f.nearField;
        opt.nearWidthTexels = f.nearWidthTexels;
        maps = sf::bake(net, opt);
    }
    auto a = std::make_shared<FeatureMapsAsset>();
    a->gpu = maps.packGpu();
    a->bandTexels = maps.bandTexels;
    a->quadratic = maps.mode == sf::BakeMode::Quadratic;
    a->nearBandTexels = maps.nearBandTexels;
    a->uid = nextUid++;
    return a;
}

// A texture a layer reads and the RGBA components it reads from it
// (bit c: component c).
struct TextureUse {
    const TextureSource* src;
    uint32_t channels;
    const char* why; // for messages: what reads them
};

void collectTextures(const Layer& L, std::vector<TextureUse>& out) {
    if (!L.enabled) return; // effects on demand: nothing for disabled layers
    const char* why = "the layer";
    const uint32_t channels = L.kind->mapChannels ? L.kind->mapChannels(L, why) : kRgbaChannels;
    for (const auto& m : L.maps) out.push_back({&m, channels, why});
    for (const auto& md : L.modifiers)
        if (md.mask) // modulate: the mask channel it reads
            out.push_back({&*md.mask, 1u << md.channel, "the modulate channel"});
    for (const auto& c : L.children) collectTextures(c, out);
}

std::string componentList(uint32_t mask) {
    std::string s;
    for (int c = 0; c < 4; ++c)
        if (mask >> c & 1u) s += std::string(s.empty() ? "" : ", ") + "rgba"[c];
    return s;
}

// A feature layer's chain (both of its textures, built in one pass from
// the loaded maps; the part not asked for is stored under its own key)
// within the texture budget `opt`.
std::shared_ptr<const TextureImage> loadFeatureChain(const Scene& scene, SceneAssets& assets,
                                                     const TextureSource& src,
                                                     const TextureLoadOptions& opt) {
    const FeatureChainSource& c = *src.featureChain;
    auto fm = assets.featureMaps.find(c.mapsKey);
    SG_ASSERT(fm != assets.featureMaps.end(), "feature maps load before their chains");
    const int n = fm->second->gpu.size;
    try {
        detail::checkTextureBudget("prefiltered chain of feature maps " + c.mapsKey, opt,
                                   std::to_string(n) + "x" + std::to_string(n) +
                                       " texels, 2 x 4 channels as float",
                                   2 * textureBytes(n, n, 4, TexelType::Float), 0);
    } catch (const io::InputError& e) {
        throw io::InputError(scene.sourceName, src.fieldPath, e.what());
    }
    detail::FeatureChainTextures chain = detail::featureChainTextures(*fm->second, c);
    TextureSource other = src;
    other.featureChain->part = 1 - c.part;
    assets.textures[other.key()] =
        std::make_shared<const TextureImage>(std::move(chain.part[1 - c.part]));
    return std::make_shared<const TextureImage>(std::move(chain.part[c.part]));
}

// Loads every texture of `uses` the assets lack, or lack components of
// (a newly enabled layer may read more of a file than the ones before),
// within the scene's texture budget; then refuses a layer that reads a
// component its file does not have.
void loadTextures(const Scene& scene, SceneAssets& assets, const std::vector<TextureUse>& uses) {
    std::map<std::string, uint32_t> need;
    for (const TextureUse& u : uses) need[u.src->key()] |= u.channels;
    for (const TextureUse& u : uses) {
        const std::string key = u.src->key();
        auto it = assets.textures.find(key);
        uint32_t channels = need[key];
        if (it != assets.textures.end()) {
            const TextureImage& t = *it->second;
            const uint32_t inFile =
                t.sourceChannels == 1 ? 0x7u : (1u << std::min(t.sourceChannels, 4)) - 1u;
            if (t.sourceChannels == 0 || (channels & ~t.channelMask & inFile) == 0) continue;
            channels |= t.channelMask; // reload with every component in use
        }
        TextureLoadOptions opt;
        opt.channels = channels;
        opt.budgetBytes = assets.textureBudgetBytes;
        for (const auto& [k, t] : assets.textures) {
            if (k == key) continue;
            opt.usedBytes += t->bytes();
            ++opt.otherTextures;
        }
        std::shared_ptr<const TextureImage> tex;
        if (u.src->featureChain) {
            tex = loadFeatureChain(scene, assets, *u.src, opt);
        } else {
            tex = loadTexture(*u.src, scene.sourceName, opt);
        }
        assets.textures[key] = tex;
        const TexelType type = tex->levels[0].type;
        assets.log.push_back(
            "texture " + key + ": " + std::to_string(tex->width()) + "x" +
            std::to_string(tex->height()) + ", " + std::to_string(tex->levels.size()) +
            " levels, " + std::to_string(tex->levels[0].channels) +
            (tex->sourceChannels > 0 ? " of " + std::to_string(tex->sourceChannels) : "") +
            " channels, " +
            (type == TexelType::Unorm8    ? "8-bit"
             : type == TexelType::Unorm16 ? "16-bit"
             : type == TexelType::Half    ? "half"
                                          : "float") +
            " level 0, " + io::formatBytes(tex->bytes()));
    }
    for (const TextureUse& u : uses) {
        const TextureImage& t = *assets.textures.at(u.src->key());
        if (const uint32_t missing = u.channels & ~t.channelMask) {
            throw io::InputError(
                scene.sourceName, u.src->fieldPath,
                u.src->file.string() + ": " + u.why + " reads channel" +
                    (missing & (missing - 1) ? "s " : " ") + componentList(missing) +
                    ", but the image has " + std::to_string(t.sourceChannels) +
                    (t.sourceChannels == 1 ? " channel (grey: r, g, b)"
                                           : " channels (" + componentList(t.channelMask) + ")"));
        }
    }
}

namespace sm = sg::mesh;

// Files are parsed once per loadAssets (a glTF scene may feed many instances).
struct FileCache {
    std::map<std::string, sm::Scene> scenes;
    const sm::Scene& scene(const fs::path& file) {
        auto it = scenes.find(file.string());
        if (it != scenes.end()) return it->second;
        return scenes.emplace(file.string(), sm::loadScene(file)).first->second;
    }
};

std::string elementOf(const MeshInstance& mi, const std::string& sub) {
    return mi.fieldPath + "." + sub;
}

// Vertex tangents for the UV sets in `wanted` (bit k: set k), each from its
// own source. Limit tangents first: they need the limit frame aligned with
// the vertices, which holds only until MikkTSpace splits one. Each
// MikkTSpace pass may split vertices (sg::mesh::applyCornerTangents keeps
// the first copy in place and appends the others); the arrays of the sets
// done before are extended by copying each new vertex's original, found
// through the index buffer (corner c pointed at the original before and
// at the copy after). MikkTSpace welds corners by value, so a split made
// for one set does not change another set's tangents.
void generateVertexTangents(const Scene& scene, const MeshInstance& mi, uint32_t wanted,
                            const sm::LimitFrame& limit, MeshAsset& a) {
    a.vertexTangents.assign(a.mesh.uvSets.size(), {});
    auto source = [&](size_t k) {
        return k < mi.tangents.size() ? mi.tangents[k] : TangentSource::Pixel;
    };
    auto element = [&](size_t k) { return elementOf(mi, "tangents[" + std::to_string(k) + "]"); };
    for (size_t k = 0; k < mi.tangents.size(); ++k) {
        if (mi.tangents[k] != TangentSource::Pixel && k >= a.mesh.uvSets.size()) {
            throw io::InputError(scene.sourceName, element(k),
                                 "the mesh has no UV set " + std::to_string(k));
        }
    }
    for (size_t k = 0; k < a.mesh.uvSets.size(); ++k) {
        if (!(wanted >> k & 1u) || source(k) != TangentSource::Limit) continue;
        if (limit.empty()) {
            throw io::InputError(scene.sourceName, element(k),
                                 "\"limit\" tangents need \"subdivision\": {\"limit\": true}");
        }
        const std::string why =
            sm::tangentInputProblem(a.mesh, sm::TangentMethod::Limit, int(k), &limit);
        if (!why.empty())
            throw io::InputError(scene.sourceName, element(k), "limit tangents failed: " + why);
        sm::generateLimitTangents(a.mesh, limit, int(k));
        a.vertexTangents[k] = std::move(a.mesh.tangents);
    }
    for (size_t k = 0; k < a.mesh.uvSets.size(); ++k) {
        if (!(wanted >> k & 1u) || source(k) != TangentSource::MikkTSpace) continue;
        const std::vector<uint32_t> cornersBefore = a.mesh.indices;
        const size_t countBefore = a.mesh.vertexCount();
        const std::string why =
            sm::tangentInputProblem(a.mesh, sm::TangentMethod::MikkTSpace, int(k));
        if (!why.empty())
            throw io::InputError(scene.sourceName, element(k), "MikkTSpace failed: " + why);
        sm::generateMikkTSpaceTangents(a.mesh, int(k));
        const size_t countAfter = a.mesh.vertexCount();
        if (countAfter > countBefore) {
            std::vector<uint32_t> original(countAfter);
            for (size_t v = 0; v < countBefore; ++v) original[v] = uint32_t(v);
            for (size_t c = 0; c < cornersBefore.size(); ++c)
                original[a.mesh.indices[c]] = cornersBefore[c];
            for (auto& t : a.vertexTangents) {
                if (t.empty()) continue;
                t.resize(countAfter);
                for (size_t v = countBefore; v < countAfter; ++v) t[v] = t[original[v]];
            }
        }
        a.vertexTangents[k] = std::move(a.mesh.tangents);
    }
    // The per-set arrays are the renderer's; the mesh's single slot stays empty.
    a.mesh.tangents.clear();
    a.mesh.tangentUvSet = -1;
}

// The UV sets of `mi` that get vertex tangents: asked for by the mesh and
// read by an enabled layer of its material.
uint32_t vertexTangentSets(const Scene& scene, const MeshInstance& mi) {
    uint32_t asked = 0;
    for (size_t k = 0; k < mi.tangents.size(); ++k) {
        if (mi.tangents[k] != TangentSource::Pixel) asked |= 1u << k;
    }
    return asked & tangentBasisUvSets(scene.materials[size_t(mi.material)]);
}

uint64_t nextLayoutId() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

// The mesh of a file instance: as stored, or refined (and its limit frame
// when asked). Errors of the file name the file.
sm::RenderMesh loadMeshFile(const Scene& scene, const MeshInstance& mi, FileCache& files,
                            sm::LimitFrame& limit) {
    if (!mi.subdivide) {
        if (mi.fileInstance < 0) return sm::loadRenderMesh(mi.file);
        const sm::Scene& fs = files.scene(mi.file);
        if (size_t(mi.fileInstance) >= fs.instances.size()) {
            throw io::InputError(scene.sourceName, elementOf(mi, "file"),
                                 "the file has no mesh instance " +
                                     std::to_string(mi.fileInstance));
        }
        return fs.instances[size_t(mi.fileInstance)].mesh;
    }
    // Effects on demand: refined exactly to the level asked, with limit
    // evaluation only when asked.
    sm::PolygonMesh cage = sm::loadPolygonMesh(mi.file);
    sm::SubdivisionSettings st;
    st.level = mi.subdivLevel;
    st.options = cage.options;
    if (!mi.subdivScheme.empty() && !sm::parseScheme(mi.subdivScheme, st.options.scheme)) {
        throw io::InputError(scene.sourceName, elementOf(mi, "subdivision.scheme"),
                             "unknown scheme");
    }
    st.limit = mi.subdivLimit;
    st.memoryBudget = mi.subdivMaxMemory;
    st.memoryBudgetHint = "the scene field " + elementOf(mi, "subdivision.max_memory_mib");
    sm::Subdivider sub(cage, st, mi.file.string());
    if (mi.subdivLimit) limit = sub.limitFrame();
    return sub.renderMesh();
}

// An adaptive mesh ("subdivision": {"mode": "adaptive"}): the cage's
// feature-adaptive patches with its UV sets (and the derived ones); `mesh`
// keeps their control points for the bounds. Morph targets of the cage
// (blendshapes) animate the cage (applyFrame -> setCagePositions: the
// patches' points follow through the stencils). Vertex tangents: "limit"
// only, evaluated by the tessellation stages from the patch derivatives
// (MeshAsset::patchTangentSets); MikkTSpace needs a vertex list the patches
// do not have: refused (the scene parser refuses it too; this also covers
// scenes built in code).
MeshAsset loadAdaptiveMeshAsset(const Scene& scene, const MeshInstance& mi) {
    for (size_t k = 0; k < mi.tangents.size(); ++k) {
        if (mi.tangents[k] == TangentSource::MikkTSpace) {
            throw io::InputError(scene.sourceName,
                                 elementOf(mi, "tangents[" + std::to_string(k) + "]"),
                                 "\"mikktspace\" tangents need a vertex list; \"subdivision\": "
                                 "{\"mode\": \"adaptive\"} meshes are patches (use \"limit\" or "
                                 "\"pixel\", or \"mode\": \"uniform\")");
        }
    }
    MeshAsset a;
    sm::PolygonMesh cage;
    std::shared_ptr<const sm::AdaptivePatches> patches =
        detail::fromReferencedFile(scene.sourceName, elementOf(mi, "file"), [&] {
            cage = sm::loadPolygonMesh(mi.file);
            sm::SubdivOptions options = cage.options;
            if (!mi.subdivScheme.empty() && !sm::parseScheme(mi.subdivScheme, options.scheme)) {
                throw io::InputError(scene.sourceName, elementOf(mi, "subdivision.scheme"),
                                     "unknown scheme");
            }
            return std::make_shared<sm::AdaptivePatches>(
                sm::buildAdaptivePatches(cage, options, mi.subdivIsolation, mi.file.string()));
        });
    // Derived UV sets, and every set only repeating maps read moved by
    // whole units next to 0 (uv_sets.cpp).
    const uint32_t repeatOnly = detail::repeatOnlyUvSets(scene, mi);
    if (!mi.derivedUvSets.empty() || repeatOnly != 0u) {
        auto own = std::make_shared<sm::AdaptivePatches>(*patches);
        detail::addDerivedPatchUvSets(scene, mi, repeatOnly, *own);
        patches = std::move(own);
    }
    // "limit" tangents for the sets an enabled layer reads (vertexTangentSets).
    const uint32_t tangentSets = vertexTangentSets(scene, mi);
    for (size_t k = 0; k < size_t(kMaxUvSets); ++k) {
        if (!(tangentSets >> k & 1u)) continue;
        if (k >= patches->uvSets.size()) {
            throw io::InputError(scene.sourceName,
                                 elementOf(mi, "tangents[" + std::to_string(k) + "]"),
                                 "the mesh has no UV set " + std::to_string(k));
        }
        a.patchTangentSets |= 1u << k;
    }
    if (mi.displacement && size_t(mi.displacement->uvSet) >= patches->uvSets.size()) {
        throw io::InputError(scene.sourceName, mi.displacement->fieldPath + ".uv_set",
                             "the mesh has " + std::to_string(patches->uvSets.size()) +
                                 " UV set(s), no set " + std::to_string(mi.displacement->uvSet));
    }
    a.mesh.positions = patches->points;
    a.mesh.normals.assign(a.mesh.positions.size(), glm::vec3(0.0f, 0.0f, 1.0f));
    const size_t targets = cage.morphTargets.size();
    if (targets) {
        a.mesh.morphWeights = cage.morphWeights;
        if (a.mesh.morphWeights.size() != targets) a.mesh.morphWeights.assign(targets, 0.0f);
        a.morphCage = std::make_shared<const sm::PolygonMesh>(std::move(cage));
    }
    if ((!mi.morphWeights.empty() && mi.morphWeights.size() != targets) ||
        (!mi.morphKeys.empty() && mi.morphKeys[0].weights.size() != targets)) {
        throw io::InputError(scene.sourceName, elementOf(mi, "morph"),
                             "the cage has " + std::to_string(targets) +
                                 " morph targets; the weights must match");
    }
    a.patches = std::move(patches);
    a.basePositions = a.mesh.positions;
    a.baseNormals = a.mesh.normals;
    a.layoutId = nextLayoutId();
    return a;
}

MeshAsset loadMeshAsset(const Scene& scene, const MeshInstance& mi, FileCache& files) {
    if (mi.subdivide && mi.subdivAdaptive) return loadAdaptiveMeshAsset(scene, mi);
    MeshAsset a;
    sm::LimitFrame limit;
    if (mi.procedural) {
        a.mesh = detail::makeProceduralMesh(*mi.procedural);
    } else {
        a.mesh = detail::fromReferencedFile(scene.sourceName, elementOf(mi, "file"),
                                            [&] { return loadMeshFile(scene, mi, files, limit); });
    }
    if (a.mesh.normals.size() != a.mesh.positions.size()) sm::computeVertexNormals(a.mesh);
    // Derived UV sets (uv_sets.cpp), then tangents from the sets as loaded,
    // then every set only repeating maps read moved by whole units next to
    // 0 (MikkTSpace sees the file's own coordinates).
    const uint32_t repeatOnly = detail::repeatOnlyUvSets(scene, mi);
    const uint32_t ownSets = uint32_t(a.mesh.uvSets.size());
    detail::addDerivedUvSets(scene, mi, repeatOnly, a.mesh, limit);
    generateVertexTangents(scene, mi, vertexTangentSets(scene, mi), limit, a);
    detail::recentreUvSets(repeatOnly & ((1u << ownSets) - 1u), a.mesh.uvSets);
    if (!mi.morphWeights.empty() && mi.morphWeights.size() != a.mesh.morphTargets.size()) {
        throw io::InputError(scene.sourceName, mi.fieldPath + ".morph.weights",
                             "the mesh has " + std::to_string(a.mesh.morphTargets.size()) +
                                 " morph targets, but " + std::to_string(mi.morphWeights.size()) +
                                 " weights are given");
    }
    if (!mi.morphKeys.empty() && mi.morphKeys[0].weights.size() != a.mesh.morphTargets.size()) {
        throw io::InputError(scene.sourceName, mi.fieldPath + ".morph.animation.keys",
                             "the mesh has " + std::to_string(a.mesh.morphTargets.size()) +
                                 " morph targets; every key needs that many weights");
    }
    a.basePositions = a.mesh.positions;
    a.baseNormals = a.mesh.normals;
    a.baseTangents = a.vertexTangents;
    a.layoutId = nextLayoutId();
    return a;
}

// Sets the morph weights of one mesh asset (positions, normals, vertex
// tangents from the base arrays plus weighted deltas).
void applyWeights(MeshAsset& a, const std::vector<float>& w) {
    a.appliedWeights = w;
    a.mesh.positions = a.basePositions;
    a.mesh.normals = a.baseNormals;
    a.vertexTangents = a.baseTangents;
    for (size_t t = 0; t < a.mesh.morphTargets.size() && t < w.size(); ++t) {
        const auto& mt = a.mesh.morphTargets[t];
        for (size_t v = 0; v < mt.positionDeltas.size(); ++v)
            a.mesh.positions[v] += w[t] * mt.positionDeltas[v];
        for (size_t v = 0; v < mt.normalDeltas.size() && v < a.mesh.normals.size(); ++v) {
            a.mesh.normals[v] += w[t] * mt.normalDeltas[v];
        }
        // Vertex tangents follow the glTF rule too (blended deltas);
        // without deltas they stay those of the base shape: only the
        // per-pixel frame is exact on a morphed mesh (Mikkelsen 2019, 1).
        for (auto& vt : a.vertexTangents) {
            for (size_t v = 0; v < mt.tangentDeltas.size() && v < vt.size(); ++v) {
                vt[v] += glm::vec4(w[t] * mt.tangentDeltas[v], 0.0f);
            }
        }
    }
    // glTF's rule: blended normals are renormalized.
    for (auto& n : a.mesh.normals) {
        float l = glm::length(n);
        if (l > 1e-20f && std::isfinite(l)) n /= l;
    }
    for (auto& vt : a.vertexTangents) {
        for (auto& t : vt) {
            float l = glm::length(glm::vec3(t));
            if (l > 1e-20f && std::isfinite(l)) t = glm::vec4(glm::vec3(t) / l, t.w);
        }
    }
}

} // namespace

SceneAssets loadAssets(const Scene& scene, const AssetOptions& options) {
    static std::atomic<uint64_t> nextUid{1};
    SceneAssets assets;
    assets.uid = nextUid++;
    assets.textureBudgetBytes =
        options.textureBudgetBytes ? options.textureBudgetBytes : defaultTextureBudget();
    FileCache files;
    for (const auto& mi : scene.meshes) {
        try {
            assets.meshes.push_back(loadMeshAsset(scene, mi, files));
        } catch (const std::bad_alloc&) {
            throw io::InputError(
                scene.sourceName, mi.fieldPath,
                "out of memory loading " +
                    (mi.file.empty() ? std::string("the procedural mesh") : mi.file.string()));
        }
        const auto& m = assets.meshes.back().mesh;
        assets.log.push_back("mesh " + (mi.name.empty() ? mi.fieldPath : mi.name) + ": " +
                             std::to_string(m.vertexCount()) + " vertices, " +
                             std::to_string(m.triangleCount()) + " triangles, " +
                             std::to_string(m.uvSets.size()) + " UV sets");
    }
    loadMissingAssets(scene, assets);
    applyFrame(scene, assets, 0.0f);
    return assets;
}

void loadMissingAssets(const Scene& scene, SceneAssets& assets) {
    // Textures of materials that some mesh uses and layers that are enabled.
    std::set<int> usedMaterials;
    for (const auto& mi : scene.meshes) usedMaterials.insert(mi.material);
    std::vector<TextureUse> textureUses;
    for (int mIdx : usedMaterials) {
        const Material& mat = scene.materials[size_t(mIdx)];
        if (mat.baseColorMap)
            textureUses.push_back(
                {&*mat.baseColorMap, kChannelR | kChannelG | kChannelB, "the colour"});
        for (const Layer& L : mat.layers) collectTextures(L, textureUses);
    }
    // Height maps of displaced adaptive meshes (red channel).
    for (const auto& mi : scene.meshes)
        if (mi.displacement && mi.subdivAdaptive)
            textureUses.push_back({&mi.displacement->map, 1u, "the displacement"});
    std::vector<const Layer*> features;
    for (int mIdx : usedMaterials)
        for (const Layer& L : scene.materials[size_t(mIdx)].layers) collectFeatures(L, features);
    for (const Layer* L : features) {
        const FeatureSource& src = *L->kind->featureSource(*L);
        std::string key = src.key();
        if (!assets.featureMaps.count(key)) {
            assets.featureMaps[key] = loadFeatureMaps(src, scene.sourceName);
            assets.log.push_back("feature maps " + key + ": " +
                                 std::to_string(assets.featureMaps[key]->gpu.size) + "^2 texels");
        }
        if (L->kind->checkAssets) L->kind->checkAssets(*L, assets, scene.sourceName);
    }
    // Meshes whose enabled layers now read the basis of a UV set they ask
    // vertex tangents for, but do not have them: rebuilt (MikkTSpace may
    // split vertices, so the whole vertex layout is new), same morph weights.
    FileCache files;
    for (size_t i = 0; i < scene.meshes.size() && i < assets.meshes.size(); ++i) {
        MeshAsset& a = assets.meshes[i];
        uint32_t have = a.patchTangentSets;
        for (size_t k = 0; k < a.vertexTangents.size(); ++k) {
            if (!a.vertexTangents[k].empty()) have |= 1u << k;
        }
        const size_t uvSets = a.patches ? a.patches->uvSets.size() : a.mesh.uvSets.size();
        const uint32_t sets = (1u << std::min(uvSets, size_t(kMaxUvSets))) - 1u;
        if ((vertexTangentSets(scene, scene.meshes[i]) & sets & ~have) == 0) continue;
        std::vector<float> weights = a.appliedWeights;
        a = loadMeshAsset(scene, scene.meshes[i], files);
        if (!weights.empty()) applyWeights(a, weights);
        ++assets.meshVersion;
        assets.log.push_back("mesh " + scene.meshes[i].fieldPath +
                             ": rebuilt with vertex tangents for newly enabled layers");
    }
    if (assets.textureBudgetBytes == 0) assets.textureBudgetBytes = defaultTextureBudget();
    loadTextures(scene, assets, textureUses);
}

namespace {

std::vector<float> weightsAt(const MeshInstance& mi, const sg::mesh::RenderMesh& m, float t) {
    if (!mi.morphKeys.empty()) {
        const auto& k = mi.morphKeys;
        float t0 = k.front().time, t1 = k.back().time;
        if (mi.morphLoop && t1 > t0) t = t0 + std::fmod(std::max(t - t0, 0.0f), t1 - t0);
        if (t <= t0) return k.front().weights;
        if (t >= t1) return k.back().weights;
        size_t i = 1;
        while (i < k.size() && k[i].time < t) ++i;
        float a = (t - k[i - 1].time) / (k[i].time - k[i - 1].time);
        std::vector<float> w(k[i].weights.size());
        for (size_t j = 0; j < w.size(); ++j)
            w[j] = (1.0f - a) * k[i - 1].weights[j] + a * k[i].weights[j];
        return w;
    }
    if (!mi.morphWeights.empty()) return mi.morphWeights;
    return m.morphWeights;
}

} // namespace

void setCagePositions(const Scene& scene, SceneAssets& assets, size_t mesh,
                      std::vector<glm::vec3> cagePositions) {
    SG_EXPECTS(mesh < assets.meshes.size() && mesh < scene.meshes.size() &&
                   assets.meshes[mesh].patches &&
                   cagePositions.size() == assets.meshes[mesh].patches->cagePointCount,
               "setCagePositions: an adaptive mesh and one position per cage vertex");
    for (size_t v = 0; v < cagePositions.size(); ++v) {
        const glm::vec3 p = cagePositions[v];
        if (!(std::fabs(p.x) <= kMaxCagePosition && std::fabs(p.y) <= kMaxCagePosition &&
              std::fabs(p.z) <= kMaxCagePosition)) {
            throw io::InputError(scene.sourceName, elementOf(scene.meshes[mesh], "morph"),
                                 "cage vertex " + std::to_string(v) +
                                     " is not finite or beyond 2^100 after animation; the "
                                     "frame is refused");
        }
    }
    MeshAsset& a = assets.meshes[mesh];
    a.cagePositions = std::move(cagePositions);
    ++assets.meshVersion;
}

void applyFrame(const Scene& scene, SceneAssets& assets, float seconds) {
    for (size_t i = 0; i < scene.meshes.size() && i < assets.meshes.size(); ++i) {
        MeshAsset& a = assets.meshes[i];
        if (a.patches && a.morphCage) {
            // Blendshapes on the cage of an adaptive mesh: the cage moves.
            std::vector<float> w = weightsAt(scene.meshes[i], a.mesh, seconds);
            if (w == a.appliedWeights) continue; // nothing moved
            std::vector<glm::vec3> cage;
            sm::morphCagePositions(*a.morphCage, w, cage);
            setCagePositions(scene, assets, i, std::move(cage));
            a.appliedWeights = std::move(w);
            continue;
        }
        if (a.mesh.morphTargets.empty()) continue;
        std::vector<float> w = weightsAt(scene.meshes[i], a.mesh, seconds);
        if (w == a.appliedWeights) continue; // nothing moved
        applyWeights(a, w);
        ++assets.meshVersion;
    }
}

Scene sceneForModel(const fs::path& model) {
    // A model's own materials: base colour (factor and map) and its normal
    // map as a uv_normal layer on the map's texture coordinate set with the
    // glTF normal scale as strength. glTF normal maps are green-up in the
    // image (+Y up, section 3.9.3); with images and t both flipped on load
    // that is our "gl" convention. glTF's doubleSided (sec. 3.9.5) decides
    // the back faces: false (the default, also of the default material)
    // culls them; true renders them in MIRROR mode (Mikkelsen 2019, 2.10),
    // which is glTF's rule: the normal is reversed on the back side.
    Scene s;
    s.sourceName = model.string();
    s.baseDir = model.parent_path();
    sm::Scene fs = sm::loadScene(model);
    for (size_t i = 0; i < fs.materials.size(); ++i) {
        const sm::Material& gm = fs.materials[i];
        Material m;
        m.name = gm.name.empty() ? "material" + std::to_string(i) : gm.name;
        m.fieldPath = model.filename().string() + " materials[" + std::to_string(i) + "]";
        m.baseColor = glm::clamp(glm::vec3(gm.baseColorFactor), glm::vec3(0.0f), glm::vec3(1.0f));
        m.doubleSided = gm.doubleSided ? DoubleSided::Mirror : DoubleSided::Off;
        if (!gm.baseColorTexture.empty()) {
            TextureSource t;
            t.file = gm.baseColorTexture;
            t.srgb = true;
            t.fieldPath = m.fieldPath + ".baseColorTexture";
            m.baseColorMap = t;
            m.baseColorUvSet = std::clamp(gm.baseColorTexCoord, 0, kMaxUvSets - 1);
        }
        if (!gm.normalTexture.empty()) {
            Layer L = makeLayer("uv_normal");
            L.fieldPath = m.fieldPath + ".normalTexture";
            TextureSource t;
            t.file = gm.normalTexture;
            t.fieldPath = L.fieldPath;
            L.maps.push_back(t);
            L.uvSet = std::clamp(gm.normalTexCoord, 0, kMaxUvSets - 1);
            L.strength = gm.normalScale;
            m.layers.push_back(L);
        }
        s.materials.push_back(std::move(m));
    }
    Material fallback;
    fallback.name = "default";
    fallback.fieldPath = "(default material)";
    fallback.doubleSided = DoubleSided::Off; // glTF's default material is single-sided
    for (size_t i = 0; i < fs.instances.size(); ++i) {
        const sm::SceneInstance& inst = fs.instances[i];
        MeshInstance mi;
        mi.name = inst.mesh.name;
        mi.fieldPath = model.filename().string() + " instance " + std::to_string(i);
        mi.file = model;
        mi.fileInstance = int(i);
        mi.transform = glm::dmat4(inst.objectToWorld);
        // The node's weight animation (glTF sec. 3.11) as linear keys: the
        // animation's own keys when linear, else samples at 30 Hz of
        // sampleWeights (step / cubic spline).
        for (const auto& anim : fs.animations) {
            if (anim.node != inst.node || anim.times.empty() ||
                anim.targetCount != inst.mesh.morphTargets.size() || anim.targetCount == 0) {
                continue;
            }
            std::vector<float> times;
            if (anim.interpolation == sm::AnimInterpolation::Linear) {
                times = anim.times;
            } else {
                float t0 = anim.times.front(), t1 = anim.times.back();
                int n = std::clamp(int((t1 - t0) * 30.0f) + 1, 2, 4096);
                for (int k = 0; k < n; ++k)
                    times.push_back(t0 + (t1 - t0) * float(k) / float(n - 1));
            }
            for (float t : times) mi.morphKeys.push_back(MorphKey{t, sm::sampleWeights(anim, t)});
            mi.morphLoop = true;
            float duration = anim.times.back();
            s.frameCount = std::max(s.frameCount, int(std::ceil(duration * s.fps)) + 1);
            break;
        }
        if (inst.material >= 0 && size_t(inst.material) < s.materials.size()) {
            mi.material = inst.material;
        } else {
            if (s.materials.empty() || s.materials.back().name != "default")
                s.materials.push_back(fallback);
            mi.material = int(s.materials.size()) - 1;
        }
        s.meshes.push_back(std::move(mi));
    }
    if (s.meshes.empty())
        throw io::InputError(model.string(), "", "the file has no triangle meshes");
    s.lights.push_back(Light{});
    Light fill;
    fill.direction = glm::vec3(0.6f, -0.2f, 0.5f);
    fill.color = glm::vec3(0.6f, 0.7f, 0.9f);
    fill.intensity = 1.0f;
    s.lights.push_back(fill);
    return s;
}

// ---------------------------------------------------------------------------
// Views

namespace {

View finishView(glm::dvec3 eye, glm::dvec3 target, glm::dvec3 up, float fovDeg, float nearP,
                float farP, int w, int h, Aov aov) {
    View v;
    v.width = w;
    v.height = h;
    v.aov = aov;
    v.cameraPos = eye;
    // In binary64: the direction target - eye of a camera 1e6 from the
    // origin keeps its digits.
    const glm::dmat4 view = glm::lookAt(eye, target, up);
    v.view = glm::mat4(view);
    v.proj = glm::perspective(glm::radians(fovDeg), float(w) / float(h), nearP, farP);
    // Camera-relative: the view's rotation only (listing 16's relative
    // world position keeps the translation out of every derivative).
    v.viewProjRel = v.proj * glm::mat4(glm::mat3(view));
    return v;
}

} // namespace

View makeView(const Scene& scene, const SceneAssets& assets, int width, int height, Aov aov) {
    int w = width > 0 ? width : scene.output.width;
    int h = height > 0 ? height : scene.output.height;
    glm::vec3 lo, hi;
    detail::sceneBounds(scene, assets, lo, hi);
    const glm::dvec3 center = 0.5 * (glm::dvec3(lo) + glm::dvec3(hi));
    float radius = std::max(0.5f * glm::length(hi - lo), 1e-3f);
    const Camera& c = scene.camera;
    glm::dvec3 eye = c.position, target = c.target;
    float halfFov = glm::radians(c.fovDeg) * 0.5f;
    if (c.automatic) {
        float az = glm::radians(c.azimuthDeg), el = glm::radians(c.elevationDeg);
        glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
        // Fit the bounding sphere in the narrower of the two fields of view.
        float halfFovX = std::atan(std::tan(halfFov) * float(w) / float(h));
        float dist = radius / std::sin(std::min(halfFov, halfFovX)) * c.distanceScale;
        target = center;
        eye = center + glm::dvec3(dir * dist);
    }
    float dist = float(glm::length(eye - center));
    float nearP = c.nearPlane > 0 ? c.nearPlane
                                  : std::max(dist - 2.0f * radius, std::max(dist, radius) * 1e-3f);
    float farP = c.farPlane > 0 ? c.farPlane : dist + 3.0f * radius;
    return finishView(eye, target, c.up, c.fovDeg, nearP, farP, w, h, aov);
}

View makeOrbitView(glm::dvec3 target, float distance, float azimuthDeg, float elevationDeg,
                   float fovDeg, float nearPlane, float farPlane, int width, int height, Aov aov) {
    float az = glm::radians(azimuthDeg), el = glm::radians(elevationDeg);
    glm::vec3 dir(std::sin(az) * std::cos(el), std::sin(el), std::cos(az) * std::cos(el));
    return finishView(target + glm::dvec3(distance * dir), target, glm::dvec3(0, 1, 0), fovDeg,
                      nearPlane, farPlane, width, height, aov);
}

} // namespace sg::render

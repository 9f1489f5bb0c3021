// Scene assets: meshes (procedural ones from procedural_mesh.cpp, files
// through the mesh module), textures (files through texture_file.cpp, or
// procedural, or made by a layer kind's producer), the layer kinds' own
// assets through their registry hooks (LayerKindAssets::load), and
// per-frame morphing. (The scene made for a bare model:
// model_scene.cpp; the camera views: view.cpp.) Effects on demand: only textures of
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
#include "surfgrad/base/contract.h"
#include "surfgrad/image/image_header.h"
#include "surfgrad/base/io.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/mesh/morph.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/mesh/subdivision.h"
#include "surfgrad/mesh/tangents.h"
#include "surfgrad/render.h"
#include "surfgrad/render/render_shaders.h"

namespace sg::render {

namespace fs = std::filesystem;

namespace detail {

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

// Enabled layers (children included) of `kind` that read its own assets.
void collectKindLayers(const Layer& L, const LayerKind& kind, std::vector<const Layer*>& out) {
    if (!L.enabled) return;
    if (L.kind == &kind && kind.assets->reads(L)) out.push_back(&L);
    for (const auto& c : L.children) collectKindLayers(c, kind, out);
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
        if (u.src->producer) { // made by a layer kind from its own assets
            tex = u.src->producer->make(scene, assets, *u.src, opt);
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
    // The layer kinds' own assets (LayerKindAssets::load), before the
    // textures, some of which kinds make from them (TextureSource::producer).
    for (const LayerKind* kind : layerKinds()) {
        if (!kind->assets || !kind->assets->load) continue;
        std::vector<const Layer*> layers;
        for (int mIdx : usedMaterials)
            for (const Layer& L : scene.materials[size_t(mIdx)].layers)
                collectKindLayers(L, *kind, layers);
        kind->assets->load(scene, layers, assets);
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

} // namespace sg::render

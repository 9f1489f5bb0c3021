// Material plans (effects on demand): which layers, UV sets, volume
// domains, textures, kinds' own assets (feature maps) and vertex tangents
// one material on one mesh uses, its effect signature (the program cache
// key), and the uniform records its layers read. Everything a layer kind
// contributes comes from its registry entry (layer_kind.h); the GLSL
// program and its CPU twin are assembled from the plan in plan.cpp.
#include <algorithm>
#include <map>
#include <sstream>

#include "layer_kind.h"
#include "render_internal.h"
#include "surfgrad/mesh/adaptive_patches.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/base/io.h"

namespace sg::render {

namespace {

// Short code of a layer in the effect signature: the kind, its UV set and
// frame source, volume domain, modifiers and texture / kind-asset slots.
std::string sigCode(const PlanLayer& pl, const MaterialPlan& plan) {
    const Layer& L = *pl.layer;
    std::string s = L.kind->sigCode;
    if (L.kind->readsUv) {
        s += "@uv" + std::to_string(L.uvSet) +
             ((plan.vertexTangentMask >> L.uvSet) & 1u ? "v" : "p");
    }
    if (L.kind->volume) s += *L.kind->volume(L) == Space::World ? "@w" : "@o";
    if (L.kind->signature) s += L.kind->signature(L);
    if (pl.hasModifiers) {
        s += "+mods[";
        for (size_t i = 0; i < L.modifiers.size(); ++i) {
            s += L.modifiers[i].kind->sigCode;
            if (pl.modTex[i] >= 0) s += std::to_string(pl.modTex[i]);
        }
        s += "]";
    }
    std::string slots;
    for (int t : pl.tex)
        if (t >= 0) slots += (slots.empty() ? "" : ",") + std::to_string(t);
    if (!slots.empty()) s += ":t" + slots;
    if (pl.kindSlot >= 0) s += L.kind->assets->slotCode + std::to_string(pl.kindSlot);
    return s;
}

struct Planner {
    const Scene& scene;
    const SceneAssets& assets;
    int meshIndex;
    MaterialPlan plan;
    std::map<std::string, int> slotByKey;

    int slot(const TextureSource* src) {
        std::string key = src ? src->key() : std::string();
        auto it = slotByKey.find(key);
        if (it != slotByKey.end()) return it->second;
        int s = int(plan.textureKeys.size());
        if (s >= kMaxTextureSlots) {
            throw io::InputError(scene.sourceName, src ? src->fieldPath : "(material)",
                                 "the material uses more than " + std::to_string(kMaxTextureSlots) +
                                     " distinct textures");
        }
        slotByKey[key] = s;
        plan.textureKeys.push_back(key);
        plan.textureSources.push_back(src);
        return s;
    }

    void modifiers(const Layer& L, PlanLayer& pl) {
        pl.hasModifiers = !L.modifiers.empty() && L.kind->modifiers != nullptr;
        if (!pl.hasModifiers) return;
        pl.modRecord = plan.recordCount;
        plan.recordCount += int(L.modifiers.size());
        for (size_t i = 0; i < L.modifiers.size() && i < size_t(kMaxModifiers); ++i) {
            const Modifier& m = L.modifiers[i];
            if (m.mask) pl.modTex[i] = slot(&*m.mask);
        }
    }

    void uvSet(const Layer& L) {
        if (!L.kind->readsUv) return;
        if (L.uvSet >= plan.uvCount) {
            const MeshInstance& mi = scene.meshes[size_t(meshIndex)];
            throw io::InputError(scene.sourceName, L.fieldPath + ".uv_set",
                                 "UV set " + std::to_string(L.uvSet) + " is used, but mesh " +
                                     (mi.name.empty() ? mi.fieldPath : "\"" + mi.name + "\"") +
                                     " has " + std::to_string(plan.uvCount) + " UV set(s)");
        }
        plan.uvUsedMask |= 1u << L.uvSet;
    }

    // The layer's share of its kind's own assets (LayerKindAssets::plan).
    void kindAssets(const Layer& L, PlanLayer& pl) {
        const LayerKindAssets* ka = L.kind->assets;
        if (!ka || !ka->plan || !ka->reads(L)) return;
        auto it = std::find_if(plan.kindPlans.begin(), plan.kindPlans.end(),
                               [&](const KindPlan& kp) { return kp.kind == L.kind; });
        if (it == plan.kindPlans.end()) {
            plan.kindPlans.push_back(KindPlan{});
            plan.kindPlans.back().kind = L.kind;
            it = plan.kindPlans.end() - 1;
        }
        ka->plan(L, assets, *it, pl);
    }

    PlanLayer add(const Layer& L, bool uber) {
        PlanLayer pl;
        pl.layer = &L;
        pl.record = plan.recordCount;
        pl.recordCount = L.kind->recordCount();
        plan.recordCount += pl.recordCount;
        modifiers(L, pl);
        uvSet(L);
        if (L.kind->volume) {
            (*L.kind->volume(L) == Space::World ? plan.usesWorldVolume : plan.usesObjectVolume) =
                true;
        }
        kindAssets(L, pl);
        if (L.kind->antialias && L.kind->antialias(L)) plan.antialias = true;
        const int slots = L.kind->textureSlotsOf ? L.kind->textureSlotsOf(L) : L.kind->textureSlots;
        SG_ASSERT(slots <= 6, "PlanLayer::tex holds 6 slots");
        for (int i = 0; i < slots; ++i) {
            const TextureSource* src = nullptr;
            if (!L.maps.empty()) src = &L.maps[std::min(size_t(i), L.maps.size() - 1)];
            pl.tex[i] = slot(src);
        }
        if (uber) pl.uberIndex = plan.uberFlagCount++;
        if (std::find(plan.kinds.begin(), plan.kinds.end(), L.kind) == plan.kinds.end())
            plan.kinds.push_back(L.kind);
        return pl;
    }

    void addGroups(const std::vector<Layer>& layers, bool uber) {
        for (const Layer& L : layers) {
            if (!L.enabled && !uber) continue;
            if (L.kind->group) {
                std::vector<PlanLayer> g;
                for (const Layer& c : L.children) {
                    if (c.enabled || uber) g.push_back(add(c, uber));
                }
                if (!g.empty()) {
                    plan.groups.push_back(std::move(g));
                    plan.groupLayers.push_back(&L);
                    plan.groupUberIndex.push_back(uber ? plan.uberFlagCount++ : -1);
                }
            } else {
                plan.groups[0].push_back(add(L, uber));
            }
        }
    }

    void baseColor(const Material& mat) {
        if (!mat.baseColorMap) return;
        if (mat.baseColorUvSet >= plan.uvCount) {
            // A colour map on a missing UV set is skipped rather than fatal:
            // models often declare maps their meshes cannot use.
            return;
        }
        plan.baseColorTex = slot(&*mat.baseColorMap);
        plan.baseColorUvSet = mat.baseColorUvSet;
        plan.uvUsedMask |= 1u << mat.baseColorUvSet;
    }

    void finish() {
        // Kinds in registry order (program-level parts come in that order).
        std::vector<const LayerKind*> kinds;
        for (const LayerKind* k : layerKinds())
            if (std::find(plan.kinds.begin(), plan.kinds.end(), k) != plan.kinds.end())
                kinds.push_back(k);
        plan.kinds = kinds;
        std::ostringstream sig;
        sig << "uv" << plan.uvCount << ":vt" << plan.vertexTangentMask << ":l" << plan.lightCount
            << (plan.uber ? ":uber" : "") << (plan.adaptive ? ":patches" : "");
        if (plan.displacementUvSet >= 0) sig << ":disp" << plan.displacementUvSet;
        for (size_t g = 0; g < plan.groups.size(); ++g) {
            sig << "|g" << g << "[";
            for (const auto& pl : plan.groups[g]) sig << sigCode(pl, plan) << ";";
            sig << "]";
        }
        if (plan.baseColorTex >= 0)
            sig << "|bc@uv" << plan.baseColorUvSet << ":t" << plan.baseColorTex;
        for (const LayerKind* k : plan.kinds)
            if (k->programSignature) sig << k->programSignature(plan);
        sig << "|tex" << plan.textureKeys.size();
        plan.signature = sig.str();
    }
};

MaterialPlan makePlan(const Scene& scene, const SceneAssets& assets, int meshIndex,
                      int materialIndex, bool uber) {
    SG_EXPECTS(meshIndex >= 0 && size_t(meshIndex) < scene.meshes.size(),
               "meshIndex indexes scene.meshes");
    SG_EXPECTS(materialIndex >= 0 && size_t(materialIndex) < scene.materials.size(),
               "materialIndex indexes scene.materials");
    SG_EXPECTS(assets.meshes.size() == scene.meshes.size(), "assets loaded from this scene");
    Planner p{scene, assets, meshIndex, {}, {}};
    const MeshAsset& ma = assets.meshes[size_t(meshIndex)];
    p.plan.materialIndex = materialIndex;
    p.plan.uber = uber;
    p.plan.adaptive = ma.patches != nullptr;
    // Adaptive meshes: the patches' UV sets (ma.mesh holds only their
    // control points).
    const size_t uvSets = ma.patches ? ma.patches->uvSets.size() : ma.mesh.uvSets.size();
    p.plan.uvCount = std::min(int(uvSets), kMaxUvSets);
    const MeshInstance& mi = scene.meshes[size_t(meshIndex)];
    if (ma.patches && mi.displacement) {
        if (mi.displacement->uvSet >= p.plan.uvCount) {
            throw io::InputError(scene.sourceName, mi.displacement->fieldPath + ".uv_set",
                                 "the mesh has " + std::to_string(p.plan.uvCount) +
                                     " UV set(s), no set " +
                                     std::to_string(mi.displacement->uvSet));
        }
        p.plan.displacementUvSet = mi.displacement->uvSet;
    }
    // Vertex tangents are read only where an enabled layer uses the set's
    // basis (a mesh may keep tangents of a set whose layers were switched off).
    const uint32_t basisSets = tangentBasisUvSets(scene.materials[size_t(materialIndex)]);
    for (int k = 0; k < p.plan.uvCount && k < int(ma.vertexTangents.size()); ++k) {
        if (!ma.vertexTangents[size_t(k)].empty() && (basisSets >> k & 1u))
            p.plan.vertexTangentMask |= 1u << k;
    }
    // Adaptive meshes: the evaluation stage writes the same vTangentk.
    p.plan.vertexTangentMask |= patchTangentMask(ma, scene.materials[size_t(materialIndex)]);
    p.plan.lightCount = std::max(1, int(scene.lights.size()));
    p.plan.groups.emplace_back();
    p.plan.groupLayers.push_back(nullptr);
    p.plan.groupUberIndex.push_back(-1);
    p.addGroups(scene.materials[size_t(materialIndex)].layers, uber);
    p.baseColor(scene.materials[size_t(materialIndex)]);
    if (uber) {
        // Stand-ins: every kind compiled in (the registry's, in its order).
        auto owned = std::make_shared<std::vector<Layer>>();
        for (const LayerKind* k : layerKinds()) {
            if (!k->uberStandIns) continue;
            for (Layer& L : k->uberStandIns(*k, p.plan.uvCount)) owned->push_back(std::move(L));
        }
        p.plan.ownedLayers = owned;
        p.addGroups(*owned, true);
    }
    p.finish();
    return p.plan;
}

} // namespace

uint32_t tangentBasisUvSets(const Material& material) {
    uint32_t sets = 0;
    // Group 0 only: post_resolve groups re-derive every UV basis per pixel
    // from the resolved normal (section 2.11), so they never read vertex tangents.
    for (const Layer& L : material.layers) {
        if (L.enabled && L.kind->readsTangentBasis && L.kind->readsTangentBasis(L) &&
            L.uvSet >= 0 && L.uvSet < kMaxUvSets)
            sets |= 1u << L.uvSet;
    }
    return sets;
}

uint32_t patchTangentMask(const MeshAsset& mesh, const Material& material) {
    if (!mesh.patches) return 0u;
    const size_t sets = std::min(mesh.patches->uvSets.size(), size_t(kMaxUvSets));
    return mesh.patchTangentSets & tangentBasisUvSets(material) & ((1u << sets) - 1u);
}

MaterialPlan planMaterial(const Scene& scene, const SceneAssets& assets, int meshIndex,
                          int materialIndex) {
    return makePlan(scene, assets, meshIndex, materialIndex, false);
}

MaterialPlan planUberMaterial(const Scene& scene, const SceneAssets& assets, int meshIndex,
                              int materialIndex) {
    return makePlan(scene, assets, meshIndex, materialIndex, true);
}

// ---------------------------------------------------------------------------
// Uniform records

namespace {

// Every layer's records (its kind's layouts) and its modifiers' records.
std::vector<glm::vec4> packRecords(const MaterialPlan& plan, const View& view,
                                   const SceneAssets* assets) {
    std::vector<glm::vec4> r(size_t(std::max(plan.recordCount, 1)), glm::vec4(0.0f));
    for (const auto& group : plan.groups) {
        for (const PlanLayer& pl : group) {
            const Layer& L = *pl.layer;
            packLayer(L, view, assets, &r[size_t(pl.record)]);
            if (!pl.hasModifiers) continue;
            glm::vec4* m = &r[size_t(pl.modRecord)];
            for (size_t i = 0; i < L.modifiers.size() && i < size_t(kMaxModifiers); ++i)
                m[i] = L.modifiers[i].kind->pack(L.modifiers[i]);
        }
    }
    return r;
}

} // namespace

std::vector<glm::vec4> packLayerRecords(const MaterialPlan& plan, const View& view) {
    return packRecords(plan, view, nullptr);
}

std::vector<glm::vec4> packLightRecords(const Scene& scene, const View& view) {
    std::vector<glm::vec4> r;
    for (const Light& l : scene.lights) {
        // Record w: the light type shading.glsl tests (SG_LIGHT_*).
        if (l.point) {
            r.emplace_back(glm::vec3(l.position - view.cameraPos),
                           float(SG_LIGHT_POINT)); // binary64
        } else {
            r.emplace_back(-l.direction, float(SG_LIGHT_DIRECTIONAL));
        }
        r.emplace_back(l.color * l.intensity, 0.0f);
    }
    if (r.empty()) { // SG_LIGHT_COUNT >= 1: one black light
        r.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
        r.emplace_back(0.0f);
    }
    return r;
}

glm::mat4 modelToCameraRelative(const glm::dmat4& model, const glm::dvec3& cameraPos) {
    glm::dmat4 rel = model;
    for (int i = 0; i < 3; ++i) rel[3][i] = model[3][i] - cameraPos[i];
    return glm::mat4(rel);
}

namespace detail {

glm::mat3 normalMatrix(const glm::dmat4& model) {
    return glm::mat3(glm::transpose(glm::inverse(glm::dmat3(model))));
}

namespace {

// Uber plans: only the material's enabled layers are on; stand-ins
// (created disabled) and disabled layers are compiled in but switched off.
std::vector<float> uberFlags(const MaterialPlan& plan) {
    std::vector<float> flags(size_t(std::max(plan.uberFlagCount, 1)), 0.0f);
    for (size_t g = 0; g < plan.groups.size(); ++g) {
        bool anyOn = false;
        for (const auto& pl : plan.groups[g]) {
            flags[size_t(pl.uberIndex)] = pl.layer->enabled ? 1.0f : 0.0f;
            anyOn = anyOn || pl.layer->enabled;
        }
        if (g > 0) {
            bool on = anyOn && plan.groupLayers[g]->enabled;
            flags[size_t(plan.groupUberIndex[g])] = on ? 1.0f : 0.0f;
        }
    }
    return flags;
}

} // namespace

DrawUniforms drawUniforms(const Scene& scene, const SceneAssets& assets, const MaterialPlan& plan,
                          const View& view, int meshIndex, float primBase) {
    DrawUniforms u;
    const Material& mat = scene.materials[size_t(plan.materialIndex)];
    const MeshInstance& mi = scene.meshes[size_t(meshIndex)];
    u.bfaceMode = mat.doubleSided == DoubleSided::Mirror ? 1
                  : mat.doubleSided == DoubleSided::Flip ? 2
                                                         : 0;
    u.aov = int(view.aov);
    u.primBase = primBase;
    u.baseColor = mat.baseColor;
    u.roughness = mat.roughness;
    u.ambient = scene.ambient;
    u.model = glm::mat4(mi.transform);
    u.modelRel = modelToCameraRelative(mi.transform, view.cameraPos);
    u.model3 = glm::mat3(u.model);
    // Inverse, normal matrix and handedness in binary64 from the scene's
    // transform, then rounded (a flattened instance's inverse is large).
    const glm::dmat3 m3(mi.transform);
    u.modelInv3 = glm::mat3(glm::inverse(m3));
    u.normalMat = normalMatrix(mi.transform);
    u.detSign = glm::determinant(m3) < 0.0 ? -1.0f : 1.0f;
    u.lights = packLightRecords(scene, view);
    u.records = packRecords(plan, view, &assets);
    if (plan.uber) u.uberFlags = uberFlags(plan);
    return u;
}

std::vector<std::any> planKindCpuData(const MaterialPlan& plan, const SceneAssets& assets) {
    std::vector<std::any> data(plan.kindPlans.size());
    for (size_t i = 0; i < data.size(); ++i) {
        const LayerKindAssets* ka = plan.kindPlans[i].kind->assets;
        if (ka->cpuData) data[i] = ka->cpuData(plan.kindPlans[i], assets);
    }
    return data;
}

std::vector<sg::glsl::sampler2D> planSamplers(const MaterialPlan& plan, const SceneAssets& assets,
                                              sg::glsl::LodRule lodRule) {
    std::vector<sg::glsl::sampler2D> s(plan.textureKeys.size());
    for (size_t i = 0; i < s.size(); ++i) {
        s[i].lodRule = lodRule;
        auto it = assets.textures.find(plan.textureKeys[i]);
        if (it != assets.textures.end()) s[i].image = it->second.get();
    }
    return s;
}

} // namespace detail

} // namespace sg::render

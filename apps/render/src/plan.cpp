// Shader assembly with effects on demand, and the CPU twin of the assembled
// program.
//
// A MaterialPlan lists a material's enabled layers in groups (group 0, then
// one group per post_resolve entry: Mikkelsen 2019, section 3), with the
// uniform records and texture slots each layer reads. From one plan:
//   - fragmentBody() writes the GLSL main(): the prologue (listing 16), one
//     call per layer into shaders/sg/render/layer_*.glsl, a resolve per group
//     (listing 1) and a re-prologue between groups (sections 2.11 and 3);
//     only the layer files the plan uses are #included;
//   - shadePixelCpu() makes the same calls, in the same order, through the
//     C++ build of the same files (surfgrad/render_shaders.h).
// The two are written side by side below, layer kind by layer kind, so a
// change to one is visibly a change to the other.
#include <algorithm>
#include <map>
#include <cctype>
#include <set>
#include <sstream>

#include "render_internal.h"
#include "surfgrad/contract.h"
#include "surfgrad/io.h"
#include "surfgrad/render_shaders.h"
#include "surfgrad/shader_files.h"

namespace sg::render {

namespace {

// Records (vec4 uniforms) each layer kind reads.
int recordCountOf(LayerKind k) {
    switch (k) {
    case LayerKind::UvNormal:
        return 2;
    case LayerKind::ObjectNormal:
        return 1;
    case LayerKind::Height:
        return 1;
    case LayerKind::DerivMap:
        return 2;
    case LayerKind::Triplanar:
        return 2;
    case LayerKind::Decal:
        return 6;
    case LayerKind::Noise:
        return 3;
    case LayerKind::Feature:
        return 9;
    case LayerKind::PostResolve:
        return 0;
    }
    return 0;
}

bool usesUv(LayerKind k) {
    return k == LayerKind::UvNormal || k == LayerKind::ObjectNormal || k == LayerKind::Height ||
           k == LayerKind::DerivMap || k == LayerKind::Feature;
}

// Layer kinds whose surface gradient is built on the UV set's tangent
// basis (vT, vB of SgUvFrame: listing 5 / section 2.2).
bool readsTangentBasis(const Layer& L) {
    return L.kind == LayerKind::UvNormal || L.kind == LayerKind::Feature ||
           (L.kind == LayerKind::DerivMap && !L.derivTexelSpace);
}

// The shader file of a layer (with or without derivative-space modifiers).
const char* layerFile(LayerKind k, bool mods) {
    switch (k) {
    case LayerKind::UvNormal:
        return mods ? "sg/render/layer_uv_normal_mods.glsl" : "sg/render/layer_uv_normal.glsl";
    case LayerKind::ObjectNormal:
        return "sg/render/layer_object_normal.glsl";
    case LayerKind::Height:
        return "sg/render/layer_height.glsl";
    case LayerKind::DerivMap:
        return mods ? "sg/render/layer_deriv_map_mods.glsl" : "sg/render/layer_deriv_map.glsl";
    case LayerKind::Triplanar:
        return "sg/render/layer_triplanar.glsl";
    case LayerKind::Decal:
        return "sg/render/layer_decal.glsl";
    case LayerKind::Noise:
        return "sg/render/layer_noise.glsl";
    case LayerKind::Feature:
        return "sg/render/layer_feature.glsl";
    case LayerKind::PostResolve:
        return "";
    }
    return "";
}

// Short code of a layer in the effect signature.
std::string sigCode(const PlanLayer& pl, const MaterialPlan& plan) {
    const Layer& L = *pl.layer;
    std::string s;
    switch (L.kind) {
    case LayerKind::UvNormal:
        s = "uvn";
        break;
    case LayerKind::ObjectNormal:
        s = "osn";
        break;
    case LayerKind::Height:
        s = "hgt";
        break;
    case LayerKind::DerivMap:
        s = "drv";
        break;
    case LayerKind::Triplanar:
        s = "tri";
        break;
    case LayerKind::Decal:
        s = "dec";
        break;
    case LayerKind::Noise:
        s = "noi";
        break;
    case LayerKind::Feature:
        s = "fea";
        break;
    case LayerKind::PostResolve:
        s = "grp";
        break;
    }
    if (usesUv(L.kind)) {
        s += "@uv" + std::to_string(L.uvSet) +
             ((plan.vertexTangentMask >> L.uvSet) & 1u ? "v" : "p");
    }
    if (L.kind == LayerKind::Triplanar || L.kind == LayerKind::Noise) {
        s += L.space == Space::World ? "@w" : "@o";
    }
    if (pl.hasModifiers) {
        s += "+mods[";
        for (size_t i = 0; i < L.modifiers.size(); ++i) {
            static const char* code = "?scmd";
            s += code[int(L.modifiers[i].kind)];
            if (pl.modTex[i] >= 0) s += std::to_string(pl.modTex[i]);
        }
        s += "]";
    }
    std::string slots;
    for (int t : pl.tex)
        if (t >= 0) slots += (slots.empty() ? "" : ",") + std::to_string(t);
    if (!slots.empty()) s += ":t" + slots;
    if (pl.featureSlot >= 0) s += "f" + std::to_string(pl.featureSlot);
    return s;
}

// Stand-in layers of an uber plan: one of each kind, all compiled in.
std::vector<Layer> uberStandIns(int uvCount) {
    std::vector<Layer> v;
    auto add = [&](LayerKind k) {
        Layer L;
        L.kind = k;
        L.fieldPath = std::string("(uber ") + layerKindName(k) + ")";
        L.enabled = false; // compiled in, switched off by its uniform flag
        v.push_back(L);
        return &v.back();
    };
    v.reserve(16);
    if (uvCount > 0) {
        add(LayerKind::UvNormal);
        Layer* m = add(LayerKind::UvNormal);
        m->modifiers.push_back(Modifier{ModifierKind::Scale, 1.0f, 0.0f, 0, std::nullopt});
        add(LayerKind::ObjectNormal);
        add(LayerKind::Height);
        add(LayerKind::DerivMap);
        Layer* d = add(LayerKind::DerivMap);
        d->modifiers.push_back(Modifier{ModifierKind::Scale, 1.0f, 0.0f, 0, std::nullopt});
    }
    add(LayerKind::Triplanar)->space = Space::World;
    add(LayerKind::Triplanar)->space = Space::Object;
    add(LayerKind::Decal);
    add(LayerKind::Noise)->space = Space::Object;
    add(LayerKind::Noise)->space = Space::World;
    // A post-resolve group with one layer of detail.
    Layer* g = add(LayerKind::PostResolve);
    Layer child;
    child.kind = LayerKind::Noise;
    child.fieldPath = "(uber post_resolve noise)";
    child.enabled = false;
    g->children.push_back(child);
    return v;
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

    PlanLayer add(const Layer& L, bool uber) {
        PlanLayer pl;
        pl.layer = &L;
        pl.record = plan.recordCount;
        pl.recordCount = recordCountOf(L.kind);
        plan.recordCount += pl.recordCount;
        pl.hasModifiers = !L.modifiers.empty() &&
                          (L.kind == LayerKind::UvNormal || L.kind == LayerKind::DerivMap);
        if (pl.hasModifiers) {
            pl.modRecord = plan.recordCount;
            plan.recordCount += int(L.modifiers.size());
            for (size_t i = 0; i < L.modifiers.size() && i < size_t(kMaxModifiers); ++i) {
                const Modifier& m = L.modifiers[i];
                if (m.kind == ModifierKind::Modulate && m.mask) pl.modTex[i] = slot(&*m.mask);
            }
        }
        if (usesUv(L.kind)) {
            if (L.uvSet >= plan.uvCount) {
                const MeshInstance& mi = scene.meshes[size_t(meshIndex)];
                throw io::InputError(scene.sourceName, L.fieldPath + ".uv_set",
                                     "UV set " + std::to_string(L.uvSet) + " is used, but mesh " +
                                         (mi.name.empty() ? mi.fieldPath : "\"" + mi.name + "\"") +
                                         " has " + std::to_string(plan.uvCount) + " UV set(s)");
            }
            plan.uvUsedMask |= 1u << L.uvSet;
        }
        if (L.kind == LayerKind::Triplanar || L.kind == LayerKind::Noise) {
            (L.space == Space::World ? plan.usesWorldVolume : plan.usesObjectVolume) = true;
        }
        if (L.kind == LayerKind::Feature && L.feature) {
            std::string key = L.feature->key();
            auto it = std::find(plan.featureKeys.begin(), plan.featureKeys.end(), key);
            pl.featureSlot = int(it - plan.featureKeys.begin());
            if (it == plan.featureKeys.end()) plan.featureKeys.push_back(key);
            pl.featureIndex = plan.featureLayerCount++;
            // Effects on demand inside the evaluator: the curved-segment
            // code (TOG 2008) only when some map was baked with curves.
            auto fm = assets.featureMaps.find(key);
            if (fm != assets.featureMaps.end() && fm->second->quadratic) plan.featureCurved = true;
            // ... and the exact near field only when a layer uses one.
            if (fm != assets.featureMaps.end() && L.featNearExact &&
                fm->second->nearBandTexels > 0.0)
                plan.featureNear = true;
        }
        int nTex = L.kind == LayerKind::Triplanar ? 3 : (L.kind == LayerKind::Noise ? 0 : 1);
        for (int i = 0; i < nTex; ++i) {
            const TextureSource* src = nullptr;
            if (!L.maps.empty()) src = &L.maps[std::min(size_t(i), L.maps.size() - 1)];
            pl.tex[i] = slot(src);
        }
        if (uber) pl.uberIndex = plan.uberFlagCount++;
        return pl;
    }

    void addGroups(const std::vector<Layer>& layers, bool uber) {
        for (const Layer& L : layers) {
            if (!L.enabled && !uber) continue;
            if (L.kind == LayerKind::PostResolve) {
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
        std::ostringstream sig;
        sig << "uv" << plan.uvCount << ":vt" << plan.vertexTangentMask << ":l" << plan.lightCount
            << (plan.uber ? ":uber" : "");
        for (size_t g = 0; g < plan.groups.size(); ++g) {
            sig << "|g" << g << "[";
            for (const auto& pl : plan.groups[g]) sig << sigCode(pl, plan) << ";";
            sig << "]";
        }
        if (plan.baseColorTex >= 0)
            sig << "|bc@uv" << plan.baseColorUvSet << ":t" << plan.baseColorTex;
        if (plan.featureLayerCount > 0)
            sig << (plan.featureCurved ? "|featcurved" : "|featstraight")
                << (plan.featureNear ? "|featnear" : "");
        sig << "|tex" << plan.textureKeys.size();
        plan.signature = sig.str();
    }
};

} // namespace

uint32_t tangentBasisUvSets(const Material& material) {
    uint32_t sets = 0;
    // Group 0 only: post_resolve groups re-derive every UV basis per pixel
    // from the resolved normal (section 2.11), so they never read vertex tangents.
    for (const Layer& L : material.layers) {
        if (L.enabled && readsTangentBasis(L) && L.uvSet >= 0 && L.uvSet < kMaxUvSets)
            sets |= 1u << L.uvSet;
    }
    return sets;
}

namespace {

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
    p.plan.uvCount = std::min(int(ma.mesh.uvSets.size()), kMaxUvSets);
    // Vertex tangents are read only where an enabled layer uses the set's
    // basis (a mesh may keep tangents of a set whose layers were switched off).
    const uint32_t basisSets = tangentBasisUvSets(scene.materials[size_t(materialIndex)]);
    for (int k = 0; k < p.plan.uvCount && k < int(ma.vertexTangents.size()); ++k) {
        if (!ma.vertexTangents[size_t(k)].empty() && (basisSets >> k & 1u))
            p.plan.vertexTangentMask |= 1u << k;
    }
    p.plan.lightCount = std::max(1, int(scene.lights.size()));
    p.plan.groups.emplace_back();
    p.plan.groupLayers.push_back(nullptr);
    p.plan.groupUberIndex.push_back(-1);
    p.addGroups(scene.materials[size_t(materialIndex)].layers, uber);
    p.baseColor(scene.materials[size_t(materialIndex)]);
    if (uber) {
        auto owned = std::make_shared<std::vector<Layer>>(uberStandIns(p.plan.uvCount));
        p.plan.ownedLayers = owned;
        p.addGroups(*owned, true);
    }
    p.finish();
    return p.plan;
}

} // namespace

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

std::vector<glm::vec4> packLayerRecords(const MaterialPlan& plan, const View& view) {
    std::vector<glm::vec4> r(size_t(std::max(plan.recordCount, 1)), glm::vec4(0.0f));
    auto b = [](bool x) { return x ? 1.0f : 0.0f; };
    for (const auto& group : plan.groups) {
        for (const PlanLayer& pl : group) {
            const Layer& L = *pl.layer;
            glm::vec4* o = &r[size_t(pl.record)];
            float enc = float(int(L.encoding));
            switch (L.kind) {
            case LayerKind::UvNormal:
                o[0] = {L.strength, enc, b(L.flipV), float(L.heightChannel)};
                o[1] = {L.heightScale, 0, 0, 0};
                break;
            case LayerKind::ObjectNormal:
                o[0] = {L.strength, enc, b(L.space == Space::Object), 0};
                break;
            case LayerKind::Height:
                o[0] = {L.heightWorld, float(L.channel), 0, 0};
                break;
            case LayerKind::DerivMap:
                o[0] = {L.strength, b(L.derivSigned), L.derivRange, b(L.derivTexelSpace)};
                o[1] = {b(L.flipV), float(L.heightChannel), L.heightScale, 0};
                break;
            case LayerKind::Triplanar:
                o[0] = {L.strength, L.triScale, L.triSharpness, b(L.triRightHanded)};
                o[1] = {enc, b(L.flipV), 0, 0};
                break;
            case LayerKind::Decal:
                o[0] = glm::vec4(L.decalPosition - view.cameraPos, L.strength);
                o[1] = glm::vec4(L.decalAxisX, L.decalHalfSize.x);
                o[2] = glm::vec4(L.decalAxisY, L.decalHalfSize.y);
                o[3] = glm::vec4(L.decalAxisZ, L.decalHalfSize.z);
                o[4] = {L.decalFade, L.decalCosStart, L.decalCosEnd, enc};
                o[5] = {b(L.flipV), 0, 0, 0};
                break;
            case LayerKind::Noise:
                o[0] = {L.noiseAmplitude, L.noiseFrequency, float(int(L.noiseType)),
                        float(L.noiseOctaves)};
                o[1] = {L.noiseLacunarity, L.noiseGain, L.noiseExponent, b(L.noiseAntialias)};
                o[2] = glm::vec4(L.noiseOffset, 0.0f);
                break;
            case LayerKind::Feature: {
                // The map size comes from the assets; packLayerRecords does not
                // see them, so the renderers patch r0.z (featureMapSizes()).
                o[0] = {L.strength, b(L.featPaperMode), 0.0f, L.featTiling};
                o[1] = {L.featOffset.x, L.featOffset.y, b(!L.maps.empty()), enc};
                o[2] = {b(L.flipV), b(L.featNearExact), 0, 0};
                sg::glsl::SgFeatProfile pr =
                    sg::features::makeProfile(L.featProfile, L.featDepth, L.featW0, L.featWidth);
                o[3] = {float(pr.kind), pr.depth, pr.w0, pr.w};
                o[4] = {float(pr.tableCount), 0, 0, 0};
                for (int t = 0; t < 4; ++t) {
                    o[5 + t] = {pr.table[4 * t], pr.table[4 * t + 1], pr.table[4 * t + 2],
                                pr.table[4 * t + 3]};
                }
                break;
            }
            case LayerKind::PostResolve:
                break;
            }
            if (pl.hasModifiers) {
                glm::vec4* m = &r[size_t(pl.modRecord)];
                for (size_t i = 0; i < L.modifiers.size() && i < size_t(kMaxModifiers); ++i) {
                    const Modifier& md = L.modifiers[i];
                    float kind = float(int(md.kind));
                    if (md.kind == ModifierKind::Modulate) {
                        m[i] = {kind, float(md.channel), md.a, 0};
                    } else {
                        m[i] = {kind, md.a, md.b, 0};
                    }
                }
            }
        }
    }
    return r;
}

std::vector<glm::vec4> packLightRecords(const Scene& scene, const View& view) {
    std::vector<glm::vec4> r;
    for (const Light& l : scene.lights) {
        if (l.point) {
            r.emplace_back(l.position - view.cameraPos, 1.0f);
        } else {
            r.emplace_back(-l.direction, 0.0f);
        }
        r.emplace_back(l.color * l.intensity, 0.0f);
    }
    if (r.empty()) { // SG_LIGHT_COUNT >= 1: one black light
        r.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
        r.emplace_back(0.0f);
    }
    return r;
}

namespace detail {

glm::mat3 normalMatrix(const glm::mat4& model) {
    return glm::transpose(glm::inverse(glm::mat3(model)));
}

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
    u.model = mi.transform;
    u.model3 = glm::mat3(mi.transform);
    u.modelInv3 = glm::inverse(u.model3);
    u.normalMat = normalMatrix(mi.transform);
    u.detSign = glm::determinant(u.model3) < 0.0f ? -1.0f : 1.0f;
    u.lights = packLightRecords(scene, view);
    u.records = packLayerRecords(plan, view);
    for (const auto& g : plan.groups)
        for (const auto& pl : g) {
            if (pl.featureSlot < 0) continue;
            auto it = assets.featureMaps.find(plan.featureKeys[size_t(pl.featureSlot)]);
            if (it != assets.featureMaps.end())
                u.records[size_t(pl.record)].z = float(it->second->gpu.size);
        }
    if (plan.uber) {
        u.uberFlags.assign(size_t(std::max(plan.uberFlagCount, 1)), 0.0f);
        // Only the material's enabled layers are on; stand-ins (created
        // disabled) and disabled layers are compiled in but switched off.
        for (size_t g = 0; g < plan.groups.size(); ++g) {
            bool anyOn = false;
            for (const auto& pl : plan.groups[g]) {
                u.uberFlags[size_t(pl.uberIndex)] = pl.layer->enabled ? 1.0f : 0.0f;
                anyOn = anyOn || pl.layer->enabled;
            }
            if (g > 0) {
                bool on = anyOn && plan.groupLayers[g]->enabled;
                u.uberFlags[size_t(plan.groupUberIndex[g])] = on ? 1.0f : 0.0f;
            }
        }
    }
    return u;
}

std::vector<FeatureSamplers> planFeatureSamplers(const MaterialPlan& plan,
                                                 const SceneAssets& assets) {
    std::vector<FeatureSamplers> s(plan.featureKeys.size());
    for (size_t i = 0; i < s.size(); ++i) {
        auto it = assets.featureMaps.find(plan.featureKeys[i]);
        if (it == assets.featureMaps.end()) continue;
        s[i].corners = it->second->gpu.cornerSampler();
        s[i].edges = it->second->gpu.edgeSampler();
        if (it->second->gpu.hasNearField()) {
            s[i].nearLists = it->second->gpu.nearSampler();
            s[i].pieces = it->second->gpu.pieceSampler();
        }
    }
    return s;
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

// ---------------------------------------------------------------------------
// GLSL generation

namespace {

std::string rec(int i) {
    return "uLayerData[" + std::to_string(i) + "]";
}
std::string recs(int first, int count) {
    std::string s;
    for (int i = 0; i < count; ++i) s += (i ? ", " : "") + rec(first + i);
    return s;
}
std::string tex(int slot) {
    return "uTex" + std::to_string(slot);
}
std::string uvVar(int set) {
    return "uv" + std::to_string(set);
}

// The GLSL expression of a layer's surface gradient.
std::string layerCall(const PlanLayer& pl) {
    const Layer& L = *pl.layer;
    std::string uv = uvVar(L.uvSet);
    std::string vol = L.space == Space::World ? "volWorld" : "volObject";
    switch (L.kind) {
    case LayerKind::UvNormal:
        return "sgLayerUvNormal(" + uv + ", sgUnpackUvNormal(" + recs(pl.record, 2) + "), " +
               tex(pl.tex[0]) + ")";
    case LayerKind::ObjectNormal:
        return "sgLayerObjectNormal(frame, " + uv + ", sgUnpackObjectNormal(" + recs(pl.record, 1) +
               "), uNormalMat, " + tex(pl.tex[0]) + ")";
    case LayerKind::Height:
        return "sgLayerHeight(frame, " + uv + ", sgUnpackHeight(" + recs(pl.record, 1) + "), " +
               tex(pl.tex[0]) + ")";
    case LayerKind::DerivMap:
        return "sgLayerDerivMap(frame, " + uv + ", sgUnpackDerivMap(" + recs(pl.record, 2) + "), " +
               tex(pl.tex[0]) + ")";
    case LayerKind::Triplanar:
        return "sgLayerTriplanar(frame, " + vol + ", sgUnpackTriplanar(" + recs(pl.record, 2) +
               "), " + tex(pl.tex[0]) + ", " + tex(pl.tex[1]) + ", " + tex(pl.tex[2]) + ")";
    case LayerKind::Decal:
        return "sgLayerDecal(frame, vRelPos, sgUnpackDecal(" + recs(pl.record, 6) + "), " +
               tex(pl.tex[0]) + ")";
    case LayerKind::Noise:
        return "sgLayerNoise(frame, " + vol + ", sgUnpackNoise(" + recs(pl.record, 3) + "))";
    case LayerKind::Feature:
        break; // emitted as a loop per group (fragmentBody)
    case LayerKind::PostResolve:
        break;
    }
    return "vec3(0.0)";
}

// A layer with derivative-space modifiers as a block of statements: the
// sample as height and derivative, one call per modifier in order (only
// the kinds used are compiled in; nothing branches on a uniform), and the
// surface gradient.
std::string modifierBlock(const PlanLayer& pl, const std::string& indent) {
    const Layer& L = *pl.layer;
    std::string uv = uvVar(L.uvSet), in = indent + "    ";
    bool uvn = L.kind == LayerKind::UvNormal;
    bool deform = !L.modifiers.empty() && L.modifiers[0].kind == ModifierKind::Deform;
    std::string o = "{\n";
    o += in +
         (uvn ? "SgUvNormalParams p = sgUnpackUvNormal("
              : "SgDerivMapParams p = sgUnpackDerivMap(") +
         recs(pl.record, 2) + ");\n";
    if (deform) {
        o += in + "mat2 jac;\n";
        o += in + "vec2 st = sgModWarp(" + rec(pl.modRecord) + ", " + uv + ".st, jac);\n";
        o +=
            in + "vec2 dx = jac * " + uv + ".dSTdx;\n" + in + "vec2 dy = jac * " + uv + ".dSTdy;\n";
    } else {
        o += in + "vec2 st = " + uv + ".st;\n" + in + "vec2 dx = " + uv + ".dSTdx;\n" + in +
             "vec2 dy = " + uv + ".dSTdy;\n";
    }
    o += in + "SgHeightDeriv hd = " + (uvn ? "sgSampleUvNormalHD(" : "sgSampleDerivMapHD(") +
         tex(pl.tex[0]) + ", st, dx, dy, p);\n";
    for (size_t i = 0; i < L.modifiers.size(); ++i) {
        std::string op = rec(pl.modRecord + int(i));
        switch (L.modifiers[i].kind) {
        case ModifierKind::Deform:
            o += in + "hd = sgModDeform(hd, jac);\n";
            break;
        case ModifierKind::Scale:
            o += in + "hd = sgModScale(hd, " + op + ");\n";
            break;
        case ModifierKind::Curve:
            o += in + "hd = sgModCurve(hd, " + op + ");\n";
            break;
        case ModifierKind::Modulate:
            o += in + "hd = sgModModulate(hd, " + op + ", " + tex(pl.modTex[i]) + ", st, dx, dy, " +
                 (deform ? "jac" : "mat2(1.0f)") + ");\n";
            break;
        }
    }
    o += in + "surfGrad += " +
         (uvn ? "sgUvNormalSurfgrad(" + uv + ", p, hd)"
              : "sgDerivMapSurfgrad(frame, " + uv + ", p, hd.d, vec2(textureSize(" +
                    tex(pl.tex[0]) + ", 0)))") +
         ";\n";
    return o + indent + "}\n";
}

uint32_t groupUvMask(const std::vector<PlanLayer>& g) {
    uint32_t m = 0;
    for (const auto& pl : g)
        if (usesUv(pl.layer->kind)) m |= 1u << pl.layer->uvSet;
    return m;
}

} // namespace

std::string fragmentBody(const MaterialPlan& plan) {
    std::ostringstream o;
    const bool hasUv0 = plan.uvCount > 0;
    o << "// surfgrad assembled fragment program (apps/render/src/plan.cpp).\n"
      << "// Effect signature: " << plan.signature << "\n"
      << "// Only the layer kinds this material uses are included below.\n"
      << "#include \"sg/render/surface_fs.glsl\"\n";
    std::vector<std::string> files;
    for (const auto& g : plan.groups)
        for (const auto& pl : g) {
            std::string f = layerFile(pl.layer->kind, pl.hasModifiers);
            if (std::find(files.begin(), files.end(), f) == files.end()) files.push_back(f);
        }
    for (const auto& f : files) o << "#include \"" << f << "\"\n";
    for (size_t i = 0; i < plan.textureKeys.size(); ++i) {
        o << "uniform sampler2D uTex" << i << "; // "
          << (plan.textureKeys[i].empty() ? "(none)" : plan.textureKeys[i]) << "\n";
    }
    if (plan.featureLayerCount > 0) {
        // Feature layers run in one loop per group (below), so the large
        // evaluator is compiled once however many feature layers there are:
        // llvmpipe's compile time grows faster than linearly with program
        // size (two inlined copies took 40x the time of one). Per-layer data
        // come from these arrays, indexed by the (dynamically uniform) loop
        // counter.
        std::vector<int> rec(size_t(plan.featureLayerCount)), uvs(rec.size()), flags(rec.size());
        for (const auto& g : plan.groups)
            for (const auto& pl : g) {
                if (pl.featureIndex < 0) continue;
                rec[size_t(pl.featureIndex)] = pl.record;
                uvs[size_t(pl.featureIndex)] = pl.layer->uvSet;
                flags[size_t(pl.featureIndex)] = pl.uberIndex;
            }
        auto arr = [&](const char* name, const std::vector<int>& v) {
            o << "const int " << name << "[" << v.size() << "] = int[" << v.size() << "](";
            for (size_t i = 0; i < v.size(); ++i) o << (i ? ", " : "") << v[i];
            o << ");\n";
        };
        int n = plan.featureLayerCount;
        o << "uniform usampler2D uFeatCorners[" << n << "];\n"
          << "uniform usampler2D uFeatEdges[" << n << "];\n"
          << "uniform sampler2D uFeatBase[" << n << "];\n";
        if (plan.featureNear) {
            o << "uniform usampler2D uFeatNear[" << n << "];   // exact near field: lists\n"
              << "uniform usampler2D uFeatPieces[" << n << "]; // exact near field: pieces\n";
        }
        arr("kFeatRecord", rec);
        arr("kFeatUvSet", uvs);
        if (plan.uber) arr("kFeatFlag", flags);
    }
    if (plan.uber) o << "uniform float uLayerOn[" << std::max(plan.uberFlagCount, 1) << "];\n";
    o << "\nvoid main() {\n"
      << "    // Prologue (Mikkelsen 2019, listing 16): derivatives of the camera-relative "
         "position.\n"
      << "    vec3 dPdx = dFdxFine(vRelPos);\n"
      << "    vec3 dPdy = dFdyFine(vRelPos);\n"
      << "    SgFrame frame = sgPrologue(vNormal, dPdx, dPdy, gl_FrontFacing, uBfaceMode);\n"
      << "    vec3 baseNormal = frame.nrmBase;\n";
    // UV frames of group 0 (set 0 always, for the tangent/uv outputs).
    uint32_t uvMask0 = groupUvMask(plan.groups[0]) | (hasUv0 ? 1u : 0u);
    for (int k = 0; k < plan.uvCount; ++k) {
        if (!((uvMask0 | plan.uvUsedMask) >> k & 1u)) continue;
        std::string v = "vUv" + std::to_string(k);
        o << "    vec2 dUv" << k << "dx = dFdxFine(" << v << ");\n"
          << "    vec2 dUv" << k << "dy = dFdyFine(" << v << ");\n";
        if (plan.vertexTangentMask >> k & 1u) {
            o << "    SgUvFrame uv" << k << " = sgUvFrameVertex(" << v << ", dUv" << k << "dx, dUv"
              << k << "dy, vNormal, vTangent" << k << ");\n";
        } else {
            o << "    SgUvFrame uv" << k << " = sgUvFramePixel(frame, " << v << ", dUv" << k
              << "dx, dUv" << k << "dy);\n";
        }
    }
    if (plan.usesWorldVolume) {
        o << "    SgVolumeSpace volWorld = sgVolumeSpace(frame, vWorldPos, mat3(1.0), "
             "mat3(1.0));\n";
    }
    if (plan.usesObjectVolume) {
        o << "    SgVolumeSpace volObject = sgVolumeSpace(frame, vObjPos, uModel3, uModelInv3);\n";
    }
    o << "    vec3 baseColor = uBaseColor;\n";
    if (plan.baseColorTex >= 0) {
        std::string uv = uvVar(plan.baseColorUvSet);
        o << "    baseColor *= textureGrad(" << tex(plan.baseColorTex) << ", " << uv << ".st, "
          << uv << ".dSTdx, " << uv << ".dSTdy).xyz; // base colour map (linear)\n";
    }
    o << "    vec3 surfGrad = vec3(0.0);\n";
    for (size_t g = 0; g < plan.groups.size(); ++g) {
        std::string indent = "    ";
        if (g > 0) {
            o << "    // Post-resolve group " << g
              << " (section 3): the resolved normal is the new base.\n";
            if (plan.uber) {
                o << "    if (uLayerOn[" << plan.groupUberIndex[g] << "] > 0.5) {\n";
                indent = "        ";
            }
            o << indent << "frame = sgReprologue(frame, nrm, frame.dPdx, frame.dPdy);\n";
            uint32_t m = groupUvMask(plan.groups[g]);
            for (int k = 0; k < plan.uvCount; ++k) {
                if (m >> k & 1u) {
                    o << indent << "uv" << k << " = sgUvFramePixel(frame, uv" << k << ".st, uv" << k
                      << ".dSTdx, uv" << k << ".dSTdy);\n";
                }
            }
            o << indent << "surfGrad = vec3(0.0);\n";
        }
        int featFirst = -1, featCount = 0;
        uint32_t featUvMask = 0;
        for (const auto& pl : plan.groups[g]) {
            if (pl.featureIndex >= 0) {
                if (featFirst < 0) featFirst = pl.featureIndex;
                ++featCount;
                featUvMask |= 1u << pl.layer->uvSet;
                continue;
            }
            o << indent << "// " << layerKindName(pl.layer->kind) << " (" << pl.layer->fieldPath
              << ")\n";
            if (plan.uber) {
                o << indent << "if (uLayerOn[" << pl.uberIndex << "] > 0.5) ";
            } else {
                o << indent;
            }
            if (pl.hasModifiers) {
                o << modifierBlock(pl, indent);
            } else {
                o << "surfGrad += " << layerCall(pl) << ";\n";
            }
        }
        if (featCount > 0) {
            o << indent << "// feature layers " << featFirst << ".." << featFirst + featCount - 1
              << " (one loop: the evaluator is compiled once)\n"
              << indent << "for (int fi = " << featFirst << "; fi < " << featFirst + featCount
              << "; ++fi) {\n";
            if (plan.uber) o << indent << "    if (!(uLayerOn[kFeatFlag[fi]] > 0.5)) continue;\n";
            o << indent << "    int r = kFeatRecord[fi];\n";
            int firstUv = -1;
            for (int k = 0; k < plan.uvCount; ++k) {
                if (!(featUvMask >> k & 1u)) continue;
                if (firstUv < 0) {
                    firstUv = k;
                    o << indent << "    SgUvFrame fuv = uv" << k << ";\n";
                } else {
                    o << indent << "    if (kFeatUvSet[fi] == " << k << ") fuv = uv" << k << ";\n";
                }
            }
            o << indent
              << "    surfGrad += " << (plan.featureNear ? "sgLayerFeatureNear" : "sgLayerFeature")
              << "(fuv, sgUnpackFeatureLayer(uLayerData[r], "
                 "uLayerData[r + 1], "
                 "uLayerData[r + 2]),\n"
              << indent
              << "        sgUnpackFeatProfile(uLayerData[r + 3], uLayerData[r + 4], uLayerData[r + "
                 "5], "
                 "uLayerData[r + 6], uLayerData[r + 7], uLayerData[r + 8]),\n"
              << indent << "        uFeatCorners[fi], uFeatEdges[fi], "
              << (plan.featureNear ? "uFeatNear[fi], uFeatPieces[fi], " : "") << "uFeatBase[fi]);\n"
              << indent << "}\n";
        }
        if (g == 0) {
            o << "    vec3 nrm = sgResolve(frame, surfGrad); // listing 1\n"
              << "    vec3 surfGradOut = surfGrad;\n";
        } else {
            o << indent << "nrm = sgResolve(frame, surfGrad);\n";
            if (plan.uber) o << "    }\n";
        }
    }
    o << "    vec3 color = sgShadeAmbient(nrm, uAmbient, baseColor);\n"
      << "    for (int i = 0; i < SG_LIGHT_COUNT; ++i) {\n"
      << "        color += sgShadeLight(nrm, vRelPos, uLights[2 * i], uLights[2 * i + 1], "
         "baseColor, uRoughness);\n"
      << "    }\n";
    if (hasUv0) {
        o << "    outValue = sgAovValue(uAov, color, nrm, surfGradOut, uv0.vT, uv0.vB, baseNormal, "
             "vUv0,\n";
    } else {
        o << "    outValue = sgAovValue(uAov, color, nrm, surfGradOut, vec3(0.0), vec3(0.0), "
             "baseNormal, vec2(0.0),\n";
    }
    o << "                          float(gl_PrimitiveID) + 1.0 + uPrimBase);\n"
      << "}\n";
    return o.str();
}

namespace {

bool isIdentStart(char c) {
    return std::isalpha(static_cast<unsigned char>(c)) || c == '_';
}
bool isIdent(char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_';
}

// Effects on demand, at the level of functions: the shared library files
// hold whole families of functions (e.g. every listing of the paper in
// sg/surfgrad.glsl); a program keeps only those main() reaches. Shared
// functions are recognised by their `SG_FN type name(` opening line;
// removed ones are replaced by as many empty lines, so #line numbers stay
// right. Overloads are kept or dropped together (by name).
std::string stripUnreachableFunctions(const std::string& text) {
    std::vector<std::string> lines;
    {
        std::istringstream in(text);
        std::string l;
        while (std::getline(in, l)) lines.push_back(l);
    }
    struct Fn {
        std::string name;
        size_t first, last; // line range
    };
    std::vector<Fn> fns;
    std::vector<char> inFn(lines.size(), 0);
    for (size_t i = 0; i < lines.size(); ++i) {
        const std::string& l = lines[i];
        if (l.rfind("SG_FN ", 0) != 0) continue;
        size_t paren = l.find('(');
        if (paren == std::string::npos) continue;
        size_t e = paren;
        while (e > 0 && l[e - 1] == ' ') --e;
        size_t b = e;
        while (b > 0 && isIdent(l[b - 1])) --b;
        Fn f{l.substr(b, e - b), i, i};
        // The body ends where the braces opened after the name balance.
        int depth = 0;
        bool opened = false;
        size_t j = i;
        for (; j < lines.size(); ++j) {
            for (char c : lines[j]) {
                if (c == '{') {
                    ++depth;
                    opened = true;
                } else if (c == '}') {
                    --depth;
                }
            }
            if (opened && depth == 0) break;
        }
        if (j == lines.size()) continue; // unbalanced: leave the file alone
        f.last = j;
        for (size_t k = f.first; k <= f.last; ++k) inFn[k] = 1;
        fns.push_back(f);
        i = j;
    }
    auto tokens = [&](size_t from, size_t to, std::set<std::string>& out) {
        for (size_t k = from; k <= to; ++k) {
            const std::string& l = lines[k];
            for (size_t p = 0; p < l.size();) {
                if (l.compare(p, 2, "//") == 0) break;
                if (isIdentStart(l[p]) && (p == 0 || !isIdent(l[p - 1]))) {
                    size_t q = p;
                    while (q < l.size() && isIdent(l[q])) ++q;
                    out.insert(l.substr(p, q - p));
                    p = q;
                } else {
                    ++p;
                }
            }
        }
    };
    // Roots: everything outside shared functions (main, declarations).
    std::set<std::string> used;
    for (size_t k = 0; k < lines.size(); ++k) {
        if (!inFn[k]) tokens(k, k, used);
    }
    std::set<std::string> kept;
    for (bool changed = true; changed;) {
        changed = false;
        for (const Fn& f : fns) {
            if (kept.count(f.name) || !used.count(f.name)) continue;
            kept.insert(f.name);
            for (const Fn& g : fns) {
                if (g.name == f.name) tokens(g.first, g.last, used);
            }
            changed = true;
        }
    }
    std::string out;
    out.reserve(text.size());
    std::vector<char> drop(lines.size(), 0);
    for (const Fn& f : fns) {
        if (!kept.count(f.name)) {
            for (size_t k = f.first; k <= f.last; ++k) drop[k] = 1;
            // ... and the comment block documenting it, directly above.
            for (size_t k = f.first; k > 0; --k) {
                const std::string& l = lines[k - 1];
                size_t p = l.find_first_not_of(" \t");
                if (p == std::string::npos || l.compare(p, 2, "//") != 0) break;
                drop[k - 1] = 1;
            }
        }
    }
    for (size_t k = 0; k < lines.size(); ++k) {
        if (!drop[k]) out += lines[k];
        out += '\n';
    }
    return out;
}

} // namespace

ProgramSource assembleProgram(const MaterialPlan& plan) {
    std::vector<std::string> defs = {"SG_UV_COUNT " + std::to_string(plan.uvCount)};
    for (int k = 0; k < kMaxUvSets; ++k) {
        defs.push_back("SG_VTX_TANGENT_" + std::to_string(k) + " " +
                       std::to_string((plan.vertexTangentMask >> k) & 1u));
    }
    std::vector<std::string> fdefs = defs;
    fdefs.push_back("SG_LIGHT_COUNT " + std::to_string(plan.lightCount));
    fdefs.push_back("SG_LAYER_RECORDS " + std::to_string(std::max(plan.recordCount, 1)));
    if (plan.featureLayerCount > 0)
        fdefs.push_back(std::string("SG_FEAT_CURVED ") + (plan.featureCurved ? "1" : "0"));
    if (plan.featureNear) fdefs.push_back("SG_FEAT_NEAR 1"); // effects on demand
    const char* vs = sg::shaders::find("sg/render/surface_vs.glsl");
    SG_ASSERT(vs, "the vertex stage is embedded");
    auto v = sg::shaders::assemble(vs, "sg/render/surface_vs.glsl", defs);
    auto f = sg::shaders::assemble(fragmentBody(plan), "(assembled fragment program)", fdefs);
    return ProgramSource{v.text, stripUnreachableFunctions(f.text), v.files, f.files};
}

// ---------------------------------------------------------------------------
// The CPU twin of fragmentBody(): same calls, same order.

namespace detail {

namespace {

namespace G = sg::glsl;

glm::vec3 layerCpu(const PlanLayer& pl, const DrawUniforms& u, const std::vector<G::sampler2D>& smp,
                   const std::vector<FeatureSamplers>& fsmp, const G::SgFrame& frame,
                   const std::array<G::SgUvFrame, kMaxUvSets>& uv, const G::SgVolumeSpace& volWorld,
                   const G::SgVolumeSpace& volObject, const PixelInputs& in) {
    const Layer& L = *pl.layer;
    const glm::vec4* r = &u.records[size_t(pl.record)];
    auto t = [&](int slot) { return slot >= 0 ? smp[size_t(slot)] : G::sampler2D{}; };
    const G::SgUvFrame& f = uv[size_t(L.uvSet)];
    const G::SgVolumeSpace& vol = L.space == Space::World ? volWorld : volObject;
    if (pl.hasModifiers) {
        // modifierBlock(), statement by statement.
        const glm::vec4* m = &u.records[size_t(pl.modRecord)];
        bool uvn = L.kind == LayerKind::UvNormal;
        bool deform = L.modifiers[0].kind == ModifierKind::Deform;
        glm::mat2 jac(1.0f);
        glm::vec2 st = f.st, dx = f.dSTdx, dy = f.dSTdy;
        if (deform) {
            st = G::sgModWarp(m[0], f.st, jac);
            dx = jac * f.dSTdx;
            dy = jac * f.dSTdy;
        }
        G::SgUvNormalParams pu = G::sgUnpackUvNormal(r[0], r[1]);
        G::SgDerivMapParams pd = G::sgUnpackDerivMap(r[0], r[1]);
        G::SgHeightDeriv hd = uvn ? G::sgSampleUvNormalHD(t(pl.tex[0]), st, dx, dy, pu)
                                  : G::sgSampleDerivMapHD(t(pl.tex[0]), st, dx, dy, pd);
        for (size_t i = 0; i < L.modifiers.size(); ++i) {
            switch (L.modifiers[i].kind) {
            case ModifierKind::Deform:
                hd = G::sgModDeform(hd, jac);
                break;
            case ModifierKind::Scale:
                hd = G::sgModScale(hd, m[i]);
                break;
            case ModifierKind::Curve:
                hd = G::sgModCurve(hd, m[i]);
                break;
            case ModifierKind::Modulate:
                hd = G::sgModModulate(hd, m[i], t(pl.modTex[i]), st, dx, dy, jac);
                break;
            }
        }
        return uvn ? G::sgUvNormalSurfgrad(f, pu, hd)
                   : G::sgDerivMapSurfgrad(frame, f, pd, hd.d,
                                           glm::vec2(G::textureSize(t(pl.tex[0]), 0)));
    }
    switch (L.kind) {
    case LayerKind::UvNormal:
        return G::sgLayerUvNormal(f, G::sgUnpackUvNormal(r[0], r[1]), t(pl.tex[0]));
    case LayerKind::ObjectNormal:
        return G::sgLayerObjectNormal(frame, f, G::sgUnpackObjectNormal(r[0]), u.normalMat,
                                      t(pl.tex[0]));
    case LayerKind::Height:
        return G::sgLayerHeight(frame, f, G::sgUnpackHeight(r[0]), t(pl.tex[0]));
    case LayerKind::DerivMap:
        return G::sgLayerDerivMap(frame, f, G::sgUnpackDerivMap(r[0], r[1]), t(pl.tex[0]));
    case LayerKind::Triplanar:
        return G::sgLayerTriplanar(frame, vol, G::sgUnpackTriplanar(r[0], r[1]), t(pl.tex[0]),
                                   t(pl.tex[1]), t(pl.tex[2]));
    case LayerKind::Decal:
        return G::sgLayerDecal(frame, in.relPos,
                               G::sgUnpackDecal(r[0], r[1], r[2], r[3], r[4], r[5]), t(pl.tex[0]));
    case LayerKind::Noise:
        return G::sgLayerNoise(frame, vol, G::sgUnpackNoise(r[0], r[1], r[2]));
    case LayerKind::Feature: {
        if (pl.featureSlot < 0 || !fsmp[size_t(pl.featureSlot)].corners.rgba)
            return glm::vec3(0.0f);
        const FeatureSamplers& fs = fsmp[size_t(pl.featureSlot)];
        if (fs.nearLists.rgba) {
            return G::sgLayerFeatureNear(f, G::sgUnpackFeatureLayer(r[0], r[1], r[2]),
                                         G::sgUnpackFeatProfile(r[3], r[4], r[5], r[6], r[7], r[8]),
                                         fs.corners, fs.edges, fs.nearLists, fs.pieces,
                                         t(pl.tex[0]));
        }
        return G::sgLayerFeature(f, G::sgUnpackFeatureLayer(r[0], r[1], r[2]),
                                 G::sgUnpackFeatProfile(r[3], r[4], r[5], r[6], r[7], r[8]),
                                 fs.corners, fs.edges, t(pl.tex[0]));
    }
    case LayerKind::PostResolve:
        break;
    }
    return glm::vec3(0.0f);
}

bool layerOn(const PlanLayer& pl, const MaterialPlan& plan, const DrawUniforms& u) {
    return !plan.uber || u.uberFlags[size_t(pl.uberIndex)] > 0.5f;
}

} // namespace

glm::vec4 shadePixelCpu(const MaterialPlan& plan, const DrawUniforms& u,
                        const std::vector<G::sampler2D>& smp,
                        const std::vector<FeatureSamplers>& fsmp, const PixelInputs& in) {
    G::SgFrame frame = G::sgPrologue(in.normal, in.dPdx, in.dPdy, in.frontFacing, u.bfaceMode);
    glm::vec3 baseNormal = frame.nrmBase;
    std::array<G::SgUvFrame, kMaxUvSets> uv{};
    const bool hasUv0 = plan.uvCount > 0;
    uint32_t uvMask0 = groupUvMask(plan.groups[0]) | (hasUv0 ? 1u : 0u);
    for (int k = 0; k < plan.uvCount; ++k) {
        if (!((uvMask0 | plan.uvUsedMask) >> k & 1u)) continue;
        size_t kk = size_t(k);
        uv[kk] = (plan.vertexTangentMask >> k & 1u)
                     ? G::sgUvFrameVertex(in.uv[kk], in.dUVdx[kk], in.dUVdy[kk], in.normal,
                                          in.tangent[kk])
                     : G::sgUvFramePixel(frame, in.uv[kk], in.dUVdx[kk], in.dUVdy[kk]);
    }
    G::SgVolumeSpace volWorld{}, volObject{};
    if (plan.usesWorldVolume)
        volWorld = G::sgVolumeSpace(frame, in.worldPos, glm::mat3(1.0f), glm::mat3(1.0f));
    if (plan.usesObjectVolume)
        volObject = G::sgVolumeSpace(frame, in.objPos, u.model3, u.modelInv3);
    glm::vec3 baseColor = u.baseColor;
    if (plan.baseColorTex >= 0) {
        const G::SgUvFrame& f = uv[size_t(plan.baseColorUvSet)];
        baseColor *=
            glm::vec3(G::textureGrad(smp[size_t(plan.baseColorTex)], f.st, f.dSTdx, f.dSTdy));
    }
    glm::vec3 surfGrad(0.0f);
    // Same order as the GLSL: other layers first, then the feature loop.
    for (int pass = 0; pass < 2; ++pass)
        for (const auto& pl : plan.groups[0]) {
            if ((pl.featureIndex >= 0) != (pass == 1)) continue;
            if (layerOn(pl, plan, u))
                surfGrad += layerCpu(pl, u, smp, fsmp, frame, uv, volWorld, volObject, in);
        }
    glm::vec3 nrm = G::sgResolve(frame, surfGrad);
    glm::vec3 surfGradOut = surfGrad;
    glm::vec3 tangentOut = uv[0].vT, bitangentOut = uv[0].vB;
    for (size_t g = 1; g < plan.groups.size(); ++g) {
        if (plan.uber && !(u.uberFlags[size_t(plan.groupUberIndex[g])] > 0.5f)) continue;
        frame = G::sgReprologue(frame, nrm, frame.dPdx, frame.dPdy);
        uint32_t m = groupUvMask(plan.groups[g]);
        for (int k = 0; k < plan.uvCount; ++k) {
            size_t kk = size_t(k);
            if (m >> k & 1u)
                uv[kk] = G::sgUvFramePixel(frame, uv[kk].st, uv[kk].dSTdx, uv[kk].dSTdy);
        }
        surfGrad = glm::vec3(0.0f);
        for (int pass = 0; pass < 2; ++pass)
            for (const auto& pl : plan.groups[g]) {
                if ((pl.featureIndex >= 0) != (pass == 1)) continue;
                if (layerOn(pl, plan, u))
                    surfGrad += layerCpu(pl, u, smp, fsmp, frame, uv, volWorld, volObject, in);
            }
        nrm = G::sgResolve(frame, surfGrad);
    }
    glm::vec3 color = G::sgShadeAmbient(nrm, u.ambient, baseColor);
    for (int i = 0; i < plan.lightCount; ++i) {
        color += G::sgShadeLight(nrm, in.relPos, u.lights[size_t(2 * i)],
                                 u.lights[size_t(2 * i + 1)], baseColor, u.roughness);
    }
    if (!hasUv0) tangentOut = bitangentOut = glm::vec3(0.0f);
    return G::sgAovValue(u.aov, color, nrm, surfGradOut, tangentOut, bitangentOut, baseNormal,
                         hasUv0 ? in.uv[0] : glm::vec2(0.0f), in.primId + 1.0f + u.primBase);
}

} // namespace detail

} // namespace sg::render

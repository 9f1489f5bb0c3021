// Material plans and shader assembly (effects on demand): which layer kinds,
// UV sets, textures and vertex tangents one material on one mesh uses, the
// GLSL program assembled from only those (shaders/sg/render/*.glsl), and
// the uniform records the program reads.
//
// Contract: `scene` is validated and `assets` was loaded from it;
// meshIndex and materialIndex index scene.meshes and scene.materials
// (caller bugs otherwise: contract checks). A layer that reads a UV set the
// mesh does not have is an sg::io::InputError (scene input). The plan
// points into the Scene, which must outlive it.
#pragma once

#include <any>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/render/assets.h"
#include "surfgrad/shaders/shader_files.h"
#include "surfgrad/render/scene.h"
#include "surfgrad/render/view.h"

namespace sg::render {

// What a program depends on: the material's enabled layers in order (kinds,
// UV sets, modifier presence, volume spaces, texture slot sharing), the
// mesh's vertex layout (UV set count, which sets carry vertex tangents) and
// the light count. Parameters (strengths, colours, decal frames, ...) are
// uniforms and do not change the program.
struct PlanLayer {
    const Layer* layer = nullptr;
    int record = 0; // first vec4 record in the material's uLayerData
    int recordCount = 0;
    int tex[6] = {-1, -1, -1, -1, -1, -1}; // texture slots (6: LEAN triplanar)
    // Layers reading their kind's own assets (KindPlan): the slot of theirs
    // (index into KindPlan::keys) and the layer's index among the plan's
    // layers of the kind that read them (all groups).
    int kindSlot = -1;
    int kindIndex = -1;
    int modTex[kMaxModifiers] = {-1, -1, -1, -1}; // modulate mask slot per modifier
    bool hasModifiers = false;
    int modRecord = -1; // first modifier record (one per modifier)
    int uberIndex = -1; // uber-shader enable flag
};

// A layer kind's own share of a plan: the kind's assets its layers read
// (e.g. the feature kind's feature maps; render/src/layer_kind.h,
// LayerKindAssets), planned by the kind's hook.
struct KindPlan {
    const LayerKind* kind = nullptr;
    std::vector<std::string> keys; // slot (PlanLayer::kindSlot) -> the asset's key
    int layerCount = 0;            // layers reading them (PlanLayer::kindIndex), all groups
    std::any data;                 // the kind's own (what its program depends on)
};

struct MaterialPlan {
    std::string signature; // effect signature: the program cache key
    int materialIndex = 0;
    int uvCount = 0;                // UV sets the mesh provides (vertex attributes)
    uint32_t vertexTangentMask = 0; // bit k: UV set k uses vertex tangents
    int lightCount = 1;
    bool uber = false; // every kind compiled in, enabled by uniforms
    // The mesh is drawn as adaptive patches (MeshAsset::patches): the
    // vertex stage is sg/patch/patch_vs.glsl with the tessellation stages
    // (the fragment program is the same as for triangles).
    bool adaptive = false;
    // Adaptive meshes with a "displacement" (MeshInstance::displacement):
    // its UV set (else -1). The evaluation stage then moves every point
    // along the limit normal (SG_DISPLACEMENT) and writes the displaced
    // position for rasterisation and lighting (vRelPosLit) and the
    // undisplaced one for the frame (vRelPos: Mikkelsen 2019 section 2.5,
    // a bump layer of the same height field takes dPdx/dPdy of the surface
    // before displacement); the fragment program lights at vRelPosLit.
    int displacementUvSet = -1;
    std::vector<std::vector<PlanLayer>> groups; // [0] base layers, then post-resolve groups
    std::vector<const LayerKind*> kinds;        // kinds of the plan's layers, registry order
    std::vector<const Layer*> groupLayers; // the post_resolve layer of each group (nullptr for 0)
    std::vector<int> groupUberIndex;       // uber plans: flag of each group (-1 for 0)
    std::vector<std::string> textureKeys;  // slot -> TextureSource::key()
    std::vector<const TextureSource*> textureSources; // slot -> source
    std::vector<KindPlan> kindPlans;                  // kinds whose layers read their own assets
    int recordCount = 0;
    int uberFlagCount = 0;
    uint32_t uvUsedMask = 0; // UV sets read by some layer (or the base colour map)
    int baseColorTex = -1;   // texture slot of the base colour map (-1: none)
    int baseColorUvSet = 0;
    bool usesWorldVolume = false, usesObjectVolume = false;
    // Some layer antialiases (LayerKind::antialias): the program sums the
    // layers' slope covariances and widens the lobe (sg/render/antialias.glsl).
    bool antialias = false;
    // Uber plans: the disabled stand-in layers (shared so copies of the
    // plan stay valid). Other layer and texture pointers point into the Scene,
    // which must outlive the plan.
    std::shared_ptr<const std::vector<Layer>> ownedLayers;
};

// Plans the program for material `materialIndex` on mesh `meshIndex`.
// Throws InputError if a layer reads a UV set the mesh does not have.
MaterialPlan planMaterial(const Scene& scene, const SceneAssets& assets, int meshIndex,
                          int materialIndex);
// The same material with every layer kind compiled in (the stand-in layers
// each registered kind provides, after the material's own), each enabled by
// a uniform flag: the "uber-shader" baseline of bench/render_bench.
MaterialPlan planUberMaterial(const Scene& scene, const SceneAssets& assets, int meshIndex,
                              int materialIndex);

struct ProgramSource {
    std::string vertex; // complete GLSL (includes expanded)
    std::string fragment;
    std::vector<std::string> vertexFiles, fragmentFiles; // #line source-string names
    // Adaptive plans only (else empty): the tessellation evaluation stage
    // (sg/patch/patch_tes.glsl; `vertex` is then sg/patch/patch_vs.glsl).
    // The control stage depends on the patch type: assemblePatchControl.
    std::string tessEval;
    std::vector<std::string> tessEvalFiles;
};
ProgramSource assembleProgram(const MaterialPlan& plan);
// The tessellation control stage (sg/patch/patch_tcs.glsl) of patches with
// `pointsPerPatch` control points (16 regular, 20 Gregory basis).
sg::shaders::Assembled assemblePatchControl(int pointsPerPatch);
// The generated fragment body before include expansion (readable).
std::string fragmentBody(const MaterialPlan& plan);

// Packed uniform records of a plan's layers for a view (decal origins are
// stored relative to the camera).
std::vector<glm::vec4> packLayerRecords(const MaterialPlan& plan, const View& view);
// Light records uLights for a view (2 per light).
std::vector<glm::vec4> packLightRecords(const Scene& scene, const View& view);

} // namespace sg::render

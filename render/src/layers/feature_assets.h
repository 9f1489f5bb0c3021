// The feature layer kind's own assets (layer_feature.cpp; LayerKindAssets,
// layer_kind.h section 5): the feature maps its layers read (loaded or
// baked once per scene, by FeatureSource::key(), into
// SceneAssets::kindAssets["feature"]), their slots in a plan (KindPlan),
// their GL textures and CPU samplers, and the prefiltered slope chain of
// "antialias": "lean" layers, textures the kind makes from the maps (a
// TextureSource producer). Internal to surfgrad_render.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "layer_kind.h"
#include "surfgrad/features/feature_maps.h"

namespace sg::render {

// Baked feature maps as both renderers read them.
struct FeatureMapsAsset {
    sg::features::GpuFeatureMaps gpu;
    double bandTexels = 16.0;
    bool quadratic = false;      // baked in quadratic mode (curved segments)
    double nearBandTexels = 0.0; // exact near field's band (0: the maps have none)
    uint64_t uid = 0;            // unique per load (GPU caches key on it)
};

// The feature kind's entry of SceneAssets::kindAssets: the maps by
// FeatureSource::key().
struct FeatureAssets : KindAsset {
    std::map<std::string, std::shared_ptr<const FeatureMapsAsset>> maps;
};

// The loaded maps of FeatureSource key `key` (nullptr: not loaded).
const FeatureMapsAsset* findFeatureMaps(const SceneAssets& assets, const std::string& key);

// The prefiltered slope chain of a feature layer with "antialias": "lean"
// (shaders/sg/render/layer_feature_aa.glsl): built when the scene loads from
// the layer's feature maps and its profile (the slopes depend on both).
struct FeatureChainSource {
    std::string mapsKey; // FeatureSource::key() of the maps
    std::string profile; // sg::features::makeProfile name
    float depth = 1.0f, w0 = 0.0f, width = 3.0f;
    bool paperMode = false;
    bool nearExact = false;
    int part = 0; // 0: texA (E[d], E[d.x^2], E[d.y^2]); 1: texB (E[d.x d.y])
};

// The producer of one part of a chain (TextureSource::producer): its key
// "featchain:<mapsKey>:<profile>:..." and, when the textures load (the maps
// are loaded first), both parts in one pass within the texture budget (the
// part not asked for stored under its own key).
std::shared_ptr<const TextureProducer> featureChainProducer(const FeatureChainSource& chain);

// What the program of a plan with feature layers depends on (KindPlan::data
// of the feature kind) and how many feature layers it has.
struct FeaturePlan {
    int layerCount = 0;  // layers reading feature maps, all groups (PlanLayer::kindIndex)
    bool curved = false; // some feature map has curved segments (SG_FEAT_CURVED)
    bool near = false;   // some feature layer uses an exact near field (SG_FEAT_NEAR)
    bool lean = false;   // some feature layer antialiases (layer_feature_aa.glsl)
};
// The plan's (all zero without feature layers).
FeaturePlan featurePlan(const MaterialPlan& plan);

// The hooks of the feature kind's registry entry (LayerKind::assets):
// loading the maps and checking each layer's profile against them, plan
// slots, GL textures (corner pairs and edges, and the exact near field's
// lists and pieces when the plan uses it: 2 or 4 units per slot), CPU
// samplers (std::vector<detail::FeatureSamplers>, one per slot).
const LayerKindAssets& featureKindAssets();

namespace detail {

// Feature-map samplers of one feature slot of a plan (CPU).
struct FeatureSamplers {
    sg::glsl::SgFeatCornerSampler corners;
    sg::glsl::SgFeatEdgeSampler edges;
    sg::glsl::SgFeatNearSampler nearLists; // exact near field (rgba null: none)
    sg::glsl::SgFeatPieceSampler pieces;
};

// The prefiltered slope chain of a feature layer with "antialias": "lean"
// (layer_feature_aa.glsl describes the texels), both of
// its textures in one pass: level 0 texel (i, j) of an N x N map is the
// average of sgFeatAaMomentTexel of the layer's flat-base slope
// (sgFeatAaSlope of the evaluator's result, the profile and mode of `src`;
// src.part is not read) over samplesPerAxis^2 midpoints of the texel square
// (a texel farther than the profile's reach from every curve holds zeros);
// smaller levels are box averages (makeTexture). Clamp wrap, float RGBA:
// part 0 texA, part 1 texB. The midpoint rule's error on a texel a crease
// crosses is at most the area of the samples' cells the crease cuts, about
// 1/samplesPerAxis of the slope jump (tests/render).
// threads (surfgrad/base/threads.h): 0 = all cores, 1..kMaxThreads (else a
// contract violation); rows of texels run in parallel, each texel's sum in
// its own sample order, so level 0 is the same bits for every count. Maps
// of fewer than kFeatureChainSerialBelowSize texels per side run on the
// calling thread. The cut-over is an estimate, not a benchmark: a texel in
// reach of a curve costs 64 evaluator samples (tens of microseconds), so a
// 32^2 map is milliseconds of compute-bound work against an arena's start
// of tens of microseconds.
inline constexpr int kFeatureChainSamples = 8;
inline constexpr int kFeatureChainSerialBelowSize = 32;
struct FeatureChainTextures {
    TextureImage part[2];
};
FeatureChainTextures featureChainTextures(const FeatureMapsAsset& maps,
                                          const FeatureChainSource& src,
                                          int samplesPerAxis = kFeatureChainSamples,
                                          int threads = 0);

} // namespace detail

} // namespace sg::render

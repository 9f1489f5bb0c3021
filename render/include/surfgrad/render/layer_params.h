// Parameters of the built-in layer kinds: the C++ side of each kind's
// scene fields, read with Layer::params<P>() (e.g.
// layer.params<DecalParams>().axisZ). Each struct belongs to its kind's unit
// (shaders/sg/render/layer_<kind>.{glsl,cpp}): the kind's parameter table
// there maps scene fields to these members, validates them and packs them
// into the records its GLSL unpacker reads. The fields every kind shares
// (strength, maps, uv_set, modifiers, ...) are members of Layer itself.
// Defaults are the member initializers (makeLayer() gives them; the scene
// parser keeps them for absent fields). A kind added later may keep its
// parameter struct in its own .cpp when nothing else reads it.
//
// Spaces and units as in docs/scene.md: world space right-handed, y up;
// st with t up.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include <glm/glm.hpp>

#include "surfgrad/render/scene.h"

namespace sg::render {

// uv_normal: tangent-space normal map on a UV set (listings 4, 5, 6).
struct UvNormalParams {
    NormalEncoding encoding = NormalEncoding::Rgb;
    bool flipV = false;       // green convention "dx"
    int heightChannel = -1;   // height channel read by modifiers (-1: none)
    float heightScale = 1.0f; // height channel -> height per st unit
    // "antialias": 0 "none", SG_AA_LEAN 1 "lean", SG_AA_TOKSVIG 2 "toksvig"
    // (layer_uv_normal_aa.glsl). With it, Layer::maps holds the map's
    // moment textures (TextureSource::moments) instead of the map.
    int antialias = 0;
};

// object_normal: object/world-space normal map (listing 7).
struct ObjectNormalParams {
    Space space = Space::Object;
    NormalEncoding encoding = NormalEncoding::Rgb; // Rgb or Float
};

// height: height map, displacement style (listings 8, 9).
struct HeightParams {
    int channel = 0;     // channel holding the height (0 r .. 3 a)
    float scale = 0.05f; // world units per unit of the channel
};

// deriv_map: derivative map, TBN style or texel space (section 2.1).
struct DerivMapParams {
    bool signedTexels = true; // float texels (else unorm: (2 rg - 1) * range)
    float range = 1.0f;
    bool texelSpace = false; // texel-space derivatives (scale dependent)
    bool flipV = false;
    int heightChannel = -1;
    float heightScale = 1.0f;
};

// triplanar: projection on three planes (listings 13, 14).
struct TriplanarParams {
    float scale = 1.0f;     // repeats per domain unit
    float sharpness = 4.0f; // listing 14's k
    bool rightHanded = true;
    Space space = Space::World;
    NormalEncoding encoding = NormalEncoding::Rgb;
    bool flipV = false;
    // "antialias" as UvNormalParams::antialias (layer_triplanar_aa.glsl):
    // Layer::maps holds the planes' moment textures (x A, x B, y A, ... for
    // LEAN; x, y, z for Toksvig).
    int antialias = 0;
};

// decal: projector (listing 15). position, direction, up and size are the
// scene's fields; the frame and half size are derived from them when the
// scene is read (z toward the surface the decal lands on, x = up x z).
struct DecalParams {
    glm::dvec3 position{0.0};               // centre (world, binary64)
    glm::vec3 direction{0.0f, 0.0f, -1.0f}; // projection direction
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    glm::vec3 axisX{1, 0, 0}, axisY{0, 1, 0}, axisZ{0, 0, 1}; // unit, orthogonal
    glm::vec3 halfSize{0.5f};                                 // world units, > 0
    float fade = 0.25f;                                       // of the half depth
    float cosStart = 0.5f, cosEnd = 0.17f;                    // angle fade (cosines)
    NormalEncoding encoding = NormalEncoding::Rgb;
    bool flipV = false;
    // "antialias" as UvNormalParams::antialias (layer_decal_aa.glsl).
    int antialias = 0;
};

// noise's "antialias": None (false, "none"): every octave at full weight;
// Fade (true, "fade", the default): octaves above the pixel's Nyquist fade
// out; Lean ("lean"): fade, and their slope energy widens the lobe
// (layer_noise_aa.glsl).
enum class NoiseAntialias { None = 0, Fade = 1, Lean = 2 };

// noise: volume noise with analytic gradient (listing 12, section 4).
struct NoiseParams {
    NoiseType type = NoiseType::Turbulence;
    float amplitude = 0.02f, frequency = 4.0f; // domain units, per domain unit
    int octaves = 5;
    float lacunarity = 2.0f, gain = 0.5f, exponent = 1.0f;
    glm::vec3 offset{0.0f};
    Space space = Space::Object;
    NoiseAntialias antialias = NoiseAntialias::Fade;
};

// Where a feature-curve layer's maps come from: a file written by
// `surfgrad features bake`, or curves baked when the scene loads (only if
// the layer is enabled: effects on demand). Loaded by the kind
// (render/src/layers/feature_assets.cpp, which defines key()).
struct FeatureSource {
    std::filesystem::path mapsFile; // .exr feature maps, or empty
    std::string curvesKind;         // "svg", "json" or "font" (bake at load)
    std::filesystem::path curvesFile;
    std::string text;       // font: the characters
    int size = 256;         // bake: texels per side
    bool quadratic = false; // bake: quadratic (TOG 2008) or linear (TR2005)
    double marginTexels = 8.0;
    // bake: keep the exact near field (the layer's "near": "exact"), its
    // band covering the layer's profile width.
    bool nearField = false;
    double nearWidthTexels = 3.0;
    std::string fieldPath;
    std::string key() const;
};

// feature: feature-curve maps (Parilov-Zorin 2008) as a TBN-style layer.
// Layer::maps holds the optional base map.
struct FeatureParams {
    std::optional<FeatureSource> source;         // the maps (always set by the parser)
    std::string profile = "crease";              // sg::features::makeProfile name
    float depth = 1.0f, w0 = 0.0f, width = 3.0f; // texels
    bool paperMode = false;
    bool nearExact = false; // "near": "exact": the maps' exact near field, per-curve profiles
    // "antialias": "lean": exact below a texel, the prefiltered chain above
    // (layer_feature_aa.glsl); Layer::maps then holds the chain's two
    // textures (TextureSource::producer) and no base map.
    bool lean = false;
    float tiling = 1.0f;
    glm::vec2 offset{0.0f};
    NormalEncoding encoding = NormalEncoding::Rgb; // base map
    bool flipV = false;
};

} // namespace sg::render

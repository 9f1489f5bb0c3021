// Scenes: the schema of a scene file (docs/scene.md) as C++ types, and its
// parser and validator. A Scene is plain data: meshes (files or procedural,
// optional OpenSubdiv refinement, derived UV sets, tangent sources, morph
// animation), materials with their bump layers, lights, camera, output.
//
// Contract: parseScene()/loadScene() return only scenes that satisfy every
// rule of docs/scene.md (indices in range, sizes within the kMax* limits
// below, finite numbers); everything downstream (assets, plans, renderers)
// may rely on that. Anything else in a scene file is untrusted input:
// sg::io::InputError naming the file, the field path (e.g.
// "materials[0].layers[2].strength") and the reason. Scenes built in code
// must follow the same rules (they are caller contracts there).
//
// Spaces: world space is right-handed, y up; a camera looks down its -z
// axis; texture coordinates have (0,0) at the lower-left image corner, t up.
#pragma once

#include <any>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/base/contract.h"
#include "surfgrad/render/glsl_texture.h"

namespace sg::render {

inline constexpr int kMaxUvSets = 4;
inline constexpr int kMaxLights = 8;
inline constexpr int kMaxLayers = 32;       // per material, post-resolve layers included
inline constexpr int kMaxTextureSlots = 16; // distinct textures per material
inline constexpr int kMaxModifiers = 4;     // derivative-space modifiers per layer
inline constexpr int kMaxImageSize = 8192;  // output width/height

enum class TangentSource { Pixel, MikkTSpace, Limit };
// "off" culls back faces; none/mirror/flip are Mikkelsen 2019 section 2.10.
enum class DoubleSided { Off, None, Mirror, Flip };
// A layer kind: one entry of the layer-kind registry (its parameter table,
// records, GLSL emission and CPU call; render/src/layer_kind.h and
// docs/architecture.md, "Adding a layer kind"). Compared by address.
struct LayerKind;
// A derivative-space modifier kind (render/src/layers/deriv_mods.cpp).
struct ModifierKind;
enum class Space { World, Object };
// The values are SG_ENC_* of sg/render/common.glsl (a static_assert in
// sg/render/layer_uv_normal.cpp keeps them equal).
enum class NormalEncoding { Rgb = 0, Rg = 1, Ag = 2, Float = 3 };
// Moment textures of a normal map (layer_uv_normal_aa.glsl): LEAN's
// (E[d], E[d.x^2], E[d.y^2]) and (E[d.x d.y]), Toksvig's E[n].
enum class TexMoments { None = 0, LeanA = 1, LeanB = 2, Toksvig = 3 };
enum class NoiseType { Perlin = 0, Turbulence = 1, Fbm = 2 }; // SG_NOISE_*

struct Scene;
struct SceneAssets;
struct TextureLoadOptions;
struct TextureSource;

// Texels a layer kind makes from its own assets instead of a file (the
// feature kind's prefiltered slope chain, render/src/layers/feature_assets.h):
// TextureSource::producer. Made by the kind's parser; the asset loader calls
// it after the kinds' own assets are loaded (LayerKindAssets::load).
struct TextureProducer {
    virtual ~TextureProducer() = default;
    // The texture's identity: TextureSource::key() of a source with this
    // producer (equal keys share one texture).
    virtual std::string key() const = 0;
    // Makes the texture of `src` (whose producer this is) from `assets`
    // within the texture budget of `opt` (else sg::io::InputError naming
    // scene.sourceName and src.fieldPath); it may store textures it makes
    // in the same pass in assets.textures under their own keys.
    virtual std::shared_ptr<const TextureImage> make(const Scene& scene, SceneAssets& assets,
                                                     const TextureSource& src,
                                                     const TextureLoadOptions& opt) const = 0;
};

// Where a texture's texels come from: a file (PNG, EXR, ... through
// OpenImageIO), a built-in procedural pattern (tileable over [0,1]^2) or a
// layer kind's producer.
struct TextureSource {
    std::filesystem::path file;    // resolved path; empty for procedural
    std::string procedural;        // "bricks", "tiles", "bumps", "weave", "scratches"
    std::string output = "normal"; // procedural: "normal" | "height" | "derivative"
    int size = 256;                // procedural resolution
    float bumpHeight = 0.04f;      // procedural: height per unit st (slope scale)
    Wrap wrap = Wrap::Repeat;
    bool srgb = false;     // colour texture: sRGB-decoded to linear on load
    std::string fieldPath; // for messages, e.g. "materials[0].layers[1].map"
    // Antialiasing: not the file's texels but the slope moments of the
    // normal map they encode (momentsEncoding), with their own mip chain
    // (shaders/sg/render/layer_uv_normal_aa.glsl, sgUvNormalMomentTexel).
    TexMoments moments = TexMoments::None;
    NormalEncoding momentsEncoding = NormalEncoding::Rgb;
    // Not a file: texels a layer kind makes from its own assets (e.g. a
    // feature layer's prefiltered chain); null for files and procedurals.
    std::shared_ptr<const TextureProducer> producer;
    std::string key() const; // identity: equal keys share one texture
};

struct Modifier {
    const ModifierKind* kind = nullptr; // findModifierKind("scale"), ...
    float a = 1.0f;  // scale: alpha; curve: P; deform: amplitude A; modulate: gain
    float b = 0.0f;  // curve: centre H; deform: frequency B
    int channel = 0; // modulate: mask channel
    std::optional<TextureSource> mask; // modulate

    bool is(std::string_view kindName) const; // kind's schema name, e.g. "deform"
};

// One bump layer. The fields every kind shares are members; the kind's own
// parameters (a struct of the kind's, e.g. DecalParams of
// surfgrad/render/layer_params.h) are held type-erased and read with
// params<DecalParams>(). A layer made by makeLayer(kind) holds the kind's
// defaults; a default-constructed Layer has no kind and is not valid.
struct Layer {
    const LayerKind* kind = nullptr;
    std::string fieldPath; // e.g. "materials[0].layers[2]"
    bool enabled = true;
    float strength = 1.0f; // bump scale (listing 2)
    // Maps: one per texture the kind reads (triplanar: x, y, z planes, one
    // map repeated when given once; feature: the optional base map).
    std::vector<TextureSource> maps;
    int uvSet = 0;                   // kinds that read a UV set
    std::vector<Modifier> modifiers; // kinds that take derivative-space modifiers
    std::vector<Layer> children;     // groups (post_resolve)
    std::any kindParams;             // the kind's parameter struct

    // The kind's parameters. Contract: P is the kind's parameter type.
    template <class P>
    P& params() {
        P* p = std::any_cast<P>(&kindParams);
        SG_EXPECTS(p != nullptr, "Layer::params<P>: P is the layer kind's parameter type");
        return *p;
    }
    template <class P>
    const P& params() const {
        const P* p = std::any_cast<P>(&kindParams);
        SG_EXPECTS(p != nullptr, "Layer::params<P>: P is the layer kind's parameter type");
        return *p;
    }
    bool is(std::string_view kindName) const; // kind's schema name, e.g. "decal"
};

// The registry (render/src/layer_registry.cpp): the kind named `name`
// (the schema's "type"), or nullptr.
const LayerKind* findLayerKind(std::string_view name);
const char* layerKindName(const LayerKind* kind); // "?" for nullptr
// A layer of the named kind with the kind's default parameters.
// Contract: findLayerKind(kindName) != nullptr.
Layer makeLayer(std::string_view kindName);
const ModifierKind* findModifierKind(std::string_view name);

// One numeric parameter of a layer that an interactive front end (the
// viewer) offers as a slider: the JSON name and doc line of the kind's
// parameter-table entry, the float it edits inside the layer, and the
// slider's range and printf format.
struct LayerSlider {
    const char* name = "";
    const char* doc = "";
    float* value = nullptr;
    float lo = 0.0f, hi = 1.0f;
    const char* format = "%.3f";
};
// The sliders of `layer`'s kind, in parameter-table order. The pointers
// point into `layer` (valid while it lives and is not moved or copied over).
// A layer without a kind has none.
std::vector<LayerSlider> layerSliders(Layer& layer);
// Whether the layer's kind groups child layers (Layer::children).
bool layerIsGroup(const Layer& layer);

struct Material {
    std::string name;
    std::string fieldPath;
    glm::vec3 baseColor{0.7f};
    float roughness = 0.45f;
    DoubleSided doubleSided = DoubleSided::Off;
    std::optional<TextureSource> baseColorMap; // sRGB colour, multiplies baseColor
    int baseColorUvSet = 0;
    std::vector<Layer> layers;
};

struct MorphKey {
    float time = 0.0f;
    std::vector<float> weights;
};

struct Procedural {
    std::string type;          // "sphere", "plane", "torus", "cube", "terrain"
    float size = 1.0f;         // radius (sphere), edge (plane, cube, terrain), major radius (torus)
    float minorRadius = 0.35f; // torus
    int segments = 64;         // tessellation
    float terrainHeight = 0.25f; // terrain relief (world units)
    int uvSets = 2;              // UV sets generated (set 1 = set 0 * 4: a tiling detail set)
};

// A UV set derived from an existing one by an affine map of the texture
// plane (the mesh-level "uv_sets" field): st' = R(rotateDeg) (scale * st)
// + offset, R counter-clockwise in the (s, t) plane (t up). Appended after
// the mesh's own sets, in order; `from` may name an earlier derived set.
// Applied to the refined (and limit) mesh: every subdivision mask is an
// affine combination, so the map commutes with face-varying refinement
// and limit evaluation (the limit UV derivatives take its linear part).
struct DerivedUvSet {
    int from = 0;
    glm::vec2 scale{1.0f}; // non-zero; negative mirrors the set
    float rotateDeg = 0.0f;
    glm::vec2 offset{0.0f};
    std::string fieldPath; // e.g. "meshes[0].uv_sets[0]"
};

// "displacement": {"map", "scale", "uv_set"} of an adaptive mesh: the
// tessellation evaluation stage (and the CPU tessellator) moves every
// tessellated point along the limit normal by scale * height(uv), height
// the map's red channel on UV set uvSet (shaders/sg/patch/displace.glsl;
// docs/scene.md). Object-space units: the height map's values times scale.
struct Displacement {
    TextureSource map;
    float scale = 0.0f;
    float offset = 0.0f; // object units: the distance is scale * map.r + offset
    int uvSet = 0;
    std::string fieldPath; // e.g. "meshes[0].displacement"
};

struct MeshInstance {
    std::string name;
    std::string fieldPath;
    std::filesystem::path file; // OBJ/PLY/OFF/glTF (via the mesh module), or empty
    int fileInstance = -1;      // glTF: one instance of the file's scene (-1: all, merged)
    std::optional<Procedural> procedural;
    bool subdivide = false;   // "subdivision" given: refine with OpenSubdiv
    std::string subdivScheme; // "" (the file's tags, else catmark), "catmark", "loop", "bilinear"
    int subdivLevel = 0;
    bool subdivLimit = false;
    // "subdivision.max_memory_mib" in bytes: the refusal threshold of the
    // estimated peak memory (sg::mesh::SubdivisionSettings::memoryBudget;
    // 0: sg::mesh::defaultSubdivisionBudget()).
    uint64_t subdivMaxMemory = 0;
    // "subdivision.mode": "uniform" (refined on the CPU to subdivLevel and
    // drawn as triangles) or "adaptive" (OpenSubdiv feature-adaptive patches
    // isolated to subdivIsolation, drawn by the GPU's tessellation stages at
    // subdivPixelsPerEdge screen pixels per tessellated edge segment;
    // sg::mesh::buildAdaptivePatches, shaders/sg/patch/).
    bool subdivAdaptive = false;
    int subdivIsolation = 3;                  // 1..10
    float subdivPixelsPerEdge = 8.0f;         // > 0
    std::optional<Displacement> displacement; // adaptive meshes only
    std::vector<DerivedUvSet> derivedUvSets;  // appended after the mesh's own UV sets
    std::vector<TangentSource> tangents;      // per UV set; missing = pixel
    std::vector<float> morphWeights;          // empty: the file's defaults
    std::vector<MorphKey> morphKeys;          // weight animation (linear between keys)
    bool morphLoop = true;
    // Object -> world, in binary64 like every scene position: composed with
    // the camera in binary64 (modelToCameraRelative, render/view.h) before
    // anything is rounded, so an object and its camera 1e6 from the origin
    // keep the relative placement the file gives.
    glm::dmat4 transform{1.0};
    int material = 0;

    // Drawn as the subdivision limit surface with its derivatives: uniform
    // with "limit": true, or adaptive patches. "limit" tangents need it.
    bool drawsLimitSurface() const { return subdivide && (subdivLimit || subdivAdaptive); }
    // Adaptive patches: no vertex list, so no MikkTSpace tangents.
    bool drawsPatches() const { return subdivide && subdivAdaptive; }
};

struct Light {
    bool point = false;
    glm::vec3 direction{-0.4f, -0.7f, -0.6f}; // directional: direction light travels
    glm::dvec3 position{0.0};                 // point: world position (binary64)
    glm::vec3 color{1.0f};
    float intensity = 3.0f; // point: radiant intensity (1/d^2 falloff)
};

struct Camera {
    bool automatic = true; // frame the scene's bounds
    float azimuthDeg = 30.0f, elevationDeg = 20.0f, distanceScale = 1.0f; // automatic
    glm::dvec3 position{0.0, 0.0, 5.0}; // binary64, as every scene position
    glm::dvec3 target{0.0};
    glm::dvec3 up{0.0, 1.0, 0.0};
    float fovDeg = 35.0f;
    float nearPlane = 0.0f, farPlane = 0.0f; // 0: from the scene bounds
};

struct OutputSettings {
    int width = 960, height = 540;
    float exposure = 1.0f;
    glm::vec3 background{0.06f, 0.065f, 0.075f};
};

struct Scene {
    std::string sourceName = "<built-in>"; // file name for messages
    std::filesystem::path baseDir;         // relative paths resolve here
    std::vector<MeshInstance> meshes;
    std::vector<Material> materials;
    std::vector<Light> lights;
    Camera camera;
    OutputSettings output;
    glm::vec3 ambient{0.08f, 0.085f, 0.1f};
    int frameCount = 1;
    float fps = 24.0f;
};

// Parses and validates a scene. `sourceName` names the file in messages;
// relative file paths resolve against baseDir, "data:..." against
// dataDirectory(). Throws sg::io::InputError naming the field path.
Scene parseScene(const std::string& jsonText, const std::string& sourceName,
                 const std::filesystem::path& baseDir);
Scene loadScene(const std::filesystem::path& file);
// The built-in scene `surfgrad render` draws without arguments: procedural
// meshes and textures only (needs no files).
Scene defaultScene();
// A scene that frames one model file (glTF/OBJ) with a default camera and
// light, using the model's own materials' normal maps (needs the mesh module).
Scene sceneForModel(const std::filesystem::path& model);
// Directory "data:" paths resolve against, the first that applies:
//  1. $SURFGRAD_DATA_DIR when set and not empty;
//  2. the source tree's data/ when the running executable is in the bin/
//     directory of the build tree surfgrad was built in (build/bin/surfgrad,
//     the tests);
//  3. share/surfgrad/data of the installation the executable belongs to,
//     found relative to it (<prefix>/bin/../share/surfgrad/data): an
//     installed or relocated prefix, the Debian package, and programs
//     installed into the same prefix;
//  4. the data directory of the configured install prefix
//     (CMAKE_INSTALL_PREFIX at build time) when it exists: programs
//     elsewhere that link an installed surfgrad::render;
//  5. otherwise the source tree's data/ (paths under it then name what is
//     missing).
// Never fails; whether a file exists is checked where it is read.
std::filesystem::path dataDirectory();

} // namespace sg::render

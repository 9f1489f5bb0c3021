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

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/glsl_texture.h"

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
enum class LayerKind {
    UvNormal,     // tangent-space normal map on a UV set (listings 4, 5, 6)
    ObjectNormal, // object/world-space normal map (listing 7)
    Height,       // height map, displacement style (listings 8, 9)
    DerivMap,     // derivative map, TBN style or texel space (listings 5, 8)
    Triplanar,    // triplanar projection (listings 13, 14)
    Decal,        // decal projector (listing 15)
    Noise,        // volume noise with analytic gradient (listing 12, section 4)
    Feature,      // feature-curve maps (Parilov-Zorin 2008) as a TBN-style layer
    PostResolve,  // group resolved on top of the previous result (section 3)
};
const char* layerKindName(LayerKind k); // the schema's "type" string
enum class Space { World, Object };
enum class NormalEncoding { Rgb = 0, Rg = 1, Ag = 2, Float = 3 };           // SG_ENC_*
enum class NoiseType { Perlin = 0, Turbulence = 1, Fbm = 2 };               // SG_NOISE_*
enum class ModifierKind { Scale = 1, Curve = 2, Modulate = 3, Deform = 4 }; // SG_MOD_*

// Where a texture's texels come from: a file (PNG, EXR, ... through
// OpenImageIO) or a built-in procedural pattern (tileable over [0,1]^2).
struct TextureSource {
    std::filesystem::path file;    // resolved path; empty for procedural
    std::string procedural;        // "bricks", "tiles", "bumps", "weave", "scratches"
    std::string output = "normal"; // procedural: "normal" | "height" | "derivative"
    int size = 256;                // procedural resolution
    float bumpHeight = 0.04f;      // procedural: height per unit st (slope scale)
    Wrap wrap = Wrap::Repeat;
    bool srgb = false;       // colour texture: sRGB-decoded to linear on load
    std::string fieldPath;   // for messages, e.g. "materials[0].layers[1].map"
    std::string key() const; // identity: equal keys share one texture
};

// Where a feature-curve layer's maps come from: a file written by
// `surfgrad features bake`, or curves baked when the scene loads (only if
// the layer is enabled: effects on demand).
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

struct Modifier {
    ModifierKind kind = ModifierKind::Scale;
    float a = 1.0f;  // scale: alpha; curve: P; deform: amplitude A; modulate: gain
    float b = 0.0f;  // curve: centre H; deform: frequency B
    int channel = 0; // modulate: mask channel
    std::optional<TextureSource> mask; // modulate
};

struct Layer {
    LayerKind kind = LayerKind::UvNormal;
    std::string fieldPath; // e.g. "materials[0].layers[2]"
    bool enabled = true;
    float strength = 1.0f; // bump scale (listing 2); noise: see amplitude

    // Maps: uv_normal, object_normal, height, deriv_map, decal use map[0];
    // triplanar uses map[0..2] (x, y, z planes; one map repeated when given once).
    std::vector<TextureSource> maps;
    int uvSet = 0;
    NormalEncoding encoding = NormalEncoding::Rgb;
    bool flipV = false;       // green convention "dx"
    int heightChannel = -1;   // uv_normal/deriv_map height channel for modifiers
    float heightScale = 1.0f; // height channel -> height per st unit
    std::vector<Modifier> modifiers;

    Space space = Space::Object; // object_normal, triplanar, noise
    int channel = 0;             // height: channel of the height
    float heightWorld = 0.05f;   // height: world units per unit of the channel
    bool derivSigned = true;     // deriv_map: float texels (else unorm * range)
    float derivRange = 1.0f;
    bool derivTexelSpace = false; // deriv_map: texel-space (scale dependent)

    float triScale = 1.0f;     // triplanar: repeats per domain unit
    float triSharpness = 4.0f; // listing 14's k
    bool triRightHanded = true;

    glm::vec3 decalPosition{0.0f}; // decal centre (world)
    glm::vec3 decalAxisX{1, 0, 0}, decalAxisY{0, 1, 0},
        decalAxisZ{0, 0, 1}; // z toward the surface it lands on
    glm::vec3 decalHalfSize{0.5f};
    float decalFade = 0.25f;
    float decalCosStart = 0.5f, decalCosEnd = 0.17f;

    NoiseType noiseType = NoiseType::Turbulence;
    float noiseAmplitude = 0.02f, noiseFrequency = 4.0f, noiseLacunarity = 2.0f, noiseGain = 0.5f,
          noiseExponent = 1.0f;
    int noiseOctaves = 5;
    glm::vec3 noiseOffset{0.0f};
    bool noiseAntialias = true;

    std::optional<FeatureSource> feature; // feature: the maps (maps[0] is the optional base map)
    std::string featProfile = "crease";   // sg::features::makeProfile name
    float featDepth = 1.0f, featW0 = 0.0f, featWidth = 3.0f; // texels
    bool featPaperMode = false;
    bool featNearExact = false; // "near": "exact": the maps' exact near field, per-curve profiles
    float featTiling = 1.0f;
    glm::vec2 featOffset{0.0f};

    std::vector<Layer> children; // post_resolve group
};

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
    std::vector<DerivedUvSet> derivedUvSets; // appended after the mesh's own UV sets
    std::vector<TangentSource> tangents;     // per UV set; missing = pixel
    std::vector<float> morphWeights;         // empty: the file's defaults
    std::vector<MorphKey> morphKeys;         // weight animation (linear between keys)
    bool morphLoop = true;
    glm::mat4 transform{1.0f};
    int material = 0;
};

struct Light {
    bool point = false;
    glm::vec3 direction{-0.4f, -0.7f, -0.6f}; // directional: direction light travels
    glm::vec3 position{0.0f};                 // point: world position
    glm::vec3 color{1.0f};
    float intensity = 3.0f; // point: radiant intensity (1/d^2 falloff)
};

struct Camera {
    bool automatic = true; // frame the scene's bounds
    float azimuthDeg = 30.0f, elevationDeg = 20.0f, distanceScale = 1.0f; // automatic
    glm::vec3 position{0.0f, 0.0f, 5.0f};
    glm::vec3 target{0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
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

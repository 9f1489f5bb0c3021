// surfgrad renderer: scenes (JSON, validated), shader assembly with effects
// on demand, the OpenGL 4.5 renderer, the CPU reference renderer and image
// output. The bump math is the surface-gradient framework of Mikkelsen,
// "Surface Gradient Based Bump Mapping Framework" (2019); every layer is a
// function of shaders/sg/render/*.glsl that both renderers run (the GPU as
// GLSL, the CPU through surfgrad/render_shaders.h).
//
// Pipeline:
//   Scene scene = loadScene("scene.json");       // or defaultScene()
//   SceneAssets assets = loadAssets(scene);      // meshes, only textures layers use
//   GlRenderer gl;                               // needs a current GL 4.5 context
//   Image img = gl.render(scene, assets, view);  // or renderCpu(scene, assets, view)
//   writeImage("out.png", img, Aov::Color, scene.output.exposure);
//
// Spaces and conventions (the whole module):
//  - world space is right-handed, y up; a camera looks down its -z axis;
//  - shading happens in world space RELATIVE TO THE CAMERA (listing 16);
//  - texture coordinates have (0,0) at the lower-left image corner, t up;
//    images are flipped on load so texel row 0 is the bottom row;
//  - images (Image) are stored bottom row first, as OpenGL reads them back;
//    writers flip them to the usual top-first order.
// Errors: invalid scenes and assets throw sg::io::InputError naming the file,
// the field path (e.g. "materials[0].layers[2].strength") and the reason; GL
// failures throw sg::gl::GlError.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/glsl_texture.h"
#include "surfgrad/render_mesh.h"

namespace sg::render {

// ---------------------------------------------------------------------------
// Scene (schema: docs/scene.md)

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

enum class Aov { Color = 0, Normal, SurfGrad, Tangent, Bitangent, BaseNormal, Uv, PrimId };
const char* aovName(Aov a);
// Parses an AOV name ("color", "normal", "surfgrad", "tangent", "bitangent",
// "basenormal", "uv", "primid"); nullopt for anything else.
std::optional<Aov> parseAov(const std::string& name);

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
// Directory "data:" paths resolve against: $SURFGRAD_DATA_DIR, else the
// data directory this build was configured with (the source tree's data/).
std::filesystem::path dataDirectory();

// ---------------------------------------------------------------------------
// Assets: what the scene needs, loaded once (effects on demand: textures of
// disabled or absent layers are not loaded; meshes are refined only as far as
// asked; nothing is baked unless a layer uses it).

struct FeatureMapsAsset;

struct MeshAsset {
    sg::mesh::RenderMesh mesh; // object space; morph targets kept
    // Vertex tangents per UV set (empty = that set uses per-pixel frames),
    // aligned with mesh's vertices. Generated for a set only when the mesh
    // asks for vertex tangents on it AND an enabled layer reads its basis
    // (tangentBasisUvSets); any number of sets at once, each with its own
    // source (MikkTSpace may split vertices: earlier sets' arrays follow).
    std::vector<std::vector<glm::vec4>> vertexTangents;
    std::vector<glm::vec3> basePositions, baseNormals; // before morphing
    std::vector<std::vector<glm::vec4>> baseTangents;  // before morphing
    std::vector<float> appliedWeights;                 // morph weights in the arrays now
    uint64_t layoutId = 0; // unique per built vertex/index layout (GPU caches key on it)
};

// UV sets whose tangent basis the enabled layers of `material` read (bit k:
// UV set k): the TBN-style layers uv_normal, deriv_map in "tbn" space and
// feature, outside post_resolve groups (those use the per-pixel frame of
// the resolved normal, section 2.11). Vertex tangents are generated, and
// read by the shader, only for these sets (effects on demand).
uint32_t tangentBasisUvSets(const Material& material);

struct SceneAssets {
    uint64_t uid = 0;              // unique per loadAssets() call (GPU caches key on it)
    uint64_t meshVersion = 0;      // bumped by applyFrame() when vertex data changed
    std::vector<MeshAsset> meshes; // one per Scene::meshes entry
    std::map<std::string, std::shared_ptr<const TextureImage>> textures; // by TextureSource::key()
    // Feature maps in their GPU layout, by FeatureSource::key().
    std::map<std::string, std::shared_ptr<const FeatureMapsAsset>> featureMaps;
    std::vector<std::string> log; // what was loaded/generated (for -v output and tests)
};

SceneAssets loadAssets(const Scene& scene);
// Loads the textures and feature maps of layers that are enabled now but
// were not when the assets were loaded (the viewer's layer toggles), and
// rebuilds a mesh whose newly enabled layers read a UV set it asks vertex
// tangents for but does not have yet (its morph weights are kept).
void loadMissingAssets(const Scene& scene, SceneAssets& assets);
// Applies the morph weights of time `seconds` to every animated mesh
// (positions and normals; pixel frames need nothing else).
void applyFrame(const Scene& scene, SceneAssets& assets, float seconds);
// Loads or generates one texture (also used by tests).
std::shared_ptr<const TextureImage> loadTexture(const TextureSource& src,
                                                const std::string& sceneName);

// ---------------------------------------------------------------------------
// Views

struct View {
    int width = 0, height = 0;
    glm::vec3 cameraPos{0.0f};
    glm::mat4 viewProjRel{1.0f}; // camera-relative world -> clip
    glm::mat4 view{1.0f}, proj{1.0f};
    Aov aov = Aov::Color;
};
// The view of the scene's camera (automatic framing uses the assets' bounds)
// at the given output size (0: the scene's).
View makeView(const Scene& scene, const SceneAssets& assets, int width = 0, int height = 0,
              Aov aov = Aov::Color);
// An orbit view around `target` (viewer).
View makeOrbitView(glm::vec3 target, float distance, float azimuthDeg, float elevationDeg,
                   float fovDeg, float nearPlane, float farPlane, int width, int height, Aov aov);

// ---------------------------------------------------------------------------
// Shader assembly (effects on demand)

// What a program depends on: the material's enabled layers in order (kinds,
// UV sets, modifier presence, volume spaces, texture slot sharing), the
// mesh's vertex layout (UV set count, which sets carry vertex tangents) and
// the light count. Parameters (strengths, colours, decal frames, ...) are
// uniforms and do not change the program.
struct PlanLayer {
    const Layer* layer = nullptr;
    int record = 0; // first vec4 record in the material's uLayerData
    int recordCount = 0;
    int tex[3] = {-1, -1, -1}; // texture slots
    int featureSlot = -1;      // feature layers: index into MaterialPlan::featureKeys
    int featureIndex = -1;     // feature layers: index among the plan's feature layers
    int modTex[kMaxModifiers] = {-1, -1, -1, -1}; // modulate mask slot per modifier
    bool hasModifiers = false;
    int modRecord = -1; // first modifier record (one per modifier)
    int uberIndex = -1; // uber-shader enable flag
};

struct MaterialPlan {
    std::string signature; // effect signature: the program cache key
    int materialIndex = 0;
    int uvCount = 0;                // UV sets the mesh provides (vertex attributes)
    uint32_t vertexTangentMask = 0; // bit k: UV set k uses vertex tangents
    int lightCount = 1;
    bool uber = false;                          // every kind compiled in, enabled by uniforms
    std::vector<std::vector<PlanLayer>> groups; // [0] base layers, then post-resolve groups
    std::vector<const Layer*> groupLayers; // the post_resolve layer of each group (nullptr for 0)
    std::vector<int> groupUberIndex;       // uber plans: flag of each group (-1 for 0)
    std::vector<std::string> textureKeys;  // slot -> TextureSource::key()
    std::vector<const TextureSource*> textureSources; // slot -> source
    std::vector<std::string> featureKeys;             // feature slot -> FeatureSource::key()
    int featureLayerCount = 0;                        // feature layers (all groups)
    bool featureCurved = false; // some feature map has curved segments (SG_FEAT_CURVED)
    int recordCount = 0;
    int uberFlagCount = 0;
    uint32_t uvUsedMask = 0; // UV sets read by some layer (or the base colour map)
    int baseColorTex = -1;   // texture slot of the base colour map (-1: none)
    int baseColorUvSet = 0;
    bool usesWorldVolume = false, usesObjectVolume = false;
    // Uber plans: the disabled stand-in layers (shared so copies of the
    // plan stay valid). Other layer and texture pointers point into the Scene,
    // which must outlive the plan.
    std::shared_ptr<const std::vector<Layer>> ownedLayers;
};

// Plans the program for material `materialIndex` on mesh `meshIndex`.
// Throws InputError if a layer reads a UV set the mesh does not have.
MaterialPlan planMaterial(const Scene& scene, const SceneAssets& assets, int meshIndex,
                          int materialIndex);
// The same material with every layer kind compiled in (one stand-in layer of
// each kind the material lacks), each enabled by a uniform flag: the
// "uber-shader" baseline of bench/render_bench.
MaterialPlan planUberMaterial(const Scene& scene, const SceneAssets& assets, int meshIndex,
                              int materialIndex);

struct ProgramSource {
    std::string vertex; // complete GLSL (includes expanded)
    std::string fragment;
    std::vector<std::string> vertexFiles, fragmentFiles; // #line source-string names
};
ProgramSource assembleProgram(const MaterialPlan& plan);
// The generated fragment body before include expansion (readable).
std::string fragmentBody(const MaterialPlan& plan);

// Packed uniform records of a plan's layers for a view (decal origins are
// stored relative to the camera).
std::vector<glm::vec4> packLayerRecords(const MaterialPlan& plan, const View& view);
// Light records uLights for a view (2 per light).
std::vector<glm::vec4> packLightRecords(const Scene& scene, const View& view);

// ---------------------------------------------------------------------------
// Images

struct Image {
    int width = 0, height = 0;
    std::vector<glm::vec4> pixels; // bottom row first
    glm::vec4& at(int x, int y) { return pixels[size_t(y) * size_t(width) + size_t(x)]; }
    const glm::vec4& at(int x, int y) const {
        return pixels[size_t(y) * size_t(width) + size_t(x)];
    }
};

// Writes an image atomically (sg::io::writeAtomically). ".exr": linear RGBA
// float (the AOV's raw values). ".png" (8-bit sRGB): colour is tone-mapped
// (sgToneMap with `exposure`); vector AOVs are mapped v -> 0.5 v + 0.5; uv
// is written as fract(uv); primid as a hashed colour. Throws InputError for
// an unsupported extension or a failed write.
void writeImage(const std::filesystem::path& path, const Image& image, Aov aov, float exposure);
Image readImage(const std::filesystem::path& path); // RGBA float, bottom row first
// Writes display-referred values in [0, 1] as they are (8-bit PNG, RGB), e.g.
// a window capture.
void writeDisplayImage(const std::filesystem::path& path, const Image& image);

// Per-pixel comparison of two images of unit vectors (normal, tangent, ...
// AOVs), e.g. the GPU and CPU renderers' outputs. Only pixels covered by the
// same primitive in both images are compared (primA/primB: primid AOVs of
// the same views); coverage differences (silhouettes, rasterisation ties)
// are counted, not compared. Angles in degrees.
struct VectorImageDiff {
    size_t compared = 0;         // pixels covered by the same primitive in both
    size_t coverageMismatch = 0; // pixels covered in one image only, or by different primitives
    size_t nonFinite = 0;        // compared pixels with a NaN/Inf component in either image
    double meanDeg = 0, p50Deg = 0, p90Deg = 0, p99Deg = 0, p999Deg = 0, maxDeg = 0;
    int maxX = -1, maxY = -1; // where the largest angle is
};
VectorImageDiff compareVectorImages(const Image& a, const Image& b, const Image& primA,
                                    const Image& primB);

// ---------------------------------------------------------------------------
// Renderers

struct RenderStats {
    // GPU time of the draws (GL_TIME_ELAPSED). Meaningful on hardware; on
    // llvmpipe rasterisation happens at the flush, outside the query, so it
    // reads near 0 (bench/render_bench times render + glFinish instead).
    double gpuMs = 0.0;
    int programsCompiled = 0; // programs compiled by this call (cache misses)
    int drawCalls = 0;
};

// The OpenGL 4.5 renderer. Needs a current GL 4.5 core context (from
// sg::gl::HeadlessContext or a GLFW window); all calls on that thread.
// Programs are cached by effect signature; meshes and textures are uploaded
// once per SceneAssets and re-uploaded when applyFrame changed positions.
class GlRenderer {
public:
    GlRenderer();
    ~GlRenderer();
    GlRenderer(const GlRenderer&) = delete;
    GlRenderer& operator=(const GlRenderer&) = delete;

    // Renders into an internal RGBA32F framebuffer of the view's size and
    // reads it back.
    Image render(const Scene& scene, const SceneAssets& assets, const View& view);
    // Renders into the internal framebuffer without reading back (viewer,
    // benchmarks); returns its GL texture name.
    unsigned renderToTexture(const Scene& scene, const SceneAssets& assets, const View& view);
    // While set, every material renders through its uber-shader plan
    // (planUberMaterial; the bench baseline).
    void setUber(bool uber) { uber_ = uber; }
    // Meshes are re-uploaded when SceneAssets::uid or meshVersion changes
    // (applyFrame bumps it); this forces it otherwise.
    void invalidateMeshes();
    const RenderStats& stats() const { return stats_; }
    size_t cachedPrograms() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    RenderStats stats_;
    bool uber_ = false;
};

// The CPU reference renderer: rasterises the same triangles (GL coverage
// at pixel centres, near-plane clipping, depth test), interpolates the same
// attributes perspective-correctly, computes screen-space derivatives
// ANALYTICALLY (exact derivatives of the perspective-correct interpolants;
// the GPU uses 2x2-quad differences, dFdxFine) and runs the same shared
// layer functions in the same order as the assembled GLSL program.
//   CpuDerivatives::Analytic - the reference: exact derivatives;
//   CpuDerivatives::Quad     - emulates dFdxFine/dFdyFine (differences
//                              across the pixel's 2x2 quad), so a comparison
//                              with the GPU isolates the driver's arithmetic
//                              (texture LOD, filtering, float rounding).
enum class CpuDerivatives { Analytic, Quad };
struct CpuOptions {
    CpuDerivatives derivatives = CpuDerivatives::Analytic;
    // Texture LOD: the GL specification's log2 (reference), or llvmpipe's
    // piecewise-linear approximation (sg::glsl::LodRule::FastLog2).
    sg::glsl::LodRule textureLod = sg::glsl::LodRule::Exact;
};
Image renderCpu(const Scene& scene, const SceneAssets& assets, const View& view,
                const CpuOptions& options = {});

} // namespace sg::render

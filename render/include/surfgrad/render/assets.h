// Scene assets: what a scene needs, loaded once (meshes refined only as far
// as asked, vertex tangents only for the UV sets enabled layers read,
// textures and the layer kinds' own assets only of enabled layers: effects
// on demand).
//
// Contract: `scene` is a validated Scene (surfgrad/render/scene.h); the
// files it names are untrusted: a missing or malformed mesh, texture or
// curve file, or a mesh that cannot give what the scene asks of it (a UV
// set it lacks, tangents its values do not allow), throws
// sg::io::InputError naming the scene file and field. Image files go
// through the guarded decoder (surfgrad/image/image_decode.h: header scan, size
// limit) and the texture budget before anything is allocated (docs/scene.md,
// "Texture files").
// SceneAssets::meshes is aligned with Scene::meshes.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/render/glsl_texture.h"
#include "surfgrad/render/scene.h"
#include "surfgrad/mesh/render_mesh.h"

namespace sg::mesh {
struct AdaptivePatches;
struct PolygonMesh;
} // namespace sg::mesh

namespace sg::render {

// A layer kind's own assets (data its layers read besides the textures of
// Layer::maps, e.g. the feature kind's feature maps): a type of the kind's
// files, loaded by its registry entry (render/src/layer_kind.h,
// LayerKindAssets) and stored in SceneAssets::kindAssets.
struct KindAsset {
    virtual ~KindAsset() = default;
};

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
    // "subdivision": {"mode": "adaptive"}: the cage's feature-adaptive
    // patches (surfgrad/mesh/adaptive_patches.h), drawn by the tessellation
    // stages; null for every other mesh. Then `mesh` holds the patches'
    // control points as positions (bounds: the limit surface lies in their
    // convex hull) and no triangles, no UV sets and no morph targets.
    std::shared_ptr<const sg::mesh::AdaptivePatches> patches;
    // Adaptive meshes: bit k set when UV set k gets "limit" tangents from
    // the patch derivatives (the tessellation evaluation stage and the CPU
    // tessellator, shaders/sg/patch/limit_tangent.glsl): asked for by the
    // mesh and read by an enabled layer, as vertexTangents. 0 otherwise.
    uint32_t patchTangentSets = 0;
    // Adaptive meshes whose cage moves (blendshapes on the cage, or
    // setCagePositions): the cage positions now, object space,
    // patches->cagePointCount entries. The GPU renderer uploads only these
    // per frame and recomputes the control points with the stencils in a
    // compute stage; the CPU reference applies the same stencils
    // (sg::mesh::updateAdaptivePoints). Empty: patches->points as built.
    std::vector<glm::vec3> cagePositions;
    // Adaptive meshes whose cage has morph targets: the cage (applyFrame
    // morphs it, sg::mesh::morphCagePositions); null otherwise.
    std::shared_ptr<const sg::mesh::PolygonMesh> morphCage;
};

// UV sets whose tangent basis the enabled layers of `material` read (bit k:
// UV set k): the TBN-style layers uv_normal, deriv_map in "tbn" space and
// feature, outside post_resolve groups (those use the per-pixel frame of
// the resolved normal, section 2.11). Vertex tangents are generated, and
// read by the shader, only for these sets (effects on demand).
uint32_t tangentBasisUvSets(const Material& material);

// The UV sets whose "limit" tangents the tessellation stages of adaptive
// mesh `mesh` write when drawn with `material` (bit k: vTangentk): its
// patchTangentSets read by an enabled layer; 0 for other meshes. The plan's
// vertexTangentMask and the CPU tessellator use this one rule.
uint32_t patchTangentMask(const MeshAsset& mesh, const Material& material);

struct SceneAssets {
    uint64_t uid = 0;                // unique per loadAssets() call (GPU caches key on it)
    uint64_t textureBudgetBytes = 0; // what all textures may take (AssetOptions)
    uint64_t meshVersion = 0;        // bumped by applyFrame() when vertex data changed
    std::vector<MeshAsset> meshes;   // one per Scene::meshes entry
    std::map<std::string, std::shared_ptr<const TextureImage>> textures; // by TextureSource::key()
    // Layer kinds' own assets by the kind's name (LayerKind::name), e.g.
    // "feature": its feature maps. Replaced, not changed, when more load.
    std::map<std::string, std::shared_ptr<const KindAsset>> kindAssets;
    std::vector<std::string> log; // what was loaded/generated (for -v output and tests)
};

struct AssetOptions {
    // Memory all of the scene's textures may take together (bytes): every
    // texture's mip chain in its stored format (TextureImage::bytes()), plus
    // the decoder's own buffers while a file is read. A texture that would
    // exceed it is refused (sg::io::InputError) before anything is
    // allocated. 0: defaultTextureBudget().
    uint64_t textureBudgetBytes = 0;
};
// A quarter of physical memory, at most 8 GiB, and at most half of the
// process's address-space or data-segment limit (setrlimit, `ulimit -v`).
uint64_t defaultTextureBudget();

SceneAssets loadAssets(const Scene& scene, const AssetOptions& options = {});
// Loads the textures and kinds' own assets of layers that are enabled now but
// were not when the assets were loaded (the viewer's layer toggles), and
// rebuilds a mesh whose newly enabled layers read a UV set it asks vertex
// tangents for but does not have yet (its morph weights are kept). The
// texture budget is the one the assets were loaded with.
void loadMissingAssets(const Scene& scene, SceneAssets& assets);
// Applies the morph weights of time `seconds` to every animated mesh
// (positions and normals; pixel frames need nothing else).
void applyFrame(const Scene& scene, SceneAssets& assets, float seconds);
// Moves the cage of adaptive mesh `mesh` (an animated cage:
// cagePointCount positions, object space) and bumps meshVersion; the
// renderers then draw the patches of that cage. A position that is not
// finite, or larger in magnitude than kMaxCagePosition, refuses the frame
// (InputError naming the scene and the mesh's field; the assets are left as
// they were). Contract: `mesh` is an adaptive mesh and the count matches.
void setCagePositions(const Scene& scene, SceneAssets& assets, size_t mesh,
                      std::vector<glm::vec3> cagePositions);
// Largest cage coordinate an animated cage may reach: the stencil passes
// apply subdivision masks level by level (convex weights: no growth) and
// then the Gregory end caps' local points (weights of magnitudes summing to
// about ten), so the control points stay within a small multiple of the
// cage's magnitude and finite in float with a wide margin (2^100 * 2^10
// << FLT_MAX = 2^128; tested at 2^100 on the GPU and the CPU).
inline constexpr float kMaxCagePosition = 0x1p100f;
// Largest texture file accepted (pixels per side).
inline constexpr int kMaxTextureSize = 16384;

// What the layers read from one texture and what it may cost.
struct TextureLoadOptions {
    // RGBA components some layer reads (bit c: component c). A file's
    // channels beyond the highest one read are not decoded. Components the
    // file does not have are left to the caller (TextureImage::channelMask;
    // loadAssets refuses a layer that reads one: a grey image has r, g and
    // b, not a).
    uint32_t channels = 0xFu;
    uint64_t budgetBytes = 0; // the scene's texture budget (0: defaultTextureBudget())
    uint64_t usedBytes = 0;   // taken by the scene's other textures
    int otherTextures = 0;    // how many those are (messages)
};

// Loads or generates one texture. A file goes through the guarded decoder
// (surfgrad/image/image_decode.h), the size limit (kMaxTextureSize) and the
// budget before it is decoded, scanline band by band, into level 0 in the
// file's own precision (TexelType): 8/16-bit unorm, half, or float. Errors
// name the scene file and the field: InputError(sceneName, src.fieldPath,
// "<image>: <reason>").
std::shared_ptr<const TextureImage> loadTexture(const TextureSource& src,
                                                const std::string& sceneName,
                                                const TextureLoadOptions& options = {});
// The decoding of loadTexture for an image already in memory (fuzzing and
// tests); `name` stands for the file in messages and gives TGA's extension.
// Throws InputError(name, element, reason).
TextureImage decodeTextureImage(std::string_view bytes, const std::string& name, bool srgb,
                                Wrap wrap, const TextureLoadOptions& options = {});

} // namespace sg::render

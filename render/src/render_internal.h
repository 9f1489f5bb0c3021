// Internal interfaces of surfgrad_render shared between its source files
// (not installed; the public API is surfgrad/render.h).
#pragma once

#include <any>
#include <array>
#include <string>
#include <vector>

#include "surfgrad/render/glsl_texture.h"
#include "surfgrad/base/io.h"
#include "surfgrad/render.h"

namespace sg::render::detail {

// Procedural meshes (assets.cpp): UV set 0 spans the surface once, further
// sets are set 0 scaled by 4 (a tiling detail set), normals analytic.
sg::mesh::RenderMesh makeProceduralMesh(const Procedural& p);

// UV sets of a mesh asset (uv_sets.cpp).
// The sets of `mi` (bit k: set k) that only repeating textures read: the
// maps of UV-reading layers of its material (post_resolve groups and
// disabled layers included: the viewer may enable them), its base colour
// map and its displacement map, each on its set. A set read by a clamped
// map or by its kind's own assets (LayerKindAssets: clamped at their
// border) is not one.
uint32_t repeatOnlyUvSets(const Scene& scene, const MeshInstance& mi);
// Appends the derived UV sets of `mi` (DerivedUvSet: st' = R S st + o,
// computed in binary64 from the source set as loaded) to the built mesh,
// and their limit derivatives (R S times the source set's) to `limit` when
// it has them; a derived set in `repeatOnly` is stored moved by whole units
// next to 0 (recentreUvSets) before it is rounded to binary32. InputError
// naming the field for a missing source set or a full mesh.
void addDerivedUvSets(const Scene& scene, const MeshInstance& mi, uint32_t repeatOnly,
                      sg::mesh::RenderMesh& mesh, sg::mesh::LimitFrame& limit);
// The same for adaptive patches' face-varying values (every patch basis
// sums to one, so an affine map of the values maps the evaluated UVs), and
// the patches' own sets in `repeatOnly` re-centred.
void addDerivedPatchUvSets(const Scene& scene, const MeshInstance& mi, uint32_t repeatOnly,
                           sg::mesh::AdaptivePatches& ap);
// Moves every set k in `sets` by the whole units (per coordinate) of the
// centre of its bounding box, rounded toward zero: world-unit terrain UVs
// around 1e4 come back next to 0, where binary32 keeps 13 more bits of the
// fraction for interpolation and dFdxFine; repeating textures sample the
// same texels. Sets whose centre is within one unit of 0 are unchanged.
void recentreUvSets(uint32_t sets, std::vector<std::vector<glm::vec2>>& uvSets);

// Procedural textures (procedural_textures.cpp): a tileable height field on
// [0,1]^2 converted to the requested output (see TextureSource).
TextureImage makeProceduralTexture(const TextureSource& src);

// The moment texture `moments` (not None) of a normal map in `encoding`
// (layer_uv_normal.cpp: level 0 by sgUvNormalMomentTexel, then the usual
// box-filtered mip chain, so every level holds the footprint's moments).
// Same size and wrap as `map`; float RGBA.
TextureImage normalMomentTexture(const TextureImage& map, TexMoments moments,
                                 NormalEncoding encoding);

// Refuses (InputError naming `name`) a texture of `residentBytes` (and
// `transientBytes` more while it is built) that does not fit the budget of
// `opt` next to the scene's other textures (texture_file.cpp).
void checkTextureBudget(const std::string& name, const TextureLoadOptions& opt,
                        const std::string& what, uint64_t residentBytes, uint64_t transientBytes);

// The per-patch records the tessellation stages read (binding 1; layout in
// sg/patch/patch_tes.glsl): 28 words per patch: PatchParam field1, the four
// corner vertices, the patch type, its first entry in the index buffer, the
// transition mask, the four edge owners, the four corner owners, the four
// transition edges' lower-half owners, upper-half owners, midpoint owners
// (gl_renderer.cpp; the crack tests draw with the same records).
std::vector<uint32_t> patchRecords(const sg::mesh::AdaptivePatches& ap);

glm::mat3 normalMatrix(const glm::dmat4& model);

// The triangles of adaptive patches for one view, as the GPU's
// tessellation stages make them (patch_tessellation.cpp: the same levels,
// from sgPatchEdgeTessLevel of the corner vertices through modelRel; GL's
// domain points; the triangulation documented there): object-space
// positions and limit normals per point, counter-clockwise triangles;
// patchAov per point: the patch AOV of its patch (Aov::Patch).
// With a displacement (dispMap non-null): mesh.positions are displaced
// along the limit normal by dispScale * dispMap.r + offset at UV set dispUvSet
// (sg/patch/displace.glsl, as the evaluation stage), and framePositions
// holds the undisplaced ones (the frame's, Mikkelsen 2019 section 2.5).
// tangentMask bit k: UV set k gets its "limit" tangents (vertexTangents[k],
// object space, sg/patch/limit_tangent.glsl as the evaluation stage;
// vertexTangents has one entry per UV set, empty where the bit is clear).
struct TessellatedPatches {
    sg::mesh::RenderMesh mesh;
    std::vector<glm::vec4> patchAov;
    std::vector<glm::vec3> framePositions;              // displaced meshes only
    std::vector<std::vector<glm::vec4>> vertexTangents; // per UV set (tangentMask)
};
struct PatchDisplacement {
    sg::glsl::sampler2D map;
    float scale = 0.0f;
    float offset = 0.0f; // object units added to scale * height
    int uvSet = 0;
};
TessellatedPatches tessellatePatches(const sg::mesh::AdaptivePatches& patches,
                                     const glm::mat4& modelRel, float focalPx, float pixelsPerEdge,
                                     const PatchDisplacement* displacement = nullptr,
                                     uint32_t tangentMask = 0);

// One patch's tessellation of GL's quad domain with equal spacing at
// integer outer levels (edges u = 0, v = 0, u = 1, v = 1) and inner levels
// (along u, along v), all in 1..64: the domain points and the
// counter-clockwise triangles (indices into uv) that Mesa's llvmpipe
// generates (patch_tessellation.cpp, which tessellatePatches uses).
struct QuadTessellation {
    std::vector<glm::vec2> uv;
    std::vector<uint32_t> triangles;
};
QuadTessellation tessellateQuadDomain(const std::array<int, 4>& outer, int innerU, int innerV);

// Patches per glDrawArrays of an adaptive mesh (gl_renderer.cpp). Mesa's
// draw module, which runs the vertex and tessellation stages of its
// software rasterisers (llvmpipe, softpipe), splits a draw into chunks of
// at most 4096 input vertices and cannot emit more than 65535 vertices
// from one chunk's tessellation; past that, Mesa 22.3's llvmpipe draws
// wrong, misplaced triangles (and takes seconds rasterising them), which
// happens once a chunk's patches average level ~15 (spot at 1 px/edge on
// a 960x540 view). There a draw gets at most as many patches as fit in
// 65535 vertices at the largest level (a quad patch at level L emits
// (L + 1)^2: 15 at level 64); other drivers draw each patch type at once
// (UINT32_MAX). docs/platform.md.
uint32_t patchesPerDraw(bool mesaDrawModule);

// Per-draw values that are uniforms on the GPU (both renderers fill them
// with drawUniforms()).
struct DrawUniforms {
    int bfaceMode = 0; // SG_BFACE_*
    int aov = 0;       // SG_AOV_*
    float primBase = 0.0f;
    glm::vec3 baseColor{0.7f};
    float roughness = 0.5f;
    glm::vec3 ambient{0.0f};
    glm::mat4 model{1.0f};
    glm::mat4 modelRel{1.0f}; // modelToCameraRelative(model, view.cameraPos)
    glm::mat3 model3{1.0f}, modelInv3{1.0f}, normalMat{1.0f};
    float detSign = 1.0f;
    std::vector<glm::vec4> lights;  // packLightRecords
    std::vector<glm::vec4> records; // packLayerRecords
    std::vector<float> uberFlags;   // uber plans: 1 enabled, 0 disabled
};
DrawUniforms drawUniforms(const Scene& scene, const SceneAssets& assets, const MaterialPlan& plan,
                          const View& view, int meshIndex, float primBase);

// What the fragment program reads at one pixel, computed by the CPU
// rasteriser: interpolated varyings (same names as sg/render/surface_fs.glsl)
// and their screen derivatives.
struct PixelInputs {
    glm::vec3 relPos{0.0f}, objPos{0.0f}, normal{0.0f};
    glm::vec3 relPosLit{0.0f}; // displaced adaptive meshes: vRelPosLit (the lit position)
    std::array<glm::vec2, kMaxUvSets> uv{}, dUVdx{}, dUVdy{};
    std::array<glm::vec4, kMaxUvSets> tangent{};
    glm::vec3 dPdx{0.0f}, dPdy{0.0f};     // of relPos
    glm::vec3 dObjdx{0.0f}, dObjdy{0.0f}; // of objPos (object-space volume domains)
    glm::vec3 dNdx{0.0f}, dNdy{0.0f};     // of normal (interpolated, unnormalized)
    glm::vec2 fragCoord{0.0f};            // gl_FragCoord.xy: window position of the pixel centre
    bool frontFacing = true;
    float primId = 0.0f;      // gl_PrimitiveID
    glm::vec4 patchAov{0.0f}; // adaptive meshes: vPatchAov (Aov::Patch)
};

// The per-plan CPU data of the layer kinds with their own assets
// (LayerKindAssets::cpuData, e.g. the feature maps' samplers), aligned
// with plan.kindPlans; empty std::any for a kind without the hook.
std::vector<std::any> planKindCpuData(const MaterialPlan& plan, const SceneAssets& assets);

// Runs the plan's shading on the CPU with the same shared functions, in the
// same order, as the GLSL main() that fragmentBody(plan) generates.
// kindData: planKindCpuData(plan, assets).
glm::vec4 shadePixelCpu(const MaterialPlan& plan, const DrawUniforms& u,
                        const std::vector<sg::glsl::sampler2D>& samplers,
                        const std::vector<std::any>& kindData, const PixelInputs& in);

// Samplers of a plan's texture slots.
std::vector<sg::glsl::sampler2D> planSamplers(const MaterialPlan& plan, const SceneAssets& assets,
                                              sg::glsl::LodRule lodRule = sg::glsl::LodRule::Exact);

// Errors from a file the scene references keep the scene's context, one
// rule for meshes, textures and the files of layer kinds' own assets
// (curve files, feature maps):
//   "<scene>: <field>: <file>: [<element>: ]<reason>"
// with both paths lexically normal (`field` is the JSON path of the field
// naming the file). An error about the scene file itself (a model loaded as
// its own scene) passes unchanged.
io::InputError referencedFileError(const std::string& sceneName, const std::string& field,
                                   const io::InputError& e);
template <class Load>
auto fromReferencedFile(const std::string& sceneName, const std::string& field, Load&& load)
    -> decltype(load()) {
    try {
        return load();
    } catch (const io::InputError& e) {
        throw referencedFileError(sceneName, field, e);
    }
}

} // namespace sg::render::detail

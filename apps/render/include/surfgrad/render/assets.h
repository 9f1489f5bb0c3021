// Scene assets: what a scene needs, loaded once (meshes refined only as far
// as asked, vertex tangents only for the UV sets enabled layers read,
// textures and feature maps only of enabled layers: effects on demand).
//
// Contract: `scene` is a validated Scene (surfgrad/render/scene.h); the
// files it names are untrusted: a missing or malformed mesh, texture or
// curve file, or a mesh that cannot give what the scene asks of it (a UV
// set it lacks, tangents its values do not allow), throws
// sg::io::InputError naming the scene file and field. SceneAssets::meshes
// is aligned with Scene::meshes.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "surfgrad/glsl_texture.h"
#include "surfgrad/render/scene.h"
#include "surfgrad/render_mesh.h"

namespace sg::render {

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

} // namespace sg::render

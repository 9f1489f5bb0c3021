// The scene made for a bare model file (`surfgrad render model.glb`,
// sceneForModel in surfgrad/render/scene.h): the model's own materials
// (glTF base colour and normal map, doubleSided), an automatic camera and
// two lights.
#include <algorithm>

#include "render_internal.h"
#include "surfgrad/mesh/mesh_io.h"
#include "surfgrad/render.h"

namespace sg::render {

namespace fs = std::filesystem;
namespace sm = sg::mesh;

Scene sceneForModel(const fs::path& model) {
    // A model's own materials: base colour (factor and map) and its normal
    // map as a uv_normal layer on the map's texture coordinate set with the
    // glTF normal scale as strength. glTF normal maps are green-up in the
    // image (+Y up, section 3.9.3); with images and t both flipped on load
    // that is our "gl" convention. glTF's doubleSided (sec. 3.9.5) decides
    // the back faces: false (the default, also of the default material)
    // culls them; true renders them in MIRROR mode (Mikkelsen 2019, 2.10),
    // which is glTF's rule: the normal is reversed on the back side.
    Scene s;
    s.sourceName = model.string();
    s.baseDir = model.parent_path();
    sm::Scene fs = sm::loadScene(model);
    for (size_t i = 0; i < fs.materials.size(); ++i) {
        const sm::Material& gm = fs.materials[i];
        Material m;
        m.name = gm.name.empty() ? "material" + std::to_string(i) : gm.name;
        m.fieldPath = model.filename().string() + " materials[" + std::to_string(i) + "]";
        m.baseColor = glm::clamp(glm::vec3(gm.baseColorFactor), glm::vec3(0.0f), glm::vec3(1.0f));
        m.doubleSided = gm.doubleSided ? DoubleSided::Mirror : DoubleSided::Off;
        if (!gm.baseColorTexture.empty()) {
            TextureSource t;
            t.file = gm.baseColorTexture;
            t.srgb = true;
            t.fieldPath = m.fieldPath + ".baseColorTexture";
            m.baseColorMap = t;
            m.baseColorUvSet = std::clamp(gm.baseColorTexCoord, 0, kMaxUvSets - 1);
        }
        if (!gm.normalTexture.empty()) {
            Layer L = makeLayer("uv_normal");
            L.fieldPath = m.fieldPath + ".normalTexture";
            TextureSource t;
            t.file = gm.normalTexture;
            t.fieldPath = L.fieldPath;
            L.maps.push_back(t);
            L.uvSet = std::clamp(gm.normalTexCoord, 0, kMaxUvSets - 1);
            L.strength = gm.normalScale;
            m.layers.push_back(L);
        }
        s.materials.push_back(std::move(m));
    }
    Material fallback;
    fallback.name = "default";
    fallback.fieldPath = "(default material)";
    fallback.doubleSided = DoubleSided::Off; // glTF's default material is single-sided
    for (size_t i = 0; i < fs.instances.size(); ++i) {
        const sm::SceneInstance& inst = fs.instances[i];
        MeshInstance mi;
        mi.name = inst.mesh.name;
        mi.fieldPath = model.filename().string() + " instance " + std::to_string(i);
        mi.file = model;
        mi.fileInstance = int(i);
        mi.transform = glm::dmat4(inst.objectToWorld);
        // The node's weight animation (glTF sec. 3.11) as linear keys: the
        // animation's own keys when linear, else samples at 30 Hz of
        // sampleWeights (step / cubic spline).
        for (const auto& anim : fs.animations) {
            if (anim.node != inst.node || anim.times.empty() ||
                anim.targetCount != inst.mesh.morphTargets.size() || anim.targetCount == 0) {
                continue;
            }
            std::vector<float> times;
            if (anim.interpolation == sm::AnimInterpolation::Linear) {
                times = anim.times;
            } else {
                float t0 = anim.times.front(), t1 = anim.times.back();
                int n = std::clamp(int((t1 - t0) * 30.0f) + 1, 2, 4096);
                for (int k = 0; k < n; ++k)
                    times.push_back(t0 + (t1 - t0) * float(k) / float(n - 1));
            }
            for (float t : times) mi.morphKeys.push_back(MorphKey{t, sm::sampleWeights(anim, t)});
            mi.morphLoop = true;
            float duration = anim.times.back();
            s.frameCount = std::max(s.frameCount, int(std::ceil(duration * s.fps)) + 1);
            break;
        }
        if (inst.material >= 0 && size_t(inst.material) < s.materials.size()) {
            mi.material = inst.material;
        } else {
            if (s.materials.empty() || s.materials.back().name != "default")
                s.materials.push_back(fallback);
            mi.material = int(s.materials.size()) - 1;
        }
        s.meshes.push_back(std::move(mi));
    }
    if (s.meshes.empty())
        throw io::InputError(model.string(), "", "the file has no triangle meshes");
    s.lights.push_back(Light{});
    Light fill;
    fill.direction = glm::vec3(0.6f, -0.2f, 0.5f);
    fill.color = glm::vec3(0.6f, 0.7f, 0.9f);
    fill.intensity = 1.0f;
    s.lights.push_back(fill);
    return s;
}

} // namespace sg::render

// libFuzzer entry for the renderer's scene parser (sg::render::parseScene,
// render/src/scene.cpp; schema docs/scene.md). Input: the JSON text.
// Beyond "no crash / no sanitizer report / only sg::io::InputError": every
// scene the parser accepts satisfies the invariants the renderer relies on
// (at least one mesh, material indices in range, finite numbers, unit and
// orthogonal decal frames, positive sizes), so nothing downstream divides by
// zero or indexes out of range. Assets are not loaded (no files are read).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "surfgrad/base/io.h"
#include "surfgrad/render.h"

namespace {

void check(bool ok, const char* what) {
    if (!ok) {
        std::fprintf(stderr, "fuzz_scene: accepted scene violates: %s\n", what);
        std::abort();
    }
}

bool finite3(const glm::vec3& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void checkLayer(const sg::render::Layer& L) {
    using namespace sg::render;
    check(std::isfinite(L.strength), "finite strength");
    check(L.uvSet >= 0 && L.uvSet < kMaxUvSets, "uv set in range");
    check(L.modifiers.size() <= size_t(kMaxModifiers), "modifier count");
    if (L.is("decal")) {
        const DecalParams& d = L.params<DecalParams>();
        check(finite3(d.axisX) && finite3(d.axisY) && finite3(d.axisZ), "finite decal axes");
        check(std::abs(glm::length(d.axisX) - 1.0f) < 1e-3f, "unit decal x");
        check(std::abs(glm::length(d.axisZ) - 1.0f) < 1e-3f, "unit decal z");
        check(std::abs(glm::dot(d.axisX, d.axisZ)) < 1e-3f, "orthogonal decal frame");
        check(d.halfSize.x > 0 && d.halfSize.y > 0 && d.halfSize.z > 0, "positive decal size");
    }
    if (L.is("noise")) {
        const NoiseParams& n = L.params<NoiseParams>();
        check(n.frequency > 0 && std::isfinite(n.frequency), "noise frequency");
        check(n.octaves >= 1 && n.octaves <= 12, "octaves");
        check(n.exponent >= 1.0f, "exponent >= 1");
    }
    if (L.is("triplanar")) {
        check(L.maps.size() == 1 || L.maps.size() == 3, "triplanar maps");
        const TriplanarParams& t = L.params<TriplanarParams>();
        check(t.scale > 0 && t.sharpness > 0, "triplanar scale/sharpness");
    }
    if (L.is("feature")) {
        const FeatureParams& f = L.params<FeatureParams>();
        check(f.width > f.w0 && f.source.has_value(), "feature widths");
    }
    if (L.is("post_resolve")) {
        for (const auto& c : L.children) {
            check(!c.is("post_resolve"), "no nested groups");
            checkLayer(c);
        }
    } else {
        check(L.children.empty(), "children only in groups");
    }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    std::string text(reinterpret_cast<const char*>(data), size);
    sg::render::Scene s;
    try {
        s = sg::render::parseScene(text, "fuzz.json", "/nonexistent-scene-dir");
    } catch (const sg::io::InputError&) {
        return 0; // a documented rejection
    }
    check(!s.meshes.empty(), "at least one mesh");
    check(!s.materials.empty(), "at least one material");
    check(s.lights.size() <= size_t(sg::render::kMaxLights), "light count");
    for (const auto& m : s.meshes) {
        check(m.material >= 0 && size_t(m.material) < s.materials.size(),
              "material index in range");
        check(m.procedural.has_value() != !m.file.empty(), "exactly one geometry source");
        check(std::abs(glm::determinant(glm::dmat3(m.transform))) > 0.0, "invertible transform");
    }
    size_t total = 0;
    for (const auto& mat : s.materials) {
        check(mat.roughness >= 0 && mat.roughness <= 1, "roughness range");
        for (const auto& L : mat.layers) {
            checkLayer(L);
            total += 1 + L.children.size();
        }
    }
    check(s.output.width >= 1 && s.output.height >= 1 &&
              s.output.width <= sg::render::kMaxImageSize &&
              s.output.height <= sg::render::kMaxImageSize,
          "output size");
    check(s.fps > 0 && std::isfinite(s.fps), "fps");
    (void)total;
    return 0;
}

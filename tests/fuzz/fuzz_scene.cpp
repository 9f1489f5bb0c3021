// libFuzzer entry for the renderer's scene parser (sg::render::parseScene,
// apps/render/src/scene.cpp; schema docs/scene.md). Input: the JSON text.
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

#include "surfgrad/io.h"
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
    if (L.kind == LayerKind::Decal) {
        check(finite3(L.decalAxisX) && finite3(L.decalAxisY) && finite3(L.decalAxisZ),
              "finite decal axes");
        check(std::abs(glm::length(L.decalAxisX) - 1.0f) < 1e-3f, "unit decal x");
        check(std::abs(glm::length(L.decalAxisZ) - 1.0f) < 1e-3f, "unit decal z");
        check(std::abs(glm::dot(L.decalAxisX, L.decalAxisZ)) < 1e-3f, "orthogonal decal frame");
        check(L.decalHalfSize.x > 0 && L.decalHalfSize.y > 0 && L.decalHalfSize.z > 0,
              "positive decal size");
    }
    if (L.kind == LayerKind::Noise) {
        check(L.noiseFrequency > 0 && std::isfinite(L.noiseFrequency), "noise frequency");
        check(L.noiseOctaves >= 1 && L.noiseOctaves <= 12, "octaves");
        check(L.noiseExponent >= 1.0f, "exponent >= 1");
    }
    if (L.kind == LayerKind::Triplanar) {
        check(L.maps.size() == 1 || L.maps.size() == 3, "triplanar maps");
        check(L.triScale > 0 && L.triSharpness > 0, "triplanar scale/sharpness");
    }
    if (L.kind == LayerKind::Feature)
        check(L.featWidth > L.featW0 && L.feature.has_value(), "feature widths");
    if (L.kind == LayerKind::PostResolve) {
        for (const auto& c : L.children) {
            check(c.kind != LayerKind::PostResolve, "no nested groups");
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
        check(std::abs(glm::determinant(glm::mat3(m.transform))) > 0.0f, "invertible transform");
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

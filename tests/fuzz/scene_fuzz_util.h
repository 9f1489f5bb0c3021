// Shared by the scene fuzz entry points (fuzz_scene_files.cpp,
// fuzz_scene_feature_maps.cpp): a per-process scratch folder for the files a
// scene references, the bounds the harness puts on what a scene may ask for
// (so each input runs in milliseconds; the limits themselves are the
// scene parser's and are tested there), and the render whose pixels must
// be finite.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "surfgrad/render.h"

namespace sgfuzz {

// <temp>/surfgrad_fuzz_<what>_<pid>, emptied on each call and removed when
// the process exits (the replay ctests run each target once per input
// folder and would otherwise leave one folder per run behind).
inline std::filesystem::path scratchDir(const std::string& what) {
    namespace fs = std::filesystem;
    struct RemovedAtExit {
        fs::path dir;
        ~RemovedAtExit() {
            std::error_code ec;
            fs::remove_all(dir, ec);
        }
    };
    static RemovedAtExit owned{fs::temp_directory_path() /
                               ("surfgrad_fuzz_" + what + "_" + std::to_string(::getpid()))};
    std::error_code ec;
    fs::remove_all(owned.dir, ec);
    fs::create_directories(owned.dir);
    return owned.dir;
}

// Keeps a parsed scene cheap: subdivision level <= 1, procedural meshes of
// at most 12 segments, procedural textures and baked feature maps of at
// most 32 texels per side.
inline void boundCost(sg::render::Scene& s) {
    for (auto& m : s.meshes) {
        m.subdivLevel = std::min(m.subdivLevel, 1);
        if (m.procedural) m.procedural->segments = std::min(m.procedural->segments, 12);
    }
    auto boundLayer = [](auto& self, sg::render::Layer& L) -> void {
        for (auto& t : L.maps) t.size = std::min(t.size, 32);
        for (auto& md : L.modifiers)
            if (md.mask) md.mask->size = std::min(md.mask->size, 32);
        if (L.is("feature")) {
            auto& source = L.params<sg::render::FeatureParams>().source;
            if (source) source->size = std::min(source->size, 32);
        }
        for (auto& c : L.children) self(self, c);
    };
    for (auto& mat : s.materials) {
        if (mat.baseColorMap) mat.baseColorMap->size = std::min(mat.baseColorMap->size, 32);
        for (auto& L : mat.layers) boundLayer(boundLayer, L);
    }
}

// Loads the scene's assets (InputError for bad files is the caller's to
// catch), applies the morph weights of time 0.37 and renders a small image
// on the CPU reference renderer: every pixel must be finite.
inline void renderAndCheck(const sg::render::Scene& s, sg::render::Aov aov, int w, int h) {
    using namespace sg::render;
    SceneAssets assets = loadAssets(s);
    applyFrame(s, assets, 0.37f);
    const View v = makeView(s, assets, w, h, aov);
    const Image img = renderCpu(s, assets, v);
    for (float sample : img.samples) {
        if (!std::isfinite(sample)) {
            std::fprintf(stderr, "fuzz: non-finite pixel in an accepted scene\n");
            std::abort();
        }
    }
}

} // namespace sgfuzz

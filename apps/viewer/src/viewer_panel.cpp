// The viewer panel's layout and labels (surfgrad/viewer.h): pure functions
// the viewer calls each frame and the tests call without a window.
#include <algorithm>
#include <cstdio>

#include "surfgrad/mesh/polygon_mesh.h"
#include "surfgrad/viewer.h"

namespace sg::render {

float viewerPanelWidth(int windowWidth) {
    const float w = float(std::max(windowWidth, 1));
    return std::min(std::clamp(0.3f * w, 200.0f, 300.0f), w);
}

std::string morphTargetLabel(const sg::mesh::RenderMesh& mesh, size_t t) {
    if (t < mesh.morphTargets.size() && !mesh.morphTargets[t].name.empty())
        return mesh.morphTargets[t].name;
    return "target " + std::to_string(t);
}

size_t morphTargetCount(const MeshAsset& asset) {
    return asset.morphCage ? asset.morphCage->morphTargets.size() : asset.mesh.morphTargets.size();
}

std::string morphTargetLabel(const MeshAsset& asset, size_t t) {
    if (!asset.morphCage) return morphTargetLabel(asset.mesh, t);
    const auto& targets = asset.morphCage->morphTargets;
    if (t < targets.size() && !targets[t].name.empty()) return targets[t].name;
    return "target " + std::to_string(t);
}

std::string viewerTimingText(double frameMs, const RenderStats& stats) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "frame %.1f ms | draw %.1f ms wall | ", frameMs,
                  stats.drawWallMs);
    std::string s = buf;
    if (stats.gpuMeasured) {
        std::snprintf(buf, sizeof buf, "GPU (timer query) %.2f ms", stats.gpuMs);
        s += buf;
    } else {
        s += "GPU (timer query) not measured";
    }
    return s + " | " + std::to_string(stats.drawCalls) + " draws";
}

} // namespace sg::render

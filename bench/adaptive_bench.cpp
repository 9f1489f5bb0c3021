// Adaptive patches (GPU tessellation) against the uniform CPU path on the
// spot cage, through the renderer at 960x540 on the example's view: load
// (CPU) time, triangles drawn, GPU buffer bytes, draw wall time (median of
// interleaved frames) and its ratio to uniform level 3 measured in the same
// run. On llvmpipe the tessellation stages run on the CPU: only the ratios
// mean anything. Not measured here: the screen-space distance to the exact
// limit surface (the adaptive levels target pixels_per_edge pixels per
// segment; the uniform levels do not follow the screen).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "render_internal.h"
#include "surfgrad/adaptive_patches.h"
#include "surfgrad/gl.h"
#include "surfgrad/patch_basis.h"
#include "surfgrad/render.h"

namespace {

using namespace sg::render;

struct Case {
    const char* name;
    std::string subdivision;
};

std::string scene(const std::string& subdivision) {
    return R"({"output": {"width": 960, "height": 540},
      "camera": {"azimuth_deg": 105, "elevation_deg": 14, "distance_scale": 0.72, "fov_deg": 32},
      "materials": [{"name": "m"}],
      "meshes": [{"file": "data:meshes/spot/spot_control_mesh.obj", "subdivision": )" +
           subdivision + "}]}";
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

} // namespace

int main() {
    sg::gl::HeadlessContext ctx;
    const std::vector<Case> cases = {
        {"uniform level 2 (limit)", R"({"level": 2, "limit": true})"},
        {"uniform level 3 (limit)", R"({"level": 3, "limit": true})"},
        {"uniform level 4 (limit)", R"({"level": 4, "limit": true})"},
        {"adaptive 8 px/edge", R"({"mode": "adaptive", "pixels_per_edge": 8})"},
        {"adaptive 4 px/edge", R"({"mode": "adaptive", "pixels_per_edge": 4})"},
        {"adaptive 2 px/edge", R"({"mode": "adaptive", "pixels_per_edge": 2})"},
    };
    struct Row {
        Scene scene;
        SceneAssets assets;
        double loadMs = 0.0;
        size_t triangles = 0, gpuBytes = 0;
        std::vector<double> drawMs;
    };
    std::vector<Row> rows;
    for (const Case& c : cases) {
        Row r;
        r.scene = parseScene(scene(c.subdivision), "adaptive_bench.json", ".");
        std::vector<double> loads; // median of 3 (the first also reads the file)
        for (int k = 0; k < 3; ++k) {
            const auto t0 = std::chrono::steady_clock::now();
            r.assets = loadAssets(r.scene);
            loads.push_back(
                std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0)
                    .count());
        }
        r.loadMs = median(loads);
        rows.push_back(std::move(r));
    }
    std::vector<GlRenderer> renderers(rows.size());
    const View view = makeView(rows[1].scene, rows[1].assets); // one view for all
    for (size_t i = 0; i < rows.size(); ++i) {
        Row& r = rows[i];
        const MeshAsset& a = r.assets.meshes[0];
        if (a.patches) {
            const auto& ap = *a.patches;
            const float focalPx = sg::glsl::sgPatchFocalPx(view.proj[1][1], float(view.height));
            r.triangles =
                detail::tessellatePatches(
                    ap, modelToCameraRelative(r.scene.meshes[0].transform, view.cameraPos), focalPx,
                    r.scene.meshes[0].subdivPixelsPerEdge)
                    .mesh.triangleCount();
            // Points (xyz), control-point indices, 16-word patch records.
            r.gpuBytes = ap.points.size() * 12 + ap.indices.size() * 4 + ap.patchCount() * 64;
        } else {
            r.triangles = a.mesh.triangleCount();
            // Positions, normals, UV sets, 32-bit indices.
            r.gpuBytes =
                a.mesh.vertexCount() * (24 + 8 * a.mesh.uvSets.size()) + a.mesh.indices.size() * 4;
        }
        renderers[i].render(r.scene, r.assets, view); // compile, upload
    }
    const int frames = 7;
    for (int f = 0; f < frames; ++f) {
        for (size_t i = 0; i < rows.size(); ++i) {
            renderers[i].render(rows[i].scene, rows[i].assets, view);
            rows[i].drawMs.push_back(renderers[i].stats().drawWallMs);
        }
    }
    const double base = median(rows[1].drawMs);
    std::printf("Adaptive patches vs uniform refinement, spot cage, 960x540, llvmpipe, median of "
                "%d interleaved frames\n\n",
                frames);
    std::printf("| mesh | load (CPU) ms | triangles drawn | GPU buffer KiB | draw ms | ratio to "
                "uniform level 3 |\n|---|---|---|---|---|---|\n");
    for (size_t i = 0; i < rows.size(); ++i) {
        const double ms = median(rows[i].drawMs);
        std::printf("| %s | %.1f | %zu | %.0f | %.1f | %.2fx |\n", cases[i].name, rows[i].loadMs,
                    rows[i].triangles, double(rows[i].gpuBytes) / 1024.0, ms, ms / base);
    }
    return 0;
}

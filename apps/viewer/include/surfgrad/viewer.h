// The interactive viewer (`surfgrad view`): a GLFW window with an OpenGL
// 4.5 core context, the same GlRenderer as the CLI, and a Dear ImGui panel:
// orbit camera (left drag: rotate, right drag or wheel: zoom, middle drag:
// pan), per-layer toggles and strengths (toggling recompiles through the
// program cache: effects on demand), AOV views, double-sided mode per
// material, blendshape weight sliders named by their targets (an adaptive
// mesh's cage targets too: the cage moves, the GPU recomputes the patch
// points) and animation playback, the adaptive meshes' pixels per edge, draw wall time and GPU time
// (GL_TIME_ELAPSED, where it measures the draws), and screenshots. The panel is docked narrow at
// the right edge and collapses to its title bar; `panel = false` hides it.
//
// Needs an X display (GLFW 3.3 has no headless platform); tests run it
// under `xvfb-run -a -s "-screen 0 1280x1024x24"`.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "surfgrad/render.h"

namespace sg::render {

struct ViewerOptions {
    int width = 1280, height = 720;   // window size
    int maxFrames = 0;                // quit after this many frames (0: run until closed)
    std::filesystem::path screenshot; // PNG written from the last frame on exit (empty: none)
    bool panel = true; // false: no panel (the window, and a screenshot, show the render alone)
    std::string title = "surfgrad view";
    uint64_t textureBudgetBytes = 0; // AssetOptions::textureBudgetBytes (0: the default)
};

// Runs the viewer until the window closes (or maxFrames). Returns the
// process exit status. Throws sg::gl::GlError when no window or GL 4.5 core
// context can be created, sg::io::InputError for bad scene assets.
int runViewer(Scene scene, const ViewerOptions& options);

// The panel's layout and labels (no window needed; viewer_panel.cpp).
// Width in pixels of the panel docked at the window's right edge: 30% of
// the window, at least 200 and at most 300 px, never wider than the window.
float viewerPanelWidth(int windowWidth);
// Slider label of morph target `t` of `mesh`: the target's name (glTF
// mesh.extras.targetNames) when it has one, else "target t".
std::string morphTargetLabel(const sg::mesh::RenderMesh& mesh, size_t t);
// The morph targets the panel shows sliders for, of a loaded mesh: the
// render mesh's, or for an adaptive mesh whose cage has morph targets
// (MeshAsset::morphCage) the cage's (the weights move the cage; the patch
// points follow on the GPU). Labels as above, from whichever holds them.
size_t morphTargetCount(const MeshAsset& asset);
std::string morphTargetLabel(const MeshAsset& asset, size_t t);
// The panel's timing line: frame time, the draws' wall time and the GPU
// draw time of the timer query only when it measured the frame
// (RenderStats::gpuMeasured), e.g. "frame 16.7 ms | draw 3.2 ms wall |
// GPU (timer query) not measured | 2 draws".
std::string viewerTimingText(double frameMs, const RenderStats& stats);

} // namespace sg::render

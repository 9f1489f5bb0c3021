// The interactive viewer (`surfgrad view`): a GLFW window with an OpenGL
// 4.5 core context, the same GlRenderer as the CLI, and a Dear ImGui panel:
// orbit camera (left drag: rotate, right drag or wheel: zoom, middle drag:
// pan), per-layer toggles and strengths (toggling recompiles through the
// program cache: effects on demand), AOV views, double-sided mode per
// material, blendshape weight sliders and animation playback, GPU time
// from GL_TIME_ELAPSED queries, and screenshots.
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
    std::string title = "surfgrad view";
    uint64_t textureBudgetBytes = 0; // AssetOptions::textureBudgetBytes (0: the default)
};

// Runs the viewer until the window closes (or maxFrames). Returns the
// process exit status. Throws sg::gl::GlError when no window or GL 4.5 core
// context can be created, sg::io::InputError for bad scene assets.
int runViewer(Scene scene, const ViewerOptions& options);

} // namespace sg::render

// The two renderers: the OpenGL 4.5 renderer and the CPU reference
// renderer, which run the same shared layer functions
// (shaders/sg/render/*.glsl; the CPU through surfgrad/render/render_shaders.h) in
// the same order.
//
// Contract: a validated Scene, its SceneAssets and a View of at least 1x1
// pixels. The GL renderer needs a current GL 4.5 core context on the
// calling thread (GL failures throw sg::gl::GlError). Images are bottom row
// first, one AOV (View::aov).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "surfgrad/render/glsl_texture.h"
#include "surfgrad/render/assets.h"
#include "surfgrad/render/image.h"
#include "surfgrad/render/scene.h"
#include "surfgrad/shaders/shader_files.h"
#include "surfgrad/render/view.h"

namespace sg::render {

struct RenderStats {
    // Times of the last renderToTexture/render call's draws (first draw to
    // the end of the last; the clear, uploads and program compiles before
    // them are not included, nor is render()'s read-back).
    //   gpuMs      - GPU draw time from the GL_TIME_ELAPSED query that
    //                bracketed this frame's draws (result waited for); valid
    //                only when gpuMeasured: the driver has a timer that
    //                covers its rasterisation (not llvmpipe/softpipe, which
    //                rasterise outside the query; docs/platform.md).
    //   drawWallMs - wall-clock time of the same span, ended by glFinish
    //                (CPU submission plus the GPU finishing the draws).
    double gpuMs = 0.0;
    bool gpuMeasured = false;
    double drawWallMs = 0.0;
    int programsCompiled = 0; // programs compiled by this call (cache misses)
    int drawCalls = 0;
    // Mesh data of this call, before the draws: bytes uploaded to vertex
    // and patch buffers (0 when nothing moved; an animated adaptive cage:
    // cagePointCount x 12, the cage only), and the wall time from the start
    // of those uploads to the idle GPU before the draws (uploads, the
    // cage's stencil compute stage; a call that compiles programs or
    // uploads textures includes those too).
    uint64_t meshUploadBytes = 0;
    double meshUpdateWallMs = 0.0;
};

// The OpenGL 4.5 renderer. Needs a current GL 4.5 core context (from
// sg::gl::HeadlessContext or a GLFW window); all calls on that thread.
// Programs are cached by effect signature; meshes and textures are uploaded
// once per SceneAssets and re-uploaded when applyFrame changed positions.
class GlRenderer {
public:
    GlRenderer();
    ~GlRenderer();
    GlRenderer(const GlRenderer&) = delete;
    GlRenderer& operator=(const GlRenderer&) = delete;

    // Renders into an internal RGBA32F framebuffer of the view's size and
    // reads it back.
    Image render(const Scene& scene, const SceneAssets& assets, const View& view);
    // Renders into the internal framebuffer without reading back (viewer,
    // benchmarks); returns its GL texture name.
    unsigned renderToTexture(const Scene& scene, const SceneAssets& assets, const View& view);
    // While set, every material renders through its uber-shader plan
    // (planUberMaterial; the bench baseline).
    void setUber(bool uber) { uber_ = uber; }
    // `#define` lines ("NAME" or "NAME VALUE") put after the #version line
    // of every fragment program compiled from now on (part of the program
    // cache key): compile-time variants of the shared code that studies
    // switch on, e.g. SG_AA_COV_UNMAPPED (sg/render/antialias.glsl). The
    // CPU reference renderer has none of them. Empty by default.
    void setFragmentDefines(const std::vector<std::string>& defines);
    // The GLSL dialect programs compiled from now on are written in
    // (sg::shaders::inDialect; part of the program cache key): GLSL 4.50 by
    // default, or GLSL 3.30 / ES 3.00, which an OpenGL 4.5 context compiles
    // too. Tests render the same scene in each to check the legacy paths of
    // the shared source (docs/engines.md). Contract: a GLSL dialect; plans
    // with adaptive patches need 4.50 (tessellation stages).
    void setDialect(sg::shaders::Target dialect);
    // Meshes are re-uploaded when SceneAssets::uid or meshVersion changes
    // (applyFrame bumps it); this forces it otherwise.
    void invalidateMeshes();
    const RenderStats& stats() const { return stats_; }
    size_t cachedPrograms() const;
    // Progress of long renders: images of at least 2048^2 pixels are drawn
    // in bands of 512 rows, each finished (glFinish) and then reported as
    // progress(bandsDone, bandCount) on the calling thread. Empty: one pass.
    void setProgress(std::function<void(int done, int total)> progress) {
        progress_ = std::move(progress);
    }

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    RenderStats stats_;
    bool uber_ = false;
    std::function<void(int, int)> progress_;
};

// The CPU reference renderer: rasterises the same triangles (GL coverage
// at pixel centres, near-plane clipping, depth test), interpolates the same
// attributes perspective-correctly, computes screen-space derivatives
// ANALYTICALLY (exact derivatives of the perspective-correct interpolants;
// the GPU uses 2x2-quad differences, dFdxFine) and runs the same shared
// layer functions in the same order as the assembled GLSL program.
//   CpuDerivatives::Analytic - the reference: exact derivatives;
//   CpuDerivatives::Quad     - emulates dFdxFine/dFdyFine (differences
//                              across the pixel's 2x2 quad), so a comparison
//                              with the GPU isolates the driver's arithmetic
//                              (texture LOD, filtering, float rounding).
enum class CpuDerivatives { Analytic, Quad };
struct CpuOptions {
    CpuDerivatives derivatives = CpuDerivatives::Analytic;
    // Texture LOD: the GL specification's log2 (reference), or llvmpipe's
    // piecewise-linear approximation (sg::glsl::LodRule::FastLog2), or
    // level 0 always (LodRule::Level0: no filtering, for supersampled truths).
    sg::glsl::LodRule textureLod = sg::glsl::LodRule::Exact;
    // Progress: progress(rowsDone, rowCount) after every 1/16 of the rows
    // (and at the end); called from the worker threads, one call at a time.
    std::function<void(int done, int total)> progress;
};
Image renderCpu(const Scene& scene, const SceneAssets& assets, const View& view,
                const CpuOptions& options = {});

} // namespace sg::render

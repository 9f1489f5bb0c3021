// surfgrad GL layer: a headless OpenGL 4.5 core, OpenGL 3.3 core or OpenGL
// ES 3.0 context (EGL surfaceless, Mesa llvmpipe on machines without a GPU),
// program compilation with messages mapped back to shader files, and two
// harnesses that run any shared shader function over a buffer of inputs: a
// compute one (GL 4.5) and a transform-feedback one (GL 3.3 and ES 3.0,
// which have no compute stage). Used by the CPU/GPU parity tests, `surfgrad
// selftest` and `surfgrad eval --gpu`.
//
// Threading: a context is current on the thread that created it; all other
// calls must be made on that thread. Errors (no EGL, no GL 4.5, compile or
// link failures) throw sg::gl::GlError with a message saying what failed.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "surfgrad/shaders/shader_files.h"

namespace sg::gl {

struct GlError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The API and version of a context, matching the shader dialects of
// sg::shaders::Target: Gl45Core runs Glsl450 programs, Gl33Core Glsl330,
// Es30 Es300 (an implementation may give a later ES 3.x; ES 3.00 shaders
// run on all of them).
enum class Api { Gl45Core, Gl33Core, Es30 };
// The API whose shading language is `target` (Hlsl: Gl45Core, which runs
// the GLSL 4.50 translation of an HLSL program), and the reverse.
Api apiFor(shaders::Target target);
shaders::Target targetFor(Api api);
// "OpenGL 4.5 core", "OpenGL 3.3 core", "OpenGL ES 3.0".
const char* apiName(Api api);

// A context without any window or X server:
// eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA), eglMakeCurrent with
// no surface; render into FBOs. Made current on construction.
class HeadlessContext {
public:
    explicit HeadlessContext(Api api = Api::Gl45Core);
    ~HeadlessContext();
    HeadlessContext(const HeadlessContext&) = delete;
    HeadlessContext& operator=(const HeadlessContext&) = delete;

    void makeCurrent();
    // GL_RENDERER and GL_VERSION strings, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string renderer() const;
    std::string version() const;
    Api api() const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

// Shader stage of one source in a program.
enum class Stage { Vertex, Fragment, Compute, Geometry, TessControl, TessEvaluation };

// A linked program object (RAII). Source text comes from
// sg::shaders::assemble so #line numbers map to files in messages.
class Program {
public:
    Program() = default;
    // `feedback`: output variables captured by transform feedback, in this
    // order, interleaved into one buffer (set before linking).
    explicit Program(const std::vector<std::pair<Stage, shaders::Assembled>>& stages,
                     const std::vector<std::string>& feedback = {});
    ~Program();
    Program(Program&& o) noexcept;
    Program& operator=(Program&& o) noexcept;
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    unsigned id() const { return id_; }
    int uniform(const char* name) const; // -1 when not active

private:
    unsigned id_ = 0;
};

// Runs a compute program over `count` records. Each record has `inStride`
// floats in `input` (SSBO binding 0) and produces `outStride` floats
// (SSBO binding 1). The program must declare local_size_x = kComputeGroupSize
// and read the record count from uniform uint uCount. Returns count *
// outStride floats. Large inputs are split into dispatches that fit the
// implementation's limits.
inline constexpr int kComputeGroupSize = 64;
std::vector<float> runCompute(const Program& program, const std::vector<float>& input, int inStride,
                              int outStride, size_t count);

// The same for contexts without compute shaders (GL 3.3, ES 3.0), through
// transform feedback: one point per record, rasterizer discarded. The
// program's vertex stage reads record floats 4k..4k+3 from
// `layout(location = k) in vec4` (k < ceil(inStride / 4); the missing floats
// of a last partial vec4 read as the GL defaults 0, 0, 0, 1) and writes
// output floats 4k..4k+3 to the k-th of its feedback variables, each a
// vec4 (ceil(outStride / 4) of them; floats past outStride are dropped).
// Uses only calls of GL 3.3 core and ES 3.0.
std::vector<float> runTransformFeedback(const Program& program, const std::vector<float>& input,
                                        int inStride, int outStride, size_t count);
// A program for runTransformFeedback: the assembled vertex stage `vertex`
// (of dialect `target`), the empty fragment stage a GLSL ES program must
// have, and `feedback`, the captured outputs in record order.
Program feedbackProgram(const shaders::Assembled& vertex, shaders::Target target,
                        const std::vector<std::string>& feedback);

// Throws GlError naming `what` if glGetError reports an error.
void checkError(const char* what);

} // namespace sg::gl

// Headless EGL context, program compilation and the compute harness.
// EGL surfaceless on Mesa: see docs/platform.md ("Headless OpenGL").
#include "surfgrad/gl/context.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstring>

namespace sg::gl {

namespace {
const char* eglErrorName(EGLint e) {
    switch (e) {
    case EGL_SUCCESS:
        return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
        return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
        return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
        return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
        return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
        return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
        return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
        return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
        return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
        return "EGL_BAD_PARAMETER";
    default:
        return "EGL error";
    }
}
[[noreturn]] void eglFail(const std::string& what) {
    throw GlError("headless OpenGL: " + what + " failed (" + eglErrorName(eglGetError()) +
                  "); is Mesa's EGL installed (libegl-mesa0, libgl1-mesa-dri)?");
}
} // namespace

Api apiFor(shaders::Target target) {
    switch (target) {
    case shaders::Target::Glsl450:
        return Api::Gl45Core;
    case shaders::Target::Glsl330:
        return Api::Gl33Core;
    case shaders::Target::Es300:
        return Api::Es30;
    case shaders::Target::Hlsl: // runs as its GLSL 4.50 translation
        return Api::Gl45Core;
    }
    return Api::Gl45Core;
}

shaders::Target targetFor(Api api) {
    switch (api) {
    case Api::Gl45Core:
        return shaders::Target::Glsl450;
    case Api::Gl33Core:
        return shaders::Target::Glsl330;
    case Api::Es30:
        return shaders::Target::Es300;
    }
    return shaders::Target::Glsl450;
}

const char* apiName(Api api) {
    switch (api) {
    case Api::Gl45Core:
        return "OpenGL 4.5 core";
    case Api::Gl33Core:
        return "OpenGL 3.3 core";
    case Api::Es30:
        return "OpenGL ES 3.0";
    }
    return "?";
}

struct HeadlessContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
    Api api = Api::Gl45Core;
};

HeadlessContext::HeadlessContext(Api api) : impl_(std::make_unique<Impl>()) {
    impl_->api = api;
    const bool es = api == Api::Es30;
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless") &&
        !epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_base")) {
        throw GlError("headless OpenGL: EGL has no surfaceless platform "
                      "(EGL_MESA_platform_surfaceless); install libegl-mesa0");
    }
    impl_->display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (impl_->display == EGL_NO_DISPLAY) eglFail("eglGetPlatformDisplayEXT(surfaceless)");
    EGLint major = 0, minor = 0;
    if (!eglInitialize(impl_->display, &major, &minor)) eglFail("eglInitialize");
    if (!eglBindAPI(es ? EGL_OPENGL_ES_API : EGL_OPENGL_API)) {
        eglFail(es ? "eglBindAPI(EGL_OPENGL_ES_API)" : "eglBindAPI(EGL_OPENGL_API)");
    }

    const EGLint cfgAttribs[] = {EGL_RENDERABLE_TYPE, es ? EGL_OPENGL_ES3_BIT : EGL_OPENGL_BIT,
                                 EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint numConfigs = 0;
    if (!eglChooseConfig(impl_->display, cfgAttribs, &config, 1, &numConfigs) || numConfigs < 1) {
        config = nullptr; // EGL_KHR_no_config_context
    }
    const EGLint glAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                api == Api::Gl45Core ? 4 : 3,
                                EGL_CONTEXT_MINOR_VERSION,
                                api == Api::Gl45Core ? 5 : 3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                EGL_NONE};
    const EGLint esAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0,
                                EGL_NONE};
    impl_->context =
        eglCreateContext(impl_->display, config, EGL_NO_CONTEXT, es ? esAttribs : glAttribs);
    if (impl_->context == EGL_NO_CONTEXT) {
        eglFail(std::string("eglCreateContext(") + apiName(api) + ")");
    }
    makeCurrent();
}

HeadlessContext::~HeadlessContext() {
    if (impl_->display != EGL_NO_DISPLAY) {
        eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (impl_->context != EGL_NO_CONTEXT) eglDestroyContext(impl_->display, impl_->context);
        eglTerminate(impl_->display);
    }
}

void HeadlessContext::makeCurrent() {
    if (!eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context)) {
        eglFail("eglMakeCurrent(no surface)");
    }
}

std::string HeadlessContext::renderer() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    return s ? s : "";
}
std::string HeadlessContext::version() const {
    const auto* s = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    return s ? s : "";
}
Api HeadlessContext::api() const {
    return impl_->api;
}

void checkError(const char* what) {
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "0x%04x", unsigned(e));
        throw GlError(std::string("OpenGL error ") + buf + " in " + what);
    }
}

namespace {
GLenum stageEnum(Stage s) {
    switch (s) {
    case Stage::Vertex:
        return GL_VERTEX_SHADER;
    case Stage::Fragment:
        return GL_FRAGMENT_SHADER;
    case Stage::Compute:
        return GL_COMPUTE_SHADER;
    case Stage::Geometry:
        return GL_GEOMETRY_SHADER;
    case Stage::TessControl:
        return GL_TESS_CONTROL_SHADER;
    case Stage::TessEvaluation:
        return GL_TESS_EVALUATION_SHADER;
    }
    return GL_VERTEX_SHADER;
}
const char* stageName(Stage s) {
    switch (s) {
    case Stage::Vertex:
        return "vertex";
    case Stage::Fragment:
        return "fragment";
    case Stage::Compute:
        return "compute";
    case Stage::Geometry:
        return "geometry";
    case Stage::TessControl:
        return "tessellation control";
    case Stage::TessEvaluation:
        return "tessellation evaluation";
    }
    return "?";
}
} // namespace

Program::Program(const std::vector<std::pair<Stage, shaders::Assembled>>& stages,
                 const std::vector<std::string>& feedback) {
    id_ = glCreateProgram();
    std::vector<GLuint> shaderIds;
    auto cleanup = [&] {
        for (GLuint s : shaderIds) glDeleteShader(s);
    };
    for (const auto& [stage, src] : stages) {
        GLuint sh = glCreateShader(stageEnum(stage));
        shaderIds.push_back(sh);
        const char* text = src.text.c_str();
        glShaderSource(sh, 1, &text, nullptr);
        glCompileShader(sh);
        GLint ok = 0;
        glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint len = 0;
            glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &len);
            std::string log(size_t(std::max(len, 1)), '\0');
            glGetShaderInfoLog(sh, len, nullptr, log.data());
            cleanup();
            glDeleteProgram(id_);
            id_ = 0;
            throw GlError(std::string(stageName(stage)) + " shader (" +
                          (src.files.empty() ? "?" : src.files.front()) + ") failed to compile:\n" +
                          shaders::annotateLog(log, src.files));
        }
        glAttachShader(id_, sh);
    }
    if (!feedback.empty()) {
        std::vector<const char*> names;
        for (const auto& f : feedback) names.push_back(f.c_str());
        glTransformFeedbackVaryings(id_, GLsizei(names.size()), names.data(),
                                    GL_INTERLEAVED_ATTRIBS);
    }
    glLinkProgram(id_);
    cleanup();
    GLint ok = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &len);
        std::string log(size_t(std::max(len, 1)), '\0');
        glGetProgramInfoLog(id_, len, nullptr, log.data());
        glDeleteProgram(id_);
        id_ = 0;
        throw GlError("program failed to link:\n" + log);
    }
}

Program::~Program() {
    if (id_) glDeleteProgram(id_);
}
Program::Program(Program&& o) noexcept : id_(o.id_) {
    o.id_ = 0;
}
Program& Program::operator=(Program&& o) noexcept {
    if (this != &o) {
        if (id_) glDeleteProgram(id_);
        id_ = o.id_;
        o.id_ = 0;
    }
    return *this;
}
int Program::uniform(const char* name) const {
    return glGetUniformLocation(id_, name);
}

std::vector<float> runCompute(const Program& program, const std::vector<float>& input, int inStride,
                              int outStride, size_t count) {
    if (inStride <= 0 || outStride <= 0) throw GlError("runCompute: strides must be positive");
    if (input.size() < count * size_t(inStride)) {
        throw GlError("runCompute: input holds fewer than count * inStride floats");
    }
    std::vector<float> output(count * size_t(outStride));
    if (count == 0) return output;

    GLint maxGroups = 65535;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &maxGroups);
    GLint maxSsbo = 1 << 27;
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &maxSsbo);
    // Records per dispatch: bounded by the group-count limit and by the
    // largest SSBO binding the implementation allows.
    size_t perDispatch = size_t(maxGroups) * kComputeGroupSize;
    perDispatch = std::min(
        perDispatch, size_t(maxSsbo) / (sizeof(float) * size_t(std::max(inStride, outStride))));
    perDispatch = std::max<size_t>(perDispatch / kComputeGroupSize, 1) * kComputeGroupSize;

    GLuint bufs[2];
    glCreateBuffers(2, bufs);
    glUseProgram(program.id());
    const int countLoc = program.uniform("uCount");
    for (size_t first = 0; first < count; first += perDispatch) {
        const size_t n = std::min(perDispatch, count - first);
        glNamedBufferData(bufs[0], GLsizeiptr(n * size_t(inStride) * sizeof(float)),
                          input.data() + first * size_t(inStride), GL_STATIC_DRAW);
        glNamedBufferData(bufs[1], GLsizeiptr(n * size_t(outStride) * sizeof(float)), nullptr,
                          GL_DYNAMIC_READ);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, bufs[0]);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, bufs[1]);
        if (countLoc >= 0) glUniform1ui(countLoc, GLuint(n));
        glDispatchCompute(GLuint((n + kComputeGroupSize - 1) / kComputeGroupSize), 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(bufs[1], 0, GLsizeiptr(n * size_t(outStride) * sizeof(float)),
                                output.data() + first * size_t(outStride));
    }
    glDeleteBuffers(2, bufs);
    glUseProgram(0);
    checkError("runCompute");
    return output;
}

std::vector<float> runTransformFeedback(const Program& program, const std::vector<float>& input,
                                        int inStride, int outStride, size_t count) {
    if (inStride <= 0 || outStride <= 0) {
        throw GlError("runTransformFeedback: strides must be positive");
    }
    if (input.size() < count * size_t(inStride)) {
        throw GlError("runTransformFeedback: input holds fewer than count * inStride floats");
    }
    std::vector<float> output(count * size_t(outStride));
    if (count == 0) return output;
    const int inVec4 = (inStride + 3) / 4, outVec4 = (outStride + 3) / 4;
    GLint maxAttribs = 16;
    glGetIntegerv(GL_MAX_VERTEX_ATTRIBS, &maxAttribs);
    if (inVec4 > maxAttribs) {
        throw GlError("runTransformFeedback: " + std::to_string(inVec4) +
                      " vec4 inputs exceed GL_MAX_VERTEX_ATTRIBS (" + std::to_string(maxAttribs) +
                      ")");
    }
    // Records per draw: bounds the two buffers to a few tens of MB.
    const size_t perDraw = size_t(1) << 18;
    const size_t outRecordBytes = size_t(outVec4) * 4 * sizeof(float);

    // A surfaceless context has no default framebuffer, and a draw needs a
    // complete one even with the rasterizer discarded: a 1x1 colour target.
    GLuint fbo = 0, rbo = 0;
    glGenRenderbuffers(1, &rbo);
    glBindRenderbuffer(GL_RENDERBUFFER, rbo);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, 1, 1);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rbo);
    GLuint vao = 0, bufs[2] = {0, 0};
    glGenVertexArrays(1, &vao);
    glGenBuffers(2, bufs);
    glBindVertexArray(vao);
    glBindBuffer(GL_ARRAY_BUFFER, bufs[0]);
    for (int k = 0; k < inVec4; ++k) {
        glEnableVertexAttribArray(GLuint(k));
        glVertexAttribPointer(GLuint(k), std::min(4, inStride - 4 * k), GL_FLOAT, GL_FALSE,
                              GLsizei(size_t(inStride) * sizeof(float)),
                              reinterpret_cast<const void*>(size_t(k) * 4 * sizeof(float)));
    }
    glUseProgram(program.id());
    glEnable(GL_RASTERIZER_DISCARD);
    // Restores the state and frees the objects, on return and on error.
    auto release = [&] {
        glDisable(GL_RASTERIZER_DISCARD);
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, 0);
        glBindVertexArray(0);
        glDeleteBuffers(2, bufs);
        glDeleteVertexArrays(1, &vao);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(1, &rbo);
        glUseProgram(0);
    };
    for (size_t first = 0; first < count; first += perDraw) {
        const size_t n = std::min(perDraw, count - first);
        glBindBuffer(GL_ARRAY_BUFFER, bufs[0]);
        glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(n * size_t(inStride) * sizeof(float)),
                     input.data() + first * size_t(inStride), GL_STREAM_DRAW);
        glBindBuffer(GL_TRANSFORM_FEEDBACK_BUFFER, bufs[1]);
        glBufferData(GL_TRANSFORM_FEEDBACK_BUFFER, GLsizeiptr(n * outRecordBytes), nullptr,
                     GL_STREAM_READ);
        glBindBufferBase(GL_TRANSFORM_FEEDBACK_BUFFER, 0, bufs[1]);
        glBeginTransformFeedback(GL_POINTS);
        glDrawArrays(GL_POINTS, 0, GLsizei(n));
        glEndTransformFeedback();
        // ES 3.0 has no glGetBufferSubData: map the captured records.
        const auto* mapped = static_cast<const float*>(glMapBufferRange(
            GL_TRANSFORM_FEEDBACK_BUFFER, 0, GLsizeiptr(n * outRecordBytes), GL_MAP_READ_BIT));
        if (!mapped) {
            release();
            throw GlError("runTransformFeedback: glMapBufferRange of the feedback buffer failed");
        }
        for (size_t r = 0; r < n; ++r) {
            std::memcpy(&output[(first + r) * size_t(outStride)], mapped + r * size_t(outVec4) * 4,
                        size_t(outStride) * sizeof(float));
        }
        glUnmapBuffer(GL_TRANSFORM_FEEDBACK_BUFFER);
    }
    release();
    checkError("runTransformFeedback");
    return output;
}

Program feedbackProgram(const shaders::Assembled& vertex, shaders::Target target,
                        const std::vector<std::string>& feedback) {
    const auto fragment = shaders::assemble("out vec4 fragColor;\n"
                                            "void main() { fragColor = vec4(0.0); }\n",
                                            "feedback fragment", {}, target);
    return Program({{Stage::Vertex, vertex}, {Stage::Fragment, fragment}}, feedback);
}

} // namespace sg::gl

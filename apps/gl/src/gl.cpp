// Headless EGL context, program compilation and the compute harness.
// EGL surfaceless on Mesa: see docs/platform.md ("Headless OpenGL").
#include "surfgrad/gl.h"

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

struct HeadlessContext::Impl {
    EGLDisplay display = EGL_NO_DISPLAY;
    EGLContext context = EGL_NO_CONTEXT;
};

HeadlessContext::HeadlessContext() : impl_(std::make_unique<Impl>()) {
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
    if (!eglBindAPI(EGL_OPENGL_API)) eglFail("eglBindAPI(EGL_OPENGL_API)");

    const EGLint cfgAttribs[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE,
                                 EGL_PBUFFER_BIT, EGL_NONE};
    EGLConfig config = nullptr;
    EGLint numConfigs = 0;
    if (!eglChooseConfig(impl_->display, cfgAttribs, &config, 1, &numConfigs) || numConfigs < 1) {
        config = nullptr; // EGL_KHR_no_config_context
    }
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    impl_->context = eglCreateContext(impl_->display, config, EGL_NO_CONTEXT, ctxAttribs);
    if (impl_->context == EGL_NO_CONTEXT) eglFail("eglCreateContext(OpenGL 4.5 core)");
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

Program::Program(const std::vector<std::pair<Stage, shaders::Assembled>>& stages) {
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

} // namespace sg::gl

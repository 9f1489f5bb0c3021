// engine-integration: the smallest complete OpenGL program that uses the
// surfgrad GLSL library the way a game engine would (see README.md).
//
// It creates a headless OpenGL 4.5 context (EGL, no window, no X server),
// assembles bumped.frag (which #includes "sg/surfgrad.glsl") with
// sg::shaders::assemble, draws a UV sphere with two bump layers composed as
// surface gradients (Mikkelsen 2019: a tangent-space normal map on UV0 with
// a per-pixel basis, listings 4-6, plus a decal projector, listing 15) and
// writes a PNG. Standalone on purpose: only EGL, libepoxy (GL function
// loading), GLM and the library's shader files; copy it and replace the
// pieces your engine already has.
//
//   example_engine_integration [-o out.png] [--size WxH] [--aov color|normal]
//       [--layers uv,decal|uv|decal|none] [--derivs fine|analytic]
//       [--print-shader] [--shader-dir DIR]
//
// --aov normal writes the perturbed world normal as 0.5 n + 0.5;
// --derivs analytic replaces dFdxFine(position) by sgScreenDerivOfPos
// (listing 17); --print-shader prints the assembled fragment shader.
#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include "example_setup.h"
#include "surfgrad/shaders/shader_files.h"

#ifndef EXAMPLE_SHADER_DIR
#define EXAMPLE_SHADER_DIR "."
#endif

namespace {

using namespace example;

[[noreturn]] void fail(const std::string& msg) {
    throw std::runtime_error(msg);
}

// ---------------------------------------------------------------- EGL (headless)
// Mesa's surfaceless platform: a GL 4.5 core context with no window system;
// everything is drawn into an FBO.
void createHeadlessContext() {
    EGLDisplay dpy =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major = 0, minor = 0;
    if (dpy == EGL_NO_DISPLAY || !eglInitialize(dpy, &major, &minor))
        fail("EGL: no surfaceless display");
    if (!eglBindAPI(EGL_OPENGL_API)) fail("EGL: OpenGL API unavailable");
    const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                 4,
                                 EGL_CONTEXT_MINOR_VERSION,
                                 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                 EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    // EGL_KHR_no_config_context: no surface, so no config is needed.
    EGLContext ctx = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctxAttribs);
    if (ctx == EGL_NO_CONTEXT) fail("EGL: cannot create an OpenGL 4.5 core context");
    if (!eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx))
        fail("EGL: eglMakeCurrent failed");
}

// ---------------------------------------------------------------- shaders
std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read " + path);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

GLuint compile(GLenum stage, const sg::shaders::Assembled& src) {
    GLuint sh = glCreateShader(stage);
    const char* text = src.text.c_str();
    glShaderSource(sh, 1, &text, nullptr);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[8192];
        glGetShaderInfoLog(sh, sizeof log, nullptr, log);
        // #line directives let the log name the real files.
        fail("shader compile error:\n" + sg::shaders::annotateLog(log, src.files));
    }
    return sh;
}

// ---------------------------------------------------------------- geometry and maps
struct Vertex {
    glm::vec3 position, normal;
    glm::vec2 uv0;
};

void buildSphere(std::vector<Vertex>& verts, std::vector<uint32_t>& indices) {
    for (int j = 0; j <= kSegmentsT; ++j) {
        for (int i = 0; i <= kSegmentsS; ++i) {
            glm::vec2 st(float(i) / kSegmentsS, float(j) / kSegmentsT);
            glm::vec3 p = spherePoint(st.x, st.y);
            verts.push_back({p, p, st}); // unit sphere: the normal is the position
        }
    }
    const uint32_t row = kSegmentsS + 1;
    for (uint32_t j = 0; j < uint32_t(kSegmentsT); ++j) {
        for (uint32_t i = 0; i < uint32_t(kSegmentsS); ++i) {
            uint32_t a = j * row + i, b = a + 1, c = a + row, d = c + 1;
            // Counter-clockwise seen from outside: (s right, t up) at the front.
            indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    }
}

// An RGB8 tangent-space normal map of `deriv` sampled at texel centres; row 0
// is the bottom row (t = 0), as glTexImage2D expects for a lower-left origin.
template <class DerivFn>
GLuint makeNormalMap(int w, int h, GLenum wrap, DerivFn deriv) {
    std::vector<uint8_t> texels(size_t(w) * size_t(h) * 3);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            glm::vec3 m = derivToNormal(deriv(glm::vec2((x + 0.5f) / w, (y + 0.5f) / h)));
            for (int c = 0; c < 3; ++c) {
                texels[(size_t(y) * size_t(w) + size_t(x)) * 3 + size_t(c)] =
                    uint8_t(std::lround((0.5f * m[c] + 0.5f) * 255.0f));
            }
        }
    }
    GLuint tex = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    int levels = 1;
    while ((std::max(w, h) >> levels) > 0) ++levels;
    glTextureStorage2D(tex, levels, GL_RGB8, w, h); // UNORM, never sRGB: these are vectors
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(tex, 0, 0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, texels.data());
    glGenerateTextureMipmap(tex);
    glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GLint(wrap));
    glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GLint(wrap));
    return tex;
}

// ---------------------------------------------------------------- PNG writer
// 8-bit RGB, zlib "stored" (uncompressed) blocks: no compression library.
uint32_t crc32(const uint8_t* p, size_t n, uint32_t c = 0xffffffffu) {
    for (size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c;
}

void writePng(const std::string& path, int w, int h, const std::vector<uint8_t>& rgbTopFirst) {
    std::vector<uint8_t> raw; // each row: filter byte 0 + RGB
    for (int y = 0; y < h; ++y) {
        raw.push_back(0);
        raw.insert(raw.end(), rgbTopFirst.begin() + ptrdiff_t(y) * w * 3,
                   rgbTopFirst.begin() + ptrdiff_t(y + 1) * w * 3);
    }
    std::vector<uint8_t> z = {0x78, 0x01};
    uint32_t a = 1, b = 0; // Adler-32
    size_t off = 0;
    do { // rows are never empty, so raw is not either
        size_t len = std::min<size_t>(65535, raw.size() - off);
        z.push_back(off + len == raw.size() ? 1 : 0); // BFINAL, BTYPE = stored
        z.insert(z.end(), {uint8_t(len), uint8_t(len >> 8), uint8_t(~len), uint8_t(~len >> 8)});
        z.insert(z.end(), raw.begin() + ptrdiff_t(off), raw.begin() + ptrdiff_t(off + len));
        off += len;
    } while (off < raw.size());
    for (uint8_t v : raw) a = (a + v) % 65521u, b = (b + a) % 65521u;
    uint32_t adler = (b << 16) | a;
    z.insert(z.end(),
             {uint8_t(adler >> 24), uint8_t(adler >> 16), uint8_t(adler >> 8), uint8_t(adler)});

    std::ofstream out(path, std::ios::binary);
    auto be32 = [&](uint32_t v) {
        uint8_t q[4] = {uint8_t(v >> 24), uint8_t(v >> 16), uint8_t(v >> 8), uint8_t(v)};
        out.write((const char*)q, 4);
    };
    auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
        be32(uint32_t(data.size()));
        std::vector<uint8_t> td(type, type + 4);
        td.insert(td.end(), data.begin(), data.end());
        out.write((const char*)td.data(), std::streamsize(td.size()));
        be32(crc32(td.data(), td.size()) ^ 0xffffffffu);
    };
    out.write("\x89PNG\r\n\x1a\n", 8);
    chunk("IHDR", {uint8_t(w >> 24), uint8_t(w >> 16), uint8_t(w >> 8), uint8_t(w),
                   uint8_t(h >> 24), uint8_t(h >> 16), uint8_t(h >> 8), uint8_t(h), 8, 2, 0, 0, 0});
    chunk("IDAT", z);
    chunk("IEND", {});
    if (!out) fail("cannot write " + path);
}

float linearToSrgb(float v) {
    v = std::clamp(v, 0.0f, 1.0f);
    return v <= 0.0031308f ? 12.92f * v : 1.055f * std::pow(v, 1.0f / 2.4f) - 0.055f;
}

struct Options {
    std::string out = "engine_integration.png", shaderDir = EXAMPLE_SHADER_DIR;
    int width = 640, height = 640;
    bool normalAov = false, useUv = true, useDecal = true, analyticDerivs = false,
         printShader = false;
};

Options parseArgs(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) fail(a + ": missing value");
            return argv[++i];
        };
        if (a == "-o")
            o.out = next();
        else if (a == "--shader-dir")
            o.shaderDir = next();
        else if (a == "--print-shader")
            o.printShader = true;
        else if (a == "--size") {
            std::string v = next();
            if (std::sscanf(v.c_str(), "%dx%d", &o.width, &o.height) != 2 || o.width < 1 ||
                o.height < 1 || o.width > 8192 || o.height > 8192)
                fail("--size: expected WxH (1..8192), got " + v);
        } else if (a == "--aov") {
            std::string v = next();
            if (v != "color" && v != "normal") fail("--aov: expected color or normal");
            o.normalAov = v == "normal";
        } else if (a == "--layers") {
            std::string v = next();
            if (v != "uv,decal" && v != "uv" && v != "decal" && v != "none")
                fail("--layers: expected uv,decal|uv|decal|none");
            o.useUv = v.find("uv") != std::string::npos;
            o.useDecal = v.find("decal") != std::string::npos;
        } else if (a == "--derivs") {
            std::string v = next();
            if (v != "fine" && v != "analytic") fail("--derivs: expected fine or analytic");
            o.analyticDerivs = v == "analytic";
        } else {
            fail("unknown argument " + a + " (see the comment at the top of main.cpp)");
        }
    }
    return o;
}

} // namespace

int main(int argc, char** argv) try {
    Options opt = parseArgs(argc, argv);

    // The library's #includes resolve against the copy embedded in
    // surfgrad_shaders; the sample's own shaders are read from disk.
    std::vector<std::string> defines;
    if (opt.analyticDerivs) defines.push_back("EXAMPLE_ANALYTIC_DERIVS");
    sg::shaders::Assembled vs =
        sg::shaders::assemble(readText(opt.shaderDir + "/bumped.vert"), "bumped.vert");
    sg::shaders::Assembled fs =
        sg::shaders::assemble(readText(opt.shaderDir + "/bumped.frag"), "bumped.frag", defines);
    if (opt.printShader) {
        std::fwrite(fs.text.data(), 1, fs.text.size(), stdout);
        return 0;
    }

    createHeadlessContext();
    GLuint prog = glCreateProgram();
    GLuint vsh = compile(GL_VERTEX_SHADER, vs), fsh = compile(GL_FRAGMENT_SHADER, fs);
    glAttachShader(prog, vsh);
    glAttachShader(prog, fsh);
    glLinkProgram(prog);
    GLint linked = 0;
    glGetProgramiv(prog, GL_LINK_STATUS, &linked);
    if (!linked) fail("program link failed");

    // Mesh: position, normal, UV0. No tangents.
    std::vector<Vertex> verts;
    std::vector<uint32_t> indices;
    buildSphere(verts, indices);
    GLuint vao = 0, vbo = 0, ibo = 0;
    glCreateVertexArrays(1, &vao);
    glCreateBuffers(1, &vbo);
    glCreateBuffers(1, &ibo);
    glNamedBufferStorage(vbo, GLsizeiptr(verts.size() * sizeof(Vertex)), verts.data(), 0);
    glNamedBufferStorage(ibo, GLsizeiptr(indices.size() * sizeof(uint32_t)), indices.data(), 0);
    glVertexArrayVertexBuffer(vao, 0, vbo, 0, sizeof(Vertex));
    glVertexArrayElementBuffer(vao, ibo);
    const GLuint offsets[3] = {offsetof(Vertex, position), offsetof(Vertex, normal),
                               offsetof(Vertex, uv0)};
    for (GLuint a = 0; a < 3; ++a) {
        glEnableVertexArrayAttrib(vao, a);
        glVertexArrayAttribFormat(vao, a, a == 2 ? 2 : 3, GL_FLOAT, GL_FALSE, offsets[a]);
        glVertexArrayAttribBinding(vao, a, 0);
    }

    GLuint normalMap = makeNormalMap(kNormalMapWidth, kNormalMapHeight, GL_REPEAT, dimpleDeriv);
    GLuint decalMap = makeNormalMap(kDecalMapSize, kDecalMapSize, GL_CLAMP_TO_EDGE, decalDeriv);

    // Camera: shading happens in world space relative to the camera.
    const glm::vec3 cameraPos(0.0f, 0.0f, kCameraDistance);
    const float aspect = float(opt.width) / float(opt.height);
    glm::mat4 proj = glm::perspective(glm::radians(kFovYDeg), aspect, kNear, kFar);
    glm::mat4 viewRot =
        glm::lookAt(glm::vec3(0.0f), -cameraPos, glm::vec3(0, 1, 0)); // no translation
    glm::mat4 viewProjRel = proj * viewRot;
    glm::mat4 viewport(1.0f); // NDC -> window pixels, depth -> [0,1]
    viewport[0][0] = 0.5f * opt.width;
    viewport[1][1] = 0.5f * opt.height;
    viewport[2][2] = 0.5f;
    viewport[3] = glm::vec4(0.5f * opt.width, 0.5f * opt.height, 0.5f, 1.0f);
    glm::mat4 invViewProjScr = glm::inverse(viewport * viewProjRel);

    glm::vec3 dx, dy, dz;
    decalAxes(dx, dy, dz);

    glUseProgram(prog);
    auto loc = [&](const char* name) { return glGetUniformLocation(prog, name); };
    glUniformMatrix4fv(loc("uModel"), 1, GL_FALSE, glm::value_ptr(glm::mat4(1.0f)));
    glUniformMatrix3fv(loc("uNormalMat"), 1, GL_FALSE, glm::value_ptr(glm::mat3(1.0f)));
    glUniform3fv(loc("uCameraPos"), 1, glm::value_ptr(cameraPos));
    glUniformMatrix4fv(loc("uViewProjRel"), 1, GL_FALSE, glm::value_ptr(viewProjRel));
    if (opt.analyticDerivs)
        glUniformMatrix4fv(loc("uInvViewProjScr"), 1, GL_FALSE, glm::value_ptr(invViewProjScr));
    glUniform1i(loc("uBfaceMode"), 0); // SG_BFACE_NONE (back faces are culled anyway)
    glUniform1i(loc("uNormalMap"), 0);
    glUniform1f(loc("uNormalStrength"), opt.useUv ? kNormalMapStrength : 0.0f);
    glUniform1i(loc("uDecalMap"), 1);
    glUniform3fv(loc("uDecalOrigin"), 1, glm::value_ptr(decalCenter() - cameraPos));
    glUniform3fv(loc("uDecalAxisX"), 1, glm::value_ptr(dx));
    glUniform3fv(loc("uDecalAxisY"), 1, glm::value_ptr(dy));
    glUniform3fv(loc("uDecalAxisZ"), 1, glm::value_ptr(dz));
    glUniform3f(loc("uDecalHalfSize"), kDecalHalfSize, kDecalHalfSize, kDecalHalfDepth);
    glUniform2f(loc("uDecalCosFade"), kDecalCosStart, kDecalCosEnd);
    glUniform1f(loc("uDecalStrength"), opt.useDecal ? kDecalStrength : 0.0f);
    glUniform3fv(loc("uLightDir"), 1, glm::value_ptr(lightDirection()));
    glUniform3f(loc("uBaseColor"), 0.62f, 0.42f, 0.26f);
    glUniform1i(loc("uOutput"), opt.normalAov ? 1 : 0);
    glBindTextureUnit(0, normalMap);
    glBindTextureUnit(1, decalMap);

    // Float framebuffer; draw; read back.
    GLuint fbo = 0, color = 0, depth = 0;
    glCreateFramebuffers(1, &fbo);
    glCreateTextures(GL_TEXTURE_2D, 1, &color);
    glTextureStorage2D(color, 1, GL_RGBA32F, opt.width, opt.height);
    glCreateRenderbuffers(1, &depth);
    glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, opt.width, opt.height);
    glNamedFramebufferTexture(fbo, GL_COLOR_ATTACHMENT0, color, 0);
    glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        fail("incomplete framebuffer");
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, opt.width, opt.height);
    const float background[4] = {0.02f, 0.022f, 0.026f, 0.0f};
    const float clearNormal[4] = {0.0f, 0.0f, 0.0f, 0.0f}; // "no surface" in the normal AOV
    glClearNamedFramebufferfv(fbo, GL_COLOR, 0, opt.normalAov ? clearNormal : background);
    glClearNamedFramebufferfi(fbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    glBindVertexArray(vao);
    glDrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, nullptr);
    std::vector<float> rgba(size_t(opt.width) * size_t(opt.height) * 4);
    glReadPixels(0, 0, opt.width, opt.height, GL_RGBA, GL_FLOAT, rgba.data());
    if (glGetError() != GL_NO_ERROR) fail("OpenGL error while rendering");

    // Bottom-up float rows -> top-down 8-bit rows.
    std::vector<uint8_t> rgb(size_t(opt.width) * size_t(opt.height) * 3);
    for (int y = 0; y < opt.height; ++y) {
        for (int x = 0; x < opt.width; ++x) {
            const float* p =
                &rgba[(size_t(opt.height - 1 - y) * size_t(opt.width) + size_t(x)) * 4];
            for (int c = 0; c < 3; ++c) {
                float v =
                    opt.normalAov ? (p[3] > 0.0f ? 0.5f * p[c] + 0.5f : 0.0f) : linearToSrgb(p[c]);
                rgb[(size_t(y) * size_t(opt.width) + size_t(x)) * 3 + size_t(c)] =
                    uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f));
            }
        }
    }
    writePng(opt.out, opt.width, opt.height, rgb);
    std::printf("wrote %s (%dx%d, %s)\n", opt.out.c_str(), opt.width, opt.height,
                opt.normalAov ? "normal" : "color");
    return 0;
} catch (const std::exception& e) {
    std::fprintf(stderr, "example_engine_integration: error: %s\n", e.what());
    return 1;
}

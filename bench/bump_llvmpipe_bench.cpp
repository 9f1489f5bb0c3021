// bench_bump_llvmpipe: cost of generating the tangent frame per pixel
// (Mikkelsen 2019 section 2.3: L16 prologue + L6 GenBasisTB + L5 + L1)
// against interpolated vertex tangents (section 2.2: mikktspace basis + L5 +
// L1), in a 1024x1024 fragment pass on Mesa llvmpipe (the CI "GPU").
// Same geometry (a wavy 128x128-quad grid in perspective covering the
// viewport), same 512x512 RG8 normal map, same output (the resolved normal
// written to an RGBA8 target); only the frame differs. Each frame is one
// draw followed by glFinish (llvmpipe skips draws fully covered by a later
// draw, so batching frames before one finish under-reports; docs/platform.md).
// Reports, per variant, the median frame time over several runs and the
// ratio to the vertex-tangent baseline measured in the same run (goal:
// <= 1.15x). Also checks both variants produce nearly the same
// image (they differ only by the frame's construction).
// Run: LIBGL_ALWAYS_SOFTWARE=1 GALLIUM_DRIVER=llvmpipe EGL_PLATFORM=surfaceless
//      build/bin/bench_bump_llvmpipe [--runs N] [--frames N] [--size N]
#include <epoxy/gl.h>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <ctime>
#include <vector>

#include "surfgrad/gl/context.h"
#include "surfgrad/shaders/shader_files.h"

namespace {

const char* kVertex = R"(
layout(location = 0) in vec3 aPos;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aTangent;
layout(location = 3) in vec2 aUv;
uniform mat4 uViewProj;
out vec3 vRelPos;
out vec3 vNormal;
out vec4 vTangent;
out vec2 vUv;
void main() {
    vRelPos = aPos; // camera at the origin: camera-relative world space (L16)
    vNormal = aNormal;
    vTangent = aTangent;
    vUv = aUv;
    gl_Position = uViewProj * vec4(aPos, 1.0);
}
)";

// Shared prefix of both fragment programs.
const char* kFragmentHead = R"(
#include "sg/surfgrad.glsl"
in vec3 vRelPos;
in vec3 vNormal;
in vec4 vTangent;
in vec2 vUv;
uniform sampler2D uNormalMap;
layout(location = 0) out vec4 oColor;
vec2 sampleDeriv() {
    vec2 m = texture(uNormalMap, vUv).xy * 2.0 - 1.0;
    return sgTspaceNormalToDeriv(m, false);
}
)";

// Per-pixel frame: L16 prologue, L6 basis from dFdxFine(uv), L5, L1.
const char* kFragmentPerPixel = R"(
void main() {
    SgFrame f = sgPrologue(vNormal, dFdxFine(vRelPos), dFdyFine(vRelPos), gl_FrontFacing,
                           SG_BFACE_NONE);
    vec3 t;
    vec3 b;
    sgGenBasisTB(f, vUv, dFdxFine(vUv), dFdyFine(vUv), t, b);
    vec3 n = sgResolve(f, sgSurfgradFromTBN(sampleDeriv(), t, b));
    oColor = vec4(n * 0.5 + 0.5, 1.0);
}
)";

// The same per-pixel chain written as plainly as the paper's listings 16, 6
// and 1 (no scale invariance, no degenerate-case handling): the cost floor
// of the method, to show what the robustness of the shared code costs.
const char* kFragmentPerPixelPlain = R"(
void main() {
    vec3 n = normalize(vNormal);
    vec3 dPdx = dFdxFine(vRelPos);
    vec3 dPdy = dFdyFine(vRelPos);
    vec3 sigmaX = dPdx - dot(dPdx, n) * n;
    vec3 sigmaY = dPdy - dot(dPdy, n) * n;
    float flipSign = dot(dPdy, cross(n, dPdx)) < 0.0 ? -1.0 : 1.0;
    vec2 dSTdx = dFdxFine(vUv);
    vec2 dSTdy = dFdyFine(vUv);
    float det = dot(dSTdx, vec2(dSTdy.y, -dSTdy.x));
    float signDet = det < 0.0 ? -1.0 : 1.0;
    vec2 invC0 = signDet * vec2(dSTdy.y, -dSTdx.y);
    vec3 t = sigmaX * invC0.x + sigmaY * invC0.y;
    if (abs(det) > 0.0) t = normalize(t);
    vec3 b = (signDet * flipSign) * cross(n, t);
    vec2 d = sampleDeriv();
    oColor = vec4(normalize(n - (d.x * t + d.y * b)) * 0.5 + 0.5, 1.0);
}
)";

// Vertex-tangent frame: mikktspace-compliant basis (section 2.2), L5, L1.
const char* kFragmentVertexTangent = R"(
void main() {
    SgFrame f;
    f.nrmBase = vNormal * sgRenormFactor(vNormal);
    f.resolveSign = 1.0;
    vec3 t;
    vec3 b;
    sgMikktsBasis(vNormal, vTangent, t, b);
    vec3 n = sgResolve(f, sgSurfgradFromTBN(sampleDeriv(), t, b));
    oColor = vec4(n * 0.5 + 0.5, 1.0);
}
)";

struct Vertex {
    float pos[3], nrm[3], tan[4], uv[2];
};

// A grid over [-1,1]^2 at z = -2.2 with a gentle wave, seen by a 60 degree
// camera at the origin: it covers the whole viewport. Analytic normals and
// tangents (dP/du normalized, w = +1) per vertex.
std::vector<Vertex> makeGrid(int n, std::vector<unsigned>& indices) {
    std::vector<Vertex> v;
    const float amp = 0.08f, freq = 5.0f;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) {
            const float u = float(i) / float(n), w = float(j) / float(n);
            const float x = -1.6f + 3.2f * u, y = -1.6f + 3.2f * w;
            const float z = -2.2f + amp * std::sin(freq * x) * std::cos(freq * y);
            const glm::vec3 pu(3.2f, 0,
                               3.2f * amp * freq * std::cos(freq * x) * std::cos(freq * y));
            const glm::vec3 pv(0, 3.2f,
                               -3.2f * amp * freq * std::sin(freq * x) * std::sin(freq * y));
            const glm::vec3 nn = glm::normalize(glm::cross(pu, pv));
            const glm::vec3 tt = glm::normalize(pu);
            v.push_back({{x, y, z}, {nn.x, nn.y, nn.z}, {tt.x, tt.y, tt.z, 1.0f}, {4 * u, 4 * w}});
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const unsigned a = unsigned(j * (n + 1) + i), b = a + 1, c = a + unsigned(n + 1),
                           d = c + 1;
            indices.insert(indices.end(), {a, b, d, a, d, c});
        }
    }
    return v;
}

// A procedural tangent-space normal map (bumps), RG8 in [0,1] encoding.
std::vector<unsigned char> makeNormalMap(int size) {
    std::vector<unsigned char> px(size_t(size) * size_t(size) * 2);
    for (int y = 0; y < size; ++y) {
        for (int x = 0; x < size; ++x) {
            const float s = 2 * 3.14159265f * 6 * float(x) / float(size);
            const float t = 2 * 3.14159265f * 6 * float(y) / float(size);
            glm::vec3 n = glm::normalize(glm::vec3(-0.6f * std::cos(s) * std::sin(t),
                                                   -0.6f * std::sin(s) * std::cos(t), 1.0f));
            px[(size_t(y) * size_t(size) + size_t(x)) * 2 + 0] =
                (unsigned char)std::lround((n.x * 0.5f + 0.5f) * 255);
            px[(size_t(y) * size_t(size) + size_t(x)) * 2 + 1] =
                (unsigned char)std::lround((n.y * 0.5f + 0.5f) * 255);
        }
    }
    return px;
}

// Process CPU time in ms: llvmpipe's rasterizer threads run in this
// process, so this is the work done, independent of other load on the
// machine (wall time is also reported).
double cpuMs() {
    timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const size_t m = v.size() / 2;
    return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

int argInt(int argc, char** argv, const char* name, int def) {
    for (int i = 1; i + 1 < argc; ++i) {
        if (std::strcmp(argv[i], name) == 0) return std::max(1, std::atoi(argv[i + 1]));
    }
    return def;
}

} // namespace

int main(int argc, char** argv) {
    const int size = argInt(argc, argv, "--size", 1024);
    const int runs = argInt(argc, argv, "--runs", 7);
    const int frames = argInt(argc, argv, "--frames", 10);
    try {
        sg::gl::HeadlessContext ctx;
        using sg::gl::Stage;
        auto vs = sg::shaders::assemble(kVertex, "bench_vs");
        sg::gl::Program perPixel(
            {{Stage::Vertex, vs},
             {Stage::Fragment, sg::shaders::assemble(std::string(kFragmentHead) + kFragmentPerPixel,
                                                     "per_pixel_fs")}});
        sg::gl::Program perPixelPlain(
            {{Stage::Vertex, vs},
             {Stage::Fragment,
              sg::shaders::assemble(std::string(kFragmentHead) + kFragmentPerPixelPlain,
                                    "per_pixel_plain_fs")}});
        sg::gl::Program vertexTangent(
            {{Stage::Vertex, vs},
             {Stage::Fragment,
              sg::shaders::assemble(std::string(kFragmentHead) + kFragmentVertexTangent,
                                    "vertex_tangent_fs")}});

        std::vector<unsigned> indices;
        const auto verts = makeGrid(128, indices);
        GLuint vao, vbo, ibo;
        glCreateVertexArrays(1, &vao);
        glCreateBuffers(1, &vbo);
        glCreateBuffers(1, &ibo);
        glNamedBufferData(vbo, GLsizeiptr(verts.size() * sizeof(Vertex)), verts.data(),
                          GL_STATIC_DRAW);
        glNamedBufferData(ibo, GLsizeiptr(indices.size() * sizeof(unsigned)), indices.data(),
                          GL_STATIC_DRAW);
        glVertexArrayVertexBuffer(vao, 0, vbo, 0, sizeof(Vertex));
        glVertexArrayElementBuffer(vao, ibo);
        const GLuint offsets[] = {offsetof(Vertex, pos), offsetof(Vertex, nrm),
                                  offsetof(Vertex, tan), offsetof(Vertex, uv)};
        const GLint sizes[] = {3, 3, 4, 2};
        for (GLuint a = 0; a < 4; ++a) {
            glEnableVertexArrayAttrib(vao, a);
            glVertexArrayAttribFormat(vao, a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
            glVertexArrayAttribBinding(vao, a, 0);
        }

        const int mapSize = 512;
        const auto mapPixels = makeNormalMap(mapSize);
        GLuint tex;
        glCreateTextures(GL_TEXTURE_2D, 1, &tex);
        glTextureStorage2D(tex, 10, GL_RG8, mapSize, mapSize);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTextureSubImage2D(tex, 0, 0, 0, mapSize, mapSize, GL_RG, GL_UNSIGNED_BYTE,
                            mapPixels.data());
        glGenerateTextureMipmap(tex);
        glTextureParameteri(tex, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
        glTextureParameteri(tex, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTextureParameteri(tex, GL_TEXTURE_WRAP_S, GL_REPEAT);
        glTextureParameteri(tex, GL_TEXTURE_WRAP_T, GL_REPEAT);

        GLuint fbo, color, depth;
        glCreateFramebuffers(1, &fbo);
        glCreateRenderbuffers(1, &color);
        glCreateRenderbuffers(1, &depth);
        glNamedRenderbufferStorage(color, GL_RGBA8, size, size);
        glNamedRenderbufferStorage(depth, GL_DEPTH_COMPONENT24, size, size);
        glNamedFramebufferRenderbuffer(fbo, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
        glNamedFramebufferRenderbuffer(fbo, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth);
        if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            throw sg::gl::GlError("framebuffer incomplete");
        }
        glBindFramebuffer(GL_FRAMEBUFFER, fbo);
        glViewport(0, 0, size, size);
        glEnable(GL_DEPTH_TEST);
        glBindVertexArray(vao);
        glBindTextureUnit(0, tex);
        const glm::mat4 viewProj = glm::perspective(glm::radians(60.0f), 1.0f, 0.1f, 10.0f);

        auto drawFrame = [&](const sg::gl::Program& p) {
            glUseProgram(p.id());
            glUniformMatrix4fv(p.uniform("uViewProj"), 1, GL_FALSE, &viewProj[0][0]);
            glUniform1i(p.uniform("uNormalMap"), 0);
            glClearColor(0, 0, 0, 1);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            glDrawElements(GL_TRIANGLES, GLsizei(indices.size()), GL_UNSIGNED_INT, nullptr);
            glFinish();
        };
        auto readback = [&] {
            std::vector<unsigned char> px(size_t(size) * size_t(size) * 4);
            glReadPixels(0, 0, size, size, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
            return px;
        };

        // Warm-up (shader JIT, texture upload) and the image comparison.
        drawFrame(vertexTangent);
        const auto imgVertex = readback();
        drawFrame(perPixel);
        const auto imgPixel = readback();
        size_t covered = 0, maxDiff = 0;
        double sumDiff = 0;
        for (size_t i = 0; i < imgPixel.size(); i += 4) {
            covered +=
                imgPixel[i + 3] == 255 && (imgPixel[i] | imgPixel[i + 1] | imgPixel[i + 2]) != 0;
            for (int c = 0; c < 3; ++c) {
                const size_t d =
                    size_t(std::abs(int(imgPixel[i + size_t(c)]) - int(imgVertex[i + size_t(c)])));
                maxDiff = std::max(maxDiff, d);
                sumDiff += double(d);
            }
        }
        sg::gl::checkError("bench setup");

        // Interleave the variants run by run so drift (other load on the
        // machine) affects both alike.
        std::vector<double> wall[3], cpu[3];
        for (int r = 0; r < runs; ++r) {
            for (int variant = 0; variant < 3; ++variant) {
                const auto& p = variant == 0   ? vertexTangent
                                : variant == 1 ? perPixel
                                               : perPixelPlain;
                std::vector<double> tw, tc;
                for (int f = 0; f < frames; ++f) {
                    const auto t0 = std::chrono::steady_clock::now();
                    const double c0 = cpuMs();
                    drawFrame(p);
                    tc.push_back(cpuMs() - c0);
                    tw.push_back(std::chrono::duration<double, std::milli>(
                                     std::chrono::steady_clock::now() - t0)
                                     .count());
                }
                wall[variant].push_back(median(tw));
                cpu[variant].push_back(median(tc));
            }
        }
        std::printf("bench_bump_llvmpipe: %dx%d fragment pass, %zu triangles, %s\n", size, size,
                    indices.size() / 3, ctx.renderer().c_str());
        std::printf("coverage %.1f%% of pixels; per-pixel vs vertex-tangent image: max |diff| "
                    "%zu/255, mean %.3f/255\n",
                    100.0 * double(covered) / (double(size) * size), maxDiff,
                    sumDiff / (3.0 * double(size) * size));
        std::printf("%-42s %9s %8s %11s %9s %8s\n", "variant", "wall ms", "ratio", "wall range",
                    "CPU ms", "ratio");
        const char* names[3] = {"vertex tangents (mikkts + L5 + L1)",
                                "per-pixel TBN (L16 + L6 + L5 + L1)",
                                "per-pixel TBN, plain listings (no guards)"};
        const double baseWall = median(wall[0]), baseCpu = median(cpu[0]);
        for (int v = 0; v < 3; ++v) {
            const double mw = median(wall[v]), mc = median(cpu[v]);
            std::printf("%-42s %9.2f %7.3fx %5.0f..%-5.0f %9.2f %7.3fx\n", names[v], mw,
                        mw / baseWall, *std::min_element(wall[v].begin(), wall[v].end()),
                        *std::max_element(wall[v].begin(), wall[v].end()), mc, mc / baseCpu);
        }
        std::printf(
            "(%d runs x %d frames, each frame = draw + glFinish; medians of per-run medians;\n"
            " CPU ms = process CPU time of all llvmpipe threads, robust to other load; "
            "goal: ratio <= 1.15)\n",
            runs, frames);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench_bump_llvmpipe: %s\n", e.what());
        return 1;
    }
    return 0;
}
